"""The panel's look: readable from the back of a lecture hall, light or dark.

viser's ``configure_theme`` has no font size, but its Html element renders raw HTML (viser's
``client/src/components/Html.tsx``), so one ``<style>`` block, added first to the panel, restyles it:
every text at least :data:`MIN_TEXT_PX` pixels, labels in full contrast rather than Mantine's dimmed grey.
"""

from __future__ import annotations

from typing import Any

from app.language.words import escaped, say
from app.panel.access import PATCH

__all__ = [
    "MIN_TEXT_PX",
    "PATCH",
    "PLOT_BACKGROUND",
    "PLOT_LINE_CONTRAST",
    "STYLE",
    "contrast",
    "plot_axes",
    "plot_colour",
    "configure",
    "hide_number_box",
    "side_by_side",
    "motion_html",
]

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


def side_by_side(*uuids: str) -> str:
    """CSS that sets the buttons ``uuids`` in one row, sharing its width (viser stacks every control; Step
    and Step back belong together and the clock has no room above the fold for another row). Each button's
    box keeps viser's side margins (Mantine's xs spacing)."""
    share = f"calc({100 / len(uuids):.4f}% - 2 * var(--mantine-spacing-xs))"
    boxes = ", ".join(f'div:has(> [id="{uuid}"])' for uuid in uuids)
    return f"<style>{boxes} {{ display: inline-block; vertical-align: top; width: {share}; }}</style>"


PLOT_FONT = f"{MIN_TEXT_PX}px system-ui, -apple-system, 'Segoe UI', sans-serif"
"""The plots' tick numbers: uPlot draws them on its canvas (12 px by default), out of reach of the CSS."""


def plot_axes() -> tuple[Any, Any]:
    """uPlot's x and y axes (``viser.uplot.Axis``) with their numbers at :data:`MIN_TEXT_PX`; the y axis a
    little wider for the larger digits. viser still gives them the look's colours."""
    return ({"font": PLOT_FONT, "labelFont": PLOT_FONT}, {"font": PLOT_FONT, "labelFont": PLOT_FONT, "size": 58})


PLOT_BACKGROUND = {False: "#ffffff", True: "#242424"}
"""A plot's background in the light and the dark look (Mantine's white and dark 7 under viser's plots)."""

PLOT_LINE_CONTRAST = 3.0
"""WCAG 2.1 1.4.11: the least contrast of a graphic needed to read the content (a plot's line)."""


def _luminance(colour: str) -> float:
    """WCAG's relative luminance of an ``#rrggbb`` colour."""
    channels = [int(colour[i : i + 2], 16) / 255.0 for i in (1, 3, 5)]
    r, g, b = (c / 12.92 if c <= 0.04045 else ((c + 0.055) / 1.055) ** 2.4 for c in channels)
    return 0.2126 * r + 0.7152 * g + 0.0722 * b


def contrast(a: str, b: str) -> float:
    """WCAG's contrast ratio of two ``#rrggbb`` colours, 1 to 21."""
    la, lb = _luminance(a), _luminance(b)
    return (max(la, lb) + 0.05) / (min(la, lb) + 0.05)


def plot_colour(colour: str, dark: bool) -> str:
    """A plot line's ``#rrggbb`` colour as the look shows it: unchanged when it has
    :data:`PLOT_LINE_CONTRAST` against :data:`PLOT_BACKGROUND`, otherwise mixed towards black (light look)
    or white (dark look) in steps of 5 % until it has, so the hue stays (the dark look's black becomes a
    grey, the light look's orange a brown)."""
    background, target = PLOT_BACKGROUND[dark], (255 if dark else 0)
    rgb = [int(colour[i : i + 2], 16) for i in (1, 3, 5)]
    for step in range(21):
        mixed = "#" + "".join(f"{round(c + (target - c) * step / 20):02x}" for c in rgb)
        if contrast(mixed, background) >= PLOT_LINE_CONTRAST:
            return mixed
    raise ValueError(f"no mix of {colour} reaches {PLOT_LINE_CONTRAST}:1 on {background}")


def motion_html(text: str) -> str:
    """The motion in words (:meth:`app.scenes.base.Scene.describe`) as a polite live region: a screen
    reader announces each new text when the reader is idle, without taking the focus."""
    # A template of markup alone (not for the translators): the words are the value, translated on the wire.
    return say(_MOTION, text=escaped(text))


_MOTION = '<p class="rbl-motion" aria-live="polite" aria-atomic="true">{text}</p>'


def configure(gui: Any, *, share: bool = False, dark: bool = False) -> Any:
    """Theme a simulation's panel: the large control width, dark or light, viser's share button off
    unless asked for (it would publish the server on a public tunnel), :data:`STYLE` and the accessibility
    patch (:data:`app.panel.access.PATCH`: names, contrast, the 3D view's text); returns the
    style's handle."""
    gui.configure_theme(control_width="large", dark_mode=dark, show_share_button=share)
    return gui.add_html(STYLE + PATCH, order=-1e6)
