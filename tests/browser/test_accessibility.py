"""WCAG 2.1 AA in the page (issue 23, item 1): axe-core's WCAG 2.0/2.1 A and AA rules, injected into
headless Chromium (:mod:`tests.browser.axe_scan`), on the app's page.

``python -m tests.browser.test_accessibility`` prints the table of docs/accessibility.md (every scene,
light and dark, 1280×800 and 390×844).
"""

from __future__ import annotations

import time
from typing import Any

import pytest

from app.panel.look import MIN_TEXT_PX
from app.scenes import REGISTRY, scene_names
from tests.browser.axe_scan import axe_source, counts, scan
from tests.harness import click, launch_chromium, open_page, running_app, wait_for

pytestmark = pytest.mark.browser

SIZES = ((1280, 800), (390, 844))

SHOWN = """(text) => { const el = document.querySelector('.rbl-motion');
    return !!el && el.textContent === text; }"""


@pytest.fixture(scope="module")
def axe() -> str:
    return axe_source()


def show(page: Any, app: Any, name: str) -> None:
    """Switch the app to scene ``name`` and wait until the page shows it (its words and its folder)."""
    if app.scene is None or app.scene.name != name:
        app.switch_scene(name)
    title, frames = REGISTRY[name].title, app.shared.frames
    wait_for(lambda: app.shared.frames > frames + 1, what=f"{name}'s first frames")  # its words are said
    page.wait_for_function(SHOWN, arg=app.shared.panel.said, timeout=30_000)
    page.get_by_text(title, exact=True).first.wait_for(state="visible", timeout=30_000)
    time.sleep(0.5)  # the panel's last re-render (a readout's first value) lands


def test_the_scan_finds_what_it_is_there_to_find(chromium, axe) -> None:
    """The harness itself: an unnamed text box and an image without alternative text are found, and a
    named box and a described image are not."""
    page = chromium.new_page()
    try:
        page.set_content('<html lang="en"><title>t</title><main><input type="text"><img src="data:,"></main></html>')
        assert counts(scan(page, axe)) == {"label": 1, "image-alt": 1}
        page.set_content(
            '<html lang="en"><title>t</title><main><label>n <input type="text"></label><img src="data:," alt="x"></main></html>'
        )
        assert counts(scan(page, axe)) == {}
    finally:
        page.close()


def scan_every_scene(browser: Any, source: str, dark: bool) -> list[tuple[str, str, str, dict[str, Any]]]:
    """Every scene at every size of :data:`SIZES` in one look: (scene, look, size, rule -> (impact, count))."""
    rows = []
    with running_app(scene_names()[0], dark=dark) as app:
        for width, height in SIZES:
            page, _ = open_page(browser, app, viewport={"width": width, "height": height})
            try:
                for name in scene_names():
                    show(page, app, name)
                    found = {v["id"]: (v["impact"], v["count"], v["nodes"][:3]) for v in scan(page, source)}
                    rows.append((name, "dark" if dark else "light", f"{width}×{height}", found))
            finally:
                page.close()
    return rows


@pytest.mark.parametrize("dark", [False, True], ids=["light", "dark"])
def test_no_wcag_violation_in_any_scene_at_either_size(chromium, axe, dark) -> None:
    """Item 1: zero WCAG 2.0/2.1 A and AA violations in every scene, at 1280×800 and on a 390×844 phone."""
    rows = scan_every_scene(chromium, axe, dark)
    assert len(rows) == len(scene_names()) * len(SIZES)
    found = [row for row in rows if row[3]]
    assert found == [], "\n".join(map(str, found))


PLOT_TEXT = """() => [...document.querySelectorAll('.u-title, .u-legend th, .u-legend td')]
    .filter(e => e.textContent.trim()).map(e => parseFloat(getComputedStyle(e).fontSize))"""

WORDS = "() => !!document.querySelector('.rbl-motion') && document.querySelector('.rbl-motion').textContent !== ''"


def settled_scan(page: Any, source: str) -> dict[str, Any]:
    page.wait_for_function(WORDS, timeout=30_000)
    time.sleep(0.5)
    return {v["id"]: (v["impact"], v["count"], v["nodes"][:3]) for v in scan(page, source)}


def test_no_wcag_violation_with_folders_open_a_notification_shown_and_on_the_phone_sheet(chromium, axe) -> None:
    """Item 1: the State and Export folders open and one of the app's notifications shown; on the phone,
    the Clock's buttons scrolled into view (axe-core measures the contrast of what is on screen only)."""
    with running_app("heavy_top") as app:
        for width, height in SIZES:
            page, client = open_page(chromium, app, viewport={"width": width, "height": height})
            try:
                settled_scan(page, axe)
                click(page.get_by_text("State", exact=True))
                click(page.get_by_text("Export a recording").first)
                page.get_by_role("button", name="Copy state").first.wait_for(state="visible", timeout=30_000)
                app.shared.notify("Refused", "a notification of the app's own, for the scan", client=client, error=True)
                page.get_by_text("a notification of the app's own").first.wait_for(timeout=30_000)
                page.get_by_role("button", name="Step").first.scroll_into_view_if_needed(timeout=30_000)
                assert settled_scan(page, axe) == {}, f"{width}×{height}"
                # Item 4: the plots' titles and legends (HTML; axe-core does not check a size) at 14 px.
                assert min(page.evaluate(PLOT_TEXT)) >= MIN_TEXT_PX
            finally:
                page.close()


@pytest.mark.parametrize(
    "mode",
    [{"presenter": True, "pin": "482913"}, {"private": True}, {"lecture": "rigid-body-motion"}],
    ids=["presenter-follower", "private", "lecture"],
)
def test_no_wcag_violation_as_a_follower_in_a_private_session_and_in_a_lecture(chromium, axe, mode) -> None:
    """Item 1: a follower in presenter mode (every control disabled), a private session, a lecture loaded."""
    with running_app("heavy_top", **mode) as app:
        page, _ = open_page(chromium, app, viewport={"width": 1280, "height": 800})
        try:
            assert settled_scan(page, axe) == {}
        finally:
            page.close()


def table() -> list[tuple[str, str, str, dict[str, tuple[str, int]]]]:
    """(scene, look, size, rule -> (impact, count)) for every scene, look and size."""
    source = axe_source()
    with launch_chromium() as browser:
        return [row for dark in (False, True) for row in scan_every_scene(browser, source, dark)]


if __name__ == "__main__":
    for name, look, size, found in table():
        cells = ", ".join(f"{rule} ({impact}) {n}" for rule, (impact, n, _) in sorted(found.items())) or "none"
        print(f"| {name} | {look} | {size} | {sum(n for _, n, _ in found.values())} | {cells} |")
