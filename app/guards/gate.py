"""Deny by default: the few message types a page sends, each under a size cap, read before viser sees them.

viser 1.1.1 hands every message a websocket brings to whatever handler its type has, and some of its own
handlers relay a browser's message to every other browser and keep it in the replay buffer that every
browser joining later downloads (``GuiFormDirtyMessage``, with an id of any length). The page of this app
sends only the types in :data:`ALLOWED`; anything else, anything over its type's cap, anything that is not
a msgpack message, is dropped here, before viser decodes it, and counted. A connection that keeps
offending (:data:`OFFENCES` drops) is closed with a reason its page shows.

The gate wraps the ``recv`` of each websocket (websockets' ``ServerConnection``) from viser's infra-level
connect hook, which runs before viser starts reading that connection; it also lowers the connection's
largest frame from viser's 50 MB to the largest cap, so websockets itself refuses a bigger frame before
buffering it. More in docs/security.md.
"""

from __future__ import annotations

import threading
import time
from collections import Counter
from typing import Any

import msgspec
import viser
from viser import _messages, infra

from app.language.catalogs import SOURCE, negotiate
from app.language.words import mark, translate

__all__ = ["ALLOWED", "BURST", "OFFENCES", "RATE", "REFUSED_CODE", "Gate", "close_reason", "install_gate"]

UPLOAD_PART = 512 * 1024
"""Bytes of a file in one ``FileTransferPart`` as viser's page sends them."""

ALLOWED: dict[str, int] = {
    "ViewerCameraMessage": 2_048,  # nine short tuples of floats and two integers: about 250 bytes
    # A text control takes 2,000 characters (8 kB in UTF-8); a longer paste still reaches app.guards.inputs,
    # which tells the browser the limit, up to this size.
    "GuiUpdateMessage": 1024 * 1024,
    "FileTransferStartUpload": 4_096,  # a file name of at most 255 characters, two ids, two counts
    "FileTransferPart": UPLOAD_PART + 4_096,
    "ShareUrlRequest": 256,  # refused or served by app.guards.tunnel
    "ShareUrlDisconnect": 256,
}
"""Message types a browser may send, and the most bytes (msgpack, as received) each may have."""

LARGEST = max(ALLOWED.values())
"""The largest message a connection may send, bytes: a bigger frame is refused by websockets as it comes."""

RENDER = "GetRenderResponseMessage"
"""The page's answer to the server's ``client.get_render`` (a PNG or JPEG of the view): allowed only while
the server waits for one from that connection, when that connection's largest frame is :data:`RENDER_CAP`."""

RENDER_CAP = 32 * 1024 * 1024
"""Bytes of one rendered view: a 4K PNG with its alpha channel is under half of this."""

OFFENCES = 20
"""Messages dropped from one connection before it is closed (a page of this app never has one dropped)."""

RATE = 150.0
"""Messages a connection may send per second, sustained, of the types not paced elsewhere (a page sends
at most a camera move a frame)."""

BURST = 200.0
"""Messages a connection may send at once before :data:`RATE` applies."""

_PACED_ELSEWHERE = frozenset({"FileTransferPart", "GuiUpdateMessage"})
"""Types with a limit of their own: an upload's parts add up to its declared size (app.guards.uploads),
and a control's changes are limited, with a message to the browser, by app.guards.inputs."""

REFUSED_CODE = 1002
"""The close code a refused connection gets: viser's page shows the reason of a 1002 close in a
notification ("Connection rejected: ..."), as it does for a version mismatch."""


def close_reason(text: str) -> str:
    """``text`` cut to fit a websocket close frame's reason: 120 characters and at most 123 bytes of UTF-8
    (RFC 6455, 5.5: a control frame carries at most 125 bytes, two of them the code), whole characters."""
    return text[:120].encode()[:123].decode(errors="ignore")


class _Kind(msgspec.Struct):
    """Only the ``type`` of a message: decoding into it skips every other field without building it."""

    type: str


_kind_of = msgspec.msgpack.Decoder(_Kind).decode


class Gate:
    """The allow-list check of every message a browser sends, and what it dropped.

    Attributes
    ----------
    dropped : collections.Counter
        Messages dropped, by reason: the type name (not allowed), ``"too large: <type>"``,
        ``"malformed: <type>"`` (an allowed type viser cannot decode), ``"not a message"``, ``"too fast"``.
    closed : int
        Connections closed for repeated offences.
    """

    def __init__(self) -> None:
        self.dropped: Counter[str] = Counter()
        self.closed = 0
        self._lock = threading.Lock()

    def verdict(self, raw: Any, rendering: bool = False) -> tuple[str | None, str | None]:
        """``(type, None)`` if ``raw`` (one websocket message as received) may reach viser, otherwise
        ``(type or None, why it may not)``. ``rendering``: the server waits for a rendered view from this
        connection, so :data:`RENDER` is allowed too."""
        if not isinstance(raw, bytes):
            return None, "not a message"
        if len(raw) > (RENDER_CAP if rendering else LARGEST):
            return None, "too large"
        try:
            kind = _kind_of(raw).type
        except (msgspec.DecodeError, msgspec.ValidationError):
            return None, "not a message"
        cap = RENDER_CAP if rendering and kind == RENDER else ALLOWED.get(kind)
        if cap is None:
            return kind, kind[:60]
        if len(raw) > cap:
            return kind, f"too large: {kind}"
        try:
            # viser's own decoding, as its reader will do it: a field it does not know (or one missing) would
            # raise in its reader and end the connection with a traceback in the server's log.
            _messages.Message.deserialize(raw)
        except Exception:  # noqa: BLE001 - any way viser's decoding fails
            return kind, f"malformed: {kind}"
        return kind, None

    def count(self, reason: str) -> None:
        with self._lock:
            self.dropped[reason] += 1
            if len(self.dropped) > 1_000:  # a script inventing type names: keep the table small
                self.dropped = Counter(dict(self.dropped.most_common(100)))


def install_gate(server: viser.ViserServer, gate: Gate | None = None) -> Gate:
    """Put ``gate`` (a new :class:`Gate` by default) in front of every websocket ``server`` opens from now on.

    Call before any browser connects. Returns the gate (its counters are for tests and the benchmark).
    """
    gate = gate if gate is not None else Gate()
    websock = server._websock_server

    def on_connection(client_connection: infra.WebsockClientConnection) -> None:
        # Runs on the event loop when a websocket opens, before viser starts reading from it.
        connection = websock._live_connections.get(client_connection.client_id)
        if connection is not None:
            _guard(connection, client_connection, gate)

    websock._client_connect_cb.insert(0, on_connection)
    return gate


def _guard(connection: Any, client_connection: infra.WebsockClientConnection, gate: Gate) -> None:
    protocol = getattr(connection, "protocol", None)
    if protocol is not None and hasattr(protocol, "max_message_size"):
        protocol.max_message_size = LARGEST + 1024
    original = connection.recv

    def rendering() -> bool:
        # viser's get_render registers a handler for the page's answer on this connection until it has it.
        handlers = getattr(client_connection, "_incoming_handlers", {})
        return bool(handlers.get(_messages.GetRenderResponseMessage))

    register, unregister = client_connection.register_handler, client_connection.unregister_handler

    def frame_cap() -> None:
        # websockets reads the largest frame size anew for each frame: wide only while a render is awaited.
        if protocol is not None and hasattr(protocol, "max_message_size"):
            protocol.max_message_size = (RENDER_CAP if rendering() else LARGEST) + 1024

    def register_handler(message_cls: Any, callback: Any) -> None:
        register(message_cls, callback)
        frame_cap()

    def unregister_handler(message_cls: Any, callback: Any = None) -> None:
        unregister(message_cls, callback)
        frame_cap()

    client_connection.register_handler = register_handler  # type: ignore[method-assign]
    client_connection.unregister_handler = unregister_handler  # type: ignore[method-assign]
    offences = 0
    tokens, then = BURST, time.monotonic()

    async def recv(decode: bool | None = None) -> Any:
        nonlocal offences, tokens, then
        while True:
            raw = await original(decode)
            kind, reason = gate.verdict(raw, rendering())
            if reason is None and kind not in _PACED_ELSEWHERE:
                now = time.monotonic()
                tokens, then = min(BURST, tokens + RATE * (now - then)), now
                if tokens < 1.0:
                    reason = "too fast"
                else:
                    tokens -= 1.0
            if reason is None:
                return raw
            gate.count(reason)
            offences += 1
            if offences == OFFENCES:  # once: what it sent before the close is read and dropped
                with gate._lock:
                    gate.closed += 1
                # The next read raises ConnectionClosed: viser tears the connection down as for any close.
                request = getattr(connection, "request", None)
                lang = negotiate(request.headers.get("Accept-Language") if request is not None else None, SOURCE)
                refused = mark("This server refused messages your page sent")
                await connection.close(REFUSED_CODE, close_reason(translate(refused, lang)))

    connection.recv = recv
