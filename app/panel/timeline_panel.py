"""The Timeline folder: the time slider, a jump of a second back or on, Replay; and the clock's Step back.

The slider shows the simulated time while the clock runs (at most ten times a second, as the time
readout) and spans from the earliest instant the scene can show to the furthest reached; dragged, it puts
the body at that instant (:class:`app.serving.timeline.Timeline`). Its value set by the server runs its
callback too (viser calls them for any assignment): that one is not a browser's move and is passed over.
"""

from __future__ import annotations

import math
from collections.abc import Callable
from typing import TYPE_CHECKING, Any

import viser

from app.language.words import mark

if TYPE_CHECKING:  # annotations only: the simulation is above this package
    from app.serving.simulation import Simulation

__all__ = ["BACK", "JUMP", "ON", "REPLAY_SPANS", "SLIDER_STEP", "TIMELINE", "TimelinePanel"]

TIMELINE = mark("Timeline (s)")
"""The time slider's label."""
SLIDER_STEP = 0.01
"""The slider's resolution, s (the time readout's two decimals); the server's time is not rounded to it."""
JUMP = mark("Jump 1 s")
BACK, ON = "−1 s", "+1 s"
"""The jump buttons' group label and buttons (Shift+← and Shift+→ press them)."""
REPLAY_SPANS = ("1 s", "2 s", "5 s", "10 s")
"""The spans Replay offers (the last this many seconds of simulated time); the default is 2 s."""
REPLAY_SPEEDS = ("0.01×", "0.1×", "0.25×", "0.5×")
"""The speeds a replay runs at; the default is 0.1×."""


def seconds_of(choice: str) -> float:
    """The number of a dropdown's choice such as ``"2 s"`` or ``"0.1×"`` (ValueError for anything else)."""
    text = str(choice).removesuffix("×").removesuffix(" s")
    value = float(text)
    if not (math.isfinite(value) and value > 0.0):
        raise ValueError(f"expected a positive number such as '2 s' or '0.1×', got {choice!r}")
    return value


class TimelinePanel:
    """The Timeline folder, made by the shared panel at ``order`` (under the scene's folder).

    Parameters
    ----------
    sim : Simulation
        Its ``timeline`` (seek, jump, start_replay), ``guarded`` and ``notify``.
    gui : viser.GuiApi
        Where they are made.
    order : float
        The folder's place in the panel.
    step_back : viser.GuiButtonHandle
        The Step back button (the clock's, beside Step), which this wires.
    """

    def __init__(self, sim: Simulation, gui: Any, order: float, step_back: viser.GuiButtonHandle) -> None:
        self.sim = sim
        self.step_back_button = step_back
        # Its own folder under the scene's: the Clock folder has no room left above the fold at 1280×800
        # (a scene's main controls must stay above it, tests/browser/test_look.py).
        with gui.add_folder(mark("Timeline"), order=order) as self.folder:
            self._build(sim, gui)

    def _build(self, sim: Simulation, gui: Any) -> None:
        self.showing = False  # the server is setting the slider: not a browser's move
        # The time the slider was last set to, by the server or a browser's drag. A frame drawn at the time a
        # drag asked for does not send it back: the drag's next value may be in the slider already (viser
        # stores it before the callback waits for the lock), and the old one would move the thumb back.
        self.shown = 0.0
        self.slider = gui.add_slider(
            TIMELINE,
            min=0.0,
            max=1.0,
            step=SLIDER_STEP,
            initial_value=0.0,
            hint=mark(
                "The simulated time: drag to put the body at that instant (the clock pauses; Play goes on from there)"
            ),
        )
        self.jump = gui.add_button_group(
            JUMP, options=(BACK, ON), hint=mark("Back or on one second (Shift+← / Shift+→)")
        )
        with gui.add_folder(mark("Replay"), expand_by_default=False):
            self.span = gui.add_dropdown(mark("Replay the last"), options=REPLAY_SPANS, initial_value="2 s")
            self.speed = gui.add_dropdown(mark("Replay at"), options=REPLAY_SPEEDS, initial_value="0.1×")
            self.replay_button = gui.add_button(
                mark("Replay"),
                icon=viser.Icon.PLAYER_TRACK_PREV,
                hint=mark("The last seconds again, slowly; then as before"),
            )
        # A move the clock cannot make (nothing to replay yet, too far ahead) is refused to whoever asked.
        self.slider.on_update(sim.guarded(self._refused_to_sender(self._on_slide)))
        self.jump.on_click(
            sim.guarded(
                self._refused_to_sender(lambda event: sim.timeline.jump(-1.0 if event.target.value == BACK else 1.0))
            )
        )
        self.replay_button.on_click(sim.guarded(self._refused_to_sender(self._on_replay)))
        self.step_back_button.on_click(sim.guarded(self._refused_to_sender(lambda _: sim.timeline.step_back())))

    def _refused_to_sender(self, fn: Callable[[Any], object]) -> Callable[[Any], None]:
        def told(event: Any) -> None:
            try:
                fn(event)
            except ValueError as exc:
                self.sim.notify(mark("Refused"), str(exc), client=getattr(event, "client", None), error=True)

        return told

    def _on_slide(self, event: Any) -> None:
        if self.showing:
            return
        self.shown = float(self.slider.value)
        self.sim.timeline.drag_to(self.shown)

    def _on_replay(self, event: Any) -> None:
        self.sim.timeline.start_replay(seconds_of(self.span.value), seconds_of(self.speed.value))

    def show(self, t: float, earliest: float, reached: float) -> None:
        """The slider at time ``t`` (s), spanning ``earliest`` to the whole second after ``reached``."""
        low = math.floor(earliest / SLIDER_STEP) * SLIDER_STEP
        high = max(float(math.ceil(max(reached, t) + 1e-9)), low + 1.0)
        self.showing = True
        try:
            if self.slider.min != low:
                self.slider.min = low
            if self.slider.max != high:
                self.slider.max = high
            if t != self.shown:
                self.shown = self.slider.value = t
        finally:
            self.showing = False

    def forget(self) -> None:
        """The clock was put back to the start (Reset, a new scene): the next frame sends its time."""
        self.shown = math.nan

    def enable(self, running: bool) -> None:
        """Working, or (a still scene) disabled; the jumps hidden (viser's button groups cannot be disabled)."""
        for handle in (self.slider, self.step_back_button, self.replay_button):
            if handle.disabled == running:
                handle.disabled = not running
        if self.jump.visible != running:
            self.jump.visible = running
        if self.folder.visible != running:  # a still scene has no time to move: the folder goes too
            self.folder.visible = running
