"""app.guards.serialize: a message's wire form is viser's, kept when it carries no binary buffer, made anew
(with its buffers) when it does; the disabled copy a follower gets is serialized as itself."""

from __future__ import annotations

import dataclasses

import msgspec
import numpy as np
from viser import _messages

from app.guards import broadcast, serialize
from app.guards.serialize import serialize_once


def _viser(message, buffers):
    """viser's own wire form (the original method, whatever is installed)."""
    return serialize._viser_form(message, buffers)


def _disabled(message):
    """What a read-only follower is sent instead of ``message``."""
    return broadcast._disabled(message)


def _wire(message):
    buffers: list = []
    form = message.as_serializable_dict(buffers)
    return msgspec.msgpack.encode(form), [bytes(b) for b in buffers]


def _owned(message, owner="scope-1"):
    message.owner = owner  # as viser's scene API stamps a scene message before queueing it
    return message


MESSAGES = [
    lambda: _owned(_messages.SetOrientationMessage("/scene/top", (0.5, 0.5, -0.5, 0.5))),
    lambda: _owned(_messages.SetPositionMessage("/scene/top", (1.0, -2.0, 3.5))),
    lambda: _messages.GuiUpdateMessage("uuid-1", {"_markdown": "**L₃** = 0.4"}),
    lambda: _owned(
        _messages.SceneNodeUpdateMessage("/scene/L", {"points": np.arange(6, dtype=np.float32).reshape(1, 2, 3)})
    ),
    # What the fast path leaves to viser's walk (numpy scalars, nested arrays) or passes as they are.
    lambda: _messages.GuiUpdateMessage("uuid-2", {"value": "x", "n": 3, "f": 1.5, "on": True, "none": None}),
    lambda: _messages.GuiUpdateMessage("uuid-3", {"value": np.float32(2.5), "i": np.int64(7), "b": np.bool_(True)}),
    lambda: _messages.GuiUpdateMessage("uuid-4", {"data": (np.arange(3.0), np.ones(3, dtype=np.float32))}),
    lambda: _owned(_messages.SetPositionMessage("/scene/top", (np.float64(1.0), 2.0, 3.0))),
    lambda: _owned(_messages.SceneNodeUpdateMessage("/scene/L", {"points": np.zeros((2, 3, 3))[:, ::2]})),
    lambda: _owned(_messages.SetOrientationMessage("/scene/top", (1, 0, 0, 0))),  # integers: viser casts them
]


def test_the_wire_form_is_viasers_every_time_and_kept_only_without_buffers():
    serialize_once()
    for make in MESSAGES:
        message, reference = make(), make()
        buffers: list = []
        expected = (msgspec.msgpack.encode(_viser(reference, buffers)), [bytes(b) for b in buffers])
        assert _wire(message) == expected
        assert _wire(message) == expected  # the second time: kept, or made anew with its buffers
        kept = serialize.kept_form(message)
        assert (kept is False) == bool(buffers), type(message).__name__


def test_a_kept_wire_form_goes_with_its_message():
    """Kept beside viser's messages, not on them: the table holds nothing of a message that has gone."""
    serialize_once()
    before = serialize.kept_count()
    messages = [MESSAGES[0]() for _ in range(100)]
    for message in messages:
        _wire(message)
    assert serialize.kept_count() == before + 100
    del message, messages
    assert serialize.kept_count() == before


def test_a_whole_window_is_the_same_bytes_as_viasers():
    serialize_once()
    ours, theirs = [m() for m in MESSAGES], [m() for m in MESSAGES]
    our_buffers: list = []
    their_buffers: list = []
    encoded = msgspec.msgpack.encode([m.as_serializable_dict(our_buffers) for m in ours])
    assert encoded == msgspec.msgpack.encode([_viser(m, their_buffers) for m in theirs])
    assert [bytes(b) for b in our_buffers] == [bytes(b) for b in their_buffers]


def test_buffers_of_a_message_sent_later_in_a_window_keep_their_place():
    serialize_once()
    first = MESSAGES[3]()
    second = MESSAGES[3]()
    buffers: list = []
    first.as_serializable_dict(buffers)
    form = second.as_serializable_dict(buffers)
    assert form["updates"]["points"]["__binary_index"] == 1 and len(buffers) == 2


def test_a_followers_disabled_copy_is_serialized_as_itself():
    serialize_once()
    update = _messages.GuiUpdateMessage("uuid-2", {"disabled": False})
    update.as_serializable_dict([])  # the presenter's own browser got it first
    copy = _disabled(update)
    assert copy is not update and copy.as_serializable_dict([])["updates"] == {"disabled": True}
    assert update.as_serializable_dict([])["updates"] == {"disabled": False}
    pose = MESSAGES[0]()
    assert _disabled(pose) is pose and _disabled(pose) is pose  # the second time from the types passed on
    assert dataclasses.is_dataclass(update)
