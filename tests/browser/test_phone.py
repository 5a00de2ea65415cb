"""A phone for real: Chromium emulating an iPhone 13 with Playwright's own device descriptor (390×664 CSS px,
device pixel ratio 3, touch, a mobile user agent). viser reports its canvas in device pixels, so the page
that looked fine at a plain 390 px viewport framed the body for a 780 px desktop and hid it behind the panel.

Measured in the page's pixels: the body (a screenshot with it and one without) lies in the view above the
panel's sheet, at least a quarter of that view's height, cut off nowhere; a touch drag orbits the camera and
a tap on a slider's track sets the parameter where the finger is."""

from __future__ import annotations

import io

import numpy as np
import pytest
from PIL import Image

from app.serving.framing import SHEET_FRACTION, SHEET_MARGIN_PX, framing_of
from tests.browser.test_look import CLOSE_NOTIFICATIONS, body_pixels
from tests.harness import DEVICES, control_id, running_app, wait_for

pytestmark = pytest.mark.browser

PHONE = "iPhone 13"
SLIDER_TRACK = """(id) => { const root = document.getElementById(id);
    const track = root && root.querySelector('.mantine-Slider-track');
    if (!track) return null;
    track.scrollIntoView({block: 'center'});
    const r = track.getBoundingClientRect(); return [r.left, r.top, r.right, r.bottom]; }"""
"""The box of a slider's track (viser's slider root has the control's id), scrolled into the sheet's view."""


def test_an_iphone_shows_the_body_large_above_the_sheet_and_orbits_by_touch(chromium):
    device = DEVICES[PHONE]
    assert device["is_mobile"] and device["has_touch"] and device["device_scale_factor"] == 3
    width, height = device["viewport"]["width"], device["viewport"]["height"]
    free_height = (1.0 - SHEET_FRACTION) * height - SHEET_MARGIN_PX  # CSS px above the sheet
    with running_app("tennis_racket") as app:
        context = chromium.new_context(**device)
        page = context.new_page()
        before = set(app.server.get_clients())
        page.goto(app.url, wait_until="domcontentloaded")
        new = wait_for(lambda: set(app.server.get_clients()) - before, 60, what="the phone to connect")
        page.wait_for_selector("canvas", timeout=60_000)
        client = app.server.get_clients()[next(iter(new))]
        wait_for(lambda: client.camera.image_width > 0, 60, what="the phone's view size")
        # viser's canvas is in device pixels: more than the 576 px of its phone layout, yet a phone's.
        assert client.camera.image_width > 576 and framing_of(client).mobile
        for name in ("tennis_racket",):  # the smallest body on a phone (16 px tall before); each costs a minute
            mask, _, _ = body_pixels(page, app, name)
            scale = mask.shape[1] / width  # screenshot pixels per CSS px (3)
            ys, xs = np.nonzero(mask)
            assert len(xs) > 300, f"{name}: no body in the phone's view"
            top, bottom = ys.min() / scale, ys.max() / scale
            share = max(np.ptp(ys), np.ptp(xs)) / scale / free_height
            assert share >= 0.25, f"{name}: the body spans {share:.2f} of the view above the sheet"
            assert bottom <= free_height + 0.02 * height, f"{name}: the body reaches {bottom:.0f} px, under the sheet"
            # Cut off nowhere: no body pixel on the picture's edges.
            assert top > 0 and xs.min() > 0 and xs.max() < mask.shape[1] - 1, f"{name}: the body is cut off"

        # A touch drag across the free view orbits this page's camera.
        page.evaluate(CLOSE_NOTIFICATIONS)
        start = np.array(client.camera.position)
        box = page.locator("canvas").first.bounding_box()
        x, y = box["x"] + 0.3 * width, box["y"] + 0.5 * free_height
        session = context.new_cdp_session(page)
        for kind, dx in (
            ("touchStart", 0),
            ("touchMove", 40),
            ("touchMove", 80),
            ("touchMove", 120),
            ("touchEnd", 120),
        ):
            points = [] if kind == "touchEnd" else [{"x": x + dx, "y": y}]
            session.send("Input.dispatchTouchEvent", {"type": kind, "touchPoints": points})
        moved = wait_for(
            lambda: np.linalg.norm(np.array(client.camera.position) - start) > 0.05, 30, what="the camera to orbit"
        )
        assert moved

        # A tap on a parameter slider's track in the sheet sets it there, as a finger does.
        key, slider = next(iter(app.scene.params.sliders.items()))
        low, high = float(slider.min), float(slider.max)
        before_value = app.scene.params.values[key]
        track = page.evaluate(SLIDER_TRACK, control_id(page, slider.label))
        assert track is not None, f"no track for the slider {slider.label!r} on the phone"
        left, top, right, bottom = track
        aim = 0.8  # of the track's length from its start
        tap = {"x": left + aim * (right - left), "y": 0.5 * (top + bottom)}
        session.send("Input.dispatchTouchEvent", {"type": "touchStart", "touchPoints": [tap]})
        session.send("Input.dispatchTouchEvent", {"type": "touchEnd", "touchPoints": []})
        target = low + aim * (high - low)
        assert abs(before_value - target) > 0.05 * (high - low), "the slider already stands where the tap aims"
        wait_for(
            lambda: abs(app.scene.params.values[key] - target) <= 0.05 * (high - low),
            30,
            what=f"the slider {slider.label!r} at {target:g} after a tap (it was {before_value:g})",
        )
        assert Image.open(io.BytesIO(page.screenshot())).size == (3 * width, 3 * height)  # rendered at DPR 3
