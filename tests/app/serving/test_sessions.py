"""Private sessions (``rigid-body-lab --private``): every browser its own simulation, freed when it leaves.

Real websocket clients on 127.0.0.1 stand in for browsers (tests/harness.py's raw_client).
"""

from __future__ import annotations

import gc
import weakref

import pytest

from app.serving.simulation import Simulation
from tests.harness import raw_client, running_app, send_value, still_connected, wait_for


@pytest.fixture()
def private_app():
    with running_app("heavy_top", private=True) as app:
        yield app


def test_each_browser_gets_its_own_simulation_and_drives_only_it(private_app):
    app = private_app
    with raw_client(app) as first, raw_client(app) as second:
        wait_for(lambda: len(app.sessions) == 2, what="two sessions")
        (id_a, a), (id_b, b) = sorted(app.sessions.items())
        assert isinstance(a, Simulation) and a is not b
        assert a.scene.name == b.scene.name == "heavy_top" and a.scene is not b.scene
        # The first browser (the first to connect) picks another scene in its own panel.
        send_value(first, a.scene_picker._impl.uuid, a.scene_picker._impl.props.options[1])
        wait_for(lambda: a.scene is not None and a.scene.name != "heavy_top", what="the first session to switch")
        assert b.scene.name == "heavy_top"
        # A control of one session is nothing to another browser: its message is ignored.
        spin = b.scene.params.values["spin"]
        send_value(first, b.scene.params.sliders["spin"]._impl.uuid, spin + 1.0)
        assert still_connected(first, app=a) and still_connected(second, app=b)
        assert b.scene.params.values["spin"] == spin
        # The loop drives both.
        frames_a, frames_b = a.frames, b.frames
        wait_for(lambda: a.frames > frames_a + 5 and b.frames > frames_b + 5, what="both sessions to run")
    wait_for(lambda: not app.sessions, what="the sessions of departed browsers to be freed")


def test_sessions_come_and_go_without_growing(private_app):
    app = private_app
    for _ in range(10):  # polled finely: each step takes tens of ms
        with raw_client(app, wait=False):
            wait_for(lambda: len(app.sessions) == 1, interval=0.005, what="a session")
        wait_for(lambda: not app.sessions, interval=0.005, what="the session to be freed")
    assert app.scene is None  # the app itself holds no simulation in private mode


def test_a_refusal_in_a_private_session_is_in_that_sessions_status_line(private_app):
    app = private_app
    with raw_client(app) as ws:
        wait_for(lambda: len(app.sessions) == 1, what="the session")
        (session,) = app.sessions.values()
        send_value(ws, session.speed_slider._impl.uuid, "fast")
        wait_for(lambda: "must be a number" in session.status.content, what="the refusal in its own status line")


def _collected(ref: weakref.ref) -> bool:
    """The object ``ref`` points at is gone after a full collection (the loop may hold it for one tick)."""
    gc.collect()
    return ref() is None


def _the_session(app) -> tuple[weakref.ref, weakref.ref]:
    """Weak references to the one session of ``app`` and its scene, once the loop has drawn it a few times."""
    wait_for(lambda: len(app.sessions) == 1, what="the session")
    wait_for(lambda: next(iter(app.sessions.values()), None).frames > 3, what="the session to run")
    session = next(iter(app.sessions.values()))
    return weakref.ref(session), weakref.ref(session.scene)


def test_a_departed_browsers_simulation_is_collected(private_app):
    # Dropped from app.sessions is not enough: a callback, a handle or a thread that still refers to the
    # Simulation (or its scene) keeps it alive. The loop thread did: its loop variable held the last session
    # of a departed browser until another browser came.
    app = private_app
    with raw_client(app):
        simulation, scene = _the_session(app)
    wait_for(lambda: not app.sessions, what="the session to be dropped")
    wait_for(lambda: _collected(simulation) and _collected(scene), timeout=10, what="the Simulation to be collected")


def test_an_explorers_copy_is_collected_when_its_browser_leaves():
    with running_app("heavy_top", presenter=True) as app:
        assert app.classroom is not None
        with raw_client(app) as ws:
            wait_for(lambda: app.classroom._panels, what="the follower's panel")
            # Only the button's uuid: a panel kept here would keep the browser's GUI, and so the copy, alive.
            (explore,) = (panel.explore._impl.uuid for panel in app.classroom._panels.values())
            send_value(ws, explore, True)
            simulation, scene = _the_session(app)
        wait_for(lambda: not app.sessions, what="the copy to be dropped")
        wait_for(lambda: _collected(simulation) and _collected(scene), timeout=10, what="the copy to be collected")


def test_a_session_whose_browser_was_not_sent_its_last_frame_waits_and_then_catches_up_the_time():
    with running_app("heavy_top", private=True, start_loop=False) as app, raw_client(app):
        wait_for(lambda: len(app.sessions) == 1, what="the session")
        session = next(iter(app.sessions.values()))
        client = session.server
        buffer = client._websock_connection.get_message_buffer()
        wait_for(lambda: client.client_id in buffer.generator_cursors, what="its sender to start")
        assert session.frame(0.01)  # the first frame (a new scene is drawn at once)
        wait_for(lambda: not session.behind(), what="its sender to take the frame")
        t0, frames = session.clock.t, session.frames
        # The sender has not taken a frame yet (as when the network thread is behind): no frame is drawn
        # over it, and its wall time is owed.
        buffer.atomic_start()  # viser's sender takes nothing inside an atomic block
        try:
            assert session.tick(0.01) and session.clock.t == pytest.approx(t0 + 0.01, abs=1e-12)
            assert session.behind()
            assert not session.tick(0.02) and not session.tick(0.03)
            assert session.frames == frames + 1 and session.clock.t == pytest.approx(t0 + 0.01, abs=1e-12)
        finally:
            buffer.atomic_end()
        wait_for(lambda: not session.behind(), what="its sender to take the frame")
        assert session.tick(0.01)  # the owed 0.05 s and this frame's 0.01 s
        assert session.frames == frames + 2 and session.clock.t == pytest.approx(t0 + 0.07, abs=1e-12)
        # A frame asked for directly (a test, an export) is drawn whatever the sender does.
        buffer.atomic_start()
        try:
            assert session.frame(0.01) and session.behind() and session.frame(0.01)
        finally:
            buffer.atomic_end()
