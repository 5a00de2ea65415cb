"""mgl = 0: the heavy top reduces to the symmetric free body turning about its fixed tip.

Reference: :class:`physics.free_body.FreeBody` with the moments about the tip (I1, I1, I3), an
independent closed form (rotation about L at L/I1 times the body's spin, lecture's symmetric free
body). The top's own closed form without gravity is elementary (``u = ū + A cos(ν t + c)``, ν = L/I1).
"""

from __future__ import annotations

import math

import numpy as np
import pytest
from hypothesis import given, settings
from hypothesis import strategies as st

from physics.free_body import FreeBody
from physics.heavy_top import HeavyTop, euler_attitude, omega_body_from_euler
from physics.rotations import rotation_angle

TIMES = np.linspace(-20.0, 20.0, 41)


def _reference(top: HeavyTop, ic, phi0: float, psi0: float):
    theta0, thetadot0, phidot0, psidot0 = ic
    attitude0 = euler_attitude(phi0, theta0, psi0)
    omega0 = omega_body_from_euler(theta0, psi0, thetadot0, phidot0, psidot0)
    return FreeBody([top.I1, top.I1, top.I3]).motion(omega0, TIMES, attitude0)


def _rate(hi: float):
    mag = st.floats(1e-3, hi)
    return st.one_of(st.just(0.0), mag, mag.map(lambda x: -x))


@settings(max_examples=80, deadline=None)
@given(
    ratio=st.floats(0.05, 2.0),
    theta0=st.one_of(st.just(0.0), st.just(math.pi), st.floats(1e-3, math.pi - 1e-3)),
    thetadot0=_rate(3.0),
    phidot0=_rate(3.0),
    psidot0=_rate(10.0),
)
def test_without_gravity_the_top_is_the_symmetric_free_body(ratio, theta0, thetadot0, phidot0, psidot0):
    top = HeavyTop(1.0, ratio, 0.0)
    ic = (theta0, thetadot0, phidot0, psidot0)
    solution = top.solve(*ic, TIMES, phi0=0.4, psi0=-0.2)
    omega, attitude = _reference(top, ic, 0.4, -0.2)
    # Both closed forms round their phase (up to ~200 rad here): a few 1e-12 rad apart at most.
    assert np.max(rotation_angle(solution.attitude, attitude)) < 1e-10
    # Scale of the rates given (at θ0 = π the float sin θ0 = 1.2e-16 leaves the reference a ω of that size).
    scale = max(float(np.max(np.abs(omega))), abs(thetadot0), abs(phidot0), abs(psidot0), 1e-300)
    assert np.max(np.abs(solution.omega_body - omega)) < 1e-10 * scale
    # The Euler angles are those of the attitude (φ̇, ψ̇ are each ill-conditioned at a pole passage, the
    # attitude is not: compared above).
    np.testing.assert_allclose(
        euler_attitude(solution.phi, solution.theta, solution.psi), solution.attitude, rtol=0, atol=1e-13
    )
    # One time, on floats, is the vectorised value.
    one = top.trajectory(*ic, phi0=0.4, psi0=-0.2).at(float(TIMES[7]))
    np.testing.assert_allclose(one.attitude, solution.attitude[7], rtol=0, atol=1e-15)


@pytest.mark.parametrize(
    "ic",
    [
        (0.3, 2.0, 0.0, 0.0),  # no spin: a planar turn through both poles (φ and ψ jump by π there)
        (0.0, 1.0, 0.0, 3.0),  # leaving the top pole
        (math.pi, -1.0, 0.0, 3.0),  # leaving the bottom pole
        (4.3e-6, -2.6, -1.7, -1.6),  # passing 1e-12 rad from the pole
        (0.7, 0.0, 0.5, 2.0),
    ],
)
def test_through_and_near_the_poles(ic):
    top = HeavyTop(1.0, 0.6, 0.0)
    solution = top.solve(*ic, TIMES)
    omega, attitude = _reference(top, ic, 0.0, 0.0)
    assert np.max(rotation_angle(solution.attitude, attitude)) < 1e-10
    assert np.max(np.abs(solution.omega_body - omega)) < 1e-10 * np.max(np.abs(omega))


def test_nutation_period_is_the_precession_about_L_and_the_vertical_is_never_unstable():
    top = HeavyTop(1.0, 0.6, 0.0)
    ic = (0.7, 0.3, 0.5, 2.0)
    L = np.linalg.norm(np.array([1.0, 1.0, 0.6]) * omega_body_from_euler(0.7, 0.0, 0.3, 0.5, 2.0))
    assert top.nutation_period(*ic) == pytest.approx(2.0 * math.pi / L, rel=1e-14)
    assert top.sleeping_threshold() == 0.0
    assert top.threshold_crossing_time(1.0, 0.1) == math.inf
    assert top.nutation_period(0.0, 0.0, 0.0, 4.0) == pytest.approx(2.0 * math.pi / (0.6 * 4.0), rel=1e-15)
    with pytest.raises(ValueError, match="mgl must be zero or positive"):
        HeavyTop(1.0, 0.6, -1e-3)


@pytest.mark.parametrize(
    ("ratio", "ic"),
    [
        (1.0, (0.0, 0.001, 0.0, 1.0)),  # a sphere leaving the top pole on a narrow cone (found by hypothesis)
        (0.6, (0.0, 1e-4, 0.0, 3.0)),
        (0.6, (math.pi, 1e-4, 0.0, 3.0)),  # the same at the bottom pole
    ],
)
def test_a_narrow_cone_far_from_the_other_pole_keeps_its_precession_rate(ratio, ic):
    # The far pole's gap 1 ± u was the near-double root of its quadratic (roots 2A apart): 2e-10 of the
    # precession rate was lost, 4.9e-9 rad after 20 s. Now the roundoff floor.
    top = HeavyTop(1.0, ratio, 0.0)
    solution = top.solve(*ic, TIMES)
    _, attitude = _reference(top, ic, 0.0, 0.0)
    assert np.max(rotation_angle(solution.attitude, attitude)) < 1e-12
