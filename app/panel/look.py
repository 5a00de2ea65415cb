"""The panel's look: readable from the back of a lecture hall, light or dark.

viser's ``configure_theme`` has no font size, but its Html element renders raw HTML (viser's
``client/src/components/Html.tsx``), so one ``<style>`` block, added first to the panel, restyles it:
every text at least :data:`MIN_TEXT_PX` pixels, labels in full contrast rather than Mantine's dimmed grey.
"""

from __future__ import annotations

from typing import Any

__all__ = ["MIN_TEXT_PX", "STYLE", "configure", "hide_number_box"]

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


def configure(gui: Any, *, share: bool = False, dark: bool = False) -> Any:
    """Theme a simulation's panel: the large control width, dark or light, viser's share button off
    unless asked for (it would publish the server on a public tunnel), and :data:`STYLE`; returns the
    style's handle."""
    gui.configure_theme(control_width="large", dark_mode=dark, show_share_button=share)
    return gui.add_html(STYLE, order=-1e6)
