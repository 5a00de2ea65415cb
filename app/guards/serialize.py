"""A frame's messages turned into viser's wire form quickly, and a message sent to many browsers only once.

More in docs/app-notes.md (``app.guards.serialize``).
"""

from __future__ import annotations

import weakref
from typing import Any

import numpy as np
from viser import _messages as _viser_messages
from viser.infra import _messages

__all__ = ["kept_form", "kept_count", "serialize_once"]


class _Kept(weakref.ref):  # type: ignore[type-arg]
    """A weak reference to a message that carries the message's wire form (False: it carries binary buffers,
    never kept) and the id it is filed under."""

    __slots__ = ("form", "key")

    form: dict[str, Any] | bool
    key: int


_KEPT: dict[int, _Kept] = {}
"""Each message's wire form by the message's id, for as long as the message lives. Kept here, not on viser's
message: a message is not hashable, and ours stays ours."""


def kept_form(message: Any) -> dict[str, Any] | bool | None:
    """The wire form kept for ``message`` (False: never kept, it carries buffers; None: not serialized yet)."""
    kept = _KEPT.get(id(message))
    return kept.form if kept is not None and kept() is message else None


def kept_count() -> int:
    """How many messages have a wire form kept (each entry goes with its message)."""
    return len(_KEPT)


def _forget(kept: _Kept) -> None:
    """The message has gone (before its id can be reused): its entry goes too."""
    if _KEPT.get(kept.key) is kept:
        del _KEPT[kept.key]


def _keep(message: Any, form: dict[str, Any] | bool) -> None:
    kept = _Kept(message, _forget)
    kept.form, kept.key = form, id(message)
    _KEPT[kept.key] = kept


_viser_form = _messages.Message.as_serializable_dict

_POSES: dict[type, str] = {
    _viser_messages.SetOrientationMessage: "wxyz",
    _viser_messages.SetPositionMessage: "position",
}
"""The pose messages of a frame and their tuple of floats (``name: str, <field>: tuple[float, ...],
owner: str`` on the wire)."""

_UPDATES = (_viser_messages.GuiUpdateMessage, _viser_messages.SceneNodeUpdateMessage)
"""The update messages of a frame: string fields and ``updates: dict[str, Any]``."""

_AS_IS = (str, float, int, bool, type(None))
"""Values viser's walk gives back unchanged when the type hint is ``Any`` (exact types only: a numpy
scalar or a subclass is converted by viser)."""


class _Unusual(Exception):
    """A value the fast path does not know: viser's own walk serializes the message."""


def _update_value(value: Any, buffers: list[memoryview]) -> Any:
    kind = type(value)
    if kind in _AS_IS:
        return value
    if kind is np.ndarray:
        # As viser: the array's bytes go to the window's buffers, a placeholder stays in the message.
        buffers.append(value.data if value.flags.c_contiguous else value.copy().data)
        return {"__binary_index": len(buffers) - 1, "dtype": value.dtype.str}
    raise _Unusual


def _fast_form(message: Any, buffers: list[memoryview]) -> dict[str, Any] | None:
    """viser's wire form of a frame's message, built directly (None: not a message this knows)."""
    kind = type(message)
    field = _POSES.get(kind)
    if field is not None:
        values, name, owner = getattr(message, field), message.name, message.owner
        if type(values) is not tuple or type(name) is not str or type(owner) is not str:
            return None
        if not all(type(v) is float for v in values):
            return None
        return {"name": name, field: values, "owner": owner, "type": kind.__name__}
    if kind in _UPDATES:
        updates = message.updates
        if type(updates) is not dict:
            return None
        mark = len(buffers)
        try:
            wire = {k: _update_value(v, buffers) for k, v in updates.items() if type(k) is str}
        except _Unusual:
            del buffers[mark:]
            return None
        if len(wire) != len(updates):
            del buffers[mark:]
            return None
        if kind is _viser_messages.GuiUpdateMessage:
            if type(message.uuid) is not str:
                del buffers[mark:]
                return None
            return {"uuid": message.uuid, "updates": wire, "type": kind.__name__}
        if type(message.name) is not str or type(message.owner) is not str:
            del buffers[mark:]
            return None
        return {"name": message.name, "updates": wire, "owner": message.owner, "type": kind.__name__}
    return None


def _once(message: Any, binary_buffers: list[memoryview] | None = None) -> dict[str, Any]:
    """viser's ``Message.as_serializable_dict``: the same dict, built directly for a frame's messages, and
    kept for the message's life when it adds no binary buffer.

    A message with arrays (points, meshes) puts them into ``binary_buffers`` at indices that depend on the
    window it is sent in: it is serialized anew each time, as viser does.
    """
    kept = kept_form(message)
    if isinstance(kept, dict):
        return kept
    if binary_buffers is None:
        return _viser_form(message, binary_buffers)
    before = len(binary_buffers)
    form = None if kept is False else _fast_form(message, binary_buffers)
    if form is None:
        form = _viser_form(message, binary_buffers)
    if kept is None:
        _keep(message, form if len(binary_buffers) == before else False)
    return form


def serialize_once() -> None:
    """Install :func:`_once` as every viser message's ``as_serializable_dict`` (process-wide; calling it
    again changes nothing)."""
    _messages.Message.as_serializable_dict = _once  # type: ignore[method-assign,assignment]
