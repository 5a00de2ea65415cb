"""Deny by default: every viser message type a page does not send is dropped before viser sees it.

A raw websocket (what a script sends, no page) tries every message type in viser's message module that is
not on the allow-list; another browser receives nothing and the replay buffer every newcomer downloads is
unchanged. Then: oversized allowed messages, garbage, floods, and the close after repeated offences.
"""

from __future__ import annotations

import dataclasses
import io
import threading
import time
import typing

import matplotlib.image
import msgspec
import numpy as np
import pytest
from viser import _messages
from websockets.exceptions import ConnectionClosed

from app.guards.gate import ALLOWED, LARGEST, OFFENCES, REFUSED_CODE, RENDER, RENDER_CAP, Gate
from tests.app.reading import received_until
from tests.harness import CAMERA_MESSAGE, drain, raw_client, received, running_app, send_value, wait_for

MARK = "rbl-hostile-"
"""Every string a hostile message carries starts with this: nothing another browser receives may hold it."""


def _value(hint: str) -> typing.Any:
    """A plausible value for a dataclass field of this annotation (viser's would-be handler must not choke
    on the shape before it could act)."""
    if hint.startswith("str") or hint.startswith("Optional[str") or hint == "ClientId":
        return MARK + "x" * 2_000
    if hint.startswith("int"):
        return 1
    if hint.startswith("float"):
        return 1.0
    if hint.startswith("bool"):
        return True
    if hint.startswith("Tuple[float") or hint.startswith("tuple[float"):
        return (1.0, 0.0, 0.0, 0.0) if "float, float, float, float" in hint else (1.0, 0.0, 0.0)
    if "Dict" in hint or "dict" in hint:
        return {"value": MARK}
    return None


def _message(kind: type) -> bytes:
    fields = {f.name: _value(str(f.type)) for f in dataclasses.fields(kind)}
    return msgspec.msgpack.encode({"type": kind.__name__, **fields})


FORBIDDEN = sorted(name for name in _messages.Message._subclass_from_type_string() if name not in ALLOWED)


def test_allow_list_names_real_viser_messages() -> None:
    """Every allowed name is one of viser's message types (a rename in viser would silently refuse a page)."""
    known = _messages.Message._subclass_from_type_string()
    assert set(ALLOWED) <= set(known)
    assert len(FORBIDDEN) > 80  # viser 1.1.1 has about a hundred; all but six are refused


def test_verdicts() -> None:
    gate = Gate()
    assert gate.verdict(CAMERA_MESSAGE) == ("ViewerCameraMessage", None)
    assert gate.verdict(b"\xc1garbage") == (None, "not a message")
    assert gate.verdict("text frame") == (None, "not a message")
    assert gate.verdict(msgspec.msgpack.encode({"no": "type"})) == (None, "not a message")
    assert gate.verdict(msgspec.msgpack.encode([1, 2])) == (None, "not a message")
    dirty = msgspec.msgpack.encode({"type": "GuiFormDirtyMessage", "uuid": "x"})
    assert gate.verdict(dirty) == ("GuiFormDirtyMessage", "GuiFormDirtyMessage")
    big = msgspec.msgpack.encode({"type": "ViewerCameraMessage", "pad": "x" * ALLOWED["ViewerCameraMessage"]})
    assert gate.verdict(big) == ("ViewerCameraMessage", "too large: ViewerCameraMessage")
    odd = msgspec.msgpack.encode({"type": "ShareUrlRequest", "uuid": "x"})  # a field viser does not know
    assert gate.verdict(odd) == ("ShareUrlRequest", "malformed: ShareUrlRequest")
    huge = msgspec.msgpack.encode({"type": "FileTransferPart", "content": b"x" * (LARGEST + 1)})
    assert gate.verdict(huge) == (None, "too large")
    part = {"type": "FileTransferPart", "source_component_uuid": "b", "transfer_uuid": "t", "part_index": 0}
    assert gate.verdict(msgspec.msgpack.encode({**part, "content": b"x" * (512 * 1024)})) == ("FileTransferPart", None)


def test_every_other_message_type_changes_nothing() -> None:
    """The raw-client test: each type not on the allow-list, sent with fields that viser's handler (where
    it has one) would act on; a watcher receives nothing of it, the replay buffer is as it was, and every
    message was counted by its type."""
    with running_app(presenter=True, start_loop=False) as app:
        with raw_client(app) as watcher:
            time.sleep(0.5)
            drain(watcher)
            buffer = app.server._websock_server._broadcast_buffer
            before = dict(buffer.message_from_id)
            batch = OFFENCES - 1  # a connection is closed at OFFENCES: send fewer on each
            for start in range(0, len(FORBIDDEN), batch):
                with raw_client(app) as hostile:
                    for name in FORBIDDEN[start : start + batch]:
                        hostile.send(_message(_messages.Message._subclass_from_type_string()[name]))
                    send_value(hostile, app.simulation.time_text._impl.uuid, "still here")  # allowed: answered
                    assert received_until(hostile, lambda got: any(m["type"] == "GuiUpdateMessage" for m in got))
            seen = received(watcher, 0.5)
            assert not any(MARK in repr(m) for m in seen), [m["type"] for m in seen]
            assert dict(buffer.message_from_id) == before
            for name in FORBIDDEN:
                assert app.gate.dropped[name] == 1, name
            assert app.gate.closed == 0


def test_relayed_type_is_not_relayed() -> None:
    """The type viser relays to every browser and keeps for newcomers: 300 of them, 10 kB each, leave no
    trace (without the gate the buffer grew by 3 MB)."""
    with running_app(presenter=True, start_loop=False) as app:
        with raw_client(app) as watcher:
            drain(watcher)
            buffer = app.server._websock_server._broadcast_buffer
            count = len(buffer.message_from_id)
            dirty = msgspec.msgpack.encode({"type": "GuiFormDirtyMessage", "uuid": MARK + "x" * 10_000})
            for _ in range(300 // (OFFENCES - 1) + 1):
                with raw_client(app) as hostile:
                    for _ in range(OFFENCES - 1):
                        hostile.send(dirty)
            assert not any(m["type"] == "GuiFormDirtyMessage" for m in received(watcher, 0.5))
            assert len(buffer.message_from_id) == count


@pytest.mark.parametrize(
    "hostile",
    [
        msgspec.msgpack.encode({"type": "GuiFormDirtyMessage", "uuid": "x"}),
        b"\x00\x01 not msgpack",
        msgspec.msgpack.encode({"type": "ViewerCameraMessage", "pad": "x" * 3_000}),
    ],
    ids=["refused type", "garbage", "oversized"],
)
def test_repeated_offences_close_the_connection(hostile: bytes) -> None:
    with running_app(presenter=True, start_loop=False) as app:
        with raw_client(app) as ws:
            for _ in range(OFFENCES):
                ws.send(hostile)
            with pytest.raises(ConnectionClosed):
                for _ in range(10_000):
                    ws.recv(timeout=10)
            assert ws.close_code == REFUSED_CODE
            assert "refused" in (ws.close_reason or "")
        assert app.gate.closed == 1
        with raw_client(app) as other:  # the server goes on serving
            send_value(other, app.simulation.time_text._impl.uuid, "x")
            assert received_until(other, lambda got: any(m["type"] == "GuiUpdateMessage" for m in got))


def test_a_flood_of_allowed_messages_is_cut_off() -> None:
    """Camera messages far faster than a page sends them: dropped past the burst, then the connection closed."""
    with running_app(presenter=True, start_loop=False) as app:
        with raw_client(app) as ws:
            with pytest.raises(ConnectionClosed):
                for _ in range(2_000):
                    ws.send(CAMERA_MESSAGE)
                for _ in range(10_000):
                    ws.recv(timeout=10)
            assert ws.close_code == REFUSED_CODE
        assert app.gate.dropped["too fast"] >= OFFENCES


def test_a_frame_over_the_largest_cap_is_refused_by_websockets_as_it_comes() -> None:
    """viser lets a frame be 50 MB; the gate lowers the limit to the largest cap, so a bigger one is refused
    (close 1009) before it is buffered, and the server goes on."""
    with running_app(presenter=True, start_loop=False) as app:
        with raw_client(app) as ws:
            with pytest.raises(ConnectionClosed):
                ws.send(
                    msgspec.msgpack.encode(
                        {"type": "GuiUpdateMessage", "uuid": "u", "updates": {"value": b"x" * (LARGEST + 2048)}}
                    )
                )
                for _ in range(10_000):
                    ws.recv(timeout=10)
            assert ws.close_code == 1009
        with raw_client(app) as other:
            send_value(other, app.simulation.time_text._impl.uuid, "x")
            assert received_until(other, lambda got: any(m["type"] == "GuiUpdateMessage" for m in got))


def test_a_rendered_view_passes_only_while_the_server_waits_for_it() -> None:
    """The page's answer to ``client.get_render`` (a PNG, larger than any cap) passes whole while the server
    waits for one from that connection, and is dropped as an unasked type at any other time."""
    gate = Gate()
    unasked = msgspec.msgpack.encode({"type": RENDER, "payload": b"x", "render_uuid": "r"})
    assert gate.verdict(unasked) == (RENDER, RENDER)
    assert gate.verdict(unasked, rendering=True) == (RENDER, None)
    assert gate.verdict(b"\x00" * (RENDER_CAP + 1), rendering=True) == (None, "too large")
    # Noise does not compress: this PNG is about 1 MB, twice the largest cap of a message the page sends unasked.
    view = np.random.default_rng(0).integers(0, 256, (512, 512, 4), dtype=np.uint8)
    encoded = io.BytesIO()
    matplotlib.image.imsave(encoded, view, format="png")
    png = encoded.getvalue()
    assert len(png) > LARGEST
    with running_app(presenter=True, start_loop=False) as app:
        before = set(app.server.get_clients())
        with raw_client(app) as ws:
            (client,) = [c for i, c in app.server.get_clients().items() if i not in before]
            ws.send(unasked)
            wait_for(lambda: app.gate.dropped[RENDER] == 1, what="the unasked view to be dropped")
            rendered: dict[str, np.ndarray] = {}

            def render() -> None:
                rendered["view"] = client.get_render(512, 512, transport_format="png", timeout=30)

            asking = threading.Thread(target=render)
            asking.start()
            got = received_until(ws, lambda got: any(m["type"] == "GetRenderRequestMessage" for m in got))
            uuid = next(m["render_uuid"] for m in got if m["type"] == "GetRenderRequestMessage")
            ws.send(msgspec.msgpack.encode({"type": RENDER, "payload": png, "render_uuid": uuid}))
            asking.join(timeout=40)
            np.testing.assert_array_equal(rendered["view"], view)
            assert app.gate.dropped[RENDER] == 1  # the unasked one
            # The wait is over: a second, unasked, large answer is refused by websockets as it comes (close 1009).
            with pytest.raises(ConnectionClosed):
                ws.send(msgspec.msgpack.encode({"type": RENDER, "payload": png, "render_uuid": uuid}))
                for _ in range(10_000):
                    ws.recv(timeout=10)
            assert ws.close_code == 1009
