"""The timeline headless: a scrub puts the body at the exact state of that instant, the friction top
goes back and forth through its history bit for bit, Step back, jumps, replays, and refusals."""

from __future__ import annotations

import math

import numpy as np
import pytest

from app.panel.timeline_panel import BACK, ON
from app.serving.timeline import MAX_JUMP
from physics.free_body import FreeBody
from tests.harness import FRAME, open_scene, raw_client, running_app, send_value, still_connected, wait_for


def play(app, seconds: float, wall: float = FRAME) -> None:
    for _ in range(round(seconds / wall)):
        app.frame(wall)


def test_a_scrub_back_shows_the_exact_racket_at_that_instant(app):
    scene = open_scene(app, "tennis_racket")
    play(app, 3.0)
    sim = app.simulation
    sim.panel.timeline.slider.value = 1.23  # as a browser drags it (its callback runs)
    assert not sim.playing and sim.time == 1.23
    assert app.frame(FRAME)  # the paused frame redraws at the instant chosen
    assert sim.time == 1.23
    # An exact model made afresh from the scene's start: the attitude at 1.23 s.
    exact = FreeBody(scene.moments).trajectory(scene.omega0, scene.attitude0).at(1.23).attitude
    R = sim.last_state["R"]
    angle = 2.0 * math.asin(min(1.0, float(np.linalg.norm(R - exact)) / math.sqrt(8.0)))
    assert angle < 1e-12
    # Play goes on from the instant scrubbed to.
    sim.set_playing(True)
    app.frame(FRAME)
    assert sim.time == pytest.approx(1.23 + FRAME, abs=1e-12)


def test_the_slider_shows_the_time_and_spans_what_was_reached(app):
    open_scene(app, "tennis_racket")
    play(app, 2.5)
    sim = app.simulation
    slider = sim.panel.timeline.slider
    sim.set_playing(False)
    app.frame(FRAME)  # shown at most ten times a second of wall time while playing, at every paused frame
    assert slider.value == sim.time
    assert slider.min == 0.0 and slider.max == 3.0  # the whole second after the furthest reached
    sim.timeline.seek(0.5)
    app.frame(FRAME)
    assert slider.value == 0.5 and slider.max == 3.0  # going back keeps the furthest reached


def test_the_friction_top_scrubbed_back_and_forward_again_repeats_its_states_bit_for_bit(app):
    scene = open_scene(app, "heavy_top")
    assert scene.presets.choose("sleeping top with friction: falls")
    sim = app.simulation
    app.set_speed(10.0)
    seen = {}
    for _ in range(30):  # 1 s of simulation a frame: it sleeps, falls and lands
        app.frame(0.1)
        seen[sim.time] = (sim.last_state["R"].copy(), sim.last_state["L_body"].copy(), sim.last_state["landed"])
    assert scene.landed
    times = sorted(seen)
    sim.timeline.seek(3.0)  # back
    app.frame(FRAME)
    for t in [*times[::-1], *times]:  # back through every state shown, then forward again
        sim.timeline.seek(t)
        app.frame(FRAME)
        R, L_body, landed = seen[t]
        assert sim.time == t
        assert np.array_equal(sim.last_state["R"], R) and np.array_equal(sim.last_state["L_body"], L_body)
        assert sim.last_state["landed"] == landed
    # From a scrubbed instant, playing on reaches the same states as the first run did.
    sim.timeline.seek(times[4])
    sim.set_playing(True)
    for t in times[5:9]:
        app.frame(0.1)
        assert sim.time == t
        assert np.array_equal(sim.last_state["R"], seen[t][0])
    assert scene.history.nbytes < 200_000  # five minutes kept in a fixed ring


def test_step_back_undoes_a_step_and_the_jumps_move_a_second(app):
    open_scene(app, "heavy_top")
    sim = app.simulation
    play(app, 2.0)
    sim.step()
    app.frame(FRAME)
    after = sim.time
    sim.timeline.step_back()
    app.frame(FRAME)
    assert not sim.playing and sim.time == pytest.approx(after - 1.0 / 60.0, abs=1e-12)
    before = sim.time
    sim.panel.timeline.jump.value = BACK  # a button group's click (its callback runs)
    app.frame(FRAME)
    assert sim.time == pytest.approx(before - 1.0, abs=1e-12)
    sim.panel.timeline.jump.value = ON
    app.frame(FRAME)
    assert sim.time == pytest.approx(before, abs=1e-12)
    sim.timeline.jump(-100.0)  # not before the start
    assert sim.time == 0.0


def test_a_replay_runs_the_last_seconds_at_a_tenth_then_goes_back_to_the_speed_before(app):
    open_scene(app, "tennis_racket")
    sim = app.simulation
    play(app, 3.0)
    end = sim.time
    replay = sim.timeline.start_replay(0.5, 0.1)
    assert replay is not None and sim.speed == 0.1 and sim.playing and sim.time == pytest.approx(end - 0.5)
    frames = 0
    while sim.timeline.replay is not None:
        app.frame(FRAME)
        frames += 1
        assert frames < 1000, "the replay never ended"
    # 0.5 s of simulated time at 0.1x took 5 s of the clock's wall time: 300 frames of 1/60 s.
    done = sim.timeline.last_replay
    assert done.wall == pytest.approx(5.0, abs=FRAME) and frames == pytest.approx(300, abs=1)
    assert sim.time == end and sim.speed == 1.0 and sim.playing  # as before, from where it was


def test_a_move_by_hand_ends_a_replay_and_restores_the_speed(app):
    open_scene(app, "tennis_racket")
    sim = app.simulation
    play(app, 1.0)
    sim.timeline.start_replay(0.5, 0.1)
    app.frame(FRAME)
    sim.timeline.seek(0.2)
    assert sim.timeline.replay is None and sim.speed == 1.0 and not sim.playing


@pytest.mark.parametrize("bad", [math.nan, math.inf, -math.inf])
def test_a_time_that_is_not_a_number_is_refused(app, bad):
    open_scene(app, "tennis_racket")
    with pytest.raises(ValueError, match="finite"):
        app.simulation.timeline.seek(bad)
    with pytest.raises(ValueError, match="beyond the furthest"):
        app.simulation.timeline.seek(MAX_JUMP + 10.0)
    with pytest.raises(ValueError, match="span"):
        app.simulation.timeline.start_replay(bad)


def test_a_still_scene_has_no_timeline(app):
    app.switch_scene("inertia_explorer")
    sim = app.simulation
    assert sim.timeline.seek(5.0) == 0.0 and sim.time == 0.0
    assert sim.timeline.start_replay() is None
    assert sim.panel.timeline.slider.disabled and sim.panel.step_back_button.disabled
    assert not sim.panel.timeline.folder.visible and not sim.panel.measure.folder.visible
    app.switch_scene("pendulum")
    assert (
        sim.panel.timeline.folder.visible
        and sim.panel.measure.folder.visible
        and not sim.panel.step_back_button.disabled
    )


def test_each_private_session_scrubs_its_own_timeline():
    with running_app("tennis_racket", private=True) as app, raw_client(app) as first, raw_client(app) as second:
        wait_for(lambda: len(app.sessions) == 2, what="two sessions")
        (_, a), (_, b) = sorted(app.sessions.items())
        wait_for(lambda: a.time > 1.0 and b.time > 1.0, 30, what="both clocks to run")
        # The first browser drags its own slider back to 0.5 s: its session pauses there, the other runs on.
        send_value(first, a.panel.timeline.slider._impl.uuid, 0.5)
        wait_for(lambda: not a.playing and a.time == 0.5, 20, what="the first session at 0.5 s")
        running = b.time
        wait_for(lambda: b.time > running + 0.2, 20, what="the second session to run on")
        assert b.playing and a.time == 0.5
        # A slider of one session is nothing to another browser: its message is ignored.
        send_value(second, a.panel.timeline.slider._impl.uuid, 0.9)
        assert still_connected(second, app=b) and a.time == 0.5


def test_the_friction_top_jumps_as_far_ahead_as_a_move_may_go(app):
    """A move by hand reaches at most MAX_JUMP beyond the furthest time reached: what the friction top's
    history computes ahead in one go (it steps there, and has come to rest on the table by then)."""
    scene = open_scene(app, "heavy_top")
    assert scene.presets.choose("sleeping top with friction: falls")
    sim = app.simulation
    app.frame(FRAME)
    assert sim.timeline.seek(sim.time + MAX_JUMP) == pytest.approx(FRAME + MAX_JUMP)
    assert app.frame(FRAME) and sim.last_state["landed"]
    assert scene.history.latest == pytest.approx(sim.time, abs=1.0 / 240.0)


@pytest.mark.parametrize("name", ["heavy_top", "wobble", "free_fall", "pendulum", "tennis_racket", "phone_toss"])
def test_every_moving_scene_scrubbed_back_then_on_shows_the_states_it_showed(app, name):
    """Every scene with a clock: the instants played, revisited by the timeline back then on again, give the
    same quantities (the export's columns) bit for bit, the phone toss's fitted replay and the free fall too."""
    open_scene(app, name)
    sim = app.simulation
    seen = {}
    for _ in range(90):
        app.frame(FRAME)
        seen[sim.time] = dict(app.scene.columns(sim.last_state))
    times = sorted(seen)
    for t in [times[60], times[10], times[75], times[30]]:
        sim.timeline.seek(t)
        app.frame(FRAME)
        assert sim.time == t
        assert app.scene.columns(sim.last_state) == seen[t], (name, t)
