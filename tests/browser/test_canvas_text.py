"""Text drawn on canvases, which axe-core cannot read: measured in the pixels.

* The plots' tick numbers (uPlot draws them on its canvas, in viser's grey 7 on white, grey 5 on the dark
  panel): at least 4.5:1 against the plot's background in both looks.
* The 3D view's labels (viser draws each as black glyphs on a white quad at 85 % opacity, over whatever is
  behind): at least 4.5:1 between the glyphs and their quad, and at least 14 px tall. Measured in the dark
  look, where the quad stands out from the background; in the light look the quad is white on the white
  background, so nothing behind it can be lighter or darker than what the dark look measures.

The pendulum shows both (its labels "CM", "centre of percussion", "strike point"; its energy drift plot).
"""

from __future__ import annotations

import io
import time
from typing import Any

import numpy as np
import pytest
import viser
from PIL import Image
from scipy import ndimage

from app.panel.look import MIN_TEXT_PX, PLOT_BACKGROUND, PLOT_LINE_CONTRAST
from app.panel.look import contrast as wcag
from app.scenes import scene_names
from tests.harness import open_page, running_app

pytestmark = pytest.mark.browser

WCAG_TEXT = 4.5
"""WCAG 2.1 1.4.3: the least contrast of normal text."""


def luminance(rgb: Any) -> np.ndarray:
    """WCAG's relative luminance of sRGB colours (..., 3) in 0-255."""
    c = np.asarray(rgb, dtype=float) / 255.0
    c = np.where(c <= 0.04045, c / 12.92, ((c + 0.055) / 1.055) ** 2.4)
    return c @ np.array([0.2126, 0.7152, 0.0722])


def contrast(a: Any, b: Any) -> float:
    """WCAG's contrast ratio of two sRGB colours."""
    la, lb = float(luminance(a)), float(luminance(b))
    return (max(la, lb) + 0.05) / (min(la, lb) + 0.05)


def test_contrast_is_wcags() -> None:
    """The measure itself: black on white 21:1, white on white 1:1, and WCAG's #767676 on white 4.54:1."""
    assert contrast((0, 0, 0), (255, 255, 255)) == pytest.approx(21.0)
    assert contrast((255, 255, 255), (255, 255, 255)) == pytest.approx(1.0)
    assert contrast((118, 118, 118), (255, 255, 255)) == pytest.approx(4.54, abs=0.005)


def picture(locator: Any) -> np.ndarray:
    return np.asarray(Image.open(io.BytesIO(locator.screenshot())).convert("RGB")).astype(int)


def tick_numbers(page: Any) -> list[float]:
    """For each plot: the contrast of its tick numbers (the y axis's strip, left 50 px) against its
    background (the strip's commonest colour)."""
    ratios = []
    for plot in page.locator(".uplot canvas").all():
        plot.scroll_into_view_if_needed(timeout=30_000)
        strip = picture(plot)[:, :50].reshape(-1, 3)
        colours, counts = np.unique(strip, axis=0, return_counts=True)
        background = colours[counts.argmax()]
        ink = strip[np.abs(luminance(strip) - luminance(background)).argmax()]
        ratios.append(contrast(background, ink))
    return ratios


def labels(view: np.ndarray) -> list[tuple[float, int]]:
    """For each line of label text in a dark-look 3D view: (contrast of the darkest glyph pixel of its quad
    against the quad, the height of the line's glyphs in px). Quads are bright regions (mean channel ≥ 200,
    and so is their median) at least 12 px tall; quads that touch make one region, whose runs of rows with
    glyphs in them are its lines."""
    found = []
    bright = view.mean(axis=2) >= 200
    regions, _ = ndimage.label(bright)
    for index, box in enumerate(ndimage.find_objects(regions), start=1):
        if box[0].stop - box[0].start < 12 or box[1].stop - box[1].start < 12:
            continue
        region = regions[box] == index
        quad = np.median(view[box][region], axis=0)
        if quad.mean() < 200:  # a lit face of the body, not a quad (mostly its glyph-free white)
            continue
        # The glyphs: the dark pixels the quad encloses (its holes), not the background around it.
        glyphs = ndimage.binary_fill_holes(region) & ~region & (view[box].mean(axis=2) < 100)
        if not glyphs.any():
            continue
        ratio = contrast(quad, view[box][glyphs][luminance(view[box][glyphs]).argmin()])
        rows = np.flatnonzero(glyphs.any(axis=1))
        for line in np.split(rows, np.flatnonzero(np.diff(rows) > 1) + 1):
            found.append((ratio, int(line[-1] - line[0] + 1)))
    return found


@pytest.mark.parametrize("dark", [False, True], ids=["light", "dark"])
def test_the_plots_numbers_and_the_3d_labels_are_readable(chromium, dark) -> None:
    with running_app("pendulum", dark=dark) as app:
        page, _ = open_page(chromium, app, viewport={"width": 1280, "height": 800})
        try:
            page.wait_for_function("() => window.rblAccess === true", timeout=30_000)
            page.locator(".uplot canvas").first.wait_for(timeout=30_000)
            time.sleep(2.0)  # the first frames drawn
            app.set_playing(False)
            ratios = tick_numbers(page)
            assert ratios and min(ratios) >= WCAG_TEXT, ratios
            if dark:
                page.locator("canvas[data-engine]").first.scroll_into_view_if_needed(timeout=30_000)
                found = labels(picture(page.locator("canvas[data-engine]").first))
                # "strike point", "CM", "centre of percussion": three lines, the tallest spans ascender to
                # descender (at least the 14 px of the panel's smallest text).
                assert len(found) >= 3, found
                assert min(r for r, _ in found) >= WCAG_TEXT, found
                assert max(h for _, h in found) >= MIN_TEXT_PX, found
        finally:
            page.close()


def plots(scene: Any) -> list[Any]:
    """The uPlot handles a scene holds (its own, its drift plot's, its integrator ghost's)."""
    found, seen = [], set()
    todo = list(vars(scene).values())
    for _ in range(3):  # the scene's attributes, theirs, and theirs
        nxt = []
        for value in todo:
            if id(value) in seen or isinstance(value, (str, bytes, int, float, np.ndarray)):
                continue
            seen.add(id(value))
            if isinstance(value, viser.GuiUplotHandle):
                found.append(value)
            elif hasattr(value, "__dict__") and type(value).__module__.startswith("app."):
                nxt.extend(vars(value).values())
        todo = nxt
    return found


@pytest.mark.parametrize("dark", [False, True], ids=["light", "dark"])
def test_every_plot_line_has_3_to_1_against_the_plot(dark) -> None:
    """Item 4's graphics (WCAG 1.4.11): each line of each scene's plots against the look's plot background
    (#ffffff, #242424), as the page gets it. Headless: the colours the server sends."""
    lines = []
    with running_app(start_loop=False, dark=dark) as app:
        for name in scene_names():
            app.switch_scene(name)
            for plot in plots(app.scene):
                lines += [(name, s["label"], s["stroke"]) for s in plot.series if s.get("stroke")]
    assert {name for name, _, _ in lines} >= {"heavy_top", "tennis_racket", "wobble", "pendulum"}
    low = [(n, label, c, round(wcag(c, PLOT_BACKGROUND[dark]), 2)) for n, label, c in lines]
    assert all(r >= PLOT_LINE_CONTRAST for *_, r in low), [x for x in low if x[-1] < PLOT_LINE_CONTRAST]
