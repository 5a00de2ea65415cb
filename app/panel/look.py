"""The panel's look: readable from the back of a lecture hall, light or dark.

viser's ``configure_theme`` has no font size, but its Html element renders raw HTML (viser's
``client/src/components/Html.tsx``), so one ``<style>`` block, added first to the panel, restyles it:
every text at least :data:`MIN_TEXT_PX` pixels, labels in full contrast rather than Mantine's dimmed grey.
"""

from __future__ import annotations

import html
from typing import Any

from app.panel.access import PATCH

__all__ = ["MIN_TEXT_PX", "PATCH", "STYLE", "plot_axes", "configure", "hide_number_box", "motion_html"]

MIN_TEXT_PX = 14
"""Smallest text in the panel, CSS pixels (Mantine's default is 12 to 13)."""

STYLE = f"""<style>
.mantine-Paper-root, .mantine-Paper-root * {{ font-size: max({MIN_TEXT_PX}px, 1em); }}
.mantine-Paper-root label, .mantine-Paper-root .mantine-InputWrapper-label {{
  font-size: {MIN_TEXT_PX}px !important; opacity: 1 !important; color: var(--mantine-color-text) !important; }}
.mantine-Paper-root input, .mantine-Paper-root .mantine-Input-input, .mantine-Paper-root button,
.mantine-Paper-root .mantine-Slider-markLabel, .mantine-Paper-root .mantine-Text-root,
.mantine-Paper-root .mantine-Notification-description {{ font-size: {MIN_TEXT_PX}px !important; }}
.mantine-Notification-title, .mantine-Notification-description {{ font-size: {MIN_TEXT_PX + 1}px !important; }}
</style>"""


def hide_number_box(uuid: str) -> str:
    """CSS that hides the number box of the slider ``uuid`` (viser draws one beside every slider; the
    speed slider's value is a position, not a speed, so its label shows the speed instead)."""
    return f'<style>[id="{uuid}"] ~ * {{ display: none !important; }}</style>'


PLOT_FONT = f"{MIN_TEXT_PX}px system-ui, -apple-system, 'Segoe UI', sans-serif"
"""The plots' tick numbers: uPlot draws them on its canvas (12 px by default), out of reach of the CSS."""


def plot_axes() -> tuple[Any, Any]:
    """uPlot's x and y axes (``viser.uplot.Axis``) with their numbers at :data:`MIN_TEXT_PX`; the y axis a
    little wider for the larger digits. viser still gives them the look's colours."""
    return ({"font": PLOT_FONT, "labelFont": PLOT_FONT}, {"font": PLOT_FONT, "labelFont": PLOT_FONT, "size": 58})


def motion_html(text: str) -> str:
    """The motion in words (:meth:`app.scenes.base.Scene.describe`) as a polite live region: a screen
    reader announces each new text when the reader is idle, without taking the focus."""
    return f'<p class="rbl-motion" aria-live="polite" aria-atomic="true">{html.escape(text)}</p>'


def configure(gui: Any, *, share: bool = False, dark: bool = False) -> Any:
    """Theme a simulation's panel: the large control width, dark or light, viser's share button off
    unless asked for (it would publish the server on a public tunnel), :data:`STYLE` and the accessibility
    patch (:data:`app.panel.access.PATCH`: names, contrast, the 3D view's text); returns the
    style's handle."""
    gui.configure_theme(control_width="large", dark_mode=dark, show_share_button=share)
    return gui.add_html(STYLE + PATCH, order=-1e6)
