"""The invariant-drift plot: how far an integrator's energy and momentum have drifted, on a log scale."""

from __future__ import annotations

import math
from collections.abc import Callable

import numpy as np
import viser

from app.contracts import SceneContext
from app.language.words import mark
from app.panel.look import plot_axes, plot_colour

__all__ = ["DRIFT_EVERY", "DRIFT_POINTS", "DRIFT_FLOOR", "InvariantDrift"]

DRIFT_EVERY = 15
"""The invariants are sampled (and the plot sent) every this many frames: 4 a second at 60 frames/s. A
frame of thirty private sessions should not pay for a plot nobody can read faster."""

DRIFT_POINTS = 80
"""Samples the invariant-drift plot keeps (the newest at the right)."""

DRIFT_FLOOR = 1e-17
"""A drift below this (exactly 0 included) is drawn at it: the plot is of log₁₀, and 0 has none."""


class InvariantDrift:
    """A small live plot of the relative drift of a scene's invariants (E, |L|, L_z, L₃ as they apply).

    ``add(t, values)`` takes a function returning each invariant's value and its scale (the size a drift is
    measured against: |L| for L_z, which may pass through 0), called only on the frames that sample; the
    first sample after :meth:`clear` is the reference. The plot
    shows log₁₀ |v − v₀| / scale against time: flat near −15 for an exact solution, rising for friction or
    an integrator. It is cleared with the scene's traces (Reset, a new parameter).
    """

    def __init__(
        self,
        ctx: SceneContext,
        names: tuple[str, ...],
        colours: tuple[str, ...],
        title: str = mark("Invariants: log₁₀ relative drift"),
    ) -> None:
        self.names = names
        self.handle = ctx.server.gui.add_uplot(
            data=(np.zeros(1), *(np.full(1, math.log10(DRIFT_FLOOR)) for _ in names)),
            series=(
                viser.uplot.Series(label=mark("t (s)")),
                *(
                    viser.uplot.Series(label=name, stroke=plot_colour(colour, ctx.dark), width=2)
                    for name, colour in zip(names, colours)
                ),
            ),
            scales={
                "x": viser.uplot.Scale(time=False, auto=True),
                "y": viser.uplot.Scale(auto=False, range=(-17.0, 0.0)),
            },
            title=title,
            axes=plot_axes(),
            aspect=2.2,
        )
        self.clear()

    def clear(self) -> None:
        self.reference: dict[str, float] | None = None
        self.times: list[float] = []
        self.drifts: list[list[float]] = [[] for _ in self.names]
        self._calls = 0

    def add(self, t: float, values: Callable[[], dict[str, tuple[float, float]]]) -> None:
        """A frame at time ``t`` (s); every :data:`DRIFT_EVERY`-th one samples ``values()`` (``name`` →
        ``(value, scale)``) and sends the plot."""
        self._calls += 1
        if (self._calls - 1) % DRIFT_EVERY:
            return
        sample = values()  # evaluated only on the sampling frames
        if self.reference is None:
            self.reference = {name: sample[name][0] for name in self.names}
        for k, name in enumerate(self.names):
            value, scale = sample[name]
            drift = abs(value - self.reference[name]) / scale if scale > 0.0 else 0.0
            self.drifts[k].append(math.log10(max(drift, DRIFT_FLOOR)) if math.isfinite(drift) else 0.0)
            del self.drifts[k][:-DRIFT_POINTS]
        self.times.append(float(t))
        del self.times[:-DRIFT_POINTS]
        self.handle.data = (np.array(self.times), *(np.array(d) for d in self.drifts))

    def rewind(self, t: float) -> None:
        """The clock went back or on to ``t`` (s, the timeline): the samples after ``t`` go (the reference
        stays: the drift is still measured from the start), and the next frame samples."""
        keep = sum(1 for s in self.times if s <= t)
        del self.times[keep:]
        for drifts in self.drifts:
            del drifts[keep:]
        self._calls = 0

    def latest(self) -> dict[str, float]:
        """The newest log₁₀ drift of each invariant (what the plot shows at its right end)."""
        return {name: d[-1] for name, d in zip(self.names, self.drifts) if d}
