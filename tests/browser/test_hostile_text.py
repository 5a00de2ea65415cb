"""Text is text, in Chromium (and a browser refused by a cap is told why, in its page): the payload corpus (tests/app/payloads.py; every payload sets
``window.__pwned`` if it runs) through the paths that write untrusted text, and no script runs in any page:
the sender's, a follower's, the teacher's after Spotlight. Each payload must show in the pages as the
characters it has (so it was rendered, as text); a raw payload put into a Markdown element at the end must
run (so the check would see a script that ran).
"""

from __future__ import annotations

import pytest
import trimesh

from app.guards.admission import Caps
from app.teaching.questions import check_ask
from tests.app.payloads import PAYLOADS
from tests.harness import open_page, raw_client, running_app, still_connected, wait_for

pytestmark = pytest.mark.browser

PIN = "Lab2718"
SMALL = {"width": 640, "height": 520}
MESH_NAME = PAYLOADS[7].removesuffix("x.stl") + " " + PAYLOADS[1] + " " + PAYLOADS[14] + ".stl"
"""A file name of three payloads (iframe srcdoc, a mixed-case img onerror, a Markdown image), 180 characters."""

PWNED = "() => window.__pwned !== undefined"


def _stl() -> bytes:
    return trimesh.creation.box(extents=(0.3, 0.2, 0.1)).export(file_type="stl")


def _upload(page, name: str) -> None:
    page.locator("input[type=file]").first.set_input_files(
        {"name": name, "mimeType": "application/octet-stream", "buffer": _stl()}
    )


def _shows(page, text: str) -> bool:
    """The page shows ``text`` as characters (in its panel's text, whitespace as the page lays it out)."""
    return " ".join(text.split()) in " ".join(page.inner_text("body").split())


def test_no_payload_runs_in_the_sender_or_a_follower(chromium):
    with running_app("inertia_explorer", presenter=True, pin=PIN) as app:
        sender, sender_client = open_page(chromium, app, viewport=SMALL)
        follower, _ = open_page(chromium, app, viewport=SMALL)
        pages = (sender, follower)
        try:
            assert app.classroom.present(sender_client, PIN)
            app.set_playing(False)  # two pages render on the CPU: less to draw
            _upload(sender, MESH_NAME)  # a mesh's file name: the sender uploads, every page shows the note
            wait_for(lambda: app.scene.label == MESH_NAME, 60, what="the upload to become the body")
            for page in pages:
                wait_for(lambda page=page: _shows(page, MESH_NAME), 30, what="the name in the note")
            # The status line every page shows (a refusal quoting a text): the whole corpus at once, each
            # payload then found as its own characters.
            app.simulation.notify("Refused", " | ".join(PAYLOADS), error=True)
            for page in pages:
                wait_for(lambda page=page: _shows(page, PAYLOADS[-1]), 30, what="the corpus in the status line")
                assert all(_shows(page, payload) for payload in PAYLOADS)
            ask = check_ask({"question": PAYLOADS[0], "choices": [PAYLOADS[2], PAYLOADS[12], PAYLOADS[5]]})
            app.questions.ask(ask, "panel")  # a question and its choices, in every follower's panel
            wait_for(lambda: all(_shows(follower, t) for t in (PAYLOADS[0], PAYLOADS[2])), 30, what="the question")
            for page in pages:
                assert not page.evaluate(PWNED), page
            # The check sees a script that runs: a payload written raw into a Markdown element (viser renders
            # an iframe's srcdoc, whose script sets the page's variable).
            app.simulation.status.content = PAYLOADS[7]
            wait_for(lambda: follower.evaluate(PWNED), 30, what="the raw payload to run (the check's control)")
        finally:
            for page in pages:
                page.close()


def test_no_payload_runs_in_the_teachers_page_after_spotlight(chromium):
    with running_app("inertia_explorer", private=True, pin=PIN) as app:
        student, student_client = open_page(chromium, app, viewport=SMALL)
        teacher, teacher_client = open_page(chromium, app, viewport={"width": 960, "height": 720})
        try:
            wait_for(lambda: len(app.sessions) == 2, 60, what="both sessions")
            for session in app.sessions.values():
                session.set_playing(False)
            own = app.sessions[student_client.client_id]
            _upload(student, MESH_NAME)
            wait_for(lambda: own.scene.label == MESH_NAME, 60, what="the student's upload")
            assert app.teacher.open_view(teacher_client, PIN)
            number = app.teacher.number_of(student_client.client_id)
            assert app.teacher.spotlight(teacher_client, str(number))
            mine = app.sessions[teacher_client.client_id]
            wait_for(lambda: getattr(mine.scene, "label", None) == MESH_NAME, 60, what="the spotlight")
            wait_for(lambda: _shows(teacher, MESH_NAME), 30, what="the name in the teacher's note")
            for page in (student, teacher):
                assert not page.evaluate(PWNED)
        finally:
            student.close()
            teacher.close()


def test_a_refused_browser_is_told_why_in_its_page(chromium):
    """Over a cap, the page says so (viser shows the reason of the close) and the others are not disturbed."""
    with running_app("heavy_top", caps=Caps(connections=1)) as app:
        with raw_client(app) as holder:  # the server's one place
            page = chromium.new_page(viewport=SMALL)
            try:
                page.goto(app.url, wait_until="domcontentloaded")
                words = "the server is full (1 browsers)"
                wait_for(lambda: words in page.inner_text("body"), 60, what="the refusal in the page")
                assert app.admission.refused["full"] >= 1
                assert still_connected(holder, app=app)
            finally:
                page.close()
