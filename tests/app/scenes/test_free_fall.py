"""The free-fall scene headless: the centre of mass on its parabola, the spin as in the wobble."""

from __future__ import annotations

import numpy as np

from physics import G
from physics.free_body import FreeBody
from tests.harness import FRAME, matrix, open_scene

SCENES = ["heavy_top", "wobble", "free_fall"]


# --------------------------------------------------------------------------------------------------
# Shared pieces
# --------------------------------------------------------------------------------------------------


def test_free_fall_centre_follows_the_parabola_and_spins_like_the_wobble(app):
    from app.scenes.free_fall import START, VELOCITY

    scene = open_scene(app, "free_fall")
    for _ in range(20):
        app.frame(FRAME)
    tau = app.time % scene.flight_time
    expected = START + VELOCITY * tau - 0.5 * G * tau**2 * np.array([0, 0, 1.0])
    np.testing.assert_allclose(scene.body.handle.position, expected, atol=1e-6)
    # The arrows start at the centre of mass.
    np.testing.assert_allclose(scene.L_arrow.handle.position, expected, atol=1e-6)
    np.testing.assert_allclose(scene.L_arrow.handle.points[0, 0], 0.0)
    R_expected = FreeBody(scene.moments).attitude(scene.omega0, [app.time], scene.attitude0)[0]
    np.testing.assert_allclose(matrix(scene.body.handle), R_expected, atol=2e-6)
