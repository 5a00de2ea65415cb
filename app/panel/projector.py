"""Projector mode: the panel a slim bar, the step's caption large across the top of the view, the scene's key
plot large at its bottom right, the body framed in what they leave free (:func:`projector_region`).

Laid out for a lecture hall's 1280×800 projector (CSS px); the caption and the plot are viser floating panels
(``gui.add_panel``) placed from the view's edges, the control panel is viser's ``main_panel`` minimised to
its title bar. Made on the simulation's own GUI: the server's in shared and presenter mode (every follower
sees the presenter's switch), a browser's own in a private session.
"""

from __future__ import annotations

from collections.abc import Callable
from typing import Any

from app.guards.text import lecturer_markdown
from app.language.words import mark, transformed
from app.panel.look import MIN_TEXT_PX

__all__ = [
    "CAPTION_FONT_PX",
    "LEAVE",
    "CAPTION_HEIGHT_PX",
    "MARGIN_PX",
    "PANEL_WIDTH_PX",
    "PLOT_HEIGHT_PX",
    "PLOT_WIDTH_PX",
    "SLIM_PX",
    "Projector",
    "projector_region",
]

LEAVE = mark("Leave projector mode")
"""The last button of the caption's row (and the panel's projector button while on)."""
SLIM_PX = 200.0
"""Width of the control panel as a slim bar (minimised to its title bar at the top right), CSS px."""
PANEL_WIDTH_PX = 384.0
"""The control panel's width when not a bar: viser's "large" control width (24 em of 16 px)."""
MARGIN_PX = 12.0
"""Gap between the projector's panels and the view's edges, CSS px."""
CAPTION_FONT_PX = 28
"""The caption's text size, CSS px: read from the back of a lecture hall (at least 28)."""
CAPTION_HEIGHT_PX = 262.0
"""Height of the caption's panel: a lecture step's caption (200 to 400 characters) at
:data:`CAPTION_FONT_PX` is five or six lines across the view, and the row of buttons under it."""
PLOT_WIDTH_PX = 560.0
"""Width of the key plot's panel, CSS px (44 % of a 1280 px view)."""
PLOT_HEIGHT_PX = 400.0
"""Height of the key plot's panel, CSS px."""
PLOT_FONT = f"{MIN_TEXT_PX + 6}px system-ui, -apple-system, 'Segoe UI', sans-serif"
"""The large plot's tick numbers and axis labels (uPlot draws them on its canvas)."""

STYLE = f"""<style>
div.mantine-Paper-root:has(.rbl-projector-caption) [role=tablist],
div.mantine-Paper-root:has(.rbl-projector-plot) [role=tablist] {{ display: none !important; }}
div.mantine-Paper-root:has(.rbl-projector-caption) {{
  max-width: calc(100vw - {3 * MARGIN_PX + SLIM_PX:g}px) !important; }}
div.mantine-Paper-root:has(.rbl-projector-caption)
  .mantine-Flex-root:has(> div > p > label[for]):has(> div > .mantine-Flex-root > button:disabled) {{
  display: none !important; }}
div.mantine-Paper-root:has(.rbl-projector-caption) :is(p, li, strong, em, code, a) {{
  font-size: {CAPTION_FONT_PX}px !important; line-height: 1.25 !important; }}
div.mantine-Paper-root:has(.rbl-projector-caption) :is(label, button, button *) {{
  font-size: {MIN_TEXT_PX + 4}px !important; }}
div.mantine-Paper-root:has(.rbl-projector-plot) .u-title {{ font-size: {CAPTION_FONT_PX - 6}px !important; }}
div.mantine-Paper-root:has(.rbl-projector-plot) .u-legend, div.mantine-Paper-root:has(.rbl-projector-plot) .u-legend * {{
  font-size: {MIN_TEXT_PX + 6}px !important; }}
</style>"""
"""The caption's text and the plot's title and legend at projector size, their panels' one-tab headers
hidden; the caption's panel no wider than the view left of the slim bar (it is placed for 1280 px: on a
1024 px projector it hid the bar and cut off its row's last button), and its row of buttons not drawn where
they are disabled (a follower's page: the presenter drives the lecture). Scoped to the floating panel that
holds the marker (``:has``), so the control panel keeps its own sizes; ``div`` makes it outrank
:data:`app.panel.look.STYLE`'s 14 px rules."""


def projector_region(width: float, height: float, plot: bool) -> tuple[float, float, float, float]:
    """The part of a ``width`` × ``height`` px view that projector mode leaves free for the body: (left, top,
    right, bottom), px. Below the caption's panel; left of the key plot's panel when the scene has one
    (``plot``), otherwise the whole width (the slim bar sits in the caption's band). At least 35 % of the
    width: a 1024 px view keeps its 440 px left of the plot (half of it put the racket's handle under it)."""
    top = min(2.0 * MARGIN_PX + CAPTION_HEIGHT_PX, 0.4 * height)
    right = width - (PLOT_WIDTH_PX + 2.0 * MARGIN_PX) if plot else width
    return (0.0, top, max(right, 0.35 * width), height)


def _large_axes(axes: Any) -> tuple[Any, ...]:
    """A plot's axes (``viser.uplot.Axis``) with their numbers and labels at :data:`PLOT_FONT`."""
    out = []
    axis: Any
    for axis in axes or ({}, {}):
        large = dict(axis)
        large.update(font=PLOT_FONT, labelFont=PLOT_FONT)
        if "size" in large:
            large["size"] = int(large["size"] * 1.4)
        out.append(large)
    return tuple(out)


class Projector:
    """Projector mode of one simulation's GUI.

    Parameters
    ----------
    gui : viser GuiApi
        The simulation's GUI (``server.gui`` or a browser's ``client.gui``).
    press : callable(event)
        Runs a click on the caption's row of buttons (the event's ``target.value`` is the button's name:
        "Previous", "Next", "Play", "Pause", "Reset" or :data:`LEAVE`). The minimised panel's own buttons
        are not on the page, so the row is where the clicker's and the keyboard's keys find theirs
        (:data:`app.panel.access.KEYS`) and where projector mode is left.
    """

    def __init__(self, gui: Any, press: Callable[[Any], None]) -> None:
        self.gui = gui
        self._press = press
        self.row: Any = None  # the caption's row of buttons, while on
        self._options: tuple[str, ...] = ()
        self.on = False
        self._caption_panel: Any = None
        self.caption: Any = None  # the caption's Markdown element, while on
        self._caption_text: str | None = None
        self._plot_panel: Any = None
        self.plot: Any = None  # the large copy of the scene's key plot, while on and shown
        self._source: Any = None  # the scene's plot it copies
        self._sent: dict[str, Any] = {}  # what of the source was last copied (data, scales, title)

    def show(self, on: bool) -> None:
        """Switch projector mode on (the panel a bar, the caption's and the plot's panels made) or off
        (the panel back to its width, theirs removed). What they show comes with :meth:`sync`."""
        main = self.gui.main_panel
        if on and not self.on:
            main.set_width(SLIM_PX)
            main.minimize()
            self._caption_panel = self.gui.add_panel(order=-100.0)
            with self._caption_panel.add_tab(mark("Caption")):
                self.gui.add_html(STYLE + '<span class="rbl-projector-caption"></span>')
                self.caption = self.gui.add_markdown("")
                self._options = (LEAVE,)
                self.row = self.gui.add_button_group(mark("Projector"), options=self._options)
            self.row.on_click(self._press)
            self._caption_panel.float(
                x=MARGIN_PX,
                y=MARGIN_PX,
                width=max(1280.0 - 3.0 * MARGIN_PX - SLIM_PX, 1.0),
                height=CAPTION_HEIGHT_PX,
            )
            self._caption_text = ""
        elif not on and self.on:
            self._drop_plot()
            self._drop_caption()
            self.give_panel_back()
        self.on = on

    def give_panel_back(self) -> None:
        """The control panel at its width and open, whatever this GUI's projector mode (an explorer's own
        copy starts so while the lecture it leaves is in projector mode)."""
        main = self.gui.main_panel
        main.set_width(PANEL_WIDTH_PX)
        main.expand()

    def sync(self, caption: str, plot: Any, buttons: tuple[str, ...] = ()) -> None:
        """Show ``caption`` (the lecturer's Markdown, sanitised here), the row's ``buttons`` (then
        :data:`LEAVE`) and a large copy of ``plot`` (the scene's key plot, a viser uPlot handle; None or
        hidden: none shown), sending only what changed."""
        if not self.on:
            return
        options = (*buttons, LEAVE)
        if options != self._options and self.row is not None:
            self._options = options
            self.row.options = options
        if caption != self._caption_text and self.caption is not None:
            self._caption_text = caption
            self.caption.content = transformed(caption, lecturer_markdown)  # still translatable
        if plot is None or not plot.visible:
            self._drop_plot()
            return
        if plot is not self._source:
            self._drop_plot()
            self._make_plot(plot)
            return
        for name in ("data", "scales", "title", "series"):
            value = getattr(plot, name)
            if value is not self._sent.get(name):
                self._sent[name] = value
                setattr(self.plot, name, value)

    def _make_plot(self, plot: Any) -> None:
        self._plot_panel = self.gui.add_panel(order=-99.0)
        with self._plot_panel.add_tab(mark("Plot")):
            self.gui.add_html('<span class="rbl-projector-plot"></span>')
            self.plot = self.gui.add_uplot(
                data=plot.data,
                series=plot.series,
                mode=plot.mode,
                title=plot.title,
                bands=plot.bands,
                scales=plot.scales,
                axes=_large_axes(plot.axes),
                legend=plot.legend,
                height=int(PLOT_HEIGHT_PX - 100.0),  # the panel's drag bar, the plot's title and legend
                padding=(22, 22, 4, 4),  # room above for the top tick's number, which uPlot centres on it
            )
        self._plot_panel.float(x=-MARGIN_PX, y=-MARGIN_PX, width=PLOT_WIDTH_PX, height=PLOT_HEIGHT_PX)
        self._source = plot
        self._sent = {name: getattr(plot, name) for name in ("data", "scales", "title", "series")}

    def _drop_plot(self) -> None:
        _remove(self._plot_panel)
        self._plot_panel = self.plot = self._source = None
        self._sent = {}

    def remove(self) -> None:
        """Take projector mode's panels away and give the panel its width (the simulation is closed)."""
        try:
            self.show(False)
        except Exception:  # noqa: BLE001 - its browser may have gone already
            self._drop_plot()
            self._drop_caption()
            self.on = False

    def _drop_caption(self) -> None:
        _remove(self._caption_panel)
        self._caption_panel = self.caption = self._caption_text = self.row = None
        self._options = ()


def _remove(panel: Any) -> None:
    """Remove a floating panel if there is one (its browser may have gone already)."""
    if panel is not None:
        try:
            panel.remove()
        except Exception:  # noqa: BLE001 - its browser may have gone already
            pass
