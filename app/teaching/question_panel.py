"""One browser's question panel: the question and a way to answer (a follower), or the live count, the
reveal, a question of one's own and the CSV (a presenter); the answers as a chart once revealed.

Every element is the browser's own (``client.gui``): what one browser's panel shows is sent to that
browser only, so a follower's page never receives the count or the answers before the reveal.
More in docs/app-notes.md (``app.teaching.question_panel``).
"""

from __future__ import annotations

from collections.abc import Callable
from typing import Any

import viser

from app.guards.text import html_text, markdown_text
from app.language.words import joined, mark, say
from app.teaching.questions import BINS, LETTERS, Question

__all__ = ["QuestionPanel", "results_html"]

ORDER = -20.0
"""Where the question sits in the panel: under the presenter controls, above the lecture."""


class QuestionPanel:
    """The question folder of one browser, rebuilt for each question and at the reveal.

    Parameters
    ----------
    client : viser.ClientHandle
        The browser.
    on_vote : callable(client, value)
        A follower chose a letter, or sent the text of a number.
    on_reveal, on_save : callable(client)
        The presenter's "Show answers" and "Save answers (CSV)".
    on_ask : callable(client, question text, choices text)
        The presenter's own question (choices one per line).
    """

    def __init__(
        self,
        client: viser.ClientHandle,
        on_vote: Callable[[Any, Any], None],
        on_reveal: Callable[[Any], None],
        on_ask: Callable[[Any, str, str], None],
        on_save: Callable[[Any], None],
    ) -> None:
        self.client = client
        self._on_vote, self._on_reveal, self._on_ask, self._on_save = on_vote, on_reveal, on_ask, on_save
        self.folder: Any = None
        self.presenter = False
        self.count: Any = None  # the presenter's live count (markdown)
        self.mine: Any = None  # a follower's own answer (markdown)
        self.choice: Any = None  # a follower's button group (letters)
        self.number: Any = None  # a follower's number box (text) and its Send button
        self.send: Any = None
        self.results: Any = None
        self.reveal: Any = None
        self.ask_text: Any = None
        self.ask_choices: Any = None
        self.ask_button: Any = None
        self.save_button: Any = None

    def show(self, question: Question | None, *, presenter: bool, mine: Any, count: int) -> None:
        """Rebuild the folder for ``question`` (None: no question yet) as a presenter or a follower sees it."""
        self.presenter = presenter
        if self.folder is not None:
            self.folder.remove()
        gui = self.client.gui
        self.count = self.mine = self.choice = self.number = self.send = self.results = self.reveal = None
        title = mark("Class question") if question is not None or presenter else mark("Question")
        self.folder = None
        with gui.add_folder(title, order=ORDER) as folder:
            if question is not None:
                gui.add_markdown(_question_markdown(question))
            if presenter:
                self._presenter(question, count)
            elif question is None:
                gui.add_markdown(mark("*No question now: when the lecturer asks one, answer it here.*"))
            else:
                self._follower(question, mine)
            if question is not None and question.revealed_at is not None:
                self.results = gui.add_html(results_html(question))
        self.folder = folder  # set once every control in it is made: whoever sees it sees them all

    def _follower(self, question: Question, mine: Any) -> None:
        gui = self.client.gui
        closed = not question.open
        if question.ask.range is not None:
            low, high = question.ask.range
            unit = question.ask.unit
            label = say("Your answer ({unit})", unit=unit) if unit else mark("Your answer")
            self.number = gui.add_text(label, "", disabled=closed)
            hint = say("A number from {low:g} to {high:g}", low=low, high=high)
            self.send = gui.add_button(mark("Send my answer"), disabled=closed, hint=hint)
            self.send.on_click(lambda event: self._on_vote(event.client, self.number.value))
        else:
            letters = list(LETTERS[: len(question.ask.choices)])
            self.choice = gui.add_button_group(mark("Your answer"), letters, disabled=closed)
            self.choice.on_click(lambda event: self._on_vote(event.client, event.target.value))
        self.mine = gui.add_markdown(mine_text(question, mine))

    def _presenter(self, question: Question | None, count: int) -> None:
        gui = self.client.gui
        if question is not None:
            self.count = gui.add_markdown(count_text(question, count))
            if question.revealed_at is None:
                self.reveal = gui.add_button(mark("Show answers"), icon=viser.Icon.CHART_BAR)
                self.reveal.on_click(lambda event: self._on_reveal(event.client))
        with gui.add_folder(mark("Ask the class"), expand_by_default=question is None):
            self.ask_text = gui.add_text(mark("Question"), "")
            self.ask_choices = gui.add_text(mark("Choices (one a line)"), "", multiline=True)
            self.ask_button = gui.add_button(mark("Ask"))
            self.ask_button.on_click(
                lambda event: self._on_ask(event.client, self.ask_text.value, self.ask_choices.value)
            )
        self.save_button = gui.add_button(mark("Save answers (CSV)"), icon=viser.Icon.DOWNLOAD)
        self.save_button.on_click(lambda event: self._on_save(event.client))

    def update(self, question: Question | None, mine: Any, count: int) -> None:
        """The count (presenter) or one's own answer (follower) changed; nothing else is sent."""
        if question is None:
            return
        if self.presenter and self.count is not None:
            text = count_text(question, count)
            if self.count.content != text:
                self.count.content = text
        elif self.mine is not None:
            text = mine_text(question, mine)
            if self.mine.content != text:
                self.mine.content = text

    def remove(self) -> None:
        if self.folder is not None:
            try:
                self.folder.remove()
            except Exception:  # noqa: BLE001 - its browser has gone
                pass
            self.folder = None


def _answers(n: int) -> str:
    return say("{n} answer", n=n) if n == 1 else say("{n} answers", n=n)


def _said(question: Question) -> str:
    """The chart in words, for a screen reader (the chart is one image to it)."""
    ask, counts = question.ask, question.counts()
    # Escaped part by part (the words around them have no & < > " '): the same text as escaping the whole,
    # and each part still a said text, translated on the wire.
    answers = _answers(len(question.votes))
    if ask.range is None:
        counted = joined([say("{letter}: {n}", letter=LETTERS[k], n=n) for k, n in enumerate(counts)], ", ")
        if ask.answer is None:
            return say("{answers}: {counted}", answers=answers, counted=counted)
        return say(
            "{answers}: {counted}; the right answer is {letter}",
            answers=answers,
            counted=counted,
            letter=LETTERS[int(ask.answer) - 1],
        )
    low, high = ask.range
    width = (high - low) / BINS
    bins = [
        say("{low:.3g} to {high:.3g}: {n}", low=low + k * width, high=low + (k + 1) * width, n=n)
        for k, n in enumerate(counts)
        if n
    ]
    unit = html_text(ask.unit)
    if question.true is None:
        return say("{answers} ({unit}) {bins}", answers=answers, unit=unit, bins=joined(bins, ", "))
    return say(
        "{answers} ({unit}) {bins}; the true value is {true:.4g} {unit}",
        answers=answers,
        unit=unit,
        bins=joined(bins, ", "),
        true=question.true,
    )


def _question_markdown(question: Question) -> str:
    ask = question.ask
    lines = [say(_BOLD, text=markdown_text(ask.text))]
    if ask.range is not None:
        low, high = ask.range
        unit = markdown_text(ask.unit)
        if unit.strip():
            lines.append(say("A number from {low:g} to {high:g} {unit}.", low=low, high=high, unit=unit.rstrip()))
        else:
            lines.append(say("A number from {low:g} to {high:g}.", low=low, high=high))
    else:
        lines += [say(_CHOICE, letter=LETTERS[k], text=markdown_text(choice)) for k, choice in enumerate(ask.choices)]
    return joined(lines, "\n\n")


_BOLD = "**{text}**"  # markup alone: the lecturer's question (a value, not a word of the catalogs)
_CHOICE = "**{letter}.** {text}"  # markup alone: a choice of the lecturer's


def count_text(question: Question, count: int) -> str:
    """The presenter's line: how many have answered, never what."""
    if question.open:
        return say("**{answers}** so far; the vote is open.", answers=_answers(count))
    return say("**{answers}** so far; the vote is closed.", answers=_answers(count))


def mine_text(question: Question, mine: Any) -> str:
    """A follower's line: their own answer, and whether they may still change it."""
    unit = markdown_text(question.ask.unit)  # "" without one: the answer reads "**0.5 **", as it always has
    if mine is None:
        said = mark("You have not answered yet.")
    elif isinstance(mine, float):
        said = say("Your answer: **{mine:g} {unit}**.", mine=mine, unit=unit)
    else:
        said = say("Your answer: **{mine}**.", mine=markdown_text(mine))
    if question.open:
        return say("{said} You may change it until the vote closes.", said=said)
    return say("{said} The vote is closed.", said=said)


def results_html(question: Question) -> str:
    """The class's answers as bars (choices) or a histogram with the true value marked (numbers)."""
    counts = question.counts()
    top = max(counts + [1])
    total = len(question.votes)
    ask = question.ask
    style = "font:13px sans-serif;margin:4px 0"
    if ask.range is None:
        rows = []
        for k, (choice, n) in enumerate(zip(ask.choices, counts, strict=True)):
            right = ask.answer == k + 1
            colour = "#2a9d4b" if right else "#5b7fb8"
            tick = " ✓" if right else ""
            rows.append(
                f'<div style="{style}"><b>{LETTERS[k]}</b>{tick} {html_text(choice)}'
                f'<div style="display:flex;align-items:center;gap:6px"><div style="background:{colour};'
                f'height:14px;width:{100 * n / top:.1f}%"></div><span>{n}</span></div></div>'
            )
        return say(_BARS, said=_said(question), rows="".join(rows), answers=_answers(total))
    low, high = ask.range
    bars = "".join(
        f'<div title="{n}" style="flex:1;align-self:flex-end;background:#5b7fb8;height:{100 * n / top:.1f}%;'
        f'margin:0 1px"></div>'
        for n in counts
    )
    marker = ""
    if question.true is not None and low <= question.true <= high:
        x = 100 * (question.true - low) / (high - low)
        marker = f'<div style="position:absolute;left:{x:.1f}%;top:0;bottom:0;border-left:2px solid #d1495b"></div>'
    # The text keeps the page's colour (legible on the light and the dark look); the red is the line's.
    unit = html_text(ask.unit)
    if question.true is None:
        small = say("{answers} in {bins} bars.", answers=_answers(total), bins=BINS)
    else:
        small = say(
            "{answers} in {bins} bars. True value (red line): <b>{true:.4g} {unit}</b>.",
            answers=_answers(total),
            bins=BINS,
            true=question.true,
            unit=unit,
        )
    return say(
        _HISTOGRAM,
        said=_said(question),
        style=style,
        bars=bars,
        marker=marker,
        low=low,
        high=high,
        unit=unit,
        small=small,
    )


# Markup alone (not for the translators): the words are the values, each translated.
_BARS = '<div role="img" aria-label="{said}">{rows}<small>{answers}</small></div>'
_HISTOGRAM = (
    '<div role="img" aria-label="{said}" style="{style}">'
    '<div style="position:relative;display:flex;height:80px;border-bottom:1px solid #888">{bars}{marker}</div>'
    '<div style="display:flex;justify-content:space-between"><span>{low:g}</span><span>{high:g} {unit}</span>'
    "</div><small>{small}</small></div>"
)
