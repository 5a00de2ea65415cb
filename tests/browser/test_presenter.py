"""Presenter mode in real browsers: a follower cannot drive the lecture; with the PIN it can; a student
exploring on their own changes only their copy."""

from __future__ import annotations

import pytest

from tests.harness import click, nudge_slider, open_page, running_app, slider_disabled, wait_for

pytestmark = pytest.mark.browser

PIN = "2718"
SPIN = "spin ω₃ (rad/s)"


def _disabled(page) -> bool:
    return slider_disabled(page, SPIN) is True


def _enabled(page) -> bool:
    return slider_disabled(page, SPIN) is False


def test_a_follower_drives_only_with_the_pin_and_an_explorer_only_their_copy(chromium):
    with running_app("heavy_top", presenter=True, pin=PIN) as app:
        small = {"width": 800, "height": 640}
        lecturer, lecturer_client = open_page(chromium, app, viewport=small)
        try:
            wait_for(lambda: _disabled(lecturer), what="the lecture's slider to be disabled for a follower")
            spin = app.scene.params.values["spin"]
            nudge_slider(lecturer, SPIN)
            # A disabled slider takes no key; had a value been sent, the server would refuse it anyway.
            wait_for(lambda: app.frames > 30, what="frames")
            assert app.scene.params.values["spin"] == spin
            pin_box = "xpath=//label[text()='Presenter PIN']/ancestor::div[contains(@class,'Flex-root')][1]//input"
            lecturer.locator(pin_box).first.fill(PIN)
            wait_for(
                lambda: app.classroom._panels[lecturer_client.client_id].pin.value == PIN, what="the PIN to arrive"
            )
            click(lecturer.get_by_role("button", name="Present"))
            wait_for(lambda: lecturer_client.client_id in app.classroom.presenters, what="the page to present")
            wait_for(lambda: _enabled(lecturer), what="the slider to be enabled with the PIN")
            nudge_slider(lecturer, SPIN, times=3)
            wait_for(lambda: app.scene.params.values["spin"] > spin, what="the presenter's change")
            lecturer.get_by_text("Presenting.").first.wait_for(timeout=30_000)
            app.set_playing(False)  # two pages render on the CPU: let the second one have it

            student, student_client = open_page(chromium, app, viewport=small)
            try:
                wait_for(lambda: _disabled(student), what="the student to follow read-only")
                click(student.get_by_role("button", name="Explore on my own"))
                wait_for(lambda: student_client.client_id in app.sessions, what="the student's copy")
                copy = app.sessions[student_client.client_id]
                wait_for(lambda: _enabled(student), what="the copy's own slider, enabled")
                lecture_spin = app.scene.params.values["spin"]
                assert copy.scene.params.values["spin"] == lecture_spin
                nudge_slider(student, SPIN, key="ArrowLeft", times=2)
                wait_for(lambda: copy.scene.params.values["spin"] < lecture_spin, what="the student's change")
                assert app.scene.params.values["spin"] == lecture_spin
                click(student.get_by_role("button", name="Follow the lecturer"))
                wait_for(lambda: student_client.client_id not in app.sessions, what="the copy to be dropped")
                wait_for(lambda: _disabled(student), what="the lecture back, read-only")
            finally:
                student.close()
        finally:
            lecturer.close()
