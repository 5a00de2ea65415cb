"""The teacher's view in real browsers: five students' pages and a teacher's page of one ``--private --pin``
server; the teacher's table lists the five with their scenes and a typed name, and Spotlight brings a
student's scene into the teacher's own view."""

from __future__ import annotations

import pytest

from app.scenes import REGISTRY
from tests.harness import click, control_id, running_app, wait_for

pytestmark = pytest.mark.browser

PIN = "Lab2718"
SCENES = ("heavy_top", "wobble", "pendulum", "tennis_racket", "inertia_explorer")


def _box(label: str) -> str:
    """The text input of the viser text box labelled ``label``."""
    return f"xpath=//label[text()=\"{label}\"]/ancestor::div[contains(@class,'Flex-root')][1]//input"


def _table_rows(page) -> list[str]:
    return page.evaluate("() => [...document.querySelectorAll('table.rbl-teacher tbody tr')].map(tr => tr.innerText)")


def _picked(page, title: str) -> bool:
    """Whether the page's scene picker shows ``title`` (the table has no inputs: only the picker can)."""
    return page.evaluate("(text) => [...document.querySelectorAll('input')].some(i => i.value === text)", title)


def _page_of(pages: list, number: int):
    """The page that shows ``Session number`` (its own session's number)."""
    mine = f"Session {number}"
    return wait_for(
        lambda: next((page for page in pages if page.get_by_text(mine, exact=True).count()), None),
        60,
        what=f"the page of session {number}",
    )


def _open_pages(browser, app, count: int, viewport: dict) -> tuple[list, set]:
    """``count`` pages of the app loading side by side (quicker than one after the other on a loaded
    machine); the pages and their client ids, once all are connected. Each page draws in software and takes
    what CPU it can: seven loading at once on two loaded cores took more than a minute in CI."""
    before = set(app.server.get_clients())
    pages = []
    for _ in range(count):
        page = browser.new_page(viewport=viewport)
        page.goto(app.url, wait_until="commit")
        pages.append(page)
    wait_for(lambda: len(set(app.server.get_clients()) - before) == count, 180, what=f"{count} pages to connect")
    return pages, set(app.server.get_clients()) - before


def test_a_teacher_sees_five_sessions_and_spotlights_one(chromium):
    with running_app("heavy_top", private=True, pin=PIN) as app:
        small = {"width": 480, "height": 400}  # six pages render on the CPU (SwiftShader): keep them small
        pages, ids = _open_pages(chromium, app, len(SCENES) + 1, small)
        try:
            wait_for(lambda: all(app.teacher.number_of(cid) for cid in ids), 60, what="the sessions' numbers")
            *students, teacher_id = sorted(ids, key=app.teacher.number_of)  # the last to connect teaches
            for cid in ids:
                app.sessions[cid].set_playing(False)  # paused, a page re-renders only on changes: less CPU
            for cid, scene in zip(students, SCENES, strict=True):
                if scene != "heavy_top":
                    app.sessions[cid].switch_scene(scene)
            # The first student types a name in its own page; the teacher types the PIN in theirs.
            first, teacher = (_page_of(pages, app.teacher.number_of(cid)) for cid in (students[0], teacher_id))
            teacher.set_viewport_size({"width": 960, "height": 720})  # the projector's page: room for the table
            first.locator(_box("Your name")).first.fill("Ada Lovelace")
            teacher.locator(_box("Teacher PIN")).first.fill(PIN)
            panel = app.teacher.panel_of(teacher_id)
            wait_for(lambda: app.teacher.name_of(students[0]) == "Ada Lovelace", what="the typed name")
            wait_for(lambda: panel.pin.value == PIN, what="the PIN to arrive")
            click(teacher.get_by_role("button", name="Open teacher's view"))

            # The table: the five students (not the teacher), each with its scene, the name where typed.
            rows = wait_for(lambda: len(_table_rows(teacher)) == 5 and _table_rows(teacher), what="five rows")
            numbers = [app.teacher.number_of(cid) for cid in students]
            for number, scene, row in zip(numbers, SCENES, rows, strict=True):
                assert row.split()[0] == str(number) and REGISTRY[scene].title in row
            assert "Ada Lovelace" in rows[0] and "(paused)" in rows[0]

            # Spotlight the tennis racket's session: the teacher's own view switches to it.
            racket = numbers[SCENES.index("tennis_racket")]
            click(teacher.locator(f"[id='{control_id(teacher, 'Session')}']"))
            teacher.get_by_role("option", name=str(racket), exact=True).first.click(force=True, timeout=30_000)
            wait_for(lambda: panel.choice.value == str(racket), what="the choice to arrive")
            click(teacher.get_by_role("button", name="Spotlight"))
            own = app.sessions[teacher_id]
            wait_for(lambda: getattr(own.scene, "name", None) == "tennis_racket", what="the spotlight")
            title = REGISTRY["tennis_racket"].title
            wait_for(lambda: _picked(teacher, title), what="the teacher's page to show the racket")
            assert app.sessions[students[SCENES.index("tennis_racket")]].scene.name == "tennis_racket"
        finally:
            for page in pages:
                page.close()
        wait_for(lambda: not app.sessions, what="every session to be freed")
