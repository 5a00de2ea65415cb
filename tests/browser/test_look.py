"""The projector look in headless Chromium (issue 12): the body's contrast against what is behind it,
the panel's text size, the body framed clear of the panel, the key controls above the fold, the panel
collapsible, at 1280×800, 1024×768 and on a 390×844 phone, light and dark."""

from __future__ import annotations

import io
import time

import numpy as np
import pytest
from PIL import Image
from scipy.ndimage import binary_erosion

from app.framing import free_region
from app.look import MIN_TEXT_PX
from tests.harness import click, control_id, open_page, running_app, wait_for

pytestmark = pytest.mark.browser

VIEWS = [(1280, 800), (1024, 768), (390, 844)]

CLOSE_NOTIFICATIONS = "() => document.querySelectorAll('.mantine-Notification-closeButton').forEach(b => b.click())"
OPEN_NOTIFICATIONS = "() => document.querySelectorAll('.mantine-Notification-root').length"

PANEL_RECT = """(id) => { const p = document.getElementById(id).closest('.mantine-Paper-root');
    const r = p.getBoundingClientRect(); return [r.left, r.top, r.right, r.bottom]; }"""

SMALLEST_TEXT = """(id) => { const panel = document.getElementById(id).closest('.mantine-Paper-root');
    const bounds = panel.getBoundingClientRect(); let smallest = 1e9, where = '';
    for (const el of panel.querySelectorAll('*')) {
      const own = [...el.childNodes].some(n => n.nodeType === 3 && n.textContent.trim());
      const r = el.getBoundingClientRect();
      if (!own || r.height === 0 || r.bottom < bounds.top || r.top > bounds.bottom) continue;
      const size = parseFloat(getComputedStyle(el).fontSize);
      if (size < smallest) { smallest = size; where = el.textContent.trim().slice(0, 40); }
    }
    return [smallest, where]; }"""


def _shot(page) -> np.ndarray:
    return np.asarray(Image.open(io.BytesIO(page.screenshot())).convert("RGB")).astype(float)


def _luminance(rgb: np.ndarray) -> np.ndarray:
    """WCAG 2 relative luminance of sRGB pixels (..., 3) in 0-255."""
    c = rgb / 255.0
    linear = np.where(c <= 0.04045, c / 12.92, ((c + 0.055) / 1.055) ** 2.4)
    return linear @ np.array([0.2126, 0.7152, 0.0722])


def body_pixels(page, app) -> tuple[np.ndarray, np.ndarray, np.ndarray]:
    """(mask, with the body, without it): the clock paused, the body shown, then hidden."""
    with app.lock:
        app.set_playing(False)
    # viser's "software WebGL" notice (headless Chromium has no GPU) may arrive late and cover the body.
    page.evaluate(CLOSE_NOTIFICATIONS)
    time.sleep(1.0)
    assert page.evaluate(OPEN_NOTIFICATIONS) == 0
    shown = _shot(page)
    with app.lock:
        app.scene.body.handle.visible = False
    time.sleep(1.0)
    hidden = _shot(page)
    with app.lock:
        app.scene.body.handle.visible = True
        app.set_playing(True)
    mask = np.abs(shown - hidden).max(axis=-1) > 24
    return mask, shown, hidden


def contrast(mask: np.ndarray, shown: np.ndarray, hidden: np.ndarray) -> float:
    """WCAG contrast ratio between the body's median luminance and that of what is behind it, over the
    body's inner pixels (two pixels in from its outline: no antialiased edge)."""
    inner = binary_erosion(mask, iterations=2)
    body, behind = np.median(_luminance(shown[inner])), np.median(_luminance(hidden[inner]))
    bright, dark = max(body, behind), min(body, behind)
    return float((bright + 0.05) / (dark + 0.05))


@pytest.mark.parametrize("dark", [False, True], ids=["light", "dark"])
@pytest.mark.parametrize(("width", "height"), VIEWS, ids=[f"{w}x{h}" for w, h in VIEWS])
def test_body_contrast_text_size_and_framing(chromium, width, height, dark) -> None:
    with running_app("heavy_top", dark=dark) as app:
        page, _ = open_page(chromium, app, viewport={"width": width, "height": height})
        scene_id = control_id(page, "Scene")
        time.sleep(2.0)
        mask, shown, hidden = body_pixels(page, app)
        assert binary_erosion(mask, iterations=2).sum() > 300, "the body is not in the view"
        ratio = contrast(mask, shown, hidden)
        print(f"{width}x{height} {'dark' if dark else 'light'}: body contrast {ratio:.2f}:1")
        assert ratio >= 3.0
        # Framed clear of the panel: no pixel of the body under it.
        left, top, right, bottom = page.evaluate(PANEL_RECT, scene_id)
        ys, xs = np.nonzero(mask)
        under = (xs >= left) & (xs <= right) & (ys >= top) & (ys <= bottom)
        assert not under.any(), f"{under.sum()} body pixels under the panel {left, top, right, bottom}"
        free = free_region(width, height)
        assert xs.max() <= free[2] and ys.max() <= free[3] + 0.02 * height
        smallest, where = page.evaluate(SMALLEST_TEXT, scene_id)
        assert smallest >= MIN_TEXT_PX, f"{smallest} px text in the panel: {where!r}"
        page.close()


def test_key_controls_above_the_fold_and_the_panel_collapses(chromium) -> None:
    with running_app("heavy_top") as app:
        page, _ = open_page(chromium, app, viewport={"width": 1280, "height": 800})
        scene_id = control_id(page, "Scene")
        panel_bottom = page.evaluate(PANEL_RECT, scene_id)[3]
        for label in ("Scene", "spin ω₃ (rad/s)", "tilt θ₀ (°)"):
            box = page.locator(f"[id='{control_id(page, label)}']").bounding_box()
            assert box is not None and box["y"] + box["height"] <= min(panel_bottom, 800), label
        for name in ("Pause", "Reset"):
            box = page.get_by_role("button", name=name).first.bounding_box()
            assert box is not None and box["y"] + box["height"] <= min(panel_bottom, 800), name
        click(page.get_by_label("Minimize panel"))
        wait_for(
            lambda: not page.get_by_role("button", name="Reset").first.is_visible(), 10, what="the panel to collapse"
        )
        page.close()
