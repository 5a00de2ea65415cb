"""Keep viser's asyncio events on viser's event loop.

More in docs/app-notes.md (``app.guards.event_loop``).
"""

from __future__ import annotations

import asyncio
import threading
from typing import Any

import viser
from viser import infra

__all__ = ["LoopEvent", "WINDOW_SECONDS", "confine_events"]


class LoopEvent(asyncio.Event):
    """An ``asyncio.Event`` that is only ever changed on its loop's thread.

    ``set()`` called from any other thread does nothing: it is only ever called there by viser's buffer,
    which also schedules the same call on the loop (see the module docstring).
    """

    def __init__(self, loop: asyncio.AbstractEventLoop, loop_thread: threading.Thread | None) -> None:
        super().__init__()
        self._owner = loop
        self._owner_thread = loop_thread
        self.foreign_sets = 0  # how many set() calls came from another thread (tests read it)

    def set(self) -> None:  # noqa: A003 - asyncio's name
        if self._owner_thread is None or threading.current_thread() is self._owner_thread:
            super().set()
            return
        # viser schedules the same set() on the loop itself (after a message, or when an atomic block
        # ends): the direct call from this thread is a duplicate, dropped here rather than scheduled
        # again (each scheduling writes to the loop's self-pipe, ten times a frame).
        self.foreign_sets += 1


def _loop_thread(loop: asyncio.AbstractEventLoop) -> threading.Thread | None:
    """The thread running ``loop`` (asked on the loop itself; None if it does not answer)."""
    found: list[threading.Thread] = []
    done = threading.Event()

    def ask() -> None:
        found.append(threading.current_thread())
        done.set()

    loop.call_soon_threadsafe(ask)
    done.wait(5.0)
    return found[0] if found else None


WINDOW_SECONDS = 1.0 / 240.0
"""How long viser's sender waits to gather more messages after sending a window (viser: 1/60 s).

Our loop sends each frame as one ``atomic()`` block, which viser never splits; waiting a whole frame
period after each window made the next two frames share a window about one time in four, so a page
showed about 44 of the 60 frames drawn. A quarter period keeps one window per frame."""


def _confine(buffer: Any, thread: threading.Thread | None) -> None:
    if not isinstance(buffer.message_event, LoopEvent):
        buffer.message_event = LoopEvent(buffer.event_loop, thread)
    buffer.window_duration_sec = WINDOW_SECONDS


def confine_events(server: viser.ViserServer) -> None:
    """Make every message buffer of ``server`` use a :class:`LoopEvent` (call before any browser connects)."""
    websock = server._websock_server
    broadcast = websock._broadcast_buffer
    thread = _loop_thread(broadcast.event_loop)
    _confine(broadcast, thread)

    def on_connection(connection: infra.WebsockClientConnection) -> None:
        # Runs on the event loop when a websocket opens, before its senders start waiting on the event.
        _confine(connection.get_message_buffer(), thread)

    # The infra-level hook (not ViserServer.on_client_connect, which fires only after the browser's
    # first camera message, when the sender already waits on the old event).
    websock._client_connect_cb.insert(0, on_connection)
