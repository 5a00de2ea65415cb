"""The panel kit a scene is built from (``from app import controls, draw``): sliders, readouts, presets, rollback,
drift plot, time plot, potential plot.

Re-exported from :mod:`app.panel` (and :func:`markdown_text`, a user's text escaped for Markdown, from
:mod:`app.guards.text`) for scenes, in app/ and outside it (examples/05_custom_scene.py).
"""

from __future__ import annotations

from app.guards.text import markdown_text
from app.panel.drift import (
    DRIFT_EVERY,
    DRIFT_FLOOR,
    DRIFT_POINTS,
    InvariantDrift,
)
from app.panel.parameters import (
    Gauge,
    ParameterPanel,
    Presets,
    Readout,
    SliderSpec,
    refusable_dropdown,
    take_uploads,
)
from app.panel.potential_plot import (
    POTENTIAL_PLOT_HZ,
    PotentialPlot,
)
from app.panel.rollback import (
    Rollback,
)
from app.panel.time_plot import (
    TIME_PLOT_EVERY,
    TIME_PLOT_POINTS,
    TimePlot,
)

__all__ = [
    "markdown_text",
    "SliderSpec",
    "ParameterPanel",
    "Readout",
    "Presets",
    "Gauge",
    "refusable_dropdown",
    "take_uploads",
    "Rollback",
    "DRIFT_EVERY",
    "DRIFT_POINTS",
    "DRIFT_FLOOR",
    "InvariantDrift",
    "TIME_PLOT_EVERY",
    "TIME_PLOT_POINTS",
    "TimePlot",
    "POTENTIAL_PLOT_HZ",
    "PotentialPlot",
]
