"""The simulation's clock: real time while playing, a stalled frame capped at MAX_FRAME_DT and the wall
time it did not simulate counted, single steps while paused."""

from __future__ import annotations

import pytest

from app.serving.clock import MAX_FRAME_DT, Clock


def test_playing_frames_advance_by_wall_time_times_speed():
    clock = Clock(60.0)
    assert clock.advance(0.02) == 0.02
    clock.speed = 0.25
    assert clock.advance(0.02) == 0.005
    assert clock.dropped == 0.0


def test_a_stalled_frame_advances_at_most_max_frame_dt_and_counts_the_rest():
    clock = Clock(60.0)
    clock.speed = 2.0
    assert clock.advance(0.35) == 2.0 * MAX_FRAME_DT
    assert clock.dropped == pytest.approx(0.35 - MAX_FRAME_DT, rel=1e-15)
    assert clock.advance(MAX_FRAME_DT) == 2.0 * MAX_FRAME_DT  # exactly the cap drops nothing
    assert clock.advance(-1.0) == 0.0  # a clock that ran backwards neither advances nor drops
    assert clock.dropped == pytest.approx(0.25, rel=1e-15)


def test_paused_frames_drop_nothing_and_use_the_steps_asked_for():
    clock = Clock(50.0)
    clock.playing = False
    assert clock.advance(5.0) == 0.0
    clock.steps = 3
    assert clock.advance(5.0) == pytest.approx(3 / 50.0, rel=1e-15)
    assert clock.steps == 0
    assert clock.dropped == 0.0
