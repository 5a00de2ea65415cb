"""Class questions: a question with 2 to 5 choices or a number range, one answer per browser, the count,
the reveal and the CSV of every question asked.

Nothing here knows viser: :mod:`app.teaching.class_questions` puts a :class:`Poll` on the browsers' panels.
More in docs/app-notes.md (``app.teaching.questions``).
"""

from __future__ import annotations

import csv
import io
import math
import re
import threading
import time
from collections.abc import Callable, Hashable
from dataclasses import dataclass, field, replace
from datetime import UTC, datetime
from typing import Any

from app.guards.text import csv_row
from app.language.words import say
from app.scenes.base import Scene

__all__ = [
    "BINS",
    "LETTERS",
    "MAX_QUESTION",
    "SPOILERS",
    "TRUTHS",
    "Ask",
    "Poll",
    "Question",
    "VoteRefused",
    "check_ask",
    "held_back",
    "histogram",
    "show_spoilers",
    "true_value",
]

LETTERS = "ABCDE"
"""The letters of a question's choices, in order (at most five choices)."""

MAX_QUESTION = 300
"""Longest question text, characters."""

MAX_CHOICE = 120
"""Longest text of one choice, characters."""

BINS = 10
"""Bars of a number question's histogram (over its range)."""


def _truth(quantity: str) -> Callable[[Scene], float]:
    """The scene's own true value of ``quantity`` (:meth:`app.scenes.base.Scene.truth`)."""
    return lambda scene: scene.truth(quantity)


TRUTHS: dict[str, tuple[str, str, Callable[[Scene], float]]] = {
    "precession_rate": ("heavy_top", "rad/s", _truth("precession_rate")),
    "centre_of_percussion": ("pendulum", "m", _truth("centre_of_percussion")),
}
"""A number question's true value from the physics API: name -> (scene, unit, value of the scene shown)."""

SPOILERS: dict[str, tuple[str, ...]] = {"centre_of_percussion": ("cop_marker", "cop_label")}
"""The pendulum's nodes that show the centre of percussion (kept for scripts that read it): what a scene
holds back while the class answers is its own declaration, :attr:`app.scenes.base.Scene.answers`."""


class VoteRefused(ValueError):
    """An answer was refused; the message says why, for the browser that sent it."""


@dataclass(frozen=True)
class Ask:
    """What a lecture step (or the presenter's panel) asks: choices, or a number in a range.

    Attributes
    ----------
    text : str
        The question.
    choices : tuple of str
        2 to 5 choices (empty for a number question).
    answer : int or float or None
        The right choice (1-based) or the true number, revealed with the answers.
    unit : str
        A number question's unit (SI, e.g. "rad/s").
    range : tuple of float or None
        A number question's accepted answers ``(low, high)``, in ``unit``.
    truth : str or None
        A number question's true value from the physics API (a key of :data:`TRUTHS`).
    about : tuple of str
        The quantities of the step's scene the question asks about (its ``Answer`` declarations): held
        back on every screen while the question is open. A ``truth`` is always among them.
    """

    text: str
    choices: tuple[str, ...] = ()
    answer: int | float | None = None
    unit: str = ""
    range: tuple[float, float] | None = None
    truth: str | None = None
    about: tuple[str, ...] = ()

    @property
    def numeric(self) -> bool:
        return self.range is not None

    @property
    def holds(self) -> tuple[str, ...]:
        """The quantities held back while the question is open: ``about``, and the ``truth`` asked for."""
        extra = (self.truth,) if self.truth is not None and self.truth not in self.about else ()
        return self.about + extra


def _finite(value: Any) -> bool:
    return not isinstance(value, bool) and isinstance(value, (int, float)) and math.isfinite(value)


def check_ask(raw: dict[str, Any], scene: str | None = None) -> Ask:
    """The :class:`Ask` of a lecture step's question keys (``question``, ``choices``, ``answer``, ``unit``,
    ``range``, ``truth``, ``about``), checked.

    Parameters
    ----------
    raw : dict
        The step's keys (those that are not a question's are ignored).
    scene : str, optional
        The step's scene: a ``truth`` belongs to one scene.

    Raises
    ------
    ValueError
        Naming the key, what is expected and what came.
    """
    text = raw.get("question")
    if not isinstance(text, str) or not text.strip() or len(text) > MAX_QUESTION:
        raise ValueError(f"question: a text of 1 to {MAX_QUESTION} characters, got {str(text)[:40]!r}")
    choices = raw.get("choices")
    about = _about(raw.get("about", []))
    numeric = "range" in raw or "unit" in raw or "truth" in raw
    if numeric:
        if isinstance(choices, list):
            raise ValueError("choices: a number question (range, unit, truth) has no list of choices")
        return replace(_number_ask(text.strip(), raw, scene), about=about)
    if not isinstance(choices, list) or not 2 <= len(choices) <= len(LETTERS):
        raise ValueError(f"choices: a list of 2 to {len(LETTERS)} texts for a question, got {choices!r}")
    for k, choice in enumerate(choices, start=1):
        if not isinstance(choice, str) or not choice.strip() or len(choice) > MAX_CHOICE:
            raise ValueError(f"choices[{k}]: a text of 1 to {MAX_CHOICE} characters, got {choice!r}")
    answer = raw.get("answer")
    if answer is not None and (
        isinstance(answer, bool) or not isinstance(answer, int) or not 1 <= answer <= len(choices)
    ):
        raise ValueError(f"answer: the number of the right choice, 1 to {len(choices)}, got {answer!r}")
    return Ask(text.strip(), tuple(c.strip() for c in choices), answer, about=about)


def _about(raw: Any) -> tuple[str, ...]:
    """A step's ``about``: one quantity's name or a list of them (the scene checks them when it is built)."""
    names = [raw] if isinstance(raw, str) else raw
    if not isinstance(names, list) or len(names) > 8 or not all(isinstance(n, str) and 0 < len(n) <= 40 for n in names):
        raise ValueError(
            f"about: a quantity of the scene, or a list of them (names of 1 to 40 characters), got {raw!r}"
        )
    return tuple(names)


def _number_ask(text: str, raw: dict[str, Any], scene: str | None) -> Ask:
    span = raw.get("range")
    if not (isinstance(span, list) and len(span) == 2 and all(_finite(x) for x in span) and span[0] < span[1]):
        raise ValueError(f"range: [low, high], two finite numbers with low < high, got {span!r}")
    unit = raw.get("unit", "")
    if not isinstance(unit, str) or len(unit) > 20:
        raise ValueError(f"unit: a short text such as 'rad/s' (at most 20 characters), got {unit!r}")
    truth, answer = raw.get("truth"), raw.get("answer")
    if truth is not None and answer is not None:
        raise ValueError("answer and truth: give the true value typed (answer) or from the physics (truth), not both")
    if truth is not None:
        if truth not in TRUTHS:
            raise ValueError(f"truth: one of {', '.join(TRUTHS)}, got {truth!r}")
        owner, truth_unit, _ = TRUTHS[truth]
        if scene is not None and scene != owner:
            raise ValueError(f"truth: {truth!r} is a quantity of the scene {owner!r}, the step shows {scene!r}")
        if unit and unit != truth_unit:
            raise ValueError(f"unit: {truth!r} is in {truth_unit}, got {unit!r}")
        unit = truth_unit
    if answer is not None and not _finite(answer):
        raise ValueError(f"answer: the true value, a finite number, got {answer!r}")
    low, high = float(span[0]), float(span[1])
    return Ask(text, (), None if answer is None else float(answer), unit, (low, high), truth)


def true_value(ask: Ask, scene: Scene | None) -> float | None:
    """A number question's true value: typed in the step, or computed by the physics API for ``scene``."""
    if ask.truth is None:
        return None if ask.answer is None else float(ask.answer)
    owner, _, value = TRUTHS[ask.truth]
    if scene is None or scene.name != owner:
        return None
    return value(scene)


def held_back(ask: Ask | None, scene: Scene | None) -> tuple[str, ...]:
    """The quantities of ``scene`` that ``ask`` asks about (empty for another scene's or no question)."""
    if ask is None or scene is None:
        return ()
    declared = {a.quantity for a in scene.answers}
    return tuple(q for q in ask.holds if q in declared)


def show_spoilers(ask: Ask | None, scene: Scene | None, visible: bool) -> None:
    """Hold back (``visible`` False) or show again what of ``scene`` states the answer to ``ask``
    (:meth:`app.scenes.base.Scene.hold`)."""
    if scene is not None:
        scene.hold(() if visible else held_back(ask, scene))


def histogram(values: list[float], low: float, high: float, bins: int = BINS) -> list[int]:
    """Counts of ``values`` in ``bins`` equal bars over [low, high] (the last bar includes ``high``)."""
    counts = [0] * bins
    for v in values:
        # (v - low) / (high - low) * bins, not (v - low) // width: 0.5 // 0.1 is 4.0 in floating point.
        counts[min(bins - 1, max(0, math.floor((v - low) / (high - low) * bins)))] += 1
    return counts


def _stamp(t: float | None) -> str:
    return "" if t is None else datetime.fromtimestamp(t, UTC).isoformat(timespec="seconds")


@dataclass
class Question:
    """One question put to the class, its answers (one per voter) and its times (s since the epoch)."""

    ask: Ask
    source: str
    asked_at: float
    true: float | None = None
    closed_at: float | None = None
    revealed_at: float | None = None
    votes: dict[Hashable, str | float] = field(default_factory=dict)

    @property
    def open(self) -> bool:
        return self.closed_at is None

    def counts(self) -> list[int]:
        """Answers per choice, or per bar of the histogram for a number question."""
        if self.ask.range is not None:
            return histogram([float(v) for v in self.votes.values()], *self.ask.range)
        return [sum(1 for v in self.votes.values() if v == letter) for letter in LETTERS[: len(self.ask.choices)]]

    def rows(self, number: int) -> list[list[Any]]:
        """This question's rows of the CSV (one per choice or per bar)."""
        ask = self.ask
        common = [number, _stamp(self.asked_at), _stamp(self.closed_at), _stamp(self.revealed_at), self.source]
        out: list[list[Any]] = []
        if ask.range is not None:
            low, high = ask.range
            width = (high - low) / BINS
            true = "" if self.true is None else f"{self.true:.6g}"
            for k, count in enumerate(self.counts()):
                lo, hi = low + k * width, low + (k + 1) * width
                label = f"[{lo:.6g}, {hi:.6g}{']' if k == BINS - 1 else ')'}"
                out.append([*common, ask.text, label, count, len(self.votes), true, ask.unit])
        else:
            for k, (choice, count) in enumerate(zip(ask.choices, self.counts(), strict=True), start=1):
                right = "" if ask.answer is None else ("yes" if ask.answer == k else "no")
                out.append([*common, ask.text, f"{LETTERS[k - 1]}: {choice}", count, len(self.votes), right, ""])
        return out


CSV_HEADER = [
    "question",
    "asked_utc",
    "closed_utc",
    "revealed_utc",
    "source",
    "text",
    "choice_or_range",
    "count",
    "answers",
    "right_or_true_value",
    "unit",
]


class Poll:
    """Every question asked in a lecture, the current one, and the rules of voting (thread-safe).

    A voter is any hashable identity (:mod:`app.teaching.voters`: one per browser, or per connection);
    the poll never learns a name. ``clock`` gives the times written to the CSV (s since the epoch).
    """

    def __init__(self, clock: Callable[[], float] = time.time) -> None:
        self.questions: list[Question] = []
        self.lock = threading.RLock()
        self._clock = clock

    @property
    def current(self) -> Question | None:
        """The newest question, open or not (None before the first)."""
        with self.lock:
            return self.questions[-1] if self.questions else None

    def ask(self, ask: Ask, source: str, true: float | None = None) -> Question:
        """Close the current question (if open) and put a new one to the class."""
        with self.lock:
            self.close()
            question = Question(ask, source, self._clock(), true=true)
            self.questions.append(question)
            return question

    def close(self) -> Question | None:
        """No more answers to the current question; returns it (None if there is none)."""
        with self.lock:
            question = self.current
            if question is not None and question.open:
                question.closed_at = self._clock()
            return question

    def reveal(self) -> Question | None:
        """Close the current question and show its answers (returns it, None if there is none)."""
        with self.lock:
            question = self.close()
            if question is not None and question.revealed_at is None:
                question.revealed_at = self._clock()
            return question

    def vote(self, voter: Hashable, value: Any) -> str | float:
        """Record ``voter``'s answer to the current question, replacing its earlier one; returns the answer
        as kept (a choice's letter, or the number).

        Raises
        ------
        VoteRefused
            No open question, or an answer that is not one of its choices (a letter A-E or the choice's
            1-based number) or not a finite number in its range.
        """
        with self.lock:
            question = self.current
            if question is None:
                raise VoteRefused("there is no question to answer")
            if not question.open:
                raise VoteRefused("the vote on this question is closed")
            kept = _answer(question.ask, value)
            question.votes[voter] = kept
            return kept

    def answer_of(self, voter: Hashable) -> str | float | None:
        """``voter``'s answer to the current question, or None."""
        with self.lock:
            question = self.current
            return None if question is None else question.votes.get(voter)

    def count(self) -> int:
        """Answers to the current question so far."""
        with self.lock:
            question = self.current
            return 0 if question is None else len(question.votes)

    def csv(self) -> str:
        """Every question's counts with its times, as CSV text (UTC times, ISO 8601)."""
        out = io.StringIO()
        writer = csv.writer(out, lineterminator="\n")
        writer.writerow(CSV_HEADER)
        with self.lock:
            for number, question in enumerate(self.questions, start=1):
                writer.writerows(csv_row(row) for row in question.rows(number))
        return out.getvalue()


_DECIMAL_COMMA = re.compile(r"[+-]?\d*,(\d{1,2}|\d{4,})")


def _decimal_point(text: str) -> str:
    """A number typed with a decimal comma, as a German or Spanish reader writes it (``0,5``), with a
    point; a comma before exactly three digits (``1,500``: a thousand and a half, or one and a half?) is
    left, and the answer is refused as before."""
    return text.replace(",", ".") if _DECIMAL_COMMA.fullmatch(text) else text


def _answer(ask: Ask, value: Any) -> str | float:
    if ask.range is not None:
        if isinstance(value, str):
            try:
                value = float(_decimal_point(value.strip().replace("−", "-")))
            except ValueError:
                raise VoteRefused(say("the answer is a number, got {value!r}", value=value[:20])) from None
        if not _finite(value):
            raise VoteRefused(say("the answer is a finite number, got {value!s}", value=str(value)[:20]))
        low, high = ask.range
        if not low <= value <= high:
            refused = say(
                "the answer is between {low:g} and {high:g} {unit}, got {value:g}",
                low=low,
                high=high,
                unit=ask.unit,
                value=value,
            )
            raise VoteRefused(refused)
        return float(value)
    letters = LETTERS[: len(ask.choices)]
    if isinstance(value, int) and not isinstance(value, bool) and 1 <= value <= len(letters):
        return letters[value - 1]
    if isinstance(value, str) and len(value) == 1 and value in letters:
        return value
    raise VoteRefused(
        say(
            "there is no choice {value!r}: the choices are {letters!s}",
            value=str(value)[:20],
            letters=", ".join(letters),
        )
    )
