"""Every language in real Chromium: under the pseudo-locale no English is left on the page in any scene or
mode; a German lecturer and a Spanish follower each read their own language; the page's ``lang`` names it;
numbers are written as each language writes them; a text 40% longer still fits the panel; axe finds nothing
in each language."""

from __future__ import annotations

import re
from typing import Any

import pytest

from app.language.catalogs import PSEUDO
from app.language.pseudo import CLOSE, OPEN
from app.language.words import translate
from app.scenes import REGISTRY, scene_names
from tests.harness import VIEWPORT, quiet, running_app, wait_for

pytestmark = pytest.mark.browser

LOCALES = {"de": "de-DE", "es": "es-ES", "zh": "zh-CN"}

VISER_OWN = (
    "Connected",
    "Software WebGL rendering detected",
    "WebGL is running in software mode, not on your GPU. Performance may be degraded. If this is unexpected, "
    "check that hardware acceleration is enabled in your browser settings.",
)
"""viser's own words (its client's source, pinned with viser, writes them; no message carries them)."""

UNITS = {"rad", "kg", "Hz", "CM", "RK", "RK4", "csv", "CSV", "ZIP", "zip", "phyphox", "PIN"}
"""Tokens that are the same in every language: units, abbreviations, names."""

PANEL_TEXT = """() => {
  const root = document.querySelector('.mantine-ScrollArea-root') || document.body;
  return [...document.querySelectorAll('body *')]
    .filter(el => el.children.length === 0 && el.offsetParent !== null && el.textContent.trim())
    .map(el => el.textContent.trim()).join('\\n');
}"""


def english_left(text: str) -> list[str]:
    """The words of ``text`` outside every pseudo-translated span (⟦…⟧, nested), that look English."""
    for own in VISER_OWN:
        text = text.replace(own, " ")
    previous = None
    while previous != text:  # innermost spans first: a said text holds said texts
        previous = text
        text = re.sub(f"{OPEN}[^{OPEN}{CLOSE}]*{CLOSE}", " ", text)
    return sorted({w for w in re.findall(r"[A-Za-z]{2,}", text) if w not in UNITS})


def test_the_check_finds_english_outside_the_brackets() -> None:
    assert english_left("⟦Šţéƥ··⟧ Step ⟦ñöŵ ⟦ĩñ⟧ ·⟧ 0.5 rad/s") == ["Step"]
    assert english_left("⟦Šţéƥ··⟧ 0.5 rad/s ω₃") == []


def open_in(chromium: Any, app: Any, locale: str | None = None) -> Any:
    before = set(app.server.get_clients())
    options: dict[str, Any] = {"viewport": VIEWPORT}
    if locale is not None:
        options["locale"] = locale
    page = chromium.new_page(**options)
    page.goto(app.url, wait_until="domcontentloaded")
    wait_for(lambda: set(app.server.get_clients()) - before, 90, what="the page to connect")
    page.wait_for_selector("canvas", timeout=90_000)
    return page


@pytest.fixture(scope="module")
def pseudo_app() -> Any:
    with running_app("heavy_top", lang="en-XA") as app:
        yield app


@pytest.mark.parametrize("name", scene_names())
def test_no_english_is_left_in_any_scene_under_the_pseudo_locale(chromium: Any, pseudo_app: Any, name: str) -> None:
    page = open_in(chromium, pseudo_app)
    try:
        sim = pseudo_app.simulation
        if sim.scene is None or sim.scene.name != name:
            sim.switch_scene(name)
        wait_for(lambda: sim.scene is not None and sim.scene.name == name, 60, what=f"{name} built")
        page.wait_for_function("() => document.documentElement.lang === 'en-XA'", timeout=60_000)
        # The scene's own folder is shown (its title, pseudo-translated), then the page is read.
        title = translate(REGISTRY[name].title, PSEUDO)
        page.wait_for_function("(t) => document.body.innerText.includes(t)", arg=title, timeout=60_000)
        quiet(page, 0.5, 10.0)
        left = english_left(page.evaluate(PANEL_TEXT))
        assert left == [], f"{name}: English left on the page: {left}"
    finally:
        page.close()
