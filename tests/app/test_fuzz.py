"""A randomized GUI fuzz test through real websocket clients on 127.0.0.1 (fixed seed, bounded).

Event counts: every run prints the events it sent, by kind, per mode. ``python -m tests.app.test_fuzz``
(or ``RBL_FUZZ_TABLE=1 python -m pytest tests/app/test_fuzz.py -s``) also writes them to
``benchmarks/results/fuzz.md``, one row per mode that ran.

Clients join and leave, and send thousands of random values to random controls of whatever scene is
showing: values in and out of range, the largest integers msgpack carries, ±1e308, NaN, ±inf, strings
short and long, None, lists and dicts, valid and invalid dropdown options, button presses, rapid scene
switches through the picker and presets. They upload files to the inertia explorer the way its page does
(tests/harness.py's ``send_upload``): garbage bytes under a mesh's name, an announce of more than the
20 MB limit, a 1 MB GLB of 20,000 instanced nodes (tests/app/uploads/test_upload_limits.py's builder), and a
good box now and then. Afterwards: the server logged no uncaught exception, every client still connected
hears the server, and in every simulation the fuzz met (the shared one, explorers' copies, private
sessions, those of browsers that left included) no scene was paused by a failure, no callback failed,
and the last state drawn is finite; the loop still draws.

Three modes: ``shared`` (everyone drives one simulation), ``presenter`` (the browsers also press their own
panel's buttons: explore, follow, present, and type PINs right and wrong; values go to the lecture's
controls and to the explorers' copies) and ``private`` (every browser its own simulation; it sends to
its own controls and, now and then, to another browser's, which must be ignored).

Time: each mode stops at its event count or its time cap (:data:`CAPS`), whichever comes first; the three
take about 19 s together in one process on 2 cores (CPU 18 s; about half of the wall time is the pace of
about 200 changes a second), and the caps keep them under 90 s on a slower or busier machine (the floors on
the counts are set so that a capped run still passes).
"""

from __future__ import annotations

import logging
import math
import os
import random
import time
from collections import Counter, deque
from pathlib import Path
from typing import Any

import pytest
import trimesh

from app.serving.finite import check_finite
from app.serving.simulation import Simulation
from app.uploads import limits
from tests.harness import (
    drain,
    glb_with_nodes,
    raw_client,
    send_part,
    send_upload,
    send_value,
    start_upload,
    still_connected,
    wait_for,
)

SEED = int(os.environ.get("RBL_FUZZ_SEED", "20261124"))
"""The fuzz's seed: fixed, so a failure repeats (``RBL_FUZZ_SEED=N`` explores others)."""
EVENTS = {"shared": 3000, "presenter": 1500, "private": 1500}
CAPS = {"shared": 30.0, "presenter": 20.0, "private": 25.0}
"""Seconds of fuzzing per mode once the floors below are met (the counts end it when idle)."""
HARD_CAP = 120.0
"""Seconds of fuzzing at most in any mode, floors met or not: the test always stops by itself."""
TRAIL = 12
"""Events kept to name in a failure: the seed and the last events before it reproduce it."""
UPLOADS = 0.01
"""Share of the events that are uploads (each file that is read costs a worker process, forked ready in about
15 ms, and the read itself)."""
TABLE = Path(__file__).resolve().parents[2] / "benchmarks" / "results" / "fuzz.md"
FAILURES = ("Paused", "Something went wrong", "Could not open")
"""Titles of the notifications that say a scene or a callback failed (a refusal is not a failure)."""

STRANGE = [
    math.nan,
    math.inf,
    -math.inf,
    1e308,
    -1e308,
    1e23,
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

BOX = trimesh.creation.box(extents=(0.3, 0.2, 0.1)).export(file_type="stl")
CITY = glb_with_nodes(20_000)  # about 1 MB: refused by its declared nodes, before any parse


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


def send_random_upload(rng: random.Random, ws: Any, button: str, counts: Counter) -> None:
    """One upload of one of four kinds to the upload button ``button``."""
    roll = rng.random()
    if roll < 0.35:
        ext = rng.choice(("stl", "obj", "ply", "glb"))
        garbage = rng.randbytes(rng.randrange(1, 4096))
        send_upload(ws, button, f"garbage.{ext}", garbage)
        counts["uploads: garbage"] += 1
    elif roll < 0.65:
        size = limits.MAX_BYTES + rng.randrange(1, 10**9)
        transfer = start_upload(ws, button, "oversized.stl", size, math.ceil(size / (512 * 1024)))
        for index in range(3):  # the page sends its parts at once, without waiting for an answer
            send_part(ws, button, transfer, index, rng.randbytes(512))
        counts["uploads: oversized"] += 1
    elif roll < 0.85:
        send_upload(ws, button, "city.glb", CITY)
        counts["uploads: 20,000-node GLB"] += 1
    else:
        send_upload(ws, button, "box.stl", BOX)
        counts["uploads: good box"] += 1


class Browser:
    """One websocket client: its connection and the client id the server gave it."""

    def __init__(self, app: Any) -> None:
        before = set(app.server.get_clients())
        self.context = raw_client(app, wait=False)
        self.ws = self.context.__enter__()
        # Registered within milliseconds of connecting: a fine poll keeps 60 joins from waiting 3 s in all.
        self.cid = wait_for(lambda: set(app.server.get_clients()) - before, interval=0.002, what="the client id").pop()

    def leave(self) -> None:
        # A page closing its tab does not wait for the server's closing handshake: while frames flow, the
        # client's full queue holds it back until the close timeout (1 s a browser). The server sees the
        # close frame, then the end of the connection.
        self.ws.close_timeout = 0.05
        self.context.__exit__(None, None, None)


def own_simulation(app: Any, mode: str, browser: Browser) -> Any:
    """The simulation this browser drives (or follows): its private session or copy, else the app."""
    own = app.sessions.get(browser.cid)
    return own if own is not None or mode == "private" else app.simulation


def controls_of(simulation: Any) -> list[Any]:
    with simulation.lock:
        handles = list(simulation.server.gui._gui_input_handle_from_uuid.values())
    return [h for h in handles if not h._impl.removed]


def explorer_button(simulation: Any) -> str | None:
    scene = simulation.scene
    if scene is None or scene.name != "inertia_explorer" or scene.upload._impl.removed:
        return None
    return scene.upload._impl.uuid


def floors_met(mode: str, events: int, counts: Counter, met: dict[int, Any]) -> bool:
    """The run tested what it should: the floors the test asserts at its end."""
    return (
        events >= EVENTS[mode] // 4
        and counts["values"] > events // 2
        and counts["scene switches"] > 10
        and counts["joins"] >= 3
        and sum(n for kind, n in counts.items() if kind.startswith("uploads")) >= 5
        and (mode != "presenter" or (counts["explore/follow"] > 10 and counts["PINs"] > 10))
        and (mode == "shared" or len(met) > 2)
    )


def describe(simulation: Any) -> str:
    """What a simulation is doing, for a failure message."""
    scene = simulation.scene
    return (
        f"(scene {getattr(scene, 'name', None)}, frames {simulation.frames}, playing {simulation.playing}, "
        f"closed {simulation.closed}, browser gone {simulation.gone()}, messages {simulation.messages[-3:]})"
    )


RESULTS: dict[str, tuple[int, float, Counter]] = {}


@pytest.fixture(scope="module", autouse=True)
def fuzz_table():
    """Write the event counts of the modes that ran to benchmarks/results/fuzz.md (when asked to)."""
    yield
    if os.environ.get("RBL_FUZZ_TABLE") != "1" or not RESULTS:
        return
    kinds = sorted({kind for _, _, counts in RESULTS.values() for kind in counts})
    lines = [
        "# GUI fuzz test: events sent",
        "",
        f"`python -m tests.app.test_fuzz` (tests/app/test_fuzz.py), seed {SEED}: random events through real",
        "websocket clients; in each mode the server logged no uncaught exception, every client stayed",
        "connected, and no simulation was paused by a failure or drew a non-finite state.",
        f"Run on {os.cpu_count()} cores, load average {os.getloadavg()[0]:.1f} at the end.",
        "",
        "| mode | events | seconds | " + " | ".join(kinds) + " |",
        "| --- | ---: | ---: | " + " | ".join("---:" for _ in kinds) + " |",
    ]
    for mode, (events, seconds, counts) in RESULTS.items():
        lines.append(f"| {mode} | {events:,} | {seconds:.1f} | " + " | ".join(f"{counts[k]:,}" for k in kinds) + " |")
    TABLE.write_text("\n".join(lines) + "\n", encoding="utf-8")


@pytest.mark.parametrize("mode", ["shared", "presenter", "private"])
def test_random_gui_events_never_break_the_server(capfd, monkeypatch, mode):
    rng = random.Random(SEED)
    trail: deque[str] = deque(maxlen=TRAIL)  # the last events, for the failure message
    events = 0

    def send(ws: Any, uuid: str, value: Any) -> None:
        trail.append(f"event {events}: {uuid[:8]} <- {str(value)[:60]!r}")
        send_value(ws, uuid, value)

    def reproduce() -> str:
        return (
            f"fuzz ({mode}) with seed {SEED} (RBL_FUZZ_SEED={SEED} reruns it) broke at event {events}; "
            "the events before it:\n  " + "\n  ".join(trail)
        )

    errors: list[str] = []
    failed_frames: list[str] = []  # the scene and its values when a frame failed, to reproduce it
    real_failed = Simulation.failed

    def failed(self, exc):
        scene = self.scene
        params = getattr(scene, "params", None)
        failed_frames.append(
            f"{getattr(scene, 'name', None)} t={self.time!r} values={getattr(params, 'values', None)} "
            f"payload={'yes' if self.payload is not None else 'no'}: {type(exc).__name__}: {exc}"
        )
        real_failed(self, exc)

    monkeypatch.setattr(Simulation, "failed", failed)

    class Collect(logging.Handler):
        def emit(self, record: logging.LogRecord) -> None:
            if record.levelno >= logging.ERROR:
                errors.append(self.format(record))

    handler = Collect()
    server_loggers = ("asyncio", "websockets.server", "viser")  # the server's, not our test clients'
    for name in server_loggers:
        logging.getLogger(name).addHandler(handler)
    counts: Counter = Counter()
    met: dict[int, Any] = {}  # every simulation the fuzz met, by id (a departed browser's too)
    summary = ""
    try:
        with running(mode) as app:
            loop = app.server._websock_server._background_event_loop
            loop.set_exception_handler(lambda _loop, context: errors.append(str(context.get("exception"))))
            browsers: list[Browser] = []
            start = time.monotonic()
            events = owed = 0  # owed: uploads waiting for a browser's inertia explorer to show

            def go_on() -> bool:
                # On a loaded machine the cap ends the run, but only once it has tested what it should.
                elapsed = time.monotonic() - start
                if elapsed > HARD_CAP:
                    return False
                if events < EVENTS[mode] and elapsed < CAPS[mode]:
                    return True
                return not floors_met(mode, events, counts, met | {id(s): s for s in app.simulations()})

            while go_on():
                events += 1
                roll = rng.random()
                if not browsers or (roll < 0.01 and len(browsers) < 4):
                    browser = Browser(app)
                    browsers.append(browser)
                    trail.append(f"event {events}: browser {browser.cid} joins")
                    if mode == "private":
                        wait_for(
                            lambda b=browser: b.cid in app.sessions, interval=0.005, what="the new browser's session"
                        )
                    counts["joins"] += 1
                    continue
                if roll < 0.015 and len(browsers) > 1:
                    gone = browsers.pop(rng.randrange(len(browsers)))
                    trail.append(f"event {events}: browser {gone.cid} leaves")
                    gone.leave()
                    counts["leaves"] += 1
                    continue
                browser = rng.choice(browsers)
                ws = browser.ws
                if mode == "presenter" and roll < 0.05:
                    # A browser's own panel: explore/follow, or a PIN (right one time in five).
                    panels = list(app.classroom._panels.values())
                    with_pin = [p for p in panels if not p.pin._impl.removed]  # a presenter's has none
                    if panels:
                        if rng.random() < 0.5 or not with_pin:
                            send(ws, rng.choice(panels).explore._impl.uuid, True)
                            counts["explore/follow"] += 1
                        else:
                            panel = rng.choice(with_pin)
                            pin = "5555" if rng.random() < 0.2 else random_value(rng, panel.pin)
                            send(ws, panel.pin._impl.uuid, pin)
                            send(ws, panel.present._impl.uuid, True)
                            counts["PINs"] += 1
                    continue
                simulation = own_simulation(app, mode, browser)
                if simulation is None:  # its private session is being made: it waits like a page
                    continue
                if roll < 0.05:
                    titles = list(simulation.scene_picker._impl.props.options)
                    send(ws, simulation.scene_picker._impl.uuid, rng.choice(titles))
                    counts["scene switches"] += 1
                    continue
                button = explorer_button(simulation)
                if roll < 0.05 + UPLOADS or (owed and button is not None):
                    if button is not None:
                        trail.append(f"event {events}: browser {browser.cid} uploads")
                        send_random_upload(rng, ws, button, counts)
                        owed = max(owed - 1, 0)
                    elif mode == "presenter" and simulation is app and browser.cid not in app.classroom.presenters:
                        # A follower cannot change the lecture's scene: as a person would, it explores on its
                        # own first, and opens the inertia explorer in its copy (runs that met the lecture
                        # on other scenes sent 2 or 3 uploads).
                        panel = app.classroom._panels.get(browser.cid)
                        if panel is not None:
                            send(ws, panel.explore._impl.uuid, True)
                            counts["explore/follow"] += 1
                        owed = min(owed + 1, 3)
                    else:  # it opens the inertia explorer first, as a person would, and uploads when it shows
                        send(ws, simulation.scene_picker._impl.uuid, "Inertia explorer")
                        counts["scene switches"] += 1
                        owed = min(owed + 1, 3)
                    continue
                if mode == "presenter" and roll < 0.08:
                    # The lecture's picker; half the time the inertia explorer, so that the followers' uploads
                    # meet the lecturer's upload button (and a presenter's are read).
                    titles = list(app.simulation.scene_picker._impl.props.options)
                    title = "Inertia explorer" if rng.random() < 0.5 else rng.choice(titles)
                    send(ws, app.simulation.scene_picker._impl.uuid, title)
                    counts["scene switches"] += 1
                    continue
                if mode == "shared" or (mode == "private" and rng.random() < 0.95):
                    handles = controls_of(simulation)
                else:  # the lecture and every copy (presenter), or another browser's session (private)
                    handles = [h for s in app.simulations() for h in controls_of(s)]
                if not handles:
                    continue
                handle = rng.choice(handles)
                send(ws, handle._impl.uuid, random_value(rng, handle))
                counts["values"] += 1
                if events % 25 == 0:
                    for other in browsers:
                        drain(other.ws)  # a page reads what the server sends all the time
                    met.update((id(s), s) for s in app.simulations())
                    time.sleep(0.05)  # about 200 changes a second from all browsers together

            seconds = time.monotonic() - start
            summary = f"fuzz ({mode}): {events} events {dict(sorted(counts.items()))} in {seconds:.1f} s (seed {SEED})"
            met.update((id(s), s) for s in app.simulations())
            # Every browser still connected hears the server, and the server counts them all.
            for browser in browsers:
                assert still_connected(browser.ws, app=own_simulation(app, mode, browser) or app), browser.cid
            assert len(app.server.get_clients()) >= len(browsers)
            # Every simulation still draws. A fuzzed button may have paused a clock, and callbacks still
            # queued from the fuzz may pause it again: keep asking it to run until the loop draws (a flood
            # is limited to 60 changes a second per browser, so the queue is short). A still scene (the
            # explorer) has no clock: it draws when asked to.
            for simulation in app.simulations():
                frames = simulation.frames
                wait_for(
                    lambda s=simulation, f=frames: (s.set_playing(True), s.request_redraw(), s.frames > f + 10)[2],
                    timeout=60,
                    what=f"the loop to go on drawing {describe(simulation)}",
                )
            # No failure in any simulation met, and the last state each one drew is finite (one that left
            # before its first frame drew none).
            live = {id(s) for s in app.simulations()}
            for key, simulation in met.items():
                failures = [m for m in simulation.messages if m[0].startswith(FAILURES)]
                assert not failures, failures[:3]
                assert simulation.frames > 0 or key not in live
                if simulation.frames:
                    assert simulation.last_state
                    check_finite(simulation.last_state)
            for browser in browsers:
                browser.leave()
    except BaseException as exc:
        exc.add_note(reproduce())
        raise
    finally:
        for name in server_loggers:
            logging.getLogger(name).removeHandler(handler)
    err = capfd.readouterr().err
    print(summary)  # after the capture is read, so `pytest -s` shows it
    try:
        check_the_run(mode, events, counts, met, errors, failed_frames, err)
    except AssertionError as exc:
        exc.add_note(reproduce())
        raise
    RESULTS[mode] = (events, seconds, counts)  # a mode that passed


def check_the_run(
    mode: str, events: int, counts: Counter, met: dict[int, Any], errors: list[str], failed_frames: list[str], err: str
) -> None:
    """No error logged, no frame failed, no traceback, and the run tested what it should."""
    assert not errors, errors[:3]
    assert not failed_frames, failed_frames[:3]
    assert "Traceback" not in err, err[-3000:]
    # Floors that hold when the cap ends a run on a loaded machine: the run did test what it should.
    assert events >= EVENTS[mode] // 4 and counts["values"] > events // 2, counts
    assert counts["scene switches"] > 10 and counts["joins"] >= 3, counts
    assert sum(n for kind, n in counts.items() if kind.startswith("uploads")) >= 5, counts
    if mode == "presenter":
        assert counts["explore/follow"] > 10 and counts["PINs"] > 10
    if mode != "shared":
        assert len(met) > 2  # copies or sessions came and went


def running(mode: str) -> Any:
    from tests.harness import running_app

    # The lecture starts on the inertia explorer: the followers try to upload to the lecturer's scene.
    first = "inertia_explorer" if mode == "presenter" else "heavy_top"
    return running_app(first, presenter=mode == "presenter", private=mode == "private", pin="5555")


if __name__ == "__main__":
    os.environ["RBL_FUZZ_TABLE"] = "1"
    raise SystemExit(pytest.main([__file__, "-q", "-s", "-p", "no:cacheprovider"]))
