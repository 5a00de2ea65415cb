"""Framing the camera clear of the panel (app.framing): the scene's look-at point lands at the centre of
the part of the view the panel leaves free, and the scene's own view fits in that part."""

from __future__ import annotations

import math

import numpy as np
import pytest

from app.framing import FILL, REFERENCE_ASPECT, SHEET_MARGIN_PX, framed, free_region

FOV = math.radians(50.0)
SCENE = ((1.9, -1.9, 1.45), (0.0, 0.0, 0.45))


def _pixel(point, eye, target, width, height):
    """Where a perspective camera (up +z, vertical field FOV) at ``eye`` looking at ``target`` draws ``point``."""
    forward = (target - eye) / np.linalg.norm(target - eye)
    right = np.cross(forward, (0.0, 0.0, 1.0))
    right /= np.linalg.norm(right)
    up = np.cross(right, forward)
    d = np.asarray(point) - eye
    depth = d @ forward
    scale = 0.5 * height / (math.tan(0.5 * FOV) * depth)
    return 0.5 * width + scale * (d @ right), 0.5 * height - scale * (d @ up)


@pytest.mark.parametrize(("width", "height"), [(1280, 800), (1024, 768), (390, 844), (1920, 1080)])
def test_the_look_at_point_is_drawn_at_the_centre_of_the_free_region(width, height):
    eye, target = framed(*SCENE, width, height, FOV)
    x, y = _pixel(np.array(SCENE[1]), eye, target, width, height)
    left, top, right, bottom = free_region(width, height)
    assert x == pytest.approx(0.5 * (left + right), abs=1e-6) and y == pytest.approx(0.5 * (top + bottom), abs=1e-6)
    # The camera looks along the scene's own line of sight, only backed off.
    original = np.subtract(*SCENE[::-1]) / np.linalg.norm(np.subtract(*SCENE[::-1]))
    np.testing.assert_allclose((target - eye) / np.linalg.norm(target - eye), original, atol=1e-12)
    back = np.linalg.norm(eye - target) / np.linalg.norm(np.subtract(*SCENE))
    assert back >= 1.0
    # What the scene framed (FILL of its 1280×800 view, at its own distance) fits in the free region.
    free_w, free_h = right - left, bottom - top
    metres_per_px = 2.0 * math.tan(0.5 * FOV) * np.linalg.norm(eye - target) / height
    own_half_height = math.tan(0.5 * FOV) * np.linalg.norm(np.subtract(*SCENE))
    assert 0.5 * free_w * metres_per_px >= FILL * REFERENCE_ASPECT * own_half_height * (1 - 1e-12)
    assert 0.5 * free_h * metres_per_px >= FILL * own_half_height * (1 - 1e-12)


def test_a_phone_frames_above_the_sheet_and_a_laptop_left_of_the_panel():
    assert free_region(390, 844) == (0.0, 0.0, 390.0, pytest.approx(0.4 * 844 - SHEET_MARGIN_PX))
    assert free_region(1280, 800) == (0.0, 0.0, 880.0, 800.0)


def test_an_unknown_view_size_leaves_the_camera_alone():
    eye, target = framed(*SCENE, 0, 0, FOV)
    np.testing.assert_array_equal(eye, SCENE[0]) and np.testing.assert_array_equal(target, SCENE[1])
