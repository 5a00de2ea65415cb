"""Framing the camera clear of the panel (app.serving.framing): the scene's look-at point lands at the centre of
the part of the view the panel leaves free, and the scene's own view fits in that part."""

from __future__ import annotations

import math

import numpy as np
import pytest

from app.serving import framing
from app.serving.framing import (
    FILL,
    LABEL_ROOM_PX,
    REFERENCE_ASPECT,
    SHEET_MARGIN_PX,
    framed,
    free_region,
    is_mobile,
    phone_layout,
)
from tests.harness import project

FOV = math.radians(50.0)
SCENE = ((1.9, -1.9, 1.45), (0.0, 0.0, 0.45))


def _pixel(point, eye, target, width, height):
    """Where a perspective camera (up +z, vertical field FOV) at ``eye`` looking at ``target`` draws ``point``."""
    x, y = project([point], eye, target, width, height, FOV)[0]
    return x, y


@pytest.mark.parametrize(("width", "height"), [(1280, 800), (1024, 768), (390, 844), (1920, 1080)])
def test_the_look_at_point_is_drawn_at_the_centre_of_the_free_region(width, height):
    eye, target = framed(*SCENE, width, height, FOV)
    x, y = _pixel(np.array(SCENE[1]), eye, target, width, height)
    left, top, right, bottom = free_region(width, height)
    top += LABEL_ROOM_PX  # the scene is framed below a label's line
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


class _Camera:
    def __init__(self, client, width, height):
        self.client, self.image_width, self.image_height = client, width, height
        self.position, self.look_at, self.fov = (3.0, -3.0, 2.0), (0.0, 0.0, 0.0), 0.9
        self.callbacks = []

    def on_update(self, callback):
        self.callbacks.append(callback)


class _Client:
    """What app.serving.framing.show_scene_to touches of a viser ClientHandle."""

    def __init__(self, width, height):
        self.camera = _Camera(self, width, height)

    def atomic(self):
        import contextlib

        return contextlib.nullcontext()

    def report(self, width, height, position=None):
        """The page reports a size (and where its camera is): viser runs the camera callbacks."""
        self.camera.image_width, self.camera.image_height = width, height
        if position is not None:
            self.camera.position = position
        for callback in self.camera.callbacks:
            callback(self.camera)


SCENE_EYE, SCENE_TARGET = (2.0, -2.0, 1.5), (0.0, 0.0, 0.5)


@pytest.fixture
def clock(monkeypatch):
    """``time.monotonic`` as a one-element list the test moves by hand (``clock[0] += 1.0``)."""
    import time

    now = [1000.0]
    monkeypatch.setattr(time, "monotonic", lambda: now[0])
    return now


def _framed_phone():
    """A phone's page (780×1328 device px) framed for the scene, and the eye it was framed at."""
    client = _Client(780, 1328)
    framing.show_scene_to(client, SCENE_EYE, SCENE_TARGET)
    return client, np.asarray(framing.framing_of(client).eye)


def test_a_page_is_reframed_for_its_settled_size_even_before_it_eased_to_the_first_framing(monkeypatch):
    """The page reports its first size, is framed, and reports its settled size while its camera is still
    on its way (not yet at the framed eye): within FRAMING_GRACE it is framed again for that size. After
    the grace, a camera away from the framed eye is the viewer's and a new size leaves it alone; an unmoved
    camera is re-framed."""
    import time

    from app.serving import framing
    from app.serving.framing import FRAMING_GRACE, show_scene_to

    now = [1000.0]
    monkeypatch.setattr(time, "monotonic", lambda: now[0])
    scene_eye, scene_target = (2.0, -2.0, 1.5), (0.0, 0.0, 0.5)
    client = _Client(800, 600)
    show_scene_to(client, scene_eye, scene_target)
    assert framing.framing_of(client).size == (800, 600)
    now[0] += 1.0
    client.report(1280, 800, position=(3.0, -3.0, 2.0))  # still easing: not at the eye framed for 800x600
    size, eye = framing.framing_of(client).size, framing.framing_of(client).eye
    assert size == (1280, 800) and np.array_equal(client.camera.position, eye)  # framed for the settled size
    np.testing.assert_allclose(eye, framing.framed(scene_eye, scene_target, 1280, 800, framing.FOV)[0])
    now[0] += FRAMING_GRACE + 1.0
    client.report(1024, 768, position=tuple(np.asarray(eye) + 0.5))  # the viewer orbited, then resized
    assert framing.framing_of(client).size == (1280, 800)  # theirs now: left alone
    client.camera.position = eye
    client.report(390, 844)  # unmoved: a new size re-frames it, grace or not
    assert framing.framing_of(client).size == (390, 844)


def test_a_new_pixel_ratio_keeps_the_framing_and_an_orbit_even_mid_drag(clock):
    """viser lowers a slow page's pixel ratio (and raises it again), often as a drag starts: the page reports
    its canvas at another scale, 780×1328 → 1023×1743 on an iPhone. Its layout in CSS px is unchanged, so the
    framing is kept (the size recorded) whether the camera is at the framed eye or orbited away from it."""
    now = clock
    client, eye = _framed_phone()
    now[0] += 0.5
    client.report(1023, 1743, position=tuple(np.float32(eye)))  # at the eye, at another pixel ratio
    assert framing.framing_of(client).size == (1023, 1743)
    np.testing.assert_array_equal(framing.framing_of(client).eye, eye)  # not framed again
    orbited = tuple(eye + (-1.5, -1.2, 0.0))
    now[0] += 0.5
    client.report(780, 1328, position=orbited)  # mid-drag, back to the first ratio
    assert framing.framing_of(client).size == (780, 1328)
    np.testing.assert_array_equal(client.camera.position, orbited)  # the viewer's orbit kept


def test_rescaled_is_the_same_shape_to_the_pixel_rounding_loses():
    assert framing.rescaled((780, 1328), (1023, 1743)) and framing.rescaled((1280, 800), (960, 600))
    assert framing.rescaled((1280, 800), (1119, 699))  # 0.875 of each, floored
    assert not framing.rescaled((1280, 800), (1024, 768)) and not framing.rescaled((780, 1328), (1328, 780))
    assert not framing.rescaled((780, 1328), (780, 1290))  # the sheet's browser bar: a new shape
    assert not framing.rescaled((0, 0), (1280, 800)) and not framing.rescaled((1280, 800), (0, 0))


def test_an_orbit_after_the_page_arrived_is_kept_when_its_shape_changes_within_the_grace(clock):
    """A phone turned (a new shape, not a new pixel ratio) soon after its framing: once the page had echoed the
    framed eye, a camera away from it is the viewer's and is kept, even within FRAMING_GRACE. An unmoved
    camera is framed for the new shape, and so is a page that had not yet arrived at its eye."""
    now = clock
    client, eye = _framed_phone()
    now[0] += 1.0
    client.report(780, 1328, position=tuple(np.float32(eye)))  # the page eased to the eye and echoed it
    assert framing.framing_of(client).arrived
    orbited = tuple(eye + (-1.5, -1.2, 0.0))
    now[0] += 1.0
    assert now[0] - framing.framing_of(client).when < framing.FRAMING_GRACE
    client.report(1688, 780, position=orbited)  # orbited, then turned sideways
    assert framing.framing_of(client).size == (780, 1328)
    np.testing.assert_array_equal(client.camera.position, orbited)  # the viewer's orbit kept
    client.camera.position = framing.framing_of(client).eye
    client.report(1688, 780)  # unmoved: framed for the new shape
    assert framing.framing_of(client).size == (1688, 780) and not framing.framing_of(client).arrived

    other, _ = _framed_phone()  # never arrived: a new shape within the grace frames it wherever its camera is
    now[0] += 1.0
    other.report(1688, 780, position=orbited)
    assert framing.framing_of(other).size == (1688, 780)
    np.testing.assert_allclose(
        other.camera.position, framing.framed(SCENE_EYE, SCENE_TARGET, 1688, 780, framing.FOV)[0]
    )


def test_a_page_put_back_on_the_first_view_is_framed_again_for_its_size(monkeypatch):
    """viser's client resets its camera to the initial one (the first view, framed for 1280×800) when the
    scene's root arrives, which can come after the page was framed for its own size: the echo of the first
    view, at the same size, re-frames it; any other camera the viewer moved to is left alone."""
    import time

    from app.serving import framing
    from app.serving.framing import FRAMING_GRACE, first_view, show_scene_to

    now = [1000.0]
    monkeypatch.setattr(time, "monotonic", lambda: now[0])
    scene_eye, scene_target = (2.0, -2.0, 1.5), (0.0, 0.0, 0.5)
    client = _Client(390, 844)
    show_scene_to(client, scene_eye, scene_target)
    phone_eye = framing.framed(scene_eye, scene_target, 390, 844, framing.FOV)[0]
    start = first_view(scene_eye, scene_target)[0]
    assert np.linalg.norm(phone_eye - start) > 0.1  # the phone's framing is not the first view
    now[0] += FRAMING_GRACE + 5.0
    client.report(390, 844, position=tuple(np.float32(start)))  # the page reset itself to the first view
    np.testing.assert_allclose(client.camera.position, phone_eye, rtol=1e-12)
    assert framing.framing_of(client).size == (390, 844)
    moved = tuple(np.asarray(phone_eye) + 0.3)
    client.camera.position = moved
    client.report(390, 844, position=moved)  # an orbit by the viewer: theirs
    np.testing.assert_allclose(client.camera.position, moved, rtol=0)


def test_a_phone_is_laid_out_as_one_whatever_its_device_pixels():
    """viser reports device pixels: an iPhone's 390 CSS px arrive as 780; its user agent says it is a phone."""
    iphone = "Mozilla/5.0 (iPhone; CPU iPhone OS 15_0 like Mac OS X) AppleWebKit/605.1.15 Mobile/15E148 Safari/604.1"
    assert is_mobile(iphone) and is_mobile("Mozilla/5.0 (Linux; Android 13) Chrome/120") and not is_mobile("X11; Linux")
    assert phone_layout(780, 1328, mobile=True) and not phone_layout(780, 1328) and phone_layout(390, 664)
    assert not phone_layout(1688, 780, mobile=True)  # a phone held sideways: viser's desktop layout
    assert free_region(780, 1328, mobile=True) == (0.0, 0.0, 780.0, pytest.approx(0.4 * 1328 - SHEET_MARGIN_PX))


@pytest.mark.parametrize(("width", "height"), [(1280, 800), (390, 844), (1920, 1080)])
def test_a_scene_view_just_fills_the_free_region(width, height):
    view = (2.4, 2.1)
    eye, target = framed(*SCENE, width, height, FOV, view)
    left, top, right, bottom = free_region(width, height)
    top += LABEL_ROOM_PX  # the scene is framed below a label's line
    metres_per_px = 2.0 * math.tan(0.5 * FOV) * np.linalg.norm(eye - target) / height
    shown = ((right - left) * metres_per_px, (bottom - top) * metres_per_px)
    assert shown[0] >= view[0] * (1 - 1e-12) and shown[1] >= view[1] * (1 - 1e-12)
    assert min(shown[0] / view[0], shown[1] / view[1]) == pytest.approx(1.0, rel=1e-12)  # one side exactly
    x, y = _pixel(np.array(SCENE[1]), eye, target, width, height)
    assert x == pytest.approx(0.5 * (left + right), abs=1e-6) and y == pytest.approx(0.5 * (top + bottom), abs=1e-6)
