"""viser's asyncio events are changed only on viser's event loop (app.guards.event_loop)."""

from __future__ import annotations

import asyncio
import threading

from app.guards.event_loop import LoopEvent
from tests.harness import raw_client, running_app, still_connected, wait_for


def test_set_from_another_thread_is_handed_to_the_loop():
    loop = asyncio.new_event_loop()
    ready = threading.Event()
    thread = threading.Thread(target=lambda: (ready.set(), loop.run_forever()), daemon=True)
    thread.start()
    ready.wait(5)
    try:
        event = LoopEvent(loop, thread)
        event.set()  # from this (foreign) thread: nothing changes here
        assert event.foreign_sets == 1 and not event.is_set()
        loop.call_soon_threadsafe(event.set)  # what viser also does for the same message
        wait_for(event.is_set, timeout=5, what="the loop to set the event")

        async def on_the_loop() -> tuple[int, bool]:
            event.clear()
            event.set()
            return event.foreign_sets, event.is_set()

        foreign, now = asyncio.run_coroutine_threadsafe(on_the_loop(), loop).result(5)
        assert (foreign, now) == (1, True)  # on its own thread, set() is immediate and not counted
    finally:
        loop.call_soon_threadsafe(loop.stop)
        thread.join(5)


def test_every_buffer_of_the_server_uses_a_loop_event_and_the_frame_loop_never_sets_one_directly():
    with running_app("heavy_top") as app:
        broadcast = app.server._websock_server._broadcast_buffer
        assert isinstance(broadcast.message_event, LoopEvent)
        with raw_client(app) as ws:
            client = next(iter(app.server.get_clients().values()))
            buffer = client._websock_connection.get_message_buffer()
            assert isinstance(buffer.message_event, LoopEvent)
            # The frame loop (another thread) queues messages every frame: each of its wake-ups went
            # through the loop, and the page keeps receiving.
            before = broadcast.message_event.foreign_sets
            frames = app.frames
            wait_for(lambda: app.frames > frames + 30, what="thirty frames")
            assert broadcast.message_event.foreign_sets > before
            assert still_connected(ws, app=app)
