"""Notifications in the page: a refusal is one notification, to the browser that
caused it, that closes by itself; an identical one is not stacked; the status line belongs to the scene
(its failures, for everyone: one browser's refusal is not written there)."""

from __future__ import annotations

import time

import pytest

from app.serving import notices
from app.serving.notices import NOTIFY_SECONDS
from tests.harness import click, open_page, pick_scene, running_app, wait_for

pytestmark = pytest.mark.browser

# Ours only: headless Chromium renders WebGL in software, and viser's client says so in a notification.
VISIBLE = """() => [...document.querySelectorAll('.mantine-Notification-root')]
    .filter(n => n.offsetParent && !n.innerText.includes('WebGL')).length"""
TEXTS = "() => [...document.querySelectorAll('.mantine-Notification-root')].map(n => n.innerText)"

# The page records what it shows every 50 ms (a count read at one moment races with the notification's
# arrival and its fade): for each of our notifications' texts, when it was first and last on screen (ms),
# and the most notifications with one text shown at once.
RECORD = """() => {
  clearInterval(window.rblNoticeWatch);
  window.rblNotices = {};
  window.rblNoticeWatch = setInterval(() => {
    const now = performance.now();
    const count = {};
    for (const n of document.querySelectorAll('.mantine-Notification-root')) {
      const text = n.innerText;
      if (!n.offsetParent || !text || text.includes('WebGL')) continue;
      count[text] = (count[text] || 0) + 1;
    }
    for (const [text, k] of Object.entries(count)) {
      const seen = window.rblNotices[text] || (window.rblNotices[text] = {first: now, last: now, most: 0});
      seen.last = now;
      seen.most = Math.max(seen.most, k);
    }
  }, 50);
}"""
SEEN = "() => window.rblNotices"


def _refuse(page, app, text: str, times: int = 1) -> None:
    """Open a state text that no state has, from this page (the refusal is this browser's); ``times``
    clicks in quick succession."""
    with app.simulation.lock:
        app.simulation.state_box.value = text
    # The page has the text before the click sends it back (viser's text box: an input or a textarea).
    shown = "(t) => [...document.querySelectorAll('input, textarea')].some(e => e.value === t)"
    wait_for(lambda: page.evaluate(shown, text), 30, what="the page to show the state text")
    button = page.get_by_role("button", name="Open state").first
    button.wait_for(state="visible", timeout=30_000)
    for _ in range(times):  # a person clicking again and again, within a second (the element's own click:
        button.evaluate("b => b.click()")  # Playwright's pointer sequence takes seconds on a loaded page)
        time.sleep(0.15)


def _shown(page, body: str) -> dict:
    """The page's record of the notification whose text holds ``body``, once it has been on screen."""
    found = lambda: next((seen for text, seen in page.evaluate(SEEN).items() if body in text), None)  # noqa: E731
    return wait_for(found, 20, what=f"a notification saying {body!r}")


LIFETIME = 20.0
"""s: how long a notification shows in this test. The page's answer to a click can take several seconds on a
loaded machine (CI's came 7.5 s apart), longer than NOTIFY_SECONDS: at 6 s the test would measure the
machine. What is tested (one notification for the same mistake while it shows, different ones shown
together, each closing by itself after its time) does not depend on the time's length."""


def test_refusals_close_by_themselves_and_identical_ones_are_not_stacked(chromium, monkeypatch) -> None:
    assert NOTIFY_SECONDS <= 6.0  # the product's setting: a refusal does not linger
    monkeypatch.setattr(notices, "NOTIFY_SECONDS", LIFETIME)
    # Without the real-time loop: what is tested is the page's notifications, and a moving body drawn on the
    # CPU at 1280×800 in two pages keeps the pages' main threads so busy that clicks a person makes within a
    # second reach the server seconds apart.
    with running_app("wobble", start_loop=False) as app:
        page, _ = open_page(chromium, app, viewport={"width": 1280, "height": 800})
        other, _ = open_page(chromium, app, viewport={"width": 1024, "height": 768})
        click(page.get_by_text("State", exact=True))
        time.sleep(1.0)  # the folder has finished opening: the button no longer moves
        page.evaluate(RECORD)
        before = len(app.messages)
        _refuse(page, app, "not a state", times=3)  # the same mistake three times: one notification
        wait_for(lambda: len(app.messages) >= before + 3, 20, what="three clicks at the server")
        body = app.messages[-1][1]
        assert [m for m in app.messages[before:]] == [("State refused", body)] * 3
        _shown(page, body)
        time.sleep(1.0)  # the second and third click's answers, had there been any, are in the page by now
        seen = page.evaluate(SEEN)
        assert len(seen) == 1 and next(iter(seen.values()))["most"] == 1, (seen, page.evaluate(TEXTS))
        assert other.evaluate(VISIBLE) == 0  # the other browser did nothing wrong and hears nothing
        assert "⚠" not in app.simulation.status.content  # ...not even in the status line every browser shares
        wait_for(lambda: page.evaluate(VISIBLE) == 0, LIFETIME + 30, what="the notification to close itself")
        page.evaluate(RECORD)
        bodies = []
        for text in ("not a state", "rbl1:!!!", "rbl1:AAAA"):  # three different mistakes: one each
            before = len(app.messages)
            _refuse(page, app, text)
            wait_for(lambda: len(app.messages) > before, 20, what="the click at the server")  # noqa: B023
            bodies.append(app.messages[-1][1])
            _shown(page, bodies[-1])
        assert len(set(bodies)) == 3, bodies  # three different reasons
        wait_for(lambda: page.evaluate(VISIBLE) == 0, LIFETIME + 30, interval=0.2, what="every notification to close")
        seen = page.evaluate(SEEN)
        shown = [next(s for t, s in seen.items() if b in t) for b in bodies]
        # Different refusals are each shown, not replaced: each was still on screen when the next came...
        for earlier, later in zip(shown, shown[1:]):
            assert later["first"] - earlier["first"] < 1000 * LIFETIME - 1000, (shown, "clicks came too slowly")
            assert earlier["last"] >= later["first"], shown
        # ...and each closed by itself after its time, not when the next came (at least half of it as seen: the
        # record's first sight of a notification can itself come late on a loaded page).
        for record in shown:
            assert record["last"] - record["first"] >= 1000 * LIFETIME / 2, shown
        assert "⚠" not in page.inner_text("body")
        app.simulation.pause("a numerical failure (test)")  # the scene's own failure: in the status line, for everyone
        wait_for(lambda: "⚠" in page.inner_text("body"), 10, what="the failure in the status line")
        pick_scene(page, "Heavy top")
        wait_for(lambda: getattr(app.scene, "name", None) == "heavy_top", 30, what="the heavy top")
        with app.simulation.lock:  # the switch holds it until it is done: the scene is set before the status is cleared
            assert app.simulation.status.content == ""  # the status line belonged to the wobble
        wait_for(lambda: "⚠" not in page.inner_text("body"), 10, what="the status line cleared in the page")
        page.close()
        other.close()
