"""A class question keeps its answer, in a real follower's page: while a question of the shipped lecture is
open, nothing the page shows or holds (its text, every input's value, every label read to a screen reader)
contains the answer's value in the forms the app prints it (four and three significant digits); after the
reveal it does; at the next step the question's chart leaves the panel."""

from __future__ import annotations

import pytest

from app.panel.parameters import HELD
from tests.harness import open_page, running_app, wait_for

pytestmark = pytest.mark.browser

PIN = "8642"
PENDULUM, RACKET, STEADY = 2, 6, 9  # the shipped lecture's question steps (0-based)

PAGE_TEXT = """() => [document.body.innerText,
    ...[...document.querySelectorAll('input, textarea')].map(e => e.value),
    ...[...document.querySelectorAll('[aria-label], [title]')].map(
        e => (e.getAttribute('aria-label') || '') + ' ' + (e.getAttribute('title') || ''))].join('\\n')"""
"""Everything of the page a student can read: its text, the values of its inputs (the panel's readouts are
disabled text inputs, absent from ``innerText``), and what a screen reader or a tooltip says."""


def _forms(value: float) -> list[str]:
    """The answer as the panel prints it: readouts at four significant digits, descriptions at three."""
    return [f"{value:.4g}", f"{value:.3g}"]


def _text(page) -> str:
    return page.evaluate(PAGE_TEXT)


def _shows_none(page, forms: list[str]) -> None:
    text = _text(page)
    leaked = [form for form in forms if form in text]
    assert not leaked, f"{leaked} on a follower's page while the question is open: {text[:2000]!r}"


def test_a_follower_page_holds_each_answer_back_until_the_reveal(chromium):
    with running_app(presenter=True, pin=PIN, lecture="rigid-body-motion") as app:
        questions = app.questions
        app.go_to_step(PENDULUM)
        page, _ = open_page(chromium, app, viewport={"width": 1280, "height": 800})
        # The number question: ℓ = k²/a⊥, the centre of percussion's depth.
        page.get_by_text("How far below the pivot", exact=False).first.wait_for(timeout=30_000)
        wait_for(lambda: _text(page).count(HELD) >= 2, 30, what="the readouts held back")
        true = questions.poll.current.true
        assert true == pytest.approx(app.scene.model.effective_length, rel=1e-12)
        assert "k = 0.5337 m" in _text(page) and "a⊥ = 0.4937 m" in _text(page)  # what it needs, in its text
        _shows_none(page, _forms(true))
        questions.reveal(None)
        wait_for(lambda: f"{true:.4g}" in _text(page) and "True value" in _text(page), 30, what="the reveal")
        # The readouts come back with the next frame drawn, which may reach the page after the chart's reveal.
        wait_for(lambda: HELD not in _text(page), 30, what="the readouts shown again after the reveal")

        app.go_to_step(PENDULUM + 1)  # no question: the chart leaves
        wait_for(lambda: "No question now" in _text(page), 30, what="the next step's empty question")
        assert "True value" not in _text(page)

        # A question of choices: the racket's flip (its measured period and the stability's words).
        app.go_to_step(RACKET)
        page.get_by_text("after a few seconds the racket", exact=False).first.wait_for(timeout=30_000)
        wait_for(lambda: _text(page).count(HELD) >= 4, 30, what="the racket's readouts held back")
        period = app.scene.flip_period
        _shows_none(page, [*_forms(period), "unstable", "flips over and back every"])
        questions.reveal(None)
        wait_for(lambda: f"{period:.4g}" in _text(page), 30, what="the flip period at the reveal")

        # The steady precession's rate: its readout, the φ̇₀ slider the preset sets to it, the words.
        app.go_to_step(STEADY)
        page.get_by_text("Predict the slow rate", exact=False).first.wait_for(timeout=30_000)
        wait_for(lambda: HELD in _text(page), 30, what="the precession held back")
        true = questions.poll.current.true
        assert "I₁ = 0.4 kg m²" in _text(page) and "I₃ = 0.2 kg m²" in _text(page)
        _shows_none(page, _forms(true))
        questions.reveal(None)
        wait_for(lambda: f"{true:.4g}" in _text(page), 30, what="the rate at the reveal")
