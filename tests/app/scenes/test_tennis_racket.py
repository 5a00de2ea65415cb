"""The tennis-racket scene headless: the intermediate-axis flip and growth rate, stable axes, sliders,
the polhode and separatrix.
"""

from __future__ import annotations

import math

import numpy as np
import pytest

from app.scenes.tennis_racket import AXES, SLIDERS, box_for_moments, separatrix_circles
from physics.inertia import box
from tests.harness import FRAME, open_scene


def test_separatrix_of_a_symmetric_body_is_the_circle_of_steady_rotations():
    # I2 = I3: the circle l1 = 0; rod (I1 = I2, I3 = 0): the circle l3 = 0 (exact up to cos(π/2) ~ 6e-17).
    np.testing.assert_allclose(separatrix_circles(np.array([2.0, 1.0, 1.0]))[..., 0], 0.0, atol=1e-15)
    np.testing.assert_allclose(separatrix_circles(np.array([1.0, 1.0, 0.0]))[..., 2], 0.0, atol=1e-15)


def test_racket_builds_steps_and_moves_with_L_fixed(app):
    sc = open_scene(app, "tennis_racket")
    q0 = np.array(sc.body.handle.wxyz)
    L0 = np.array(sc.L_arrow.handle.points)
    for _ in range(30):
        app.frame(FRAME)
    assert app.time == pytest.approx(31 * FRAME, rel=1e-12)
    assert np.abs(np.array(sc.body.handle.wxyz) - q0).max() > 1e-3
    np.testing.assert_allclose(sc.L_arrow.handle.points, L0, atol=1e-6)  # L fixed in space
    # L in space is R I ω at any time (exact solution: only round-off).
    st = sc.compute(0.7, 0.0)
    np.testing.assert_allclose(
        st["R"] @ (sc.moments * st["omega_body"]), sc.L_space, rtol=0, atol=1e-12 * np.linalg.norm(sc.L_space)
    )
    assert sc.plot.data[0].size >= 2


def test_racket_intermediate_axis_growth_rate_and_flip(app):
    sc = open_scene(app, "tennis_racket")
    i1, i2, i3 = sc.moments
    spin = sc.params.values["spin"]
    assert sc.stability.kind == "unstable"
    # Lecture: λ = Ω √((I1 − I2)(I2 − I3)/(I1 I3)).
    assert sc.stability.rate == pytest.approx(spin * math.sqrt((i1 - i2) * (i2 - i3) / (i1 * i3)), rel=1e-12)
    period = sc.model.period(sc.omega0)
    # Measured from sign changes on a grid of 4,000 points with linear interpolation: 1e-5.
    assert sc.flip_period == pytest.approx(period, rel=1e-5)
    # Half a period later the body has flipped: ω along axis 2 has reversed.
    assert sc.compute(period / 2, 0.0)["omega_body"][1] < -0.9 * spin


@pytest.mark.parametrize("label", ["1 — largest moment", "3 — smallest moment"])
def test_racket_stable_axes_wobble_at_the_lecture_frequency(app, label):
    sc = open_scene(app, "tennis_racket")
    sc.axis.value = label
    i = AXES[label]
    m = sc.moments
    j, k = (i + 1) % 3, (i + 2) % 3
    spin = sc.params.values["spin"]
    expected = spin * math.sqrt((m[i] - m[j]) * (m[i] - m[k]) / (m[j] * m[k]))
    assert sc.stability.kind == "stable" and sc.stability.rate == pytest.approx(expected, rel=1e-12)
    # For ε = 1e-3 the exact wobble period is the linear one to O(ε²): 1e-5.
    assert sc.flip_period == pytest.approx(2 * math.pi / expected, rel=1e-5)
    # It stays near the axis: the spin component never drops below 99 %.
    w = sc.model.omega(sc.omega0, np.linspace(0, 20, 400))
    assert np.all(np.abs(w[:, i]) > 0.99 * spin)
    # A stable axis does not flip: no readout says "flip period" for it.
    assert sc.period_readout.handle.label == "measured wobble period (s)"
    assert "does not flip" in sc.first_flip_readout.text


def test_racket_sliders_refuse_impossible_or_unordered_moments(app):
    sc = open_scene(app, "tennis_racket")
    sc.source.value = SLIDERS
    np.testing.assert_allclose(sc.moments, [3.0, 2.0, 1.0])
    refusals = sc.params.refusals
    assert not sc.params.offer({"I1": 4.0, "I2": 1.0, "I3": 1.0})  # > I2 + I3: impossible
    assert "no rigid body" in app.messages[-1][1]
    assert not sc.params.offer({"I2": 3.5})  # I2 > I1: numbering broken
    assert sc.params.refusals == refusals + 2
    np.testing.assert_allclose(sc.moments, [3.0, 2.0, 1.0])  # the last valid body stays
    assert sc.params.offer({"I2": 2.5})
    np.testing.assert_allclose(sc.moments, [3.0, 2.5, 1.0])
    # The drawn box has exactly these moments (M = 1 kg).
    ext = np.ptp(box_for_moments(sc.moments).vertices, axis=0)
    np.testing.assert_allclose(box(1.0, ext).moments, sc.moments, rtol=1e-12)


def test_racket_perturbation_slider_is_logarithmic(app):
    sc = open_scene(app, "tennis_racket")
    assert sc.params.offer({"log_eps": -6.0})
    spin = sc.params.values["spin"]
    np.testing.assert_allclose(sc.omega0, [1e-6 * spin, spin, 1e-6 * spin], rtol=1e-15)
    assert float(sc.first_flip_readout.text) == pytest.approx(math.log(1e6) / sc.stability.rate, rel=1e-3)


def test_racket_polhode_and_separatrix_lie_where_the_invariants_say(app):
    sc = open_scene(app, "tennis_racket")
    inv = 1.0 / sc.moments
    rel = lambda p: np.asarray(p, dtype=float).reshape(-1, 3) - sc.sphere_centre  # noqa: E731
    sep = rel(sc.separatrix.points)
    sep /= np.linalg.norm(sep, axis=1, keepdims=True)
    # On the separatrix 2E/L² = 1/I2 (float32 points: 1e-6).
    np.testing.assert_allclose(sep**2 @ inv, inv[1], rtol=1e-5)
    pol = rel(sc.polhode.points)
    pol /= np.linalg.norm(pol, axis=1, keepdims=True)
    energy = pol**2 @ inv  # 2E/L², constant along the polhode
    assert np.ptp(energy) < 1e-5 * energy.mean()
    circles = separatrix_circles(sc.moments)
    np.testing.assert_allclose(np.linalg.norm(circles, axis=2), 1.0, rtol=1e-14)


def test_racket_t_handle_and_book_flip_too(app):
    sc = open_scene(app, "tennis_racket")
    for source in ("T-handle, Dzhanibekov (mesh)", "Book (mesh)"):
        sc.source.value = source
        assert sc.stability.kind == "unstable" and math.isfinite(sc.flip_period)
        app.frame(FRAME)
