"""Browser tests: the app driven in Debian's headless Chromium through Playwright.

One server (with its real-time loop) and one browser serve the whole module (fixtures ``live_app`` and
``chromium`` in conftest.py); tests run in file order and each says which scene it starts from.
Skipped when /usr/bin/chromium is missing, except under RBL_REQUIRE_BROWSER=1 (CI), where that fails.
"""

from __future__ import annotations

import pytest

from app.scenes import REGISTRY
from tests.harness import image_difference, image_stats, nudge_slider, open_page, pick_scene, slider_value, wait_for

pytestmark = pytest.mark.browser

RENDER = (240, 320)  # height, width of the renders we ask the page for


@pytest.fixture(scope="module")
def page_and_client(live_app, chromium):
    page, client = open_page(chromium, live_app)
    yield page, client
    page.close()


def test_page_loads_with_the_picker_and_the_clock(live_app, page_and_client):
    page, client = page_and_client
    assert client.client_id in live_app.server.get_clients()
    page.get_by_text("Rigid Body Lab").first.wait_for()
    for label in ("Pause", "Step", "Reset"):  # exact: "Step back" is another button
        assert page.get_by_role("button", name=label, exact=True).count() == 1
    assert page.locator("input[value='Heavy top']").count() >= 1  # the visible input and Mantine's hidden one


def test_scene_renders_and_moves(live_app, page_and_client):
    _, client = page_and_client
    live_app.set_playing(True)
    first = client.get_render(*RENDER, timeout=30)
    wait_for(lambda: live_app.time > 0.5, what="the clock to run")
    t = live_app.time
    wait_for(lambda: live_app.time > t + 0.5, what="half a second of motion")
    second = client.get_render(*RENDER, timeout=30)
    # Not blank: a single-colour image has std 0; ours has the grid, the top, arrows and the trace.
    assert image_stats(first) > 5.0 and image_stats(second) > 5.0
    # The top precessed and nutated between the two renders: the pictures differ.
    assert image_difference(first, second) > 0.2


def test_moving_a_slider_in_the_page_changes_the_simulation(live_app, page_and_client):
    page, _ = page_and_client
    scene = live_app.scene
    assert scene.name == "heavy_top"
    spin = scene.params.values["spin"]
    nudge_slider(page, "spin ω₃ (rad/s)", "ArrowRight")
    wait_for(lambda: live_app.scene.params.values["spin"] != spin, what="the server to see the slider")
    assert live_app.scene.params.values["spin"] == pytest.approx(spin + 0.1, abs=1e-9)
    assert live_app.scene.exact.L3 == pytest.approx(live_app.scene.top.I3 * (spin + 0.1), rel=1e-12)


def test_a_second_browser_sees_the_same_simulation(live_app, chromium, page_and_client):
    page, _ = page_and_client
    other, _ = open_page(chromium, live_app, viewport={"width": 700, "height": 900})  # tall: the slider is visible
    try:
        assert len(live_app.server.get_clients()) >= 2
        spin = live_app.scene.params.values["spin"]
        nudge_slider(page, "spin ω₃ (rad/s)", "ArrowRight")
        wait_for(lambda: live_app.scene.params.values["spin"] != spin, what="the slider change")
        expected = f"{live_app.scene.params.values['spin']:g}"
        wait_for(
            lambda: slider_value(other, "spin ω₃ (rad/s)") == expected,
            what="the other browser's slider to follow",
        )
    finally:
        other.close()


def test_an_impossible_body_from_the_page_is_refused(live_app, page_and_client):
    page, _ = page_and_client
    scene = live_app.scene
    I3 = scene.params.values["I3"]
    top = scene.top
    nudge_slider(page, "I₃ about the axis (kg m²)", "End")  # I3 = 1.0 > 2 I1 = 0.8
    page.get_by_text("no rigid body has these moments").first.wait_for(timeout=30_000)
    assert live_app.scene.top is top and live_app.scene.params.values["I3"] == I3
    wait_for(
        lambda: slider_value(page, "I₃ about the axis (kg m²)") == f"{I3:g}",
        what="the slider to snap back",
    )
    frames = live_app.frames
    wait_for(lambda: live_app.frames > frames + 5, what="the server to go on drawing")


def test_switching_scenes_in_the_page(live_app, page_and_client):
    page, client = page_and_client
    for name in ("wobble", "free_fall", "heavy_top"):
        pick_scene(page, REGISTRY[name].title)
        wait_for(
            lambda name=name: getattr(live_app.scene, "name", None) == name, what=f"the server to switch to {name}"
        )
        page.get_by_text(REGISTRY[name].caption.split("**")[1]).first.wait_for(timeout=30_000)
        assert image_stats(client.get_render(*RENDER, timeout=30)) > 5.0
