"""The heavy top's state functions and its table: ``HeavyTop.moments``, ``energy(R, L_body)``,
``nutation_rate_squared``, ``below_sleeping_threshold``, and :mod:`physics.heavy_top.table`
(``touch_angle``, ``on_the_table``), against hand-computed values and the exact solution.
"""

from __future__ import annotations

import math

import numpy as np
import pytest

from physics.heavy_top import HeavyTop, euler_attitude, on_the_table, touch_angle
from tests.physics.test_heavy_top import CASES, TOP

EPS = np.finfo(float).eps


def _span(ic) -> float:
    """The nutation period of these initial data, s (1 s for a motion without one: steady, vertical)."""
    T = TOP.nutation_period(*ic)
    return T if math.isfinite(T) else 1.0


def _rx(angle: float) -> np.ndarray:
    c, s = math.cos(angle), math.sin(angle)
    return np.array([[1.0, 0.0, 0.0], [0.0, c, -s], [0.0, s, c]])


def _rz(angle: float) -> np.ndarray:
    c, s = math.cos(angle), math.sin(angle)
    return np.array([[c, -s, 0.0], [s, c, 0.0], [0.0, 0.0, 1.0]])


def _tilt(R: np.ndarray) -> float:
    axis = R[:, 2]
    return math.atan2(math.hypot(axis[0], axis[1]), axis[2])


# --------------------------------------------------------------------------------------------------
# Moments and energy
# --------------------------------------------------------------------------------------------------


def test_moments_are_I1_I1_I3_and_a_fresh_array():
    top = HeavyTop(0.4, 0.2, 1.0)
    m = top.moments
    assert m.dtype == np.float64 and m.tolist() == [0.4, 0.4, 0.2]
    m *= 2.0  # the caller's to scale: the top is not changed
    assert top.moments.tolist() == [0.4, 0.4, 0.2] and (top.I1, top.I3) == (0.4, 0.2)


def test_energy_of_a_hand_computed_state():
    # ω = (1, 2, 40) rad/s, axis tilted by θ with cos θ = 0.6 (R about x: R₃₃ = cos θ = 0.6 exactly):
    # E = ½ (0.02·1 + 0.02·4 + 0.015·1600) + 0.3·0.6 = 12.05 + 0.18 = 12.23 J.
    R = np.array([[1.0, 0.0, 0.0], [0.0, 0.6, -0.8], [0.0, 0.8, 0.6]])
    L_body = TOP.moments * np.array([1.0, 2.0, 40.0])
    # A handful of roundings of terms at most |E|: a few ulps.
    assert TOP.energy(R, L_body) == pytest.approx(12.23, rel=4 * EPS)
    # The same state from Euler angles and rates: the model's energy_of agrees.
    theta, phi, psi, thetadot, phidot, psidot = 0.7, 0.3, -1.1, 0.9, 2.5, 30.0
    R = euler_attitude(phi, theta, psi)
    w = np.array(
        [
            phidot * math.sin(theta) * math.sin(psi) + thetadot * math.cos(psi),
            phidot * math.sin(theta) * math.cos(psi) - thetadot * math.sin(psi),
            psidot + phidot * math.cos(theta),
        ]
    )
    expected = float(TOP.energy_of(theta, thetadot, phidot, psidot))
    assert TOP.energy(R, TOP.moments * w) == pytest.approx(expected, rel=1e-14)  # two round-off paths


@pytest.mark.parametrize("name", list(CASES))
def test_energy_is_conserved_along_the_exact_solution(name):
    ic = CASES[name]
    T = _span(ic)
    s = TOP.solve(*ic, np.linspace(-3.0 * T, 100.0 * T, 401))
    E = np.array([TOP.energy(R, TOP.moments * w) for R, w in zip(s.attitude, s.omega_body, strict=True)])
    # The solution's attitude and ω are accurate to ~1e-15 relative (test_heavy_top) and E adds a few
    # roundings of terms of at most a few |E|: measured ≤ 1.5e-15 relative; 1e-14 leaves room for the
    # platform's libm and nothing for an error in the formula (a wrong sign of V alone costs ≥ 1e-3).
    assert np.max(np.abs(E - s.energy)) <= 1e-14 * abs(s.energy)


def test_energy_refuses_wrong_shapes():
    with pytest.raises(ValueError, match=r"R of shape \(3, 3\).*got \(3,\) and \(3,\)"):
        TOP.energy(np.zeros(3), np.zeros(3))
    with pytest.raises(ValueError, match=r"L_body of shape \(3,\).*got \(3, 3\) and \(2,\)"):
        TOP.energy(np.eye(3), np.zeros(2))


# Cases whose axis keeps away from the poles: there sin θ φ̇ = (Lz − L3 cos θ)/(I1 sin θ) divides a
# difference of order θ² by θ, and θ̇² from |ω⊥|² loses eps·L3/(I1 θ) (measured 4e-5 relative on
# "through the pole"): the conditioning of the formula, not an error of it.
AWAY_FROM_THE_POLES = [
    "gentle nutation",
    "cusps",
    "loops",
    "moving start",
    "hanging (θ > π/2)",
    "fast top",
    "steady precession, slow",
    "steady precession, fast",
]


@pytest.mark.parametrize("name", AWAY_FROM_THE_POLES)
def test_nutation_rate_squared_is_thetadot_squared_and_gives_the_energy_per_I1(name):
    ic = CASES[name]
    T = _span(ic)
    s = TOP.solve(*ic, np.linspace(0.0, 20.0 * T, 401))
    td2 = np.array([TOP.nutation_rate_squared(th, s.Lz, s.L3, w) for th, w in zip(s.theta, s.omega_body, strict=True)])
    scale = max(float(np.max(s.thetadot**2)), 1.0)  # 1/s²: θ̇² passes through 0 at the turning points
    # |ω⊥|² and (sin θ φ̇)² are each at most ~|ω|², a few ulps of it: measured ≤ 2e-14 of the scale.
    assert np.max(np.abs(td2 - s.thetadot**2)) <= 1e-13 * max(scale, float(np.max(s.omega_body[:, :2] ** 2)))
    assert np.all(td2 >= 0.0)
    # ℰ = θ̇²/2 + U(θ) = (E − L3²/(2 I3))/I1: the lecture's energy equation, constant along the motion.
    curly = 0.5 * td2 + TOP.effective_potential(s.theta, s.Lz, s.L3)
    expected = (s.energy - s.L3**2 / (2.0 * TOP.I3)) / TOP.I1
    assert np.max(np.abs(curly - expected)) <= 1e-14 * abs(s.energy) / TOP.I1  # measured ≤ 4e-16


def test_nutation_rate_squared_on_the_vertical_and_bad_shapes():
    # On the vertical the precession term is taken as 0: θ̇² is |ω⊥|² itself (here 3² + 4² = 25).
    assert TOP.nutation_rate_squared(0.0, 1.0, 1.0, [3.0, 4.0, 7.0]) == 25.0
    with pytest.raises(ValueError, match=r"omega_body must have shape \(3,\), got \(2,\)"):
        TOP.nutation_rate_squared(0.5, 1.0, 1.0, [3.0, 4.0])


# --------------------------------------------------------------------------------------------------
# The sleeping threshold
# --------------------------------------------------------------------------------------------------


def test_sleeping_threshold_is_the_lectures_closed_form():
    # M = 2 kg, g = 10 m/s², ℓ = 0.2 m: M g ℓ = 4 J; I1 = 0.25 kg m²: 2 √(M g ℓ I1) = 2 √1 = 2 kg m²/s.
    top = HeavyTop(0.25, 0.3, 2.0 * 10.0 * 0.2)
    assert top.sleeping_threshold() == 2.0
    # Below or at the threshold the upright spin is unstable; the sign of L3 does not matter.
    assert top.below_sleeping_threshold(2.0) and top.below_sleeping_threshold(-2.0)
    assert top.below_sleeping_threshold(math.nextafter(2.0, 0.0))
    assert not top.below_sleeping_threshold(math.nextafter(2.0, math.inf))
    assert not top.below_sleeping_threshold(-math.nextafter(2.0, math.inf))
    # And it is where the lecture's U''(0) = L3²/(4 I1²) − M g ℓ/I1 changes sign.
    for L3 in (0.0, 0.5, 1.9, 2.1, 7.0):
        assert top.below_sleeping_threshold(L3) == (top.vertical_curvature(L3) <= 0.0)
    # The free symmetric body (M g ℓ = 0) is stable upright at any spin but none.
    free = HeavyTop(0.25, 0.3, 0.0)
    assert free.below_sleeping_threshold(0.0) and not free.below_sleeping_threshold(1e-300)
    with pytest.raises(ValueError, match="L3"):
        top.below_sleeping_threshold(math.nan)


# --------------------------------------------------------------------------------------------------
# The table
# --------------------------------------------------------------------------------------------------


def test_touch_angle_of_a_cone_and_a_disc():
    # A cone from the tip to a rim at radius 0.3 m, height 0.4 m, with a stem up the axis to 1 m:
    # the rim reaches the table at atan2(0.4, 0.3) = atan(4/3).
    ring = [[0.3 * math.cos(a), 0.3 * math.sin(a), 0.4] for a in np.linspace(0.0, 2 * math.pi, 12)]
    cone = np.array([[0.0, 0.0, 0.0], [0.0, 0.0, 1.0], *ring])
    assert touch_angle(cone) == pytest.approx(math.atan(4.0 / 3.0), rel=2 * EPS)
    # A wider, higher ring above it (0.5 m out at 0.5 m up, 45°) touches first: the smallest angle counts.
    disc = np.vstack([cone, [[0.5, 0.0, 0.5], [0.0, -0.5, 0.5]]])
    assert touch_angle(disc) == pytest.approx(math.pi / 4, rel=2 * EPS)
    # A point below the tip's height touches at a negative tilt (the body is through the table upright).
    assert touch_angle([[0.0, 0.0, 0.0], [1.0, 0.0, -1.0]]) == pytest.approx(-math.pi / 4, rel=2 * EPS)


def test_touch_angle_refuses_bad_vertices():
    with pytest.raises(ValueError, match=r"shape \(n, 3\), got \(3,\)"):
        touch_angle([0.0, 0.0, 1.0])
    with pytest.raises(ValueError, match="finite"):
        touch_angle([[0.0, 0.0, 0.0], [math.nan, 0.0, 1.0]])
    with pytest.raises(ValueError, match="off the axis"):
        touch_angle([[0.0, 0.0, 0.0], [0.0, 0.0, 1.0]])


def test_off_the_table_the_top_moves_freely():
    R, L = _rx(0.8) @ _rz(0.3), np.array([0.1, -0.2, 3.0])
    R2, L2, landed = on_the_table(R, L, False, 1.0)
    assert R2 is R and L2 is L and landed is False


def test_a_top_through_the_table_is_laid_on_it_at_the_touch_angle_at_rest():
    # Tilted 1.2 rad about x with its own spin angle ψ = 0.3, the rim 1.0 rad: turned back about the
    # horizontal line through the tip (the x axis), it lies at Rx(1.0) Rz(0.3), its azimuth kept.
    for phi in (0.0, 1.3, -2.7):
        R = _rz(phi) @ _rx(1.2) @ _rz(0.3)
        R2, L2, landed = on_the_table(R, np.array([0.1, -0.2, 3.0]), False, 1.0)
        assert landed is True and L2.tolist() == [0.0, 0.0, 0.0]
        # One rotation vector and a product of three rotations: a few ulps.
        np.testing.assert_allclose(R2, _rz(phi) @ _rx(1.0) @ _rz(0.3), rtol=0, atol=8 * EPS)
        assert _tilt(R2) == pytest.approx(1.0, abs=8 * EPS)


def test_a_landed_top_stays_at_rest_where_it_lies():
    R = _rz(0.4) @ _rx(1.0) @ _rz(0.3)
    R2, L2, landed = on_the_table(R, np.array([0.0, 0.0, 1e-3]), True, 1.0)
    assert landed is True and R2 is R and L2.tolist() == [0.0, 0.0, 0.0]
    # Exactly at the touch angle (θ = touch, not beyond) it lands without being turned.
    R3, L3, landed3 = on_the_table(R, np.array([0.0, 0.0, 1.0]), False, _tilt(R))
    assert landed3 is True and R3 is R and L3.tolist() == [0.0, 0.0, 0.0]
