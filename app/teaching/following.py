"""Following a lecture: its steps in the panel with Previous and Next, each step put on the simulation.

A step sets a state or a scene, then its dropdown choices, preset, slider values and camera, the time it
opens at and a replay of the seconds before; a step with
``seconds`` moves on by itself; a step with a question waits, paused at t = 0, and tells its
``listeners`` (:mod:`app.teaching.class_questions`). The simulation followed is any object with the methods used here
(:class:`app.serving.simulation.Simulation`).
"""

from __future__ import annotations

import time
from collections.abc import Callable
from pathlib import Path
from typing import TYPE_CHECKING, Any

import viser

from app.guards.text import lecturer_markdown
from app.language.words import joined, mark, say, transformed
from app.teaching.lectures import Lecture, Step

if TYPE_CHECKING:  # annotations only: the simulation is above this package
    from app.serving.simulation import Simulation

__all__ = ["Following", "apply_step"]


class Following:
    """The lecture a simulation follows, its step and when that step began (None: no lecture)."""

    def __init__(self, sim: Simulation) -> None:
        self.sim = sim
        self.lecture: Lecture | None = None
        self.step_index = 0
        self.step_started = 0.0
        self.text: Any = None  # the lecture's markdown in the panel, once a lecture is loaded
        self.folder: Any = None
        self.listeners: list[Callable[[int, Step], None]] = []  # told of every step shown (index, step)
        self.caption_shown = True  # a question step's caption waits for the reveal when someone listens

    def load(self, lecture: Lecture, *, check: bool = True) -> None:
        """Follow ``lecture`` from its first step; with ``check`` every step is applied once first, so that
        what only a scene can check (a preset's name, a slider's range) is checked before it starts.

        Raises
        ------
        ValueError
            Naming the step (1-based) and what was wrong with it; the simulation is left at its first scene.
        """
        sim = self.sim
        with sim.lock:
            if check:
                for k, step in enumerate(lecture.steps, start=1):
                    try:
                        apply_step(sim, step)
                    except ValueError as exc:
                        raise ValueError(f"{Path(lecture.source).name or lecture.title}, step {k}: {exc}") from None
            self.lecture = lecture
            if self.folder is None:
                gui = sim.server.gui
                with gui.add_folder(mark("Lecture"), order=-1.0) as folder:
                    self.text = gui.add_markdown("")
                    previous = gui.add_button(mark("Previous"), icon=viser.Icon.CHEVRON_LEFT)
                    following = gui.add_button(mark("Next"), icon=viser.Icon.CHEVRON_RIGHT)
                previous.on_click(sim.guarded(lambda _: self.go_to(self.step_index - 1)))
                following.on_click(sim.guarded(lambda _: self.go_to(self.step_index + 1)))
                self.folder = folder
            self.go_to(0)

    def go_to(self, index: int) -> None:
        """Show step ``index`` (0-based, clamped to the lecture)."""
        lecture, sim = self.lecture, self.sim
        if lecture is None:
            return
        with sim.lock:
            index = min(max(index, 0), len(lecture.steps) - 1)
            step = lecture.steps[index]
            self.step_index = index
            self.step_started = time.monotonic()
            try:
                apply_step(sim, step)
            except ValueError as exc:  # checked when loaded; a body handed over since may refuse it
                sim.notify(say("Step {number} could not be shown", number=index + 1), str(exc), error=True)
            if step.ask is not None:  # predict, then watch: the demonstration waits for the answers
                sim.set_playing(False)
                sim.restart()
            self.caption_shown = step.ask is None or not self.listeners
            self.show_text()
            for listener in list(self.listeners):
                listener(index, step)

    def show_text(self, caption: bool | None = None) -> None:
        """The step's text in the panel: its caption, or while a question waits for the class its question."""
        lecture = self.lecture
        if lecture is None:
            return
        if caption is not None:
            self.caption_shown = caption
        head = say(
            "**{title}** — step {number} of {count}",
            title=lecture.title,
            number=self.step_index + 1,
            count=len(lecture.steps),
        )
        body = transformed(self.step_text(), str.rstrip)
        text = say("{head}\n\n{body}", head=head, body=body) if body.strip() else head
        # Sanitized as a whole, still translatable: a reader of German gets the German, sanitized alike.
        self.text.content = transformed(text, lecturer_markdown)
        self.sim.request_redraw()  # projector mode shows the step's text too (the next frame)

    def step_text(self) -> str:
        """The step's text as the class may see it now (the lecturer's Markdown, not yet sanitised): its
        caption, or while a question waits for the class its question alone; "" without a lecture."""
        lecture = self.lecture
        if lecture is None:
            return ""
        step = lecture.steps[self.step_index]
        if step.ask is not None and not self.caption_shown:
            return say(
                "**Question.** {question}\n\n*Answer in your panel; the demonstration follows.*", question=step.ask.text
            )
        if step.ask is not None and not self.listeners:  # nobody collects answers: ask it aloud
            lines = [say("{letter}. {choice}", letter=chr(65 + k), choice=c) for k, c in enumerate(step.ask.choices)]
            rest = joined([part for part in (joined(lines, "\n"), step.caption) if part], "\n\n")
            if not rest:
                return say("**Question.** {question}", question=step.ask.text)
            return say("**Question.** {question}\n\n{rest}", question=step.ask.text, rest=rest)
        return step.caption

    def advance_if_due(self) -> None:
        """Go to the next step when the current one has ``seconds`` and they have passed (the last stays)."""
        lecture = self.lecture
        if lecture is None or self.step_index + 1 >= len(lecture.steps):
            return
        seconds = lecture.steps[self.step_index].seconds
        if seconds is not None and time.monotonic() - self.step_started >= seconds:
            self.go_to(self.step_index + 1)


def apply_step(sim: Simulation, step: Step) -> None:
    """Put ``sim`` at a step: its state or its scene from the defaults, then its dropdown choices, preset,
    values, camera (ValueError naming the key and what was refused)."""
    if step.state is not None:
        sim.open_state(step.state)
        if step.scene is not None and sim.scene is not None and sim.scene.name != step.scene:
            raise ValueError(f"scene: the state is of {sim.scene.name!r}, the step says {step.scene!r}")
    else:
        assert step.scene is not None  # read_lecture: a step has a scene or a state
        sim.switch_scene(step.scene)
    scene = sim.scene
    assert scene is not None
    if step.ask is not None:  # what the question asks about must be something the scene can hold back
        declared = sorted(a.quantity for a in scene.answers)
        unknown = [q for q in step.ask.about if q not in declared]
        if unknown:
            raise ValueError(f"about: {scene.name} declares no answer {unknown[0]!r}; it declares {declared or 'none'}")
    inputs = sim.scene_inputs
    for label, choice in step.choices.items():  # a dropdown (the body, the axis) before the sliders
        handle = next((h for h in inputs if str(h.label) == label and hasattr(h, "options")), None)
        if handle is None:
            names = [str(h.label) for h in inputs if hasattr(h, "options")]
            raise ValueError(f"choices.{label}: {scene.name} has no dropdown {label!r}; its dropdowns are {names}")
        if choice not in handle.options:
            raise ValueError(f"choices.{label}: no choice {choice!r}; the choices are {list(handle.options)}")
        handle.value = choice  # runs the dropdown's callback now: the scene adopts it or snaps back
        if handle.value != choice:
            why = sim.messages[-1][1] if sim.messages else "the scene refused it"
            raise ValueError(f"choices.{label}: {choice!r} was refused: {why}")
    if step.preset is not None:
        presets = scene.presets
        names = list(presets.presets) if presets is not None else []
        if presets is None or presets.resolve(step.preset) is None:
            raise ValueError(f"preset: {scene.name} has no preset {step.preset!r}; its presets are {names}")
        if not presets.choose(step.preset):
            raise ValueError(f"preset {step.preset!r} was refused: {presets.panel.last_refusal}")
    if step.values:
        params = scene.params
        if params is None:
            raise ValueError(f"values: {scene.name} has no sliders")
        for key, value in step.values.items():
            try:
                params.checked_number(key, value)
            except ValueError as exc:
                raise ValueError(f"values.{key}: {exc}") from None
        if not params.offer(step.values):
            raise ValueError(f"values were refused: {params.last_refusal}")
    if step.camera is not None:
        sim.set_camera(step.camera["position"], step.camera["look_at"])
    if step.time is not None:  # the step opens paused at this instant (the timeline)
        sim.timeline.seek(step.time)
    if step.replay is not None:  # then shows the last seconds again at 0.1×
        sim.timeline.start_replay(step.replay)
