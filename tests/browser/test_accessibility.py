"""WCAG 2.1 AA in the page (issue 23, item 1): axe-core's WCAG 2.0/2.1 A and AA rules, injected into
headless Chromium (:mod:`tests.browser.axe_scan`), on the app's page.

``python -m tests.browser.test_accessibility`` prints the table of docs/accessibility.md (every scene,
light and dark, 1280×800 and 390×844).
"""

from __future__ import annotations

import sys
import time
from typing import Any

import pytest

from app.scenes import REGISTRY, scene_names
from tests.browser.axe_scan import axe_source, counts, scan
from tests.harness import launch_chromium, open_page, running_app, wait_for

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


def table() -> list[tuple[str, str, str, dict[str, tuple[str, int]]]]:
    """(scene, look, size, rule -> (impact, count)) for every scene, look and size."""
    rows = []
    source = axe_source()
    with launch_chromium() as browser:
        for dark in (False, True):
            with running_app(scene_names()[0], dark=dark) as app:
                for width, height in SIZES:
                    page, _ = open_page(browser, app, viewport={"width": width, "height": height})
                    for name in scene_names():
                        show(page, app, name)
                        found = {v["id"]: (v["impact"], v["count"]) for v in scan(page, source)}
                        rows.append((name, "dark" if dark else "light", f"{width}×{height}", found))
                        print(rows[-1], file=sys.stderr, flush=True)
                    page.close()
    return rows


if __name__ == "__main__":
    for name, look, size, found in table():
        cells = ", ".join(f"{rule} ({impact}) {n}" for rule, (impact, n) in sorted(found.items())) or "none"
        print(f"| {name} | {look} | {size} | {sum(n for _, n in found.values())} | {cells} |")
