"""Notifications in the page (issue 12, item 4): a refusal is one notification, to the browser that
caused it, that closes by itself; an identical one is not stacked; the status line belongs to the scene
(its failures, for everyone: one browser's refusal is not written there)."""

from __future__ import annotations

import time

import pytest

from app.serving.notices import NOTIFY_SECONDS
from tests.harness import click, open_page, pick_scene, running_app, wait_for

pytestmark = pytest.mark.browser

# Ours only: headless Chromium renders WebGL in software, and viser's client says so in a notification.
VISIBLE = """() => [...document.querySelectorAll('.mantine-Notification-root')]
    .filter(n => n.offsetParent && !n.innerText.includes('WebGL')).length"""
TEXTS = "() => [...document.querySelectorAll('.mantine-Notification-root')].map(n => n.innerText)"


def _refuse(page, app, text: str, times: int = 1) -> None:
    """Open a state text that no state has, from this page (the refusal is this browser's); ``times``
    clicks in quick succession."""
    with app.lock:
        app.state_box.value = text
    # The page has the text before the click sends it back (viser's text box: an input or a textarea).
    shown = "(t) => [...document.querySelectorAll('input, textarea')].some(e => e.value === t)"
    wait_for(lambda: page.evaluate(shown, text), 30, what="the page to show the state text")
    button = page.get_by_role("button", name="Open state").first
    button.wait_for(state="visible", timeout=30_000)
    for _ in range(times):  # a person clicking again and again, within a second
        button.click(force=True)
        time.sleep(0.15)


def test_refusals_close_by_themselves_and_identical_ones_are_not_stacked(chromium) -> None:
    with running_app("wobble") as app:
        page, _ = open_page(chromium, app, viewport={"width": 1280, "height": 800})
        other, _ = open_page(chromium, app, viewport={"width": 1024, "height": 768})
        click(page.get_by_text("State", exact=True))
        time.sleep(1.0)  # the folder has finished opening: the button no longer moves
        before = len(app.messages)
        _refuse(page, app, "not a state", times=3)  # the same mistake three times: one notification
        wait_for(lambda: len(app.messages) >= before + 3, 20, what="three clicks at the server")
        wait_for(lambda: page.evaluate(VISIBLE) >= 1, 10, what="the refusal in the page")
        time.sleep(0.5)
        assert page.evaluate(VISIBLE) == 1, page.evaluate(TEXTS)
        assert other.evaluate(VISIBLE) == 0  # the other browser did nothing wrong and hears nothing
        assert "⚠" not in app.status.content  # ...not even in the status line every browser shares
        wait_for(lambda: page.evaluate(VISIBLE) == 0, NOTIFY_SECONDS + 4, what="the notification to close itself")
        shown = []
        for text in ("not a state", "rbl1:!!!", "rbl1:AAAA"):  # three different mistakes: one each
            _refuse(page, app, text)
            shown.append(wait_for(lambda: page.evaluate(VISIBLE), 10, what="the refusal"))
        assert max(shown) >= 2, shown  # different refusals are each shown, not replaced
        assert NOTIFY_SECONDS <= 6.0
        # All gone by themselves, the last within 12 s of the refusals (NOTIFY_SECONDS and the page's fade).
        wait_for(lambda: page.evaluate(VISIBLE) == 0, 12.0, interval=0.2, what="every notification to close itself")
        assert "⚠" not in page.inner_text("body")
        app.pause("a numerical failure (test)")  # the scene's own failure: in the status line, for everyone
        wait_for(lambda: "⚠" in page.inner_text("body"), 10, what="the failure in the status line")
        pick_scene(page, "Heavy top")
        wait_for(lambda: getattr(app.scene, "name", None) == "heavy_top", 30, what="the heavy top")
        with app.lock:  # the switch holds it until it is done: the scene is set before the status is cleared
            assert app.status.content == ""  # the status line belonged to the wobble
        wait_for(lambda: "⚠" not in page.inner_text("body"), 10, what="the status line cleared in the page")
        page.close()
        other.close()
