"""The Measure folder: the events listed are the physics API's (half a period apart, from the exact
solution), the stopwatch reads the simulated clock, and the angle between two drawn directions is
angle_between's, live."""

from __future__ import annotations

import math

import numpy as np
import pytest

from app.panel.measure_panel import EVENTS_SHOWN, HELD, NO_EVENTS, Stopwatch, angle_text, events_markdown
from physics.events import HALF_TURN, TURNING_POINT, flip_events, swing_events
from physics.free_body import FreeBody
from tests.harness import FRAME, open_scene


def test_the_racket_lists_its_half_turns_half_a_period_apart(app):
    scene = open_scene(app, "tennis_racket")
    sim = app.simulation
    sim.timeline.seek(6.0)
    app.frame(FRAME)
    text = sim.panel.measure.events_text.content
    times = [float(line.split()[2]) for line in text.splitlines() if line.startswith("- ")]
    assert HALF_TURN in text and 2 <= len(times) <= EVENTS_SHOWN
    period = FreeBody(scene.moments).period(scene.omega0)  # the physics API's, from the scene's start
    assert np.allclose(np.diff(times), period / 2.0, atol=1e-4)  # four decimals shown
    assert times[0] == pytest.approx(flip_events(scene.motion, 0.0, 20.0)[0].time, abs=5e-5)
    assert "✓ " + f"{times[0]:.4f}" in text and "· " + f"{times[-1]:.4f}" in text  # past and to come


def test_the_heavy_top_lists_its_turning_points_and_the_friction_top_none(app):
    scene = open_scene(app, "heavy_top")
    sim = app.simulation
    sim.timeline.seek(2.0)
    app.frame(FRAME)
    text = sim.panel.measure.events_text.content
    assert "θ max" in text and "θ min" in text
    times = [float(line.split()[2]) for line in text.splitlines() if line.startswith("- ")]
    assert np.allclose(np.diff(times), scene.motion.nutation_period / 2.0, atol=1e-4)
    assert scene.presets.choose("sleeping top with friction: falls")
    app.frame(FRAME)
    sim.set_playing(False)
    app.frame(FRAME)
    assert sim.panel.measure.events_text.content == NO_EVENTS


def test_the_pendulums_swings_are_timed_from_its_release_and_from_a_strike(app):
    scene = open_scene(app, "pendulum")
    sim = app.simulation
    release = scene.model.trajectory(scene.start[0], scene.start[1])
    first = swing_events(release, 0.0, 5.0)
    assert [e.time for e in scene.events(0.0, 5.0)] == [e.time for e in first] and first
    for _ in range(40):
        app.frame(FRAME)
    scene.strike()
    theta, thetadot, struck = scene.start
    after = scene.events(0.0, struck + 5.0)
    assert after and min(e.time for e in after) >= struck  # the swing before the blow is not this one's
    again = swing_events(scene.model.trajectory(theta, thetadot), 0.0, 5.0)
    assert [e.time for e in after] == pytest.approx([e.time + struck for e in again], abs=1e-12)
    assert events_markdown([], 0.0) == NO_EVENTS
    sim.set_playing(False)


def test_the_stopwatch_reads_the_simulated_clock():
    watch = Stopwatch()
    watch.start(1.0)
    assert watch.reading(3.5) == 2.5
    watch.stop(4.0)
    assert watch.reading(100.0) == 3.0  # stopped: the clock's later time does not count
    watch.start(10.0)
    assert watch.reading(10.5) == 3.5  # started again: it adds on
    watch.reset()
    assert watch.reading(50.0) == 0.0 and not watch.running


def test_the_stopwatch_buttons_in_the_panel(app):
    open_scene(app, "heavy_top")
    sim = app.simulation
    measure = sim.panel.measure
    measure.stopwatch_buttons.value = "Zero"
    measure.stopwatch_buttons.value = "Start"
    start = sim.time
    for _ in range(30):
        app.frame(FRAME)
    measure.stopwatch_buttons.value = "Stop"
    assert measure.stopwatch.value == f"{sim.time - start:.4f}" and sim.time - start == pytest.approx(0.5)


def test_the_angle_between_two_directions():
    found = {"L": np.array([0.0, 0.0, 2.0]), "ω": np.array([1.0, 0.0, 1.0]), "symmetry axis": np.zeros(3)}
    assert angle_text(found, "L", "ω") == "45.000"
    assert angle_text(found, "ω", "vertical") == "45.000"
    assert angle_text(found, "L", "symmetry axis").startswith("— (a zero vector")
    assert angle_text({}, "L", "vertical") == "— (this scene draws no L)"


def test_the_angle_between_L_and_the_axis_of_the_top_is_read_live(app):
    open_scene(app, "heavy_top")
    sim = app.simulation
    measure = sim.panel.measure
    measure.first.value, measure.second.value = "L", "symmetry axis"
    sim.timeline.seek(0.7)
    app.frame(FRAME)
    state = sim.last_state
    expected = math.degrees(math.atan2(np.linalg.norm(np.cross(state["L"], state["axis"])), state["L"] @ state["axis"]))
    assert float(measure.angle.value) == pytest.approx(expected, abs=5e-4)
    measure.second.value = "vertical"  # the top's tilt of L
    app.frame(FRAME)
    assert float(measure.angle.value) == pytest.approx(
        math.degrees(math.acos(state["L"][2] / np.linalg.norm(state["L"]))), abs=5e-4
    )


def test_the_last_event_is_said_in_the_motion_in_words(app):
    scene = open_scene(app, "tennis_racket")
    sim = app.simulation
    flip = flip_events(scene.motion, 0.0, 10.0)[0].time
    sim.timeline.seek(flip - 0.1)
    app.frame(FRAME)
    assert "Last event" not in sim.panel.said
    sim.timeline.seek(flip + 0.1)
    app.frame(FRAME)
    assert sim.panel.said.endswith(f"Last event: {HALF_TURN} at {flip:.3f} s.")


def test_the_events_wait_while_a_class_question_holds_the_answer_back(app):
    open_scene(app, "pendulum")
    sim = app.simulation
    sim.hold_back(["centre_of_percussion"])  # its swing periods would give it away
    sim.set_playing(False)
    app.frame(FRAME)
    assert sim.panel.measure.events_text.content == HELD and "Last event" not in sim.panel.said
    sim.hold_back([])
    app.frame(FRAME)
    assert TURNING_POINT in sim.panel.measure.events_text.content
