"""An absurd number typed into a slider's number box.

Before the input checks (:mod:`app.guards.inputs`), ``99999999999999999999999`` typed into a number box made
viser fail to encode the value it rebroadcast and close every other browser's connection (code 1011).
Two pages in Debian's headless Chromium: one types it, as a person does, and presses Enter; the value in
force is the slider's maximum (clamped on the server, shown back in that page), and the other page stays
connected and keeps receiving frames (its clock readout goes on). Every wait is on a condition.
"""

from __future__ import annotations

import pytest

from tests.harness import control_id, open_page, running_app, slider_value, wait_for

pytestmark = pytest.mark.browser

LABEL = "spin ω₃ (rad/s)"
ABSURD = "99999999999999999999999"


# Every read and the focus are one evaluation in the page: a page drawing the heavy top in software takes
# about a second a frame on a loaded machine, and a Playwright locator's several round trips to such a page
# (resolve, check, evaluate) took longer than 30 s in CI, where one evaluation takes about one frame.
NUMBER_BOX = """([id, focus]) => {
  const box = document.querySelector(`[id='${id}'] ~ * input.mantine-NumberInput-input`);
  if (!box) return null;
  if (focus) { box.scrollIntoView({block: 'center'}); box.focus(); box.select(); }
  return box.value;
}"""


def _number_box(page, label: str, focus: bool = False) -> str | None:
    """The text in the number box viser draws beside the slider labelled ``label`` (None while there is
    none); with ``focus`` the box is focused and its text selected first, as a click would (as
    :func:`tests.harness.slider_value` and ``nudge_slider`` do for a slider's thumb)."""
    return page.evaluate(NUMBER_BOX, [control_id(page, label), focus])


def _clock(page) -> float:
    """The time the page's clock readout shows, s (its text box is the input in the label's row)."""
    control_id(page, "Time (s)")  # waits for the readout to be drawn
    text = page.evaluate(
        """() => { for (const el of document.querySelectorAll('label[for]')) {
               if (el.textContent.trim() !== 'Time (s)') continue;
               const row = el.closest('.mantine-Flex-root');
               const box = row && row.querySelector('input');
               if (box) return box.value; }
             return null; }"""
    )
    return float(text) if text else 0.0


def test_an_absurd_number_typed_in_one_browser_is_clamped_and_the_other_browser_stays(chromium):
    with running_app("heavy_top") as app:
        typist, typist_client = open_page(chromium, app, viewport={"width": 1280, "height": 800})
        watcher, watcher_client = open_page(chromium, app, viewport={"width": 1024, "height": 768})
        try:
            slider = app.scene.params.sliders["spin"]
            maximum = float(slider.max)
            assert app.scene.params.values["spin"] < maximum
            wait_for(lambda: _clock(watcher) > 0.2, 30, what="the other page's clock to run")

            # Focus through the DOM (the panel re-renders every frame), select what is there, then type.
            wait_for(lambda: _number_box(typist, LABEL, focus=True) is not None, 60, what="the spin's number box")
            typist.keyboard.type(ABSURD)
            typist.keyboard.press("Enter")

            # The server clamps it to the slider's range: the scene takes the maximum ...
            wait_for(lambda: app.scene.params.values["spin"] == maximum, 30, what="the clamped spin in the scene")
            assert slider.value == maximum
            # ... and the page that typed it shows the value in force, in its slider and its number box.
            shown = f"{maximum:g}"
            wait_for(
                lambda: slider_value(typist, LABEL) == shown,
                30,
                what="the typing page's slider at the maximum",
            )
            typist.keyboard.press("Tab")  # leave the box, as a person does: it shows the value in force
            wait_for(lambda: _number_box(typist, LABEL) == shown, 30, what="the number box to show the maximum")

            # The other page is still connected, shows the same value, and its clock goes on.
            assert watcher_client.client_id in app.server.get_clients()
            assert typist_client.client_id in app.server.get_clients()
            wait_for(
                lambda: slider_value(watcher, LABEL) == shown,
                30,
                what="the other page's slider to follow",
            )
            now = _clock(watcher)
            wait_for(lambda: _clock(watcher) > now + 0.5, 30, what="the other page to keep receiving frames")
            assert not [m for m in app.messages if m[0] == "Paused"]
        finally:
            typist.close()
            watcher.close()
