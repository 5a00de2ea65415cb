"""Composed views, measured with the camera each browser is framed with (app.serving.framing): in every scene
the body fills at least a third of the free view's height at 1280×800 with the panel open (a quarter on a
phone, above its bottom sheet), wholly inside that view; the racket's L-sphere is beside the racket, not on it.

The body's extent is its drawn bounding box's longer side: a racket spinning flat about its middle axis is
wide, not tall, for half of every turn. Projected from the body's posed mesh vertices, at t = 1 s (the pose
the browser tests photograph) and over the first 4 s.
"""

from __future__ import annotations

import numpy as np
import pytest
import viser
from scipy.spatial.transform import Rotation

from app import draw
from app.scenes import scene_names
from app.serving.framing import FOV, framed, free_region
from tests import harness
from tests.harness import open_scene, running_app

VIEWS = {"1280x800": (1280, 800, 1 / 3), "phone 390x664": (390, 664, 1 / 4)}
"""(width, height, least share of the free view's height the body spans). 390×664 is an iPhone 13's view
(390×844 less the browser's bars)."""


def project(points: np.ndarray, eye: np.ndarray, target: np.ndarray, width: float, height: float) -> np.ndarray:
    """Pixels (n, 2) where the browsers' camera (vertical field FOV) draws ``points`` (n, 3)."""
    return harness.project(points, eye, target, width, height, FOV)


def posed(handle) -> np.ndarray:
    """A mesh handle's vertices where it is drawn (its pose applied), m, shape (n, 3)."""
    w, x, y, z = handle.wxyz
    R = Rotation.from_quat([x, y, z, w]).as_matrix()
    return np.asarray(handle.vertices, dtype=float) @ R.T + np.asarray(handle.position, dtype=float)


def box(pixels: np.ndarray) -> tuple[float, float, float, float]:
    return float(pixels[:, 0].min()), float(pixels[:, 1].min()), float(pixels[:, 0].max()), float(pixels[:, 1].max())


@pytest.mark.parametrize("name", scene_names())
def test_the_body_fills_a_third_of_the_free_view_and_stays_in_it(name):
    with running_app(start_loop=False) as app:
        scene = open_scene(app, name)
        for label, (width, height, least) in VIEWS.items():
            eye, target = framed(*scene.camera, width, height, FOV, type(scene).view)
            left, top, right, bottom = free_region(width, height)
            for t in (1.0, 2.0, 3.0, 4.0) if not scene.static else (0.0,):
                app.simulation.set_time(t)
                app.simulation.request_redraw()
                app.frame(0.0)
                x0, y0, x1, y1 = box(project(posed(scene.body.handle), eye, target, width, height))
                share = max(x1 - x0, y1 - y0) / (bottom - top)
                if t == 1.0 or scene.static:  # the photographed pose: the body this large
                    assert share >= least, f"{name} at {label}: the body spans {share:.2f} of the free view"
                else:  # in motion it may turn edge-on, never to a sliver
                    assert share >= 0.6 * least, f"{name} at {label}, t = {t}: {share:.2f}"
                # Wholly in the free view (a pixel's rounding of slack).
                assert x0 >= left - 1 and x1 <= right + 1 and y0 >= top - 1 and y1 <= bottom + 1, (
                    f"{name} at {label}, t = {t}: body at {x0:.0f}-{x1:.0f} × {y0:.0f}-{y1:.0f}, free view "
                    f"{left:.0f}-{right:.0f} × {top:.0f}-{bottom:.0f}"
                )


def test_the_racket_l_sphere_is_drawn_beside_the_racket():
    with running_app(start_loop=False) as app:
        scene = open_scene(app, "tennis_racket")
        width, height = 1280, 800
        eye, target = framed(*scene.camera, width, height, FOV, type(scene).view)
        sphere = scene.sphere_centre + scene.sphere_radius * np.array(
            [[sx, sy, sz] for sx in (-1, 1) for sy in (-1, 1) for sz in (-1, 1)], dtype=float
        )
        sx0, sy0, sx1, sy1 = box(project(sphere, eye, target, width, height))
        for t in np.linspace(0.0, 8.0, 33):  # through a flip and back
            app.simulation.set_time(float(t))
            app.simulation.request_redraw()
            app.frame(0.0)
            bx0, _, bx1, _ = box(project(posed(scene.body.handle), eye, target, width, height))
            assert sx1 < bx0, f"t = {t:.2f}: the L-sphere ({sx0:.0f}-{sx1:.0f} px) reaches the racket ({bx0:.0f} px)"


GLYPH_PX = (11.0, 22.0)
"""A label's character width and line height, px, at draw.LABEL_SCALE (viser draws 14 px glyphs ×1.6 on a
quad with padding; measured on the browser tests' screenshots, rounded up)."""


def label_box(label, eye, target, width, height, ratio=1.0) -> tuple[float, float, float, float]:
    """The pixel box a label is drawn in, from its projected position, its anchor and its text's length
    (``ratio``: device pixels per CSS pixel, where the view's size is in device pixels)."""
    ((x, y),) = project(np.asarray([label.position], dtype=float), eye, target, width, height)
    w, h = ratio * GLYPH_PX[0] * len(label.text), ratio * GLYPH_PX[1]
    vertical, horizontal = label.anchor.split("-")
    x0 = {"left": x, "center": x - w / 2, "right": x - w}[horizontal]
    y0 = {"top": y, "center": y - h / 2, "bottom": y - h}[vertical]
    return x0, y0, x0 + w, y0 + h


def _overlap(a, b) -> bool:
    return a[0] < b[2] and b[0] < a[2] and a[1] < b[3] and b[1] < a[3]


@pytest.mark.parametrize("strike", [0.577, 0.4])
def test_the_pendulum_labels_neither_overlap_nor_sit_on_the_bat(strike):
    """At the lecture's key step (the strike point on the centre of percussion) and off it, through a swing."""
    with running_app(start_loop=False) as app:
        scene = open_scene(app, "pendulum")
        assert scene.params.offer({"strike": strike})
        width, height = 1280, 800
        eye, target = framed(*scene.camera, width, height, FOV, type(scene).view)
        labels = [scene.cm_label, scene.cop_label, scene.hit_label]
        for t in np.linspace(0.0, 1.6, 9):  # a whole swing of ±30°
            app.simulation.set_time(float(t))
            app.simulation.request_redraw()
            app.frame(0.0)
            boxes = [label_box(label, eye, target, width, height) for label in labels]
            for i in range(len(boxes)):
                for j in range(i):
                    assert not _overlap(boxes[i], boxes[j]), (t, labels[i].text, labels[j].text)
            bat = project(posed(scene.body.handle), eye, target, width, height)
            for label, b in zip(labels, boxes, strict=True):
                inside = (bat[:, 0] > b[0]) & (bat[:, 0] < b[2]) & (bat[:, 1] > b[1]) & (bat[:, 1] < b[3])
                assert not inside.any(), f"t = {t:.2f}: {label.text!r} is drawn on the bat"


def shown_labels(scene) -> list:
    """Every label the scene shows now: its own (kept as attributes, alone or in a list) and its arrows'."""
    found = []
    for value in vars(scene).values():
        for item in value if isinstance(value, list) else [value]:
            if isinstance(item, draw.Arrow) and item.label is not None:
                found.append(item.label)
            elif isinstance(item, viser.LabelHandle):
                found.append(item)
    return [label for label in found if label.visible]


@pytest.mark.parametrize("name", scene_names())
def test_no_two_labels_overlap_in_any_scene(name):
    """At 1280×800 with the panel open, through the first 4 s: no two shown labels' boxes intersect."""
    with running_app(start_loop=False) as app:
        scene = open_scene(app, name)
        width, height = 1280, 800
        eye, target = framed(*scene.camera, width, height, FOV, type(scene).view)
        for t in np.linspace(0.0, 4.0, 17) if not scene.static else (0.0,):
            app.simulation.set_time(float(t))
            app.simulation.request_redraw()
            app.frame(0.0)
            labels = shown_labels(scene)
            boxes = [label_box(label, eye, target, width, height) for label in labels]
            for i in range(len(boxes)):
                for j in range(i):
                    assert not _overlap(boxes[i], boxes[j]), (name, float(t), labels[i].text, labels[j].text)


def shown_arrows(scene) -> list:
    """Every arrow the scene draws now (kept as attributes, alone or in a list), longer than a hair."""
    found = []
    for value in vars(scene).values():
        for item in value if isinstance(value, list) else [value]:
            if isinstance(item, draw.Arrow) and item.handle.visible and item.length > 1e-6:
                found.append(item)
    return found


ARROW_VIEWS = {
    "1280x800": (1280, 800, 1.0),
    "phone 390x664": (390, 664, 1.0),
    "iPhone 13, device px": (1170, 1992, 3.0),
}
"""(width, height, device pixels per CSS pixel): a phone's browser reports its view in device pixels, while a
label keeps its size in CSS pixels."""


@pytest.mark.parametrize("name", scene_names())
@pytest.mark.parametrize("view", ARROW_VIEWS)
def test_every_arrow_and_its_label_stay_in_the_free_view(name, view):
    """With the panel open (at 1280×800 beside it, on a phone above its sheet), through the first 4 s: no
    vector runs under the panel or off the view."""
    with running_app(start_loop=False) as app:
        scene = open_scene(app, name)
        width, height, ratio = ARROW_VIEWS[view]
        mobile = ratio > 1.0
        eye, target = framed(*scene.camera, width, height, FOV, type(scene).view, mobile)
        left, top, right, bottom = free_region(width, height, mobile)
        for t in np.linspace(0.0, 4.0, 17) if not scene.static else (0.0,):
            app.simulation.set_time(float(t))
            app.simulation.request_redraw()
            app.frame(0.0)
            for arrow in shown_arrows(scene):
                ((x, y),) = project(np.asarray([arrow.tip], dtype=float), eye, target, width, height)
                assert left - 1 <= x <= right + 1 and top - 1 <= y <= bottom + 1, (
                    f"{name}, t = {t:.2f}: {arrow.text}'s tip at ({x:.0f}, {y:.0f}) px, free view "
                    f"{left:.0f}-{right:.0f} × {top:.0f}-{bottom:.0f}"
                )
                if arrow.label is not None and arrow.label.visible:
                    x0, y0, x1, y1 = label_box(arrow.label, eye, target, width, height, ratio)
                    assert x0 >= left - 1 and x1 <= right + 1 and y0 >= top - 1 and y1 <= bottom + 1, (
                        f"{name}, t = {t:.2f}: {arrow.label.text!r} at {x0:.0f}-{x1:.0f} × {y0:.0f}-{y1:.0f} px"
                    )
