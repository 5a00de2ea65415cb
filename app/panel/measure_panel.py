"""The Measure folder: the motion's events with their times, a stopwatch on the simulated clock, and the
angle between two drawn directions, read out live.

The events come from the exact solution (:meth:`app.scenes.base.Scene.events`, i.e.
:func:`physics.events.events_between`), not from frames: a half-turn of the flip is at its solved time
whatever the frame rate. The stopwatch reads the simulated clock, so a replay at 0.1× or a scrub changes
what it reads exactly as the clock does; the angle is :func:`physics.rotations.angle_between` of the
directions the scene draws (:meth:`app.scenes.base.Scene.vectors`) and the vertical.
"""

from __future__ import annotations

import math
from typing import TYPE_CHECKING, Any

import numpy as np

from app.language.words import joined, mark, say
from physics.events import HALF_TURN, OVER_THE_TOP, THETA_MAX, THETA_MIN, TURNING_POINT, MotionEvent
from physics.rotations import angle_between

if TYPE_CHECKING:  # annotations only: the simulation is above this package
    from app.serving.simulation import Simulation

__all__ = [
    "DIRECTIONS",
    "EVENTS_SHOWN",
    "EVENT_WINDOW",
    "MeasurePanel",
    "Stopwatch",
    "angle_text",
    "events_markdown",
]

DIRECTIONS = ("L", "ω", mark("symmetry axis"), mark("vertical"))
"""The directions the angle is measured between."""
EVENT_WINDOW = 8.0
"""The events listed are those within this many seconds of now (s), before and after."""
EVENTS_SHOWN = 8
"""Most events listed (the nearest to now)."""
HELD = mark("*The events wait while a class question is open.*")
NO_EVENTS = mark("*No events: this motion has no flip, turning point or swing to time (or it is stepped).*")


KINDS = {
    HALF_TURN: mark("half-turn"),
    THETA_MAX: mark("θ max"),
    THETA_MIN: mark("θ min"),
    TURNING_POINT: mark("turning point"),
    OVER_THE_TOP: mark("over the top"),
}
"""The events' kinds (:mod:`physics.events`) as the panel says them."""


class Stopwatch:
    """A stopwatch on the simulated clock: :meth:`start` and :meth:`stop` at clock times (s), :meth:`reading`
    at any time. Started again after a stop, it adds on; :meth:`reset` sets it to 0 (and stops it)."""

    def __init__(self) -> None:
        self.running = False
        self.kept = 0.0  # s measured before the current run
        self.since = 0.0  # clock time the current run started at, s

    def start(self, t: float) -> None:
        if not self.running:
            self.running, self.since = True, float(t)

    def stop(self, t: float) -> None:
        if self.running:
            self.kept += float(t) - self.since
            self.running = False

    def reset(self) -> None:
        self.running, self.kept, self.since = False, 0.0, 0.0

    def reading(self, t: float) -> float:
        """The time measured, s, at clock time ``t`` (s): negative if the clock was taken back before the start."""
        return self.kept + (float(t) - self.since if self.running else 0.0)


def events_markdown(events: list[MotionEvent], t: float) -> str:
    """The events as a Markdown list, times in s to four decimals, the ones already past marked ✓."""
    if not events:
        return NO_EVENTS
    lines = [mark("**Events** (from the exact solution):")]
    for e in events:
        kind = KINDS.get(e.kind, e.kind)
        past = "✓" if e.time <= t else "·"
        if e.unit == "rad":
            line = say(
                "- {past} {time:.4f} s: {kind} ({angle:.2f}°)",
                past=past,
                time=e.time,
                kind=kind,
                angle=math.degrees(e.value),
            )
        else:
            line = say(
                "- {past} {time:.4f} s: {kind} (ω {omega:+.4g} rad/s)", past=past, time=e.time, kind=kind, omega=e.value
            )
        lines.append(line)
    if len(events) >= 2:
        lines.append(say("Spacing: {spacing:.4f} s", spacing=events[1].time - events[0].time))
    return joined(lines, "\n")


def angle_text(found: dict[str, Any], first: str, second: str) -> str:
    """The angle between two of the named directions, in degrees, or why there is none."""
    vectors = {**found, "vertical": np.array([0.0, 0.0, 1.0])}
    missing = [name for name in (first, second) if name not in vectors]
    if missing:
        return say("— (this scene draws no {direction})", direction=missing[0])
    angle = float(angle_between(vectors[first], vectors[second]))
    if math.isnan(angle):
        return mark("— (a zero vector has no direction)")
    return say("{angle:.3f}", angle=math.degrees(angle))


class MeasurePanel:
    """The Measure folder (made by the shared panel at ``order``)."""

    def __init__(self, sim: Simulation, gui: Any, order: float) -> None:
        self.sim = sim
        self.watch = Stopwatch()
        self.events: list[MotionEvent] = []  # those listed
        with gui.add_folder(mark("Measure"), expand_by_default=False, order=order) as self.folder:
            self.events_text = gui.add_markdown(NO_EVENTS)
            self.stopwatch = gui.add_text(mark("Stopwatch (s)"), initial_value="0.0000", disabled=True)
            self.stopwatch_buttons = gui.add_button_group(
                mark("Stopwatch"),
                options=(mark("Start"), mark("Stop"), mark("Zero")),
                hint=mark("Times the simulated clock"),
            )
            self.first = gui.add_dropdown(mark("Angle from"), options=DIRECTIONS, initial_value="L")
            self.second = gui.add_dropdown(mark("to"), options=DIRECTIONS, initial_value="symmetry axis")
            self.angle = gui.add_text(mark("Angle (°)"), initial_value="—", disabled=True)
        self.stopwatch_buttons.on_click(sim.guarded(self._on_stopwatch))
        self.first.on_update(sim.guarded(lambda _: sim.request_redraw()))
        self.second.on_update(sim.guarded(lambda _: sim.request_redraw()))

    def _on_stopwatch(self, event: Any) -> None:
        t = self.sim.time
        choice = event.target.value
        if choice == "Start":
            self.watch.start(t)
        elif choice == "Stop":
            self.watch.stop(t)
        else:
            self.watch.reset()
        self.show_stopwatch(t)

    def show_stopwatch(self, t: float) -> None:
        text = say("{seconds:.4f}", seconds=self.watch.reading(t))
        if self.stopwatch.value != text:
            self.stopwatch.value = text

    def update(self, t: float, state: dict[str, Any]) -> None:
        """Show what is measured at the clock's time ``t`` (s) and the state drawn there."""
        scene = self.sim.scene
        if scene is None or scene.static:
            return
        self.show_stopwatch(t)
        angle = angle_text(scene.vectors(state), str(self.first.value), str(self.second.value))
        if self.angle.value != angle:
            self.angle.value = angle
        if scene.held:  # a class question is open: the events' spacing would give periods away
            self.events, text = [], HELD
        else:
            low = max(float(scene.earliest()), t - EVENT_WINDOW)
            events = scene.events(low, max(low, t + EVENT_WINDOW))
            near = sorted(events, key=lambda e: abs(e.time - t))[:EVENTS_SHOWN]
            self.events = sorted(near, key=lambda e: e.time)
            text = events_markdown(self.events, t)
        if self.events_text.content != text:
            self.events_text.content = text

    def event_words(self, t: float) -> str:
        """The last event before the clock's time ``t`` (s) in words, for the motion's description (a screen
        reader announces it); "" when none is listed."""
        past = [e for e in self.events if e.time <= t]
        if not past:
            return ""
        return say(
            " Last event: {kind} at {time:.3f} s.", kind=KINDS.get(past[-1].kind, past[-1].kind), time=past[-1].time
        )
