"""Uploads checked when they start, before viser keeps a single byte of them: the door through which the
rules of :mod:`app.uploads.transfers` reach viser's transfers.

More in docs/app-notes.md (``app.guards.uploads``).
"""

from __future__ import annotations

import threading
import time
import weakref
from collections.abc import Callable
from typing import Any

import viser
from viser import _messages, infra

from app.contracts import ClientId
from app.guards.responses import peer_address
from app.uploads.transfers import Declared, InFlight, Transfers, overrun_refusal, start_refusal, well_formed_count

__all__ = ["guard_uploads"]

_lock = threading.Lock()
_guis: weakref.WeakSet[Any] = weakref.WeakSet()  # every guarded GUI: the in-flight count spans them all
_transfers = Transfers()  # when each accepted transfer started and last sent a part, and its address


_GUARDED: weakref.WeakSet[viser.GuiApi] = weakref.WeakSet()
"""The GUIs :func:`guard_uploads` has guarded (kept here, not on viser's objects; forgotten with them)."""


def guard_uploads(
    gui: viser.GuiApi, refuse: Callable[[Any, str], None], permit: Callable[[Any], str | None] | None = None
) -> None:
    """Check every upload that reaches ``gui`` (a server's or a client's GUI) when it starts, and every
    part it sends; ``refuse`` and ``permit`` are those of :func:`app.guards.inputs.guard_inputs`, which calls this
    (``refuse`` runs on viser's event loop). A GUI is guarded once: later calls do nothing."""
    if gui in _GUARDED:
        return
    _GUARDED.add(gui)
    handlers = gui._websock_interface._incoming_handlers
    starts: list[Any] = handlers[_messages.FileTransferStartUpload]
    parts: list[Any] = handlers[_messages.FileTransferPart]
    # A ValueError here means viser changed: the pin test catches it.
    start_index = starts.index(gui._handle_file_transfer_start)
    part_index = parts.index(gui._handle_file_transfer_part)
    original_start, original_part = starts[start_index], parts[part_index]
    if isinstance(gui._owner, viser.ViserServer):
        gui._websock_interface = _AcksToUploader(gui, gui._websock_interface)  # type: ignore[assignment]  # ours stands in for viser's
    with _lock:
        _guis.add(gui)

    def start(client_id: ClientId, message: _messages.FileTransferStartUpload) -> None:
        if message.source_component_uuid not in gui._gui_input_handle_from_uuid:
            return  # another GUI's button (viser ignores it here too)
        reason = permit(client_id) if permit is not None else None
        address = _address(gui, client_id)
        if reason is None:
            declared = Declared(message.filename, message.transfer_uuid, message.size_bytes, message.part_count)
            reason = start_refusal(declared, _in_flight(client_id, address))
        if reason is not None:
            _release(gui, client_id, message.source_component_uuid, message.transfer_uuid, message.size_bytes)
            refuse(client_id, reason)
            return
        original_start(client_id, message)
        _transfers.accepted(message.transfer_uuid, address, time.monotonic())

    def part(client_id: ClientId, message: _messages.FileTransferPart) -> None:
        state = gui._current_file_upload_states.get(message.transfer_uuid)
        if state is None:
            return  # not a transfer this GUI accepted: nothing is stored (viser drops it too)
        if state["client_id"] != client_id:
            return  # a part for another browser's transfer
        content = message.content
        if not isinstance(content, bytes) or state["transferred_bytes"] + len(content) > state["total_bytes"]:
            gui._current_file_upload_states.pop(message.transfer_uuid, None)
            _transfers.forget(message.transfer_uuid)
            _release(gui, client_id, message.source_component_uuid, message.transfer_uuid, state["total_bytes"])
            refuse(client_id, overrun_refusal(state["filename"], state["total_bytes"]))
            return
        original_part(client_id, message)
        _transfers.sent_part(message.transfer_uuid, time.monotonic())
        if message.transfer_uuid not in gui._current_file_upload_states:
            _transfers.forget(message.transfer_uuid)  # complete: viser has handed it to the button's callback

    starts[start_index] = start
    parts[part_index] = part


def _in_flight(client_id: ClientId, address: str = "") -> InFlight:
    """Transfers in flight over every guarded GUI (this browser's, everyone's, this address's); stalled ones
    (:meth:`app.uploads.transfers.Transfers.stalled`) dropped from viser's upload states."""
    now = time.monotonic()
    mine = everyone = here = 0
    with _lock:
        guis = list(_guis)
    for gui in guis:
        states = gui._current_file_upload_states
        for transfer, state in list(states.items()):
            if _transfers.stalled(transfer, now):
                states.pop(transfer, None)
                _transfers.forget(transfer)
                continue
            everyone += 1
            mine += state["client_id"] == client_id
            here += bool(address) and _transfers.address(transfer) == address
    # Transfers viser finished or dropped (a browser that left) are forgotten here.
    _transfers.keep_only({t for gui in guis for t in list(gui._current_file_upload_states)})
    return InFlight(mine, everyone, here)


def _address(gui: Any, client_id: ClientId) -> str:
    """The address of the browser ``client_id`` of ``gui``'s server ("" if it is not connected)."""
    owner = gui._owner
    server = owner if isinstance(owner, viser.ViserServer) else owner._viser_server
    return peer_address(server, client_id) or ""


class _AcksToUploader:
    """A server's message interface, for one shared GUI, that sends the acknowledgements of an upload's parts
    to the browser uploading it and everything else to every browser.

    viser 1.1.1 broadcasts them from a shared panel: every other page took the upload as its own ("Uploading"
    on its button), and they went through the broadcast buffer while a refusal's release goes through the
    browser's own, so the release could overtake an acknowledgement sent before it and leave the page's
    button waiting for bytes that never come.
    """

    def __init__(self, gui: viser.GuiApi, server: infra.WebsockServer | infra.WebsockClientConnection) -> None:
        self._gui = gui
        self._server = server

    def queue_message(self, message: Any) -> None:
        if isinstance(message, _messages.FileTransferPartAck):
            state = self._gui._current_file_upload_states.get(message.transfer_uuid)
            client = self._gui._owner.get_clients().get(state["client_id"]) if state is not None else None
            if client is not None:
                client._websock_connection.queue_message(message)
            return  # a browser that left, or a transfer already dropped: nobody to tell
        self._server.queue_message(message)

    def __getattr__(self, name: str) -> Any:
        return getattr(self._server, name)


def _release(gui: viser.GuiApi, client_id: ClientId, button: Any, transfer: Any, size: Any) -> None:
    """Give a refused browser its upload button back: the transfer acknowledged as complete (the page
    enables the button again) and its "Uploading" notification taken away (ours says why)."""
    owner = gui._owner
    client = owner if isinstance(owner, viser.ClientHandle) else owner.get_clients().get(client_id)
    if client is None or not isinstance(button, str) or not isinstance(transfer, str):
        return
    total = size if well_formed_count(size) else 0
    connection = client._websock_connection
    connection.queue_message(_messages.FileTransferPartAck(button, transfer, total, total))
    connection.queue_message(_messages.RemoveNotificationMessage("upload-" + transfer))
