"""A randomized GUI fuzz test through real websocket clients on 127.0.0.1 (fixed seed, bounded).

Clients join and leave, and send thousands of random values to random controls of whatever scene is
showing: values in and out of range, the largest integers msgpack carries, ±1e308, NaN, ±inf, strings
short and long, None, lists and dicts, valid and invalid dropdown options, button presses, rapid scene
switches through the picker and presets. Afterwards: the server logged no uncaught exception, every
client still connected hears the server, no scene was paused by a numerical failure, and the loop still
draws finite frames.

In presenter mode the browsers also press their own panel's buttons (explore, follow, present) and type
PINs, right and wrong, and send values to the lecture's controls and to the explorers' copies.

Not covered here: uploads (a separate message stream; tests/app/test_upload.py and the browser tests
send broken and oversized files).
"""

from __future__ import annotations

import logging
import math
import random
import time
from typing import Any

import pytest

from tests.harness import drain, raw_client, running_app, send_value, still_connected, wait_for

SEED = 20261124
MAX_EVENTS = 3000
MAX_SECONDS = 90.0  # the cap on a very loaded machine; idle, 3,000 events take about 9 s

STRANGE = [
    math.nan,
    math.inf,
    -math.inf,
    1e308,
    -1e308,
    2**63 - 1,
    -(2**63),
    0,
    -1,
    "",
    "0.5",
    "x" * 5000,
    "<b>bold</b>",
    None,
    True,
    False,
    [1, 2, 3],
    {"a": 1},
]


def random_value(rng: random.Random, handle: Any) -> Any:
    """A value for one control: often one it accepts, often one it must refuse."""
    state = handle._impl
    props = state.props
    if rng.random() < 0.5:
        return rng.choice(STRANGE)
    options = getattr(props, "options", None)
    if options:
        return rng.choice(options) if rng.random() < 0.8 else "no such option"
    low, high = getattr(props, "min", None), getattr(props, "max", None)
    if isinstance(state.value, bool):
        return True
    if isinstance(state.value, (int, float)) and low is not None and high is not None:
        span = float(high) - float(low)
        return float(low) + rng.uniform(-0.5, 1.5) * span
    if isinstance(state.value, str):
        return "".join(rng.choice("abc 0.5é∞") for _ in range(rng.randrange(0, 30)))
    return rng.uniform(-1e3, 1e3)


EVENTS = {"shared": MAX_EVENTS, "presenter": MAX_EVENTS // 2}


@pytest.mark.parametrize("mode", ["shared", "presenter"])
def test_random_gui_events_never_break_the_server(capfd, mode):
    rng = random.Random(SEED)
    errors: list[str] = []

    class Collect(logging.Handler):
        def emit(self, record: logging.LogRecord) -> None:
            if record.levelno >= logging.ERROR:
                errors.append(self.format(record))

    handler = Collect()
    server_loggers = ("asyncio", "websockets.server", "viser")  # the server's, not our test clients'
    for name in server_loggers:
        logging.getLogger(name).addHandler(handler)
    counts = {"values": 0, "scene switches": 0, "joins": 0, "leaves": 0, "explore/follow": 0, "PINs": 0}
    summary = ""
    try:
        with running_app("heavy_top", presenter=mode == "presenter", pin="5555") as app:
            loop = app.server._websock_server._background_event_loop
            loop.set_exception_handler(lambda _loop, context: errors.append(str(context.get("exception"))))
            picker_uuid = app.scene_picker._impl.uuid
            titles = list(app.scene_picker._impl.props.options)
            clients: list[tuple[Any, Any]] = []
            start = time.monotonic()
            events = 0
            while events < EVENTS[mode] and time.monotonic() - start < MAX_SECONDS:
                events += 1
                roll = rng.random()
                if not clients or (roll < 0.01 and len(clients) < 4):
                    context = raw_client(app)
                    clients.append((context, context.__enter__()))
                    counts["joins"] += 1
                    continue
                if roll < 0.015 and len(clients) > 1:
                    context, _ = clients.pop(rng.randrange(len(clients)))
                    context.__exit__(None, None, None)
                    counts["leaves"] += 1
                    continue
                _, ws = rng.choice(clients)
                if mode == "presenter" and roll < 0.05:
                    # A browser's own panel: explore/follow, or a PIN (right one time in five).
                    panels = list(app.classroom._panels.values())
                    if panels:
                        panel = rng.choice(panels)
                        if rng.random() < 0.5:
                            send_value(ws, panel.explore._impl.uuid, True)
                            counts["explore/follow"] += 1
                        elif not panel.pin._impl.removed:
                            pin = "5555" if rng.random() < 0.2 else random_value(rng, panel.pin)
                            send_value(ws, panel.pin._impl.uuid, pin)
                            send_value(ws, panel.present._impl.uuid, True)
                            counts["PINs"] += 1
                    continue
                if roll < 0.05 or (mode == "presenter" and roll < 0.08):
                    send_value(ws, picker_uuid, rng.choice(titles))
                    counts["scene switches"] += 1
                    continue
                with app.lock:
                    handles = [h for h in app.server.gui._gui_input_handle_from_uuid.values() if not h._impl.removed]
                    for session in list(app.sessions.values()):  # explorers' own copies (presenter mode)
                        handles += [h for h in session.server.gui._gui_input_handle_from_uuid.values()]
                    handles = [h for h in handles if not h._impl.removed]
                handle = rng.choice(handles)
                send_value(ws, handle._impl.uuid, random_value(rng, handle))
                counts["values"] += 1
                if events % 25 == 0:
                    for _, other in clients:
                        drain(other)  # a page reads what the server sends all the time
                    time.sleep(0.05)  # about 200 changes a second from all browsers together

            summary = f"fuzz ({mode}): {events} events {counts} in {time.monotonic() - start:.1f} s (seed {SEED})"
            # The clock may have been paused by a fuzzed button: run it, so the server has news to send.
            app.set_playing(True)
            # Every client still connected hears the server, and the server counts them all.
            for _, ws in clients:
                assert still_connected(ws, app=app)
            assert len(app.server.get_clients()) >= len(clients)
            # The loop still draws, and no frame was non-finite (a NaN or inf would have paused it).
            # Callbacks still queued from the fuzz may pause the clock again: keep asking for it to run
            # until the loop draws (a flood is limited to 60 changes a second per browser, so the queue
            # is short).
            frames = app.frames
            wait_for(
                lambda: (app.set_playing(True), app.frames > frames + 10)[1],
                timeout=60,
                what="the loop to go on drawing",
            )
            assert not [m for m in app.messages if m[0] == "Paused"], app.messages
            for context, _ in clients:
                context.__exit__(None, None, None)
    finally:
        for name in server_loggers:
            logging.getLogger(name).removeHandler(handler)
    err = capfd.readouterr().err
    print(summary)  # after the capture is read, so `pytest -s` shows it
    assert not errors, errors[:3]
    assert "Traceback" not in err, err[-3000:]
    floor = EVENTS[mode] // 3
    assert counts["values"] > floor and counts["scene switches"] > 10 and counts["joins"] >= 3
    if mode == "presenter":
        assert counts["explore/follow"] > 10 and counts["PINs"] > 10


if __name__ == "__main__":
    pytest.main([__file__, "-q", "-s"])
