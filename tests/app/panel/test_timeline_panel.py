"""The timeline's controls: the slider spans what the scene can show, its value set by the server is not
taken for a browser's move, and the replay's choices read as numbers."""

from __future__ import annotations

import math

import pytest

from app.panel.timeline_panel import REPLAY_SPANS, REPLAY_SPEEDS, seconds_of
from tests.harness import FRAME, open_scene


def test_the_choices_read_as_numbers_and_anything_else_is_refused():
    assert [seconds_of(c) for c in REPLAY_SPANS] == [1.0, 2.0, 5.0, 10.0]
    assert [seconds_of(c) for c in REPLAY_SPEEDS] == [0.01, 0.1, 0.25, 0.5]
    for bad in ("", "two s", "-1 s", "0×", "nan s", "inf×"):
        with pytest.raises(ValueError):
            seconds_of(bad)


def test_the_slider_set_by_the_server_does_not_move_the_clock(app):
    open_scene(app, "pendulum")
    sim = app.simulation
    panel = sim.panel.timeline
    panel.show(1.5, 0.0, 1.5)  # the server shows a time: its callback runs and is passed over
    assert sim.playing and panel.slider.value == 1.5 and panel.slider.max == 2.0
    panel.show(0.7, 0.333, 12.2)
    assert panel.slider.min == pytest.approx(0.33) and panel.slider.max == 13.0
    assert math.isclose(panel.slider.value, 0.7)
    app.frame(FRAME)
    assert sim.playing  # still running: nothing was taken for a scrub


def test_a_strike_is_as_far_back_as_the_pendulum_goes(app):
    scene = open_scene(app, "pendulum")
    sim = app.simulation
    for _ in range(60):
        app.frame(FRAME)
    scene.strike()
    struck = sim.time
    for _ in range(30):
        app.frame(FRAME)
    assert sim.timeline.seek(0.0) == struck  # not into the swing before the blow
    assert scene.earliest() == struck
