"""The effective-potential plot (app.panel.potential_plot.PotentialPlot): the curve made once per motion, the
energy line, one visible point now, every series finite, its cadence. The heavy top's U(θ) through it is in
tests/app/scenes/test_heavy_top.py."""

from __future__ import annotations

from types import SimpleNamespace

import numpy as np
import pytest

from app.controls import POTENTIAL_PLOT_HZ, PotentialPlot
from tests.harness import running_app

GRID = np.linspace(0.1, 3.0, 30)
COLOURS = ("#0072b2", "#555555", "#d55e00")


@pytest.fixture(scope="module")
def ctx():
    with running_app(start_loop=False) as app:
        yield SimpleNamespace(server=app.server, dark=False)


def _plot(ctx) -> PotentialPlot:
    return PotentialPlot(
        ctx,
        GRID,
        shown=np.degrees(GRID),
        x_range=(0.0, 180.0),
        x_label="x",
        curve_label="U",
        title="U",
        colours=COLOURS,
    )


def test_the_curve_is_made_once_per_key_and_the_point_sits_on_it(ctx) -> None:
    plot = _plot(ctx)
    made: list[float] = []

    def well(x: np.ndarray) -> np.ndarray:
        made.append(1.0)
        return (x - 1.5) ** 2

    assert plot.due() and plot.y_range is None
    plot.show("a", well, 1.0, 0.5, 0.25)
    plot.show("a", well, 2.0, 0.5, 0.25)
    assert len(made) == 1  # the same motion: its curve is kept
    plot.show("b", well, 2.0, 0.5, 0.25)
    assert len(made) == 2
    shown, curve, energy, now = (np.asarray(a) for a in plot.handle.data)
    np.testing.assert_array_equal(shown, np.degrees(GRID))
    np.testing.assert_array_equal(curve, (GRID - 1.5) ** 2)
    assert np.all(energy == 0.5)
    assert plot.y_range is not None
    lo, hi = plot.y_range
    visible = np.flatnonzero((now >= lo) & (now <= hi))
    assert visible.tolist() == [int(np.searchsorted(GRID, 2.0))] and now[visible[0]] == 0.25
    assert plot.x == 2.0
    # The energy line and the curve's minimum lie inside the range: the turning points can be read.
    assert lo < 0.0 <= 0.5 < hi


def test_a_curve_with_infinities_and_nans_is_drawn_finite(ctx) -> None:
    plot = _plot(ctx)
    curve = np.where(GRID < 0.5, np.inf, 1.0 / GRID)
    curve[10] = np.nan
    plot.show(0, lambda x: curve, 1.0, 2.0, 1.0)
    assert all(np.all(np.isfinite(np.asarray(a))) for a in plot.handle.data)
    lo, hi = plot.y_range or (0.0, 0.0)
    drawn = np.asarray(plot.handle.data[1])
    assert np.all(drawn[GRID < 0.5] > hi) and drawn[10] > hi  # off the range: a gap, not a line to zero


def test_it_is_due_again_after_its_interval_or_a_reset(ctx, monkeypatch) -> None:
    plot = _plot(ctx)
    clock = [100.0]
    monkeypatch.setattr("app.panel.potential_plot.time.monotonic", lambda: clock[0])
    plot.show(0, lambda x: x, 1.0, 1.0, 1.0)
    clock[0] = 100.0 + 0.9 / POTENTIAL_PLOT_HZ
    assert not plot.due()
    clock[0] = 100.0 + 1.1 / POTENTIAL_PLOT_HZ
    assert plot.due()
    plot.show(0, lambda x: x, 1.0, 1.0, 1.0)
    plot.reset()
    assert plot.due() and plot.y_range is None and plot.x == 0.0


def test_a_grid_that_does_not_increase_or_match_is_refused(ctx) -> None:
    with pytest.raises(ValueError, match="expected an increasing grid"):
        PotentialPlot(
            ctx, GRID[::-1], shown=GRID, x_range=(0.0, 1.0), x_label="x", curve_label="U", title="U", colours=COLOURS
        )
    with pytest.raises(ValueError, match=r"got \(30,\) and \(29,\)"):
        PotentialPlot(
            ctx, GRID, shown=GRID[1:], x_range=(0.0, 1.0), x_label="x", curve_label="U", title="U", colours=COLOURS
        )
