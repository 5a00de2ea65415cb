"""A one-dimensional motion's effective potential as a plot: the curve U(x) over a fixed grid, the energy ℰ as a
level line, and the point (x, U(x)) now. The motion turns where the line meets the curve, as the lecture
reads the heavy top's nutation from U(θ) ("The effective potential": ℰ = θ̇²/2 + U(θ)).

Drawn at most :data:`POTENTIAL_PLOT_HZ` times a second (it sends four arrays to every browser); the curve is
computed again only when the scene says it changed.
"""

from __future__ import annotations

import time
from collections.abc import Callable, Hashable

import numpy as np
import viser
from numpy.typing import NDArray

from app.contracts import SceneContext
from app.language.words import mark
from app.panel.look import plot_axes, plot_colour

__all__ = ["POTENTIAL_PLOT_HZ", "PotentialPlot"]

POTENTIAL_PLOT_HZ = 5.0
"""The plot is drawn at most this often (times a second)."""


class PotentialPlot:
    """U(x), the energy line and the point now, in the scene's panel.

    Parameters
    ----------
    ctx : SceneContext
        The scene's context: the plot is made in its panel.
    grid : ndarray, shape (n,)
        The x at which U is drawn, increasing, in the units the scene's physics uses (θ in rad).
    shown : ndarray, shape (n,)
        The same x as the plot's axis shows them (θ in °).
    x_range : (float, float)
        The x axis's fixed range, in ``shown``'s units: viser 1.1.1's client loses an automatic x scale when
        the plot's scales are sent again (its min and max become null and the curve vanishes until a
        reload), so the range is fixed.
    x_label, curve_label, title : str
        The x series' label, the curve's, and the plot's title (marked words: translated on their way).
    colours : (str, str, str)
        ``#rrggbb`` of the curve, the energy line and the point now (the palette's, as the scene draws them).

    Attributes
    ----------
    handle : viser.GuiUplotHandle
        The plot (hidden or shown as a question holds it).
    x : float
        The x of the point drawn last (0 before the first drawing).
    y_range : (float, float) or None
        The y range shown (None before the first drawing).
    """

    def __init__(
        self,
        ctx: SceneContext,
        grid: NDArray[np.float64],
        *,
        shown: NDArray[np.float64],
        x_range: tuple[float, float],
        x_label: str,
        curve_label: str,
        title: str,
        colours: tuple[str, str, str],
    ) -> None:
        grid, shown = np.asarray(grid, dtype=float), np.asarray(shown, dtype=float)
        if grid.ndim != 1 or grid.shape != shown.shape or grid.size < 2 or np.any(np.diff(grid) <= 0):
            raise ValueError(
                f"expected an increasing grid and its shown values of one shape (n ≥ 2,), got "
                f"{grid.shape} and {shown.shape}"
            )
        self.grid, self.shown = grid, shown
        self._x_scale = viser.uplot.Scale(time=False, auto=False, range=x_range)
        points = grid.size
        curve_colour, energy_colour, now_colour = colours
        self.handle = ctx.server.gui.add_uplot(
            data=(shown, np.zeros(points), np.zeros(points), np.full(points, -1e3)),
            series=(
                viser.uplot.Series(label=x_label),
                viser.uplot.Series(label=curve_label, stroke=plot_colour(curve_colour, ctx.dark), width=2),
                viser.uplot.Series(
                    label=mark("energy ℰ"),
                    stroke=plot_colour(energy_colour, ctx.dark),
                    width=1,
                    dash=(6, 4),
                ),
                viser.uplot.Series(
                    label=mark("now (θ, U)"),
                    stroke=now_colour,
                    width=0,
                    points={"show": True, "size": 10, "fill": now_colour},
                ),
            ),
            scales={"x": self._x_scale, "y": viser.uplot.Scale(auto=False, range=(0.0, 1.0))},
            title=title,
            axes=plot_axes(),
            aspect=1.6,
        )
        self.reset()

    def reset(self) -> None:
        """Forget what was drawn: the next :meth:`due` is True, the curve and the y range are made again."""
        self._drawn_at = 0.0
        self._curve_key: Hashable | None = None
        self._curve = np.zeros(self.grid.size)
        self.x = 0.0
        self.y_range: tuple[float, float] | None = None

    def due(self) -> bool:
        """Whether the plot should be drawn now: never drawn, or not for 1/:data:`POTENTIAL_PLOT_HZ` s."""
        return self._curve_key is None or time.monotonic() - self._drawn_at >= 1.0 / POTENTIAL_PLOT_HZ

    def show(
        self,
        key: Hashable,
        curve: Callable[[NDArray[np.float64]], NDArray[np.float64]],
        x: float,
        energy: float,
        height: float,
    ) -> None:
        """Draw the curve (``curve(grid)``, computed again only when ``key`` changes), the energy line and the
        point (x, ``height``) on the grid point at or after ``x`` (``height`` is U(x): the energy less the
        kinetic part the scene knows). Non-finite values of the curve are drawn off the range."""
        self._drawn_at = time.monotonic()
        if key != self._curve_key:
            self._curve_key = key
            self._curve = curve(self.grid)
        finite = self._curve[np.isfinite(self._curve)]
        lo = float(finite.min()) if finite.size else 0.0
        hi = max(energy, lo) + max(abs(energy - lo), 0.05 * max(abs(lo), 1.0))
        # uPlot draws nothing at all if a series holds NaN: off-range values (clipped by the fixed y
        # range) stand in for gaps. The "now" series is one visible point at the current x.
        floor, ceiling = lo - 1e3 * (hi - lo + 1.0), hi + 1e3 * (hi - lo + 1.0)
        points = self.grid.size
        now = np.full(points, floor)
        now[int(np.clip(np.searchsorted(self.grid, x), 0, points - 1))] = height
        drawn = np.clip(np.nan_to_num(self._curve, nan=ceiling, posinf=ceiling), floor, ceiling)
        self.handle.data = (self.shown, drawn, np.full(points, energy), now)
        self.x = x
        y_range = (round(lo - 0.1 * (hi - lo), 3), round(hi, 3))
        if y_range != self.y_range:
            # New options rebuild the chart in every browser: only when the range really changes.
            self.y_range = y_range
            self.handle.scales = {"x": self._x_scale, "y": viser.uplot.Scale(auto=False, range=y_range)}
