"""Projector mode in headless Chromium at the projector's 1280×800, measured on a follower's page after the
presenter pressed the panel's Projector button: the control panel a slim bar (its width), the lecture step's
caption at 28 px or more and on top of the 3D view (what the page draws at its centre), the key plot's canvas
at least 40 % of the view's width, the body (a screenshot with it and one without) spanning a third of the
view's height and clear of the bar, the caption and the plot; with the racket's question open the caption
holds the question, not its answer, until the reveal; a follower exploring on their own leaves it and comes
back to it; the clicker's Page Down steps the lecture; the caption's Leave button gives the panel back.
The caption's row of buttons is drawn on the presenter's page only, and at a 1024×768 projector the caption
stays clear of the bar, the presenter's row in the view and the body clear of every panel."""

from __future__ import annotations

import numpy as np
import pytest

from app.panel.projector import CAPTION_FONT_PX
from app.serving.framing import framing_of
from tests.browser.test_look import CLOSE_NOTIFICATIONS, body_pixels
from tests.harness import click, open_page, running_app, wait_for

pytestmark = pytest.mark.browser

PIN = "8642"
RACKET = 6  # the shipped lecture's racket question (0-based)
WIDTH, HEIGHT = 1280, 800

MAIN_PANEL = """() => { const p = document.querySelector('[data-testid="floating-panel"]');
    if (!p) return null; const r = p.getBoundingClientRect(); return [r.left, r.top, r.right, r.bottom]; }"""
"""The control panel's box (viser tags its window ``floating-panel``), CSS px."""

CAPTION = """() => { const mark = document.querySelector('.rbl-projector-caption');
    if (!mark) return null;
    const panel = mark.closest('.mantine-Paper-root'), box = panel.getBoundingClientRect();
    const text = [...panel.querySelectorAll('p')].find(p => p.innerText.trim());
    if (!text) return null;
    const r = text.getBoundingClientRect(), x = (r.left + r.right) / 2, y = r.top + Math.min(12, r.height / 2);
    const top = document.elementFromPoint(x, y);
    return {size: parseFloat(getComputedStyle(text).fontSize), text: panel.innerText,
            box: [box.left, box.top, box.right, box.bottom], onTop: !!top && panel.contains(top),
            shown: getComputedStyle(panel).visibility !== 'hidden' && r.width > 0 && r.height > 0}; }"""
"""The projector's caption: its text's computed size, its text, its panel's box, and whether the element the
page draws at its first line is the caption's own (not the canvas or another panel over it)."""

PLOT = """() => { const mark = document.querySelector('.rbl-projector-plot');
    if (!mark) return null;
    const panel = mark.closest('.mantine-Paper-root'), box = panel.getBoundingClientRect();
    const canvas = panel.querySelector('canvas'); if (!canvas) return null;
    const r = canvas.getBoundingClientRect();
    return {width: r.width, height: r.height, box: [box.left, box.top, box.right, box.bottom]}; }"""
"""The projector's key plot: its drawn canvas's size and its panel's box, CSS px."""

ROW = """() => { const mark = document.querySelector('.rbl-projector-caption');
    if (!mark) return null;
    const buttons = [...mark.closest('.mantine-Paper-root').querySelectorAll('button')]
        .filter(b => b.getClientRects().length > 0);
    return buttons.map(b => { const r = b.getBoundingClientRect();
        return {name: b.innerText.trim(), disabled: b.disabled, box: [r.left, r.top, r.right, r.bottom]}; }); }"""
"""The caption's row of buttons as drawn (a button hidden by CSS has no box): name, disabled, box in CSS px."""


def _framed_for(app, width: int, height: int) -> bool:
    """Whether every page reports a view of ``width`` × ``height``'s shape and its camera was framed for it
    (a page reports its new size a frame or more after it changed, and the server frames it then)."""
    for client in app.server.get_clients().values():
        w, h = client.camera.image_width, client.camera.image_height
        last = framing_of(client)
        if not (h > 0 and abs(w / h - width / height) < 0.01 and last is not None and last.size == (w, h)):
            return False
    return True


def _under(xs: np.ndarray, ys: np.ndarray, box: list[float]) -> int:
    left, top, right, bottom = box
    return int(((xs >= left) & (xs <= right) & (ys >= top) & (ys <= bottom)).sum())


def test_the_presenters_switch_puts_every_follower_in_projector_mode_with_the_answer_held(chromium):
    viewport = {"width": WIDTH, "height": HEIGHT}
    with running_app(presenter=True, pin=PIN, lecture="rigid-body-motion") as app:
        app.go_to_step(RACKET)  # the racket's question is open
        lecturer, _ = open_page(chromium, app, timeout=120, viewport=viewport)
        follower, _ = open_page(chromium, app, timeout=120, viewport=viewport)
        wait_for(lambda: follower.evaluate(MAIN_PANEL), 60, what="the follower's panel")
        normal = follower.evaluate(MAIN_PANEL)
        assert normal[2] - normal[0] >= 350  # viser's large panel before the switch

        pin_box = "xpath=//label[text()='Presenter PIN']/ancestor::div[contains(@class,'Flex-root')][1]//input"
        lecturer.locator(pin_box).first.fill(PIN)
        click(lecturer.get_by_role("button", name="Present"))
        wait_for(lambda: app.classroom.presenters, 30, what="the lecturer to present")
        click(lecturer.get_by_role("button", name="Projector"))
        wait_for(lambda: app.shared.projector.on, 30, what="projector mode on the server")

        for page in (lecturer, follower):  # followers see the presenter's switch
            page.evaluate(CLOSE_NOTIFICATIONS)
            wait_for(lambda page=page: (page.evaluate(CAPTION) or {}).get("shown"), 60, what="the large caption")
        # Drawn, not only placed: on a loaded page uPlot sizes its canvas a few frames after the panel appears.
        wait_for(lambda: (follower.evaluate(PLOT) or {}).get("width"), 60, what="the large plot drawn")

        # The panel a slim bar (it narrows and then folds: on a loaded page the fold can come after the caption).
        def slim() -> list | None:
            box = follower.evaluate(MAIN_PANEL)
            return box if box and box[2] - box[0] <= 220 and box[3] - box[1] <= 80 else None

        bar = wait_for(slim, 60, what="the panel a slim bar")
        assert bar[2] - bar[0] <= 220, f"the panel is {bar[2] - bar[0]:.0f} px wide in projector mode"
        assert bar[3] - bar[1] <= 80, f"the panel is {bar[3] - bar[1]:.0f} px tall in projector mode"

        # The caption: large, on top of the view, the question and not its answer.
        caption = follower.evaluate(CAPTION)
        assert caption["size"] >= 28 and caption["size"] == CAPTION_FONT_PX
        assert caption["onTop"], "the caption's first line is covered"
        assert 0 <= caption["box"][0] and caption["box"][2] <= WIDTH and caption["box"][3] <= HEIGHT
        period = app.scene.flip_period
        assert "Spun about its middle axis" in caption["text"]
        for leak in (f"{period:.4g}", f"{period:.3g}", "flips over and back, again"):
            assert leak not in caption["text"], f"{leak!r} in the follower's projector caption before the reveal"

        # The key plot: large in the view.
        plot = follower.evaluate(PLOT)
        assert plot["width"] >= 0.4 * WIDTH, f"the plot is drawn {plot['width']:.0f} px wide"
        assert plot["height"] >= 0.3 * HEIGHT, f"the plot is drawn {plot['height']:.0f} px tall"

        # The body: a third of the view's height, clear of the bar, the caption and the plot.
        mask, _, _ = body_pixels(follower, app)
        ys, xs = np.nonzero(mask)
        assert len(xs) > 300, "no body in the follower's view"
        span = max(np.ptp(ys), np.ptp(xs)) / HEIGHT
        assert span >= 1 / 3, f"the body spans {span:.2f} of the view's height"
        for name, box in (("the slim bar", bar), ("the caption", caption["box"]), ("the plot", plot["box"])):
            assert _under(xs, ys, box) == 0, f"{_under(xs, ys, box)} body pixels under {name}"

        # The caption's row: the presenter's buttons shown; a follower's, which cannot drive, not drawn at all.
        wait_for(lambda: "Next" in [b["name"] for b in lecturer.evaluate(ROW) or []], 30, what="the lecturer's row")
        assert follower.evaluate(ROW) == [], f"a follower's page draws {follower.evaluate(ROW)}"

        # A 1024×768 projector: the caption clear of the bar and in the view, the presenter's whole row in it,
        # the body clear of every panel.
        narrow = {"width": 1024, "height": 768}
        for page in (lecturer, follower):
            page.set_viewport_size(narrow)
        wait_for(lambda: follower.evaluate(CAPTION)["box"][2] <= narrow["width"], 30, what="the narrow caption")
        wait_for(lambda: _framed_for(app, 1024, 768), 30, what="the pages framed for 1024×768")
        caption, plot = follower.evaluate(CAPTION), follower.evaluate(PLOT)
        bar = follower.evaluate(MAIN_PANEL)
        assert caption["box"][2] <= bar[0], f"the caption {caption['box']} over the slim bar {bar}"
        assert caption["onTop"], "the caption's first line is covered at 1024 px"
        panel = lecturer.evaluate(CAPTION)["box"]
        for button in wait_for(lambda: lecturer.evaluate(ROW), 30, what="the lecturer's row at 1024 px"):
            left, top, right, bottom = button["box"]
            assert 0 <= left and right <= narrow["width"], f"{button['name']} at x {left:.0f}-{right:.0f}"
            assert bottom <= panel[3], f"{button['name']} at y {top:.0f}-{bottom:.0f}, below the caption's panel"
        mask, _, _ = body_pixels(follower, app)
        ys, xs = np.nonzero(mask)
        assert len(xs) > 300, "no body in the follower's view at 1024 px"
        for name, box in (("the slim bar", bar), ("the caption", caption["box"]), ("the plot", plot["box"])):
            assert _under(xs, ys, box) == 0, f"{_under(xs, ys, box)} body pixels under {name} at 1024 px"
        for page in (lecturer, follower):
            page.set_viewport_size(viewport)

        # The reveal: the answer comes back in the large caption too.
        app.questions.reveal(None)
        wait_for(
            lambda: "flips over and back, again" in (follower.evaluate(CAPTION) or {}).get("text", ""),
            30,
            what="the caption at the reveal",
        )

        # A follower who explores on their own gets the panel back and leaves the lecture's projector panels;
        # following again brings them back.
        click(follower.locator('[data-testid="floating-panel-handle"]'))
        click(follower.get_by_role("button", name="Explore on my own"))
        wait_for(lambda: follower.evaluate(CAPTION) is None, 60, what="the explorer's caption to go")
        wait_for(lambda: follower.evaluate(PLOT) is None, 30, what="the explorer's plot to go")
        wait_for(lambda: np.ptp(follower.evaluate(MAIN_PANEL)[::2]) >= 350, 30, what="the explorer's panel")
        click(follower.get_by_role("button", name="Follow the lecturer"))
        wait_for(lambda: (follower.evaluate(CAPTION) or {}).get("shown"), 60, what="the caption back")

        # The clicker's key steps the lecture with the panel a bar (the caption's row has the Next button).
        lecturer.mouse.click(0.3 * WIDTH, 0.6 * HEIGHT)  # the focus on the page, not on a control
        lecturer.keyboard.press("PageDown")
        wait_for(lambda: app.simulation.step_index == RACKET + 1, 30, what="the clicker's next step")

        # Switched off from the caption's row: the panel back at its width, the projector's panels gone.
        click(lecturer.get_by_role("button", name="Leave projector mode"))
        wait_for(lambda: not app.shared.projector.on, 30, what="projector mode off")
        wait_for(lambda: follower.evaluate(CAPTION) is None, 30, what="the caption to go")
        wait_for(lambda: follower.evaluate(PLOT) is None, 30, what="the plot to go")
        wait_for(
            lambda: follower.evaluate(MAIN_PANEL)[2] - follower.evaluate(MAIN_PANEL)[0] >= 350,
            30,
            what="the panel's width back",
        )
