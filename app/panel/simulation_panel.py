"""The panel every scene shares: the title, the scene picker, the clock, the state text, Export, the legend.

Its buttons call the simulation it is built for; the scene's own folder comes between the clock and the
rest (:data:`LAST_ORDER`), so a scene's controls stay above the fold at 1280×800.
"""

from __future__ import annotations

from typing import TYPE_CHECKING, Any

import viser

from app.guards.handles import uuid_of
from app.language.words import mark
from app.panel import look
from app.panel.access import keys_markdown
from app.panel.measure_panel import MeasurePanel
from app.panel.projector import LEAVE
from app.panel.speed import POSITION_MARKS, POSITION_STEP, speed_at, speed_label
from app.panel.timeline_panel import TimelinePanel

if TYPE_CHECKING:  # annotations only: the simulation is above this package
    from app.serving.simulation import Simulation

__all__ = ["EXPORT_ORDER", "LAST_ORDER", "TIMELINE_ORDER", "SimulationPanel"]

PROJECTOR_HINT = mark("Projector mode: the panel a slim bar, the caption and the key plot large over the view")

LAST_ORDER = 1e6
"""viser's panel order of what comes after the scene's folder (legend, state, export)."""
TIMELINE_ORDER = LAST_ORDER - 3
"""The Timeline folder's place: right under the scene's folder, above the projector's switch."""
EXPORT_ORDER = LAST_ORDER + 2
"""The Export folder's place (:mod:`app.recording.export_folder`): after the State folder, before Keyboard."""


class SimulationPanel:
    """The shared panel of one simulation.

    Parameters
    ----------
    sim : Simulation
        What the controls drive (``guarded``, ``set_playing``, ``step``, ``timeline``, ``restart``, ``set_speed``,
        ``state_text``, ``open_state``, ``notify``, ``pick``).
    titles : dict
        Scene title -> scene name, in picker order.
    share, dark : bool
        viser's share button; the dark look (:mod:`app.panel.look`).
    """

    def __init__(
        self,
        sim: Simulation,
        titles: dict[str, str],
        *,
        share: bool,
        dark: bool,
    ) -> None:
        self.sim = sim
        gui = sim.server.gui
        self.titles = titles
        self.choosing = False  # the picker is being set to the scene built: not a choice of a browser's
        style = look.configure(gui, share=share, dark=dark)
        title = gui.add_markdown("**Rigid Body Lab**")
        self.scene_picker = gui.add_dropdown(mark("Scene"), options=tuple(titles), initial_value=next(iter(titles)))
        self.scene_picker.on_update(sim.guarded(self._on_pick))
        # The motion in words (show_words): after the scene's folder, so its controls stay above the fold.
        self.words = gui.add_html(look.motion_html(""), order=LAST_ORDER - 1)
        # The lecture hall's switch (app.panel.projector), under the scene's folder: the scene's own controls
        # and the clock stay above the fold at 1280×800.
        self.projector_button = gui.add_button(
            mark("Projector"), icon=viser.Icon.PRESENTATION, hint=PROJECTOR_HINT, order=LAST_ORDER - 2
        )
        self.said = ""
        with gui.add_folder(mark("Clock")) as clock:
            self.play_button = gui.add_button(mark("Pause"), icon=viser.Icon.PLAYER_PAUSE)
            self.step_button = gui.add_button(mark("Step"), icon=viser.Icon.PLAYER_TRACK_NEXT)
            self.step_back_button = gui.add_button(
                mark("Step back"),
                icon=viser.Icon.PLAYER_TRACK_PREV,
                hint=mark("Back one step of the clock (pauses); the ← key"),
            )
            self.reset_button = gui.add_button(mark("Reset"), icon=viser.Icon.REFRESH)
            # Logarithmic (app.panel.speed): the value is a position in [−1, 1], the label shows the speed.
            self.speed_slider = gui.add_slider(
                speed_label(1.0), min=-1.0, max=1.0, step=POSITION_STEP, initial_value=0.0, marks=POSITION_MARKS
            )
            self.time_text = gui.add_text(mark("Time (s)"), initial_value="0.00", disabled=True)
        self.play_button.on_click(sim.guarded(lambda _: sim.set_playing(not sim.playing)))
        self.step_button.on_click(sim.guarded(lambda _: sim.step()))
        self.reset_button.on_click(sim.guarded(lambda _: sim.restart()))
        self.speed_slider.on_update(sim.guarded(lambda _: sim.set_speed(speed_at(self.speed_slider.value))))
        style.content = (
            look.STYLE
            + look.PATCH
            + look.hide_number_box(uuid_of(self.speed_slider))
            + look.side_by_side(uuid_of(self.step_button), uuid_of(self.step_back_button))
        )
        # The time slider, the jumps and Replay (it wires Step back, beside Step above).
        self.timeline = TimelinePanel(sim, gui, order=TIMELINE_ORDER, step_back=self.step_back_button)
        self.measure = MeasurePanel(sim, gui, order=LAST_ORDER + 0.5)  # events, stopwatch, angle
        with gui.add_folder(mark("State"), expand_by_default=False, order=LAST_ORDER + 1) as state:
            self.state_box = gui.add_text(mark("State text"), initial_value="", hint=mark("Copy state writes it here"))
            self.copy_state_button = gui.add_button(mark("Copy state"), icon=viser.Icon.COPY)
            self.open_state_button = gui.add_button(mark("Open state"), icon=viser.Icon.PLAYER_PLAY)
        self.copy_state_button.on_click(sim.guarded(self.on_copy_state))
        self.open_state_button.on_click(sim.guarded(self.on_open_state))
        with gui.add_folder(mark("Keyboard"), expand_by_default=False, order=LAST_ORDER + 3) as keyboard:
            gui.add_markdown(keys_markdown())
        self.status = gui.add_markdown("")
        self.legend = gui.add_html("", order=LAST_ORDER)
        self.handles: list[Any] = [style, title, self.scene_picker, self.words, self.projector_button, clock, state]
        self.handles += [keyboard, self.measure.folder, self.timeline.folder]
        self.handles += [self.status, self.legend]

    def show_playing(self, playing: bool) -> None:
        """The play button says what a click does."""
        self.play_button.label = mark("Pause") if playing else mark("Play")
        self.play_button.icon = viser.Icon.PLAYER_PAUSE if playing else viser.Icon.PLAYER_PLAY

    def show_projector(self, on: bool) -> None:
        """The projector button says what a click does."""
        self.projector_button.label = LEAVE if on else mark("Projector")
        self.projector_button.icon = viser.Icon.PRESENTATION_OFF if on else viser.Icon.PRESENTATION

    def show_clock(self, running: bool) -> None:
        """The clock's buttons and speed work, or (a still scene, nothing moves) are disabled."""
        for handle in (self.play_button, self.step_button, self.reset_button, self.speed_slider):
            if handle.disabled == running:
                handle.disabled = not running
        self.timeline.enable(running)
        if self.measure.folder.visible != running:  # nothing moves in a still scene: nothing to measure
            self.measure.folder.visible = running

    def show_words(self, text: str) -> None:
        """Put the motion in words in the live region; an unchanged text is not sent (nor announced)."""
        if text != self.said:
            self.said = text
            self.words.content = look.motion_html(text)

    def show_scene(self, title: str) -> None:
        """The picker names the scene built (without taking it for a browser's choice)."""
        self.choosing = True
        try:
            self.scene_picker.value = title  # type: ignore[misc]  # viser 1.1.1 types this setter read-only
        finally:
            self.choosing = False

    def remove(self) -> None:
        """Take the panel away (its browser may have gone already)."""
        for handle in self.handles:
            try:
                handle.remove()
            except Exception:  # noqa: BLE001 - its browser may have gone already
                pass
        self.handles = []

    def _on_pick(self, event: Any) -> None:
        if not self.choosing:
            self.sim.pick(self.titles[self.scene_picker.value], client=getattr(event, "client", None))

    def on_copy_state(self, event: Any) -> None:
        """Copy state: the state text, with the camera of the browser that clicked, in the text box."""
        client = getattr(event, "client", None)
        try:
            # viser's text props re-declare ``value``: mypy then misses the handle's setter.
            self.state_box.value = self.sim.state_text(client)  # type: ignore[misc]
        except ValueError as exc:
            self.sim.notify(mark("No state text"), str(exc), client=client, error=True)

    def on_open_state(self, event: Any) -> None:
        """Open state: go to the state the text box holds, or tell the browser why not."""
        client = getattr(event, "client", None)
        try:
            self.sim.open_state(self.state_box.value)
        except ValueError as exc:
            self.sim.notify(mark("State refused"), str(exc), client=client, error=True)
