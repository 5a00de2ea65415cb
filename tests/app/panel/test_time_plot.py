"""The live time plot (app.panel.time_plot.TimePlot): its cadence, its bounded history, a paused frame, a gap."""

from __future__ import annotations

import math
from types import SimpleNamespace

import numpy as np
import pytest

from app.controls import TimePlot
from tests.harness import running_app


@pytest.fixture(scope="module")
def ctx():
    with running_app(start_loop=False) as app:
        yield SimpleNamespace(server=app.server, dark=False)


def test_every_nth_frame_is_kept_and_only_the_newest_points(ctx):
    plot = TimePlot(ctx, "θ (°)", [("θ (°)", "#1f77b4"), ("φ (°)", "#ff7f0e")], every=3, points=5)
    for frame in range(30):
        t = frame / 60.0
        plot.sample(t, math.sin(t), math.cos(t))
    times, first, second = plot.handle.data
    # Frames 0, 3, …, 27 were sampled; the newest five are kept.
    expected = np.arange(12, 30, 3)[-5:] / 60.0
    np.testing.assert_array_equal(times, expected)
    np.testing.assert_array_equal(first, np.sin(expected))
    np.testing.assert_array_equal(second, np.cos(expected))


def test_a_paused_frame_adds_nothing_a_nan_is_a_gap_and_clear_starts_afresh(ctx):
    plot = TimePlot(ctx, "θ (°)", [("θ (°)", "#1f77b4")], every=1, points=10)
    plot.sample(0.0, 1.0)
    plot.sample(0.1, math.nan)
    plot.sample(0.1, 5.0)  # redrawn while paused: the same instant
    plot.sample(0.2, 3.0)
    times, values = plot.handle.data
    np.testing.assert_array_equal(times, [0.0, 0.1, 0.2])
    assert values[0] == 1.0 and math.isnan(values[1]) and values[2] == 3.0
    plot.clear()
    plot.sample(0.0, 7.0)
    assert plot.times == [0.0] and plot.values == [[7.0]]


def test_bad_arguments_are_refused_with_what_was_expected(ctx):
    with pytest.raises(ValueError, match="every ≥ 1"):
        TimePlot(ctx, "θ", [("θ", "#000000")], every=0)
    plot = TimePlot(ctx, "θ", [("θ", "#000000")])
    with pytest.raises(ValueError, match="expected 1 values, one per series, got 2"):
        plot.sample(0.0, 1.0, 2.0)
