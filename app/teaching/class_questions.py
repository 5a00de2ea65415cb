"""Class questions in presenter mode: a lecture step's question (or the presenter's own) on every
follower's panel, one answer per browser, the live count for the presenters, the reveal for everyone.

More in docs/app-notes.md (``app.teaching.class_questions``).
"""

from __future__ import annotations

import os
import tempfile
import threading
import traceback
from collections.abc import Callable
from pathlib import Path
from typing import TYPE_CHECKING, Any

import viser

from app.contracts import ClientId
from app.guards.callbacks import first_argument, shielded
from app.language.words import mark, say
from app.teaching.lectures import Step
from app.teaching.question_panel import QuestionPanel
from app.teaching.questions import (
    LETTERS,
    MAX_CHOICE,
    MAX_QUESTION,
    Ask,
    Poll,
    VoteRefused,
    held_back,
    true_value,
)
from app.teaching.voters import Voters

if TYPE_CHECKING:  # annotations only: the app and its simulations are above teaching/
    from app.serving.app import App

__all__ = ["ClassQuestions", "parse_choices"]


def parse_choices(text: str, choices: str) -> Ask:
    """The presenter's own question: its text and 2 to 5 choices, one a line (ValueError says what is wrong)."""
    text = text.strip() if isinstance(text, str) else ""
    if not text or len(text) > MAX_QUESTION:
        raise ValueError(say("type a question of 1 to {most} characters", most=MAX_QUESTION))
    lines = [line.strip() for line in (choices if isinstance(choices, str) else "").splitlines() if line.strip()]
    if not 2 <= len(lines) <= len(LETTERS):
        raise ValueError(say("type 2 to {most} choices, one a line (got {got})", most=len(LETTERS), got=len(lines)))
    if any(len(line) > MAX_CHOICE for line in lines):
        raise ValueError(say("a choice has at most {most} characters", most=MAX_CHOICE))
    return Ask(text, tuple(lines))


class ClassQuestions:
    """The class's questions for a presenter-mode :class:`app.serving.app.App`.

    Parameters
    ----------
    app : app.serving.app.App
        Its ``shared`` simulation is the lecture, its ``classroom`` knows the presenters.
    export : str or Path, optional
        A CSV file rewritten with every question's counts whenever a vote closes (``--export-answers``).
    """

    def __init__(self, app: App, export: str | Path | None = None) -> None:
        self.app = app
        if app.classroom is None:
            raise ValueError("class questions are asked in presenter mode: the app has no classroom")
        self.classroom = app.classroom
        self.poll = Poll()
        self.export = None if export is None else Path(export)
        self.voters = app.voters if isinstance(getattr(app, "voters", None), Voters) else Voters(app.server)
        self._panels: dict[Any, QuestionPanel] = {}
        self._identity: dict[Any, str] = {}
        self._lock = threading.RLock()
        self._waiting = False  # the question was asked with the clock paused: Play ends the vote
        self.showing = False  # the panels show the current question (a step without one takes it away)
        app.server.on_client_connect(self._joined)
        app.server.on_client_disconnect(self._left)
        self.classroom.on_present.append(self._promoted)
        app.simulation.following.listeners.append(self.step_shown)

    # ------------------------------------------------------------------ browsers
    def _joined(self, client: viser.ClientHandle) -> None:
        panel = QuestionPanel(
            client,
            on_vote=self._safely(self.vote),
            on_reveal=self._safely(self.reveal),
            on_ask=self._safely(self.ask_from_panel),
            on_save=self._safely(self.save_for),
        )
        with self._lock:
            self._identity[client.client_id] = self.voters.identity(client.client_id)
            self._panels[client.client_id] = panel
            self._show(panel)

    def _left(self, client: viser.ClientHandle) -> None:
        with self._lock:
            self._panels.pop(client.client_id, None)
            self._identity.pop(client.client_id, None)

    def _promoted(self, client: viser.ClientHandle) -> None:
        with self._lock:
            panel = self._panels.get(client.client_id)
            if panel is not None:
                self._show(panel)

    def _presenting(self, client_id: ClientId) -> bool:
        return client_id in self.classroom.presenters

    def _show(self, panel: QuestionPanel) -> None:
        cid = panel.client.client_id
        panel.show(
            self.poll.current if self.showing else None,
            presenter=self._presenting(cid),
            mine=self.poll.answer_of(self._identity.get(cid)),
            count=self.poll.count(),
        )

    def _show_all(self) -> None:
        with self._lock:
            for panel in list(self._panels.values()):
                try:
                    self._show(panel)
                except Exception:  # noqa: BLE001 - a browser that left meanwhile; the others still get it
                    traceback.print_exc()

    def _safely(self, fn: Callable[..., None]) -> Callable[..., None]:
        return shielded(fn, self._tell, client_of=first_argument)

    def _tell(self, client: viser.ClientHandle | None, title: str, body: str) -> None:
        self.app.simulation.notify(title, body, client=client, error=True)

    # ------------------------------------------------------------------ asking and answering
    def step_shown(self, index: int, step: Step) -> None:
        """The lecture shows a step (a :class:`app.teaching.following.Following` listener): ask its question,
        or close the one before."""
        if step.ask is None:  # the question before (and its chart) leaves the panels
            self.poll.close()
            self.showing = False
            self._closed()
            return
        scene = self.app.simulation.scene
        # What states the answer waits for the reveal, on the lecture and on every copy explored from it.
        self.ask(step.ask, f"step {index + 1}", true_value(step.ask, scene))
        self.hold_back(held_back(step.ask, scene))

    def ask(self, ask: Ask, source: str, true: float | None = None) -> None:
        """Put a question to the class (the one before is closed and kept for the CSV)."""
        self.poll.ask(ask, source, true=true)
        self.showing = True
        self._waiting = not self.app.simulation.playing
        self._show_all()
        self.write()

    def ask_from_panel(self, client: viser.ClientHandle, text: str, choices: str) -> None:
        if not self._presenting(client.client_id):
            self._tell(client, mark("Refused"), mark("Only the presenter asks the class."))
            return
        try:
            ask = parse_choices(text, choices)
        except ValueError as exc:
            self._tell(client, mark("Question not asked"), str(exc))
            return
        self.ask(ask, "asked from the panel")

    def vote(self, client: viser.ClientHandle, value: Any) -> None:
        """A browser's answer: refused (with a message to that browser only) or kept, one per voter."""
        cid = client.client_id
        if self._presenting(cid):
            self._tell(client, mark("Refused"), mark("The presenter does not vote: the class does."))
            return
        question = self.poll.current
        if question is not None and question.open and self._waiting and self.app.simulation.playing:
            self.poll.close()  # the demonstration has started: predictions are over
            self._closed()
        with self._lock:
            voter = self._identity.get(cid)
        if voter is None:
            self._tell(client, mark("Refused"), mark("This browser is not following the lecture."))
            return
        try:
            kept = self.poll.vote(voter, value)
        except VoteRefused as exc:
            self._tell(client, mark("Answer refused"), str(exc))
            return
        question = self.poll.current
        count = self.poll.count()
        with self._lock:
            for other, panel in list(self._panels.items()):
                if panel.presenter or self._identity.get(other) == voter:  # the count, or a copy of this page
                    panel.update(question, kept, count)

    def reveal(self, client: viser.ClientHandle) -> None:
        """The presenter's "Show answers": close the vote, put the distribution on every screen."""
        if client is not None and not self._presenting(client.client_id):
            self._tell(client, mark("Refused"), mark("Only the presenter shows the answers."))
            return
        if self.poll.reveal() is None:
            return
        self.app.simulation.following.show_text(caption=True)
        self._closed()

    def _closed(self) -> None:
        self.hold_back(())
        self._show_all()
        self.write()

    def holding(self) -> tuple[str, ...]:
        """The quantities held back now: those the open question asks about (empty once it closes)."""
        question = self.poll.current
        if question is None or not question.open:
            return ()
        return held_back(question.ask, self.app.simulation.scene)

    def hold_back(self, quantities: tuple[str, ...]) -> None:
        """Hold back (or, empty, show again) what states ``quantities`` on the lecture and on every browser's
        own copy of it that shows the same scene."""
        sims = [self.app.simulation]
        sims += self.app.sessions.values()
        name = getattr(self.app.simulation.scene, "name", None)
        for sim in sims:
            if getattr(sim.scene, "name", None) == name or not quantities:
                sim.hold_back(quantities)

    # ------------------------------------------------------------------ the CSV
    def save_for(self, client: viser.ClientHandle) -> None:
        """The presenter's "Save answers (CSV)": the file, downloaded by that browser."""
        if not self._presenting(client.client_id):
            self._tell(client, mark("Refused"), mark("Only the presenter saves the answers."))
            return
        client.send_file_download("answers.csv", self.poll.csv().encode(), save_immediately=True)

    def write(self) -> None:
        """Rewrite ``export`` (if given) with every question's counts, atomically."""
        if self.export is None:
            return
        folder = self.export.resolve().parent
        with tempfile.NamedTemporaryFile("w", dir=folder, delete=False, suffix=".csv", encoding="utf-8") as f:
            f.write(self.poll.csv())
        os.replace(f.name, self.export)
