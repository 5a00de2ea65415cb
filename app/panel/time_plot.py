"""A live plot of quantities against the simulated time: the pendulum's swing θ(t), the heavy top's nutation
θ(t). Sampled every few frames and trimmed to the newest samples, so each refresh sends a bounded message."""

from __future__ import annotations

import math
from collections.abc import Sequence

import numpy as np
import viser

from app.contracts import SceneContext
from app.language.words import mark
from app.panel.look import plot_axes, plot_colour

__all__ = ["TIME_PLOT_EVERY", "TIME_PLOT_POINTS", "TimePlot"]

TIME_PLOT_EVERY = 6
"""Frames between samples (each one sends the plot): 10 a second at 60 frames/s."""

TIME_PLOT_POINTS = 240
"""Samples kept: the last 24 s at 1× (each refresh sends at most this many per series)."""


class TimePlot:
    """Quantities against the simulated time t (s), newest at the right.

    Parameters
    ----------
    ctx
        The scene's context (its ``server`` and whether its look is ``dark``).
    title : str
        The plot's title, e.g. ``"The swing: θ (°)"``.
    series : sequence of (label, colour)
        Each plotted quantity's legend label and colour (``#rrggbb``, shown as :func:`plot_colour` makes it
        legible in the look).
    every, points : int
        Frames between samples, and samples kept.

    Attributes
    ----------
    handle : viser.GuiUplotHandle
        The plot in the panel (hidden or shown as a question holds it; drawn large in projector mode).
    """

    def __init__(
        self,
        ctx: SceneContext,
        title: str,
        series: Sequence[tuple[str, str]],
        *,
        every: int = TIME_PLOT_EVERY,
        points: int = TIME_PLOT_POINTS,
    ) -> None:
        if every < 1 or points < 2:
            raise ValueError(f"expected every ≥ 1 frame and points ≥ 2, got every={every}, points={points}")
        self.width = len(series)
        self.every, self.points = int(every), int(points)
        self.handle = ctx.server.gui.add_uplot(
            data=(np.zeros(1), *(np.zeros(1) for _ in series)),
            series=(
                viser.uplot.Series(label=mark("t (s)")),
                *(
                    viser.uplot.Series(label=label, stroke=plot_colour(colour, ctx.dark), width=2)
                    for label, colour in series
                ),
            ),
            title=title,
            axes=plot_axes(),
            scales={"x": viser.uplot.Scale(time=False, auto=True), "y": viser.uplot.Scale(auto=True)},
            aspect=1.6,
        )
        self.clear()

    def clear(self) -> None:
        """Forget the samples (a reset, a new parameter): the next frame starts a new curve."""
        self.times: list[float] = []
        self.values: list[list[float]] = [[] for _ in range(self.width)]
        self._frames = 0

    def rewind(self, t: float) -> None:
        """The clock went back or on to ``t`` (s, the timeline): the samples after ``t`` go, those before stay,
        and the next frame samples."""
        keep = sum(1 for s in self.times if s <= t)
        del self.times[keep:]
        for column in self.values:
            del column[keep:]
        self._frames = 0
        if len(self.times) >= 2:
            self.handle.data = (np.array(self.times), *(np.array(column) for column in self.values))

    def sample(self, t: float, *values: float) -> None:
        """A frame at time ``t`` (s) with the quantities' ``values``: every ``every``-th one is kept and sent.

        A frame redrawn at a time not after the last sample (paused) adds nothing; a value that is not finite
        is kept as a gap.
        """
        if len(values) != self.width:
            raise ValueError(f"expected {self.width} values, one per series, got {len(values)}")
        self._frames += 1
        if (self._frames - 1) % self.every:
            return
        if self.times and t <= self.times[-1]:
            return
        self.times.append(float(t))
        for column, value in zip(self.values, values, strict=True):
            column.append(float(value) if math.isfinite(value) else math.nan)
            del column[: -self.points]
        del self.times[: -self.points]
        if len(self.times) >= 2:
            self.handle.data = (np.array(self.times), *(np.array(column) for column in self.values))
