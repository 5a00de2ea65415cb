"""Plot text at least 14 px: uPlot draws its tick numbers on a canvas, so their size is
set where the app builds each plot (``app.panel.look.plot_axes``); titles and legends are HTML, sized by
the page patch and measured in tests/browser/test_accessibility.py."""

from __future__ import annotations

import re

import viser

from app.panel.look import MIN_TEXT_PX
from app.scenes import scene_names
from tests.harness import open_scene


def plots(scene) -> list[viser.GuiUplotHandle]:
    """The scene's plots: its own, its drift plot's and its integrator ghost's."""
    found = []
    for value in vars(scene).values():
        for candidate in (value, getattr(value, "handle", None), getattr(getattr(value, "plot", None), "handle", None)):
            if isinstance(candidate, viser.GuiUplotHandle) and candidate not in found:
                found.append(candidate)
    return found


def test_every_plot_draws_its_axis_numbers_at_14_px(app):
    seen = 0
    for name in scene_names():
        for handle in plots(open_scene(app, name)):
            axes = handle._impl.props.axes
            assert axes is not None and len(axes) == 2, (name, handle._impl.props.title)
            for axis in axes:
                for key in ("font", "labelFont"):
                    size = re.match(r"(?:bold )?(\d+)px ", axis[key])
                    assert size and int(size.group(1)) >= MIN_TEXT_PX, (name, key, axis[key])
            seen += 1
    assert seen >= 6  # U(θ), the racket's ω, the drift plots, the ghost's
