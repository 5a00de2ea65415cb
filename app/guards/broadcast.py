"""Who receives the shared simulation: each browser's view of viser's broadcast stream.

More in docs/app-notes.md (``app.guards.broadcast``).
"""

from __future__ import annotations

import dataclasses
import threading
from collections.abc import AsyncGenerator, Callable, Sequence
from typing import Any

import viser
from viser import _messages

from app.contracts import ClientId

__all__ = ["BroadcastView"]

WINDOW = 128  # messages per replayed window (viser's own window size)


@dataclasses.dataclass
class _Client:
    detached: bool = False
    read_only: bool = True
    pending: list[str] = dataclasses.field(default_factory=list)  # "detach", "attach", "unlock"


class BroadcastView:
    """Per-browser filtering of one viser server's broadcast stream.

    Parameters
    ----------
    server : viser.ViserServer
        Installed before any browser connects.
    read_only : callable(client_id) -> bool
        Whether a browser sees the lecture's controls disabled (asked when it connects).
    """

    def __init__(self, server: viser.ViserServer, read_only: Callable[[Any], bool]) -> None:
        self._server = server
        self._buffer = server._websock_server._broadcast_buffer
        self._read_only = read_only
        self._clients: dict[ClientId, _Client] = {}
        self._lock = threading.Lock()
        # An invisible element whose (unchanged) visibility is re-sent to make a window: see poke().
        self._beacon = server.gui.add_html("", visible=False, order=1e9)
        original = self._buffer.window_generator

        def window_generator(client_id: ClientId, backlog_done_message: Any = None) -> AsyncGenerator[Any, None]:
            inner = original(client_id, backlog_done_message=backlog_done_message)
            return self._windows(inner, client_id, backlog_done_message)

        self._buffer.window_generator = window_generator  # type: ignore[method-assign]

    # ------------------------------------------------------------------ asked from any thread
    def detach(self, client_id: ClientId) -> None:
        """Stop sending the lecture to this browser (and remove what it shows of it)."""
        self._request(client_id, "detach")

    def attach(self, client_id: ClientId) -> None:
        """Send the lecture to this browser again, starting with its current state."""
        self._request(client_id, "attach")

    def unlock(self, client_id: ClientId) -> None:
        """This browser may drive the lecture: show it the controls as they are."""
        self._request(client_id, "unlock")

    def detached(self, client_id: ClientId) -> bool:
        with self._lock:
            state = self._clients.get(client_id)
            return bool(state and state.detached)

    def forget(self, client_id: ClientId) -> None:
        """The browser has gone."""
        with self._lock:
            self._clients.pop(client_id, None)

    def poke(self) -> None:
        """Make the broadcast stream send a window now (a requested change happens there)."""
        # An update that changes nothing; viser keeps only the newest of them in its buffer.
        self._buffer.push(_messages.GuiUpdateMessage(self._beacon._impl.uuid, {"visible": False}))

    def _request(self, client_id: ClientId, what: str) -> None:
        with self._lock:
            self._clients.setdefault(client_id, _Client(read_only=self._read_only(client_id))).pending.append(what)
        self.poke()

    # ------------------------------------------------------------------ on viser's event loop
    async def _windows(self, inner: Any, client_id: ClientId, marker: Any) -> AsyncGenerator[Sequence[Any], None]:
        with self._lock:
            state = self._clients.setdefault(client_id, _Client(read_only=self._read_only(client_id)))
        try:
            async for window in inner:
                with self._lock:
                    pending, state.pending = state.pending, []
                for what in pending:
                    for extra in self._change(state, what, client_id):
                        yield extra
                if state.detached:
                    # Only the end-of-replay marker, which every browser needs once, gets through.
                    window = [m for m in window if m is marker]
                elif state.read_only:
                    window = [_disabled(m) for m in window]
                if window:
                    yield window
        finally:
            await inner.aclose()

    def _change(self, state: _Client, what: str, client_id: ClientId) -> list[list[Any]]:
        if what == "detach" and not state.detached:
            state.detached = True
            return _chunks(self._removals(client_id))
        if what == "attach" and state.detached:
            state.detached = False
            replay = self._persistent(client_id)
            return _chunks([_disabled(m) for m in replay] if state.read_only else replay)
        if what == "unlock" and state.read_only:
            state.read_only = False
            if state.detached:
                return []
            gui = self._server.gui
            updates: list[Any] = [
                _messages.GuiUpdateMessage(uuid, {"disabled": bool(getattr(handle._impl.props, "disabled", False))})
                for uuid, handle in list(gui._gui_input_handle_from_uuid.items())
                if not handle._impl.removed
            ]
            return _chunks(updates)
        return []

    def _persistent(self, client_id: ClientId) -> list[Any]:
        """What a browser joining now would be sent (viser's buffer keeps the newest of each)."""
        with self._buffer.buffer_lock:
            return [m for m in self._buffer.message_from_id.values() if m.excluded_self_client != client_id]

    def _removals(self, client_id: ClientId) -> list[Any]:
        """Remove, in this browser, every node and panel element the lecture has made."""
        out: list[Any] = []
        for message in self._persistent(client_id):
            if isinstance(message, _messages._CreateSceneNodeMessage):
                out.append(_messages.RemoveSceneNodeMessage(message.name))
            elif isinstance(message, _messages._CreateGuiComponentMessage):
                out.append(_messages.GuiRemoveMessage(message.uuid))
            elif isinstance(message, _messages.GuiPanelMessage):  # projector mode's caption and plot
                out.append(_messages.GuiPanelRemoveMessage(message.uuid))
        out.reverse()  # children before their parents
        return out


def _chunks(messages: list[Any]) -> list[list[Any]]:
    return [messages[i : i + WINDOW] for i in range(0, len(messages), WINDOW)]


_UNTOUCHED: set[type] = set()
"""Message types :func:`_disabled` passes on as they are (a frame's poses and points: most of the stream),
learnt as they come; only viser's event loop thread reads and adds to it."""


def _disabled(message: Any) -> Any:
    """The message as a read-only browser gets it: every control disabled."""
    kind = type(message)
    if kind in _UNTOUCHED:  # every message to every follower passes here: the common case costs one lookup
        return message
    if not issubclass(kind, (_messages._CreateGuiComponentMessage, _messages.GuiUpdateMessage)):
        _UNTOUCHED.add(kind)
        return message
    if isinstance(message, _messages._CreateGuiComponentMessage):
        props = getattr(message, "props", None)
        if props is not None and hasattr(props, "disabled") and not props.disabled:
            return dataclasses.replace(message, props=dataclasses.replace(props, disabled=True))  # type: ignore[call-arg]
    elif isinstance(message, _messages.GuiUpdateMessage) and message.updates.get("disabled") is False:
        return _messages.GuiUpdateMessage(message.uuid, {**message.updates, "disabled": True})
    return message
