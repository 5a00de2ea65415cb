"""Keyboard shortcuts: Space plays or pauses, → steps, R resets, and in a
lecture Page Down / Page Up (a presentation clicker) go to the next / previous step; none of them while the
focus is in a text field. Keyboard only (no mouse event); each change read from the server's state."""

from __future__ import annotations

import pytest

from tests.harness import open_page, running_app, wait_for

pytestmark = pytest.mark.browser

NOTHING_FOCUSED = "() => { if (document.activeElement) document.activeElement.blur(); }"
FOCUS_TEXT = """() => { const box = [...document.querySelectorAll('.mantine-NumberInput-input:not([disabled])')]
    .find(e => e.offsetParent); box.focus(); return document.activeElement === box; }"""
"""A slider's number box: a text field, where R and Space are typing."""
READY = "() => window.rblAccess === true && [...document.querySelectorAll('button')].some(b => b.textContent.trim() === 'Reset')"


def test_space_pauses_and_plays_right_arrow_steps_r_resets(chromium) -> None:
    with running_app("heavy_top") as app:
        page, _ = open_page(chromium, app, viewport={"width": 1280, "height": 800})
        try:
            page.wait_for_function(READY, timeout=30_000)
            wait_for(lambda: app.time > 0.2, what="the clock to run")
            page.evaluate(NOTHING_FOCUSED)
            page.keyboard.press("Space")
            wait_for(lambda: not app.shared.playing, 10, what="Space to pause")
            paused_at = app.time
            page.keyboard.press("ArrowRight")
            wait_for(lambda: app.time > paused_at, 10, what="→ to step")
            assert not app.shared.playing
            stepped = app.time
            assert stepped - paused_at == pytest.approx(1.0 / 60.0, rel=1e-6)  # one frame at 1×
            # R and Space while typing in a text field (a slider's number box) are text, not a reset or play.
            assert page.evaluate(FOCUS_TEXT)
            page.keyboard.press("r")
            page.keyboard.press("Space")
            page.evaluate(NOTHING_FOCUSED)
            page.wait_for_timeout(300)
            assert app.time == stepped and not app.shared.playing
            page.keyboard.press("r")
            wait_for(lambda: app.time == 0.0, 10, what="R to reset")
            page.keyboard.press("Space")
            wait_for(lambda: app.shared.playing and app.time > 0.0, 10, what="Space to play")
        finally:
            page.close()


def test_page_down_and_page_up_step_a_lecture(chromium) -> None:
    with running_app(lecture="rigid-body-motion") as app:
        page, _ = open_page(chromium, app, viewport={"width": 1280, "height": 800})
        try:
            page.wait_for_function(READY, timeout=30_000)
            assert app.shared.step_index == 0
            page.evaluate(NOTHING_FOCUSED)
            page.keyboard.press("PageDown")
            wait_for(lambda: app.shared.step_index == 1, 20, what="Page Down to go to step 2")
            page.keyboard.press("PageDown")
            wait_for(lambda: app.shared.step_index == 2, 20, what="Page Down to go to step 3")
            page.keyboard.press("PageUp")
            wait_for(lambda: app.shared.step_index == 1, 20, what="Page Up to go back to step 2")
        finally:
            page.close()
