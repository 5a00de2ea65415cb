"""WCAG 2.1 AA in the page: axe-core's WCAG 2.0/2.1 A and AA rules, injected into
headless Chromium (:mod:`tests.browser.axe_scan`), on the app's page.

``python -m tests.browser.test_accessibility [--before]`` prints the table of docs/accessibility.md (every mode,
scene, look and size; ``--before``: without the app's patch).
"""

from __future__ import annotations

from typing import Any

import pytest

from app.panel.look import MIN_TEXT_PX
from app.scenes import REGISTRY, scene_names
from tests.browser.axe_scan import axe_source, counts, scan
from tests.harness import launch_chromium, open_page, quiet, running_app, wait_for

pytestmark = pytest.mark.browser

SIZES = ((1280, 800), (390, 844))

WORDS = "() => { const el = document.querySelector('.rbl-motion'); return el ? el.textContent : null; }"


@pytest.fixture(scope="module")
def axe() -> str:
    return axe_source()


def show(page: Any, sim: Any, name: str) -> None:
    """Switch the simulation ``sim`` (the shared one, or a browser's own) to scene ``name`` and wait until the
    page shows it (its words and its folder)."""
    if sim.scene is None or sim.scene.name != name:
        sim.switch_scene(name)
    title, frames = REGISTRY[name].title, sim.frames
    # Its words are said. A still scene (the explorer) has no clock: it draws when asked to.
    wait_for(lambda: (sim.request_redraw(), sim.frames > frames + 1)[1], what=f"{name}'s first frames")
    # The words change as the motion goes (its last event): the page's are compared with the newest said.
    wait_for(lambda: page.evaluate(WORDS) == sim.panel.said, 30, what=f"{name}'s words in the page")
    page.get_by_text(title, exact=True).first.wait_for(state="visible", timeout=30_000)


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


PLOT_TEXT = """() => [...document.querySelectorAll('.u-title, .u-legend th, .u-legend td')]
    .filter(e => e.textContent.trim()).map(e => parseFloat(getComputedStyle(e).fontSize))"""

MODES = {
    "presenter-follower": {"presenter": True, "pin": "482913"},
    "private": {"private": True},
    "lecture": {"lecture": "rigid-body-motion"},
}
"""The modes of item 1 besides the shared page: a follower in presenter mode (every control disabled), a
private session (the browser's own simulation), the shipped lecture loaded (the shared page with its
Lecture folder)."""

ALL_MODES: dict[str, dict[str, Any]] = {"shared": {}, **MODES}
"""With the shared page as it opens on 127.0.0.1 (the lecture mode without its Lecture folder)."""

FOLDERS = ("State", "Export a recording")
CLOSED = """(titles) => [...document.querySelectorAll('.mantine-Paper-root[data-with-border] > .mantine-Paper-root:first-child')]
    .filter(h => titles.includes(h.textContent.trim()) && h.nextElementSibling
                 && h.nextElementSibling.hasAttribute('inert')).map(h => h.textContent.trim())"""
"""The titles of viser's folders (found by its markup, patched or not) among ``titles`` that are closed."""

OPEN = """(title) => { const h = [...document.querySelectorAll(
    '.mantine-Paper-root[data-with-border] > .mantine-Paper-root:first-child')].find(h => h.textContent.trim() === title);
  if (h) h.click(); }"""


def open_folders(page: Any) -> None:
    """The State and Export folders open (each title clicked once, then waited for)."""
    for title in page.evaluate(CLOSED, list(FOLDERS)):
        page.evaluate(OPEN, title)
    page.wait_for_function(f"() => ({CLOSED})({list(FOLDERS)!r}).length === 0", timeout=30_000)


def scan_mode(
    browser: Any, source: str, mode: str, dark: bool, every: bool = True
) -> list[tuple[str, str, str, str, dict[str, Any]]]:
    """Every scene at both sizes (``every``; otherwise the scenes :func:`pairwise` puts in this look, each at
    its size) in one mode and one look, on one page (resized), with the State and Export folders open and a
    notification of the app's own shown: (mode, scene, look, size, rule -> found)."""
    rows = []
    with running_app("heavy_top", dark=dark, **ALL_MODES[mode]) as app:  # type: ignore[arg-type]
        page, client = open_page(browser, app, viewport={"width": SIZES[0][0], "height": SIZES[0][1]})
        try:
            sim = (
                wait_for(lambda: app.sessions.get(client.client_id), what="the private session")
                if mode == "private"
                else app.shared
            )
            client.add_notification("Refused", "a notification of the app's own, for the scan", color="red")
            page.get_by_text("a notification of the app's own").first.wait_for(timeout=30_000)
            for size, (width, height) in enumerate(SIZES):
                page.set_viewport_size({"width": width, "height": height})
                for k, name in enumerate(scene_names()):
                    if not every and pairwise(list(MODES).index(mode), k) != (dark, size):
                        continue
                    show(page, sim, name)
                    open_folders(page)
                    sim.set_playing(False)  # a still page: the scan reads one layout
                    quiet(page)  # the panel's last re-render (a readout's last value) has landed
                    if width < 600:  # the phone's bottom sheet: the clock's buttons on screen for the contrast
                        page.get_by_role("button", name="Step").first.scroll_into_view_if_needed(timeout=30_000)
                    found = {v["id"]: (v["impact"], v["count"], v["nodes"][:3]) for v in scan(page, source)}
                    # Item 4: the plots' titles and legends (HTML; axe-core does not check a size) at 14 px.
                    small = [px for px in page.evaluate(PLOT_TEXT) if px < MIN_TEXT_PX]
                    if small:
                        found["plot-text-size"] = ("item 4", len(small), small[:3])
                    rows.append((mode, name, "dark" if dark else "light", f"{width}×{height}", found))
                    sim.set_playing(True)
        finally:
            page.close()
    return rows


def pairwise(mode: int, scene: int) -> tuple[bool, int]:
    """The look (dark?) and the size (index into :data:`SIZES`) the tests scan scene ``scene`` in, in mode
    ``mode`` (indices into :data:`MODES` and ``scene_names()``): a covering array of strength 2, so that
    every pair of values of two of mode, scene, look and size is scanned together at least once, in 18 scans
    where every combination takes 72."""
    return bool((scene + mode) % 2), (scene // 2 + mode) % 2


def test_the_pairwise_scans_cover_every_pair() -> None:
    """Each scene in both looks and at both sizes, each mode with every scene, both looks and both sizes,
    and every look at both sizes."""
    runs = [(m, k, *pairwise(m, k)) for m in range(len(MODES)) for k in range(len(scene_names()))]
    values = [range(len(MODES)), range(len(scene_names())), (False, True), range(len(SIZES))]
    for i in range(4):
        for j in range(i + 1, 4):
            assert {(r[i], r[j]) for r in runs} == {(a, b) for a in values[i] for b in values[j]}, (i, j)


@pytest.mark.parametrize("mode", list(MODES))
def test_no_wcag_violation_in_any_scene_as_a_follower_in_a_private_session_and_in_a_lecture(
    chromium, axe, mode
) -> None:
    """Item 1, with the State and Export folders open and a notification shown, as a follower in presenter
    mode, in a private session and with a lecture loaded: every scene, in the look and at the size of
    :func:`pairwise` (across the three modes every scene is scanned in both looks and at both sizes);
    ``python -m tests.browser.test_accessibility`` scans every combination (docs/accessibility.md)."""
    rows = [row for dark in (False, True) for row in scan_mode(chromium, axe, mode, dark, every=False)]
    assert [row[1] for row in rows] != [] and sorted(row[1] for row in rows) == sorted(scene_names())
    found = [row for row in rows if row[4]]
    assert found == [], "\n".join(map(str, found))


def table() -> list[tuple[str, str, str, str, dict[str, Any]]]:
    """(mode, scene, look, size, rule -> (impact, count, elements)) for every mode, scene, look and size."""
    source = axe_source()
    with launch_chromium() as browser:
        return [row for mode in ALL_MODES for dark in (False, True) for row in scan_mode(browser, source, mode, dark)]


if __name__ == "__main__":
    import sys

    import app.panel.look

    if "--before" in sys.argv:  # the page as viser 1.1.1 renders it, without the app's patch
        app.panel.look.PATCH = ""
    for mode, name, look, size, found in table():
        cells = ", ".join(f"{rule} ({impact}) {n}" for rule, (impact, n, _) in sorted(found.items())) or "none"
        print(f"| {mode} | {name} | {look} | {size} | {sum(n for _, n, _ in found.values())} | {cells} |", flush=True)
