"""Every mode under the pseudo-locale in real Chromium: no English is left in any step of the shipped lecture
(its captions and questions), in the presenter's panel and the follower's page, or in the teacher's view
and its table. The scenes themselves are checked in :mod:`tests.browser.test_languages`."""

from __future__ import annotations

from typing import Any

import pytest

from app.language.catalogs import PSEUDO
from app.language.words import translate
from tests.browser.test_languages import PAGE_TEXT, english_left, open_in
from tests.harness import quiet, running_app, wait_for

pytestmark = pytest.mark.browser

PIN = "482913"
IS_PSEUDO = f"() => document.documentElement.lang === '{PSEUDO}'"
SHOWS = "(t) => document.body.innerText.includes(t)"


def _box(label: str) -> str:
    """The input of the viser text box labelled ``label`` (its whole text: viser breaks a label with <wbr>)."""
    return f"xpath=//label[normalize-space(.)='{label}']/ancestor::div[contains(@class,'Flex-root')][1]//input"


def _english_on(page: Any, where: str) -> None:
    quiet(page, 0.5, 10.0)
    left = english_left(page.evaluate(PAGE_TEXT))
    assert left == [], f"{where}: English left on the page: {left}"


def test_no_english_is_left_in_any_step_of_the_lecture(chromium: Any) -> None:
    """``--lecture rigid-body-motion --lang en-XA``: every step, its caption, its question and choices, the
    step counter and Next/Previous, pseudo-translated."""
    with running_app(lecture="rigid-body-motion", lang=PSEUDO) as app:
        page = open_in(chromium, app)
        try:
            page.wait_for_function(IS_PSEUDO, timeout=60_000)
            sim = app.simulation
            steps = sim.lecture.steps
            asked = 0
            for index, step in enumerate(steps):
                if index:
                    app.go_to_step(index)
                wait_for(
                    lambda i=index, s=step: (
                        sim.step_index == i and sim.scene is not None and s.scene in (None, sim.scene.name)
                    ),
                    60,
                    what=f"step {index + 1}",
                )
                # The step's caption (its bold title, as the panel renders its Markdown) is on the page.
                title = translate(step.caption, PSEUDO).split("**")[1]
                page.wait_for_function(SHOWS, arg=title, timeout=60_000)
                if step.ask is not None:
                    asked += 1
                    page.wait_for_function(SHOWS, arg=translate(step.ask.text, PSEUDO), timeout=60_000)
                _english_on(page, f"lecture step {index + 1} ({step.scene})")
            assert asked >= 2  # the shipped lecture asks; its questions were read, not only its captions
        finally:
            page.close()


def test_no_english_is_left_in_the_presenters_panel_or_the_followers_page(chromium: Any) -> None:
    with running_app("heavy_top", presenter=True, pin=PIN, lang=PSEUDO) as app:
        lecturer = open_in(chromium, app)
        try:
            lecturer.wait_for_function(IS_PSEUDO, timeout=60_000)
            _english_on(lecturer, "the page before presenting")
            client_id = max(app.server.get_clients())
            lecturer.locator(_box(translate("Presenter PIN", PSEUDO))).first.fill(PIN)
            wait_for(lambda: app.classroom._panels[client_id].pin.value == PIN, 30, what="the PIN")
            lecturer.get_by_role("button", name=translate("Present", PSEUDO)).first.click()
            wait_for(lambda: client_id in app.classroom.presenters, 30, what="the page to present")
            follower = open_in(chromium, app)
            try:
                follower.wait_for_function(IS_PSEUDO, timeout=60_000)
                app.simulation.switch_scene("wobble")
                wait_for(lambda: app.scene is not None and app.scene.name == "wobble", 60, what="the wobble")
                for page, who in ((lecturer, "the presenter's page"), (follower, "the follower's page")):
                    _english_on(page, who)
            finally:
                follower.close()
        finally:
            lecturer.close()


TABLE_ROWS = "() => document.querySelectorAll('table.rbl-teacher tbody tr').length"


def test_no_english_is_left_in_the_teachers_view(chromium: Any) -> None:
    """``--private --pin``: a student's session and the teacher's page; the teacher's view, its table (the
    student's scene, its column heads) and its Spotlight, pseudo-translated."""
    with running_app("heavy_top", private=True, pin=PIN, lang=PSEUDO) as app:
        student = open_in(chromium, app)
        teacher = open_in(chromium, app)
        try:
            teacher_id = max(app.server.get_clients())
            teacher.wait_for_function(IS_PSEUDO, timeout=60_000)
            teacher.set_viewport_size({"width": 960, "height": 720})
            teacher.locator(_box(translate("Teacher PIN", PSEUDO))).first.fill(PIN)
            panel = app.teacher.panel_of(teacher_id)
            wait_for(lambda: panel.pin.value == PIN, 30, what="the PIN to arrive")
            teacher.get_by_role("button", name=translate("Open teacher's view", PSEUDO)).first.click()
            teacher.wait_for_function(f"{TABLE_ROWS} >= 1", timeout=60_000)
            _english_on(teacher, "the teacher's view")
            _english_on(student, "the student's page")
        finally:
            student.close()
            teacher.close()
