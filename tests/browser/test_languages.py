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
from tests.browser.axe_scan import axe_source, counts, scan
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

UNITS = {"rad", "kg", "Hz", "CM", "RK", "RK4", "csv", "CSV", "ZIP", "zip", "phyphox", "PIN", "Rigid", "Body", "Lab"}
"""Tokens that are the same in every language: units, abbreviations, names (the product's)."""

PAGE_TEXT = "() => document.body.innerText"
"""What a reader sees: the visible text of the page (a pseudo-translated span may cross elements)."""


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
        left = english_left(page.evaluate(PAGE_TEXT))
        assert left == [], f"{name}: English left on the page: {left}"
    finally:
        page.close()


PIN = "482913"
LANG_OF_PAGE = "() => document.documentElement.lang"
LABELS = """() => [...document.querySelectorAll('label, button')].map(e => e.textContent.trim()).filter(t => t)"""


def test_a_follower_reading_spanish_follows_a_lecturer_reading_german(chromium: Any) -> None:
    """Presenter mode: the lecturer's page asks for German, the follower's for Spanish (their browsers'
    Accept-Language); each reads its own, the lecturer's scene switch reaches the follower, in Spanish, and
    the clock's time is written with a decimal comma on both."""
    with running_app("heavy_top", presenter=True, pin=PIN) as app:
        lecturer = open_in(chromium, app, LOCALES["de"])
        try:
            lecturer.wait_for_function(f"{LANG_OF_PAGE} === 'de'", timeout=60_000)
            pin_label = translate("Presenter PIN", "de")
            # viser breaks a label after its hyphens (<wbr>): the label's whole text, not one text node.
            pin_box = (
                f"xpath=//label[normalize-space(.)='{pin_label}']/ancestor::div[contains(@class,'Flex-root')][1]//input"
            )
            lecturer.locator(pin_box).first.fill(PIN)
            client_id = max(app.server.get_clients())
            wait_for(lambda: app.classroom._panels[client_id].pin.value == PIN, 30, what="the PIN")
            lecturer.get_by_role("button", name=translate("Present", "de")).first.click()
            wait_for(lambda: client_id in app.classroom.presenters, 30, what="the page to present")
            follower = open_in(chromium, app, LOCALES["es"])
            try:
                follower.wait_for_function(f"{LANG_OF_PAGE} === 'es'", timeout=60_000)
                app.simulation.switch_scene("tennis_racket")
                title = REGISTRY["tennis_racket"].title
                for page, lang in ((lecturer, "de"), (follower, "es")):
                    page.wait_for_function(
                        "(t) => document.body.innerText.includes(t)", arg=translate(title, lang), timeout=60_000
                    )
                    labels = page.evaluate(LABELS)
                    assert translate("Step", lang) in labels and "Step" not in labels
                    # The clock's time, a readout: "1,23" in both languages (a decimal comma).
                    page.wait_for_function(
                        """() => [...document.querySelectorAll('input[disabled]')].some(i => /^\\d+,\\d\\d$/.test(i.value))""",
                        timeout=60_000,
                    )
                assert translate(title, "de") != translate(title, "es")
            finally:
                follower.close()
        finally:
            lecturer.close()


@pytest.mark.parametrize("lang", ["de", "es", "zh"])
def test_axe_finds_nothing_in_each_language(chromium: Any, lang: str) -> None:
    """WCAG 2.1 AA in each language: the page's lang names it (3.1.1), every control is named in it."""
    with running_app("heavy_top") as app:
        page = open_in(chromium, app, LOCALES[lang])
        try:
            page.wait_for_function(f"{LANG_OF_PAGE} === '{lang}'", timeout=60_000)
            page.wait_for_function(
                "(t) => document.body.innerText.includes(t)", arg=translate("Step", lang), timeout=60_000
            )
            quiet(page, 0.5, 10.0)
            assert counts(scan(page, axe_source())) == {}
        finally:
            page.close()


OVERFLOW = """() => {
  const panel = [...document.querySelectorAll('.mantine-Paper-root')].find(p => p.textContent.includes('⟦'));
  const box = panel.getBoundingClientRect();
  return [...panel.querySelectorAll('label, button, p, span')]
    .filter(e => e.offsetParent !== null && e.textContent.trim())
    .filter(e => { const r = e.getBoundingClientRect(); return r.right > box.right + 1 || r.left < box.left - 1; })
    .map(e => e.textContent.trim().slice(0, 40));
}"""


def test_a_text_forty_percent_longer_still_fits_the_panel(chromium: Any, pseudo_app: Any) -> None:
    """Under the pseudo-locale every text is at least 40% longer: nothing spills out of the panel (labels and
    buttons wrap), so German, which runs about 30% longer than English, fits too."""
    page = open_in(chromium, pseudo_app)
    try:
        page.wait_for_function("() => document.documentElement.lang === 'en-XA'", timeout=60_000)
        quiet(page, 0.5, 10.0)
        assert page.evaluate(OVERFLOW) == []
    finally:
        page.close()
