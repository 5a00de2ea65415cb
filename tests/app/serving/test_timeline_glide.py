"""A dragged timeline glides: viser's page sends a dragged slider's value at most every 50 ms, so within a
drag the body glides to each new instant over GLIDE_SECONDS, every frame of the loop an exact instant
between, and arrives exactly where the slider was dragged to; a lone move (a click on the track) jumps.
The wall clock is the timeline's own (``Timeline.now``), moved by hand here."""

from __future__ import annotations

import math

import numpy as np
import pytest

from app.serving.timeline import GLIDE_SECONDS, GLIDE_WINDOW
from physics.free_body import FreeBody
from tests.harness import FRAME, open_scene


class WallClock:
    def __init__(self) -> None:
        self.t = 1000.0

    def __call__(self) -> float:
        return self.t


def _angle(R, exact) -> float:
    return 2.0 * math.asin(min(1.0, float(np.linalg.norm(R - exact)) / math.sqrt(8.0)))


@pytest.fixture
def racket(app):
    scene = open_scene(app, "tennis_racket")
    for _ in range(round(3.0 / FRAME)):
        app.frame(FRAME)
    wall = WallClock()
    app.simulation.timeline.now = wall
    return app, scene, wall


def _drag(app, wall, start: float, end: float, gap: float = 0.05) -> None:
    """The slider moved to ``start``, then ``gap`` s of wall time later to ``end``: a drag's two messages."""
    app.simulation.panel.timeline.slider.value = start
    wall.t += gap
    app.simulation.panel.timeline.slider.value = end


def test_a_lone_move_jumps_at_once(racket) -> None:
    app, _, _ = racket
    sim = app.simulation
    sim.panel.timeline.slider.value = 1.25  # as a browser sets it (its callback runs)
    assert sim.time == 1.25 and sim.timeline.glide is None and not sim.playing


def test_within_a_drag_each_frame_is_an_exact_instant_between_and_the_drag_ends_where_the_slider_is(racket) -> None:
    app, scene, wall = racket
    sim = app.simulation
    model = FreeBody(scene.moments).trajectory(scene.omega0, scene.attitude0)
    slider = sim.panel.timeline.slider
    slider.value = 1.0
    app.frame(FRAME)
    wall.t += 0.05  # the page's next message of the drag, 50 ms on
    slider.value = 2.0
    assert sim.timeline.glide is not None and sim.time == 1.0  # it starts where the body was
    drawn = []
    for _ in range(4):  # the loop's frames, 1/60 s apart
        wall.t += FRAME
        assert app.frame(FRAME)
        drawn.append(sim.time)
        assert _angle(sim.last_state["R"], model.at(sim.time).attitude) < 1e-12  # an exact instant
        if sim.timeline.glide is not None:
            assert slider.value == 2.0  # the dragging page's slider is not pulled back mid-glide
    share = FRAME / GLIDE_SECONDS
    assert drawn[0] == pytest.approx(1.0 + share, abs=1e-12) and drawn[1] == pytest.approx(1.0 + 2 * share, abs=1e-12)
    assert drawn[-1] == 2.0 and sim.timeline.glide is None  # arrived, exactly
    assert len(set(drawn)) == 4 and drawn == sorted(drawn)
    assert not sim.playing


def test_a_move_after_a_pause_in_the_drag_jumps(racket) -> None:
    app, _, wall = racket
    sim = app.simulation
    sim.panel.timeline.slider.value = 1.0
    wall.t += GLIDE_WINDOW + 0.01
    sim.panel.timeline.slider.value = 2.5
    assert sim.time == 2.5 and sim.timeline.glide is None


def test_play_ends_a_glide_and_goes_on_from_where_the_body_is(racket) -> None:
    app, _, wall = racket
    sim = app.simulation
    _drag(app, wall, 1.0, 2.0)
    wall.t += FRAME
    app.frame(FRAME)
    between = sim.time
    assert 1.0 < between < 2.0
    sim.set_playing(True)
    app.frame(FRAME)
    assert sim.timeline.glide is None and sim.time == pytest.approx(between + FRAME, abs=1e-12)


def test_a_seek_by_hand_ends_a_glide(racket) -> None:
    app, _, wall = racket
    sim = app.simulation
    _drag(app, wall, 1.0, 2.0)
    sim.timeline.jump(-0.5)  # Shift+← in the middle of a drag: from where the body is
    assert sim.timeline.glide is None and sim.time == 0.5
    app.frame(FRAME)
    assert sim.time == 0.5


def test_a_drag_from_a_busy_page_glides_over_the_time_between_its_moves(racket) -> None:
    """A page that sends its moves 150 ms apart (busy drawing in software): the glide lasts those 150 ms, so
    the body moves on every frame until the next move is due, not for 50 ms and then stands."""
    app, _, wall = racket
    sim = app.simulation
    _drag(app, wall, 1.0, 2.5, gap=0.15)
    glide = sim.timeline.glide
    assert glide is not None and glide.seconds == pytest.approx(0.15)
    wall.t += 0.075
    app.frame(FRAME)
    assert sim.time == pytest.approx(1.75, abs=1e-12)  # halfway in time, halfway there
    wall.t += 0.075
    app.frame(FRAME)
    assert sim.time == 2.5 and sim.timeline.glide is None
