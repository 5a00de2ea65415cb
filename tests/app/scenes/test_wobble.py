"""The wobble scene headless: L fixed, ω on its cones, the body view, impossible shapes refused."""

from __future__ import annotations

import math

import numpy as np
import pytest

from physics.free_body import FreeBody
from tests.harness import FRAME, matrix, open_scene

SCENES = ["heavy_top", "wobble", "free_fall"]


# --------------------------------------------------------------------------------------------------
# Shared pieces
# --------------------------------------------------------------------------------------------------


def test_wobble_keeps_L_fixed_and_omega_on_the_cones(app):
    scene = open_scene(app, "wobble")
    L_tips, angles = [], []
    for _ in range(60):
        app.frame(FRAME)
        L_tips.append(np.array(scene.L_arrow.handle.points[0, 1]) + scene.L_arrow.handle.position)
        R = matrix(scene.body.handle)
        w = scene.omega_arrow.handle.points[0, 1] - scene.omega_arrow.handle.points[0, 0]
        angles.append(math.degrees(math.acos(R[:, 2] @ w / np.linalg.norm(w))))
    # L fixed in space (float32 transport: ~1e-7 m).
    assert np.ptp(np.array(L_tips), axis=0).max() < 1e-6
    # The angle between ω and the symmetry axis is constant: the body-cone half-angle.
    assert np.ptp(angles) < 1e-3
    v = scene.params.values
    fb = FreeBody(scene.moments)
    rates = fb.precession_rates(scene.omega0)
    assert scene.Omega_readout.text == f"{rates.body:.4g}"
    assert rates.body == pytest.approx(v["spin"] * math.cos(math.radians(v["tilt"])) * (1 - v["ratio"]), rel=1e-12)


def test_wobble_body_view_holds_the_body_still(app):
    scene = open_scene(app, "wobble")
    scene.body_view.value = True
    q = []
    for _ in range(20):
        app.frame(FRAME)
        q.append(np.array(scene.body.handle.wxyz))
    np.testing.assert_allclose(np.abs(np.array(q) @ np.array([1.0, 0, 0, 0])), 1.0, atol=1e-6)
    scene.body_view.value = False


def test_impossible_wobble_shape_is_refused(app):
    scene = open_scene(app, "wobble")
    scene.params.sliders["ratio"].value = 2.3
    assert scene.params.values["ratio"] == 1.6
    assert scene.params.sliders["ratio"].value == 1.6
    assert "no rigid body has these moments" in app.messages[-1][1]
    assert app.frame(FRAME)
