"""Tests for physics.pendulum against exact results.

References: the lecture's closed forms (rod on its end, point mass, ℓ > k > |a⊥|, centre of percussion),
the period as a high-precision quadrature in mpmath (independent of elliptic functions), the closed
form evaluated in mpmath at 40 digits (independent of this module's float arithmetic near the
separatrix), DOP853 integrations of θ̈ = −ω0² sin θ, and conservation of energy.
"""

from __future__ import annotations

import mpmath as mp
import numpy as np
import pytest
from hypothesis import given, settings
from hypothesis import strategies as st
from scipy.integrate import solve_ivp
from scipy.spatial.transform import Rotation

from physics import G
from physics.inertia import MassProperties, box, point_masses, rod, solid_sphere
from physics.pendulum import (
    LIBRATION,
    ROTATION,
    SEPARATRIX,
    UNIFORM,
    PhysicalPendulum,
)

# A rod of length L hanging from its end on a horizontal axis (the lecture's baseball bat).
L = 0.9
M = 1.3


def rod_on_end() -> PhysicalPendulum:
    return PhysicalPendulum(rod(M, L), pivot=[0.0, 0.0, L / 2], axis=[1.0, 0.0, 0.0])


@pytest.fixture
def bat() -> PhysicalPendulum:
    return rod_on_end()


def reference_swing(omega0: float, theta0: float, thetadot0: float, t: np.ndarray) -> np.ndarray:
    """θ(t) from the closed form in mpmath at 40 digits, with 1 − κ² taken exactly from the floats."""
    with mp.workdps(40):
        th0, w = mp.mpf(theta0), mp.mpf(omega0)
        x = mp.mpf(thetadot0) / (2 * w)
        m = mp.sin(th0 / 2) ** 2 + x**2
        out = []
        for ti in t:
            if m < 1:
                kappa = mp.sqrt(m)
                phi0 = mp.atan2(mp.sin(th0 / 2) / kappa, x / kappa)
                c = mp.ellipf(phi0, m)
                sn = mp.ellipfun("sn", w * mp.mpf(ti) + c, m=m)
                dn = mp.ellipfun("dn", w * mp.mpf(ti) + c, m=m)
                out.append(float(2 * mp.atan2(kappa * sn, dn)))
            else:
                kappa = mp.sqrt(m)
                s = 1 if thetadot0 >= 0 else -1
                c = mp.ellipf(s * th0 / 2, 1 / m)
                u = kappa * w * mp.mpf(ti) + c
                # am(u) continuous: am(u) = atan2(sn, cn) + the half-turns counted by K
                k = mp.ellipk(1 / m)
                n = mp.nint(u / (2 * k))
                r = u - 2 * k * n
                am = mp.atan2(mp.ellipfun("sn", r, m=1 / m), mp.ellipfun("cn", r, m=1 / m)) + n * mp.pi
                out.append(float(2 * s * am))
        return np.array(out)


def quadrature_period(omega0: float, amplitude: float) -> float:
    """T = (4/ω0) ∫_0^A dθ / sqrt(2 (cos θ − cos A)) by tanh-sinh quadrature at 30 digits."""
    with mp.workdps(30):
        a = mp.mpf(amplitude)
        # cos θ − cos A = 2 sin((A+θ)/2) sin((A−θ)/2): no cancellation at the endpoint
        f = lambda th: 1 / mp.sqrt(4 * mp.sin((a + th) / 2) * mp.sin((a - th) / 2))  # noqa: E731
        return float(4 / mp.mpf(omega0) * mp.quad(f, [0, a / 2, a]))


def integrated_period(omega0: float, amplitude: float) -> float:
    """The time between two returns to θ = A at rest, by DOP853 at rtol 1e-13."""

    def rhs(_t, y):
        return [y[1], -(omega0**2) * np.sin(y[0])]

    def turn(_t, y):
        return y[1]

    turn.direction = 1.0  # θ̇ rising through 0: the body at −A
    t_half_guess = 10.0 * 2 * np.pi / omega0
    sol = solve_ivp(rhs, (0.0, t_half_guess), [amplitude, 0.0], method="DOP853", rtol=1e-13, atol=1e-15, events=turn)
    return 2.0 * float(sol.t_events[0][0])


# -- lecture quantities ------------------------------------------------------------------------


def test_rod_pivoted_at_its_end_matches_lecture(bat):
    # Exact: I = M L²/3, a⊥ = L/2, k = L/√3, ℓ = 2L/3; 1e-15 relative is a few ulps of round-off.
    assert bat.moment_of_inertia == pytest.approx(M * L**2 / 3, rel=1e-15)
    assert bat.a_perp == pytest.approx(L / 2, rel=1e-15)
    assert bat.radius_of_gyration == pytest.approx(L / np.sqrt(3), rel=1e-15)
    assert bat.effective_length == pytest.approx(2 * L / 3, rel=1e-15)
    assert bat.small_oscillation_period == pytest.approx(2 * np.pi * np.sqrt(2 * L / (3 * G)), rel=1e-15)
    np.testing.assert_allclose(bat.center_of_percussion(), [0.0, 0.0, L / 2 - 2 * L / 3], rtol=0, atol=1e-15)
    assert bat.model_angle == 0.0  # it hangs as modelled


def test_tilted_rod_and_oblique_pivot_keep_the_lecture_values():
    # The same bat rotated arbitrarily with the axis perpendicular to it and the pivot at its end:
    # the numbers are frame-independent (round-off of the rotation: 1e-14 relative).
    rot = Rotation.from_rotvec([0.3, -1.1, 0.7]).as_matrix()
    body = rod(M, L).transformed(rot, [0.2, -0.4, 1.0])
    along = rot @ [0, 0, 1.0]
    axis = np.cross(along, [0.3, 0.2, 1.0])
    pend = PhysicalPendulum(body, pivot=body.center_of_mass + along * L / 2, axis=axis)
    assert pend.effective_length == pytest.approx(2 * L / 3, rel=1e-14)
    assert np.linalg.norm(pend.center_of_percussion() - pend.pivot) == pytest.approx(2 * L / 3, rel=1e-14)


def test_point_mass_has_effective_length_equal_to_its_distance():
    # All mass at one point: ℓ = k = |a⊥| (the lecture's limiting case), whatever its offset along the axis.
    pend = PhysicalPendulum(point_masses([2.0], [[0.3, 0.5, -0.4]]), pivot=[0.0, 0.0, 0.0], axis=[1.0, 0.0, 0.0])
    a = np.hypot(0.5, 0.4)
    assert pend.a_perp == pytest.approx(a, rel=1e-15)
    assert pend.radius_of_gyration == pytest.approx(a, rel=1e-15)
    assert pend.effective_length == pytest.approx(a, rel=1e-15)
    assert pend.small_oscillation_period == pytest.approx(2 * np.pi * np.sqrt(a / G), rel=1e-15)
    # A thin rod parallel to the axis has its mass on one such line too: ℓ = k = |a⊥| = 0.7 m.
    parallel = PhysicalPendulum(rod(1.0, 2.0), pivot=[0.7, 0.0, 0.0], axis=[0.0, 0.0, 1.0])
    assert parallel.effective_length == pytest.approx(0.7, rel=1e-15)
    assert parallel.radius_of_gyration == pytest.approx(0.7, rel=1e-15)


def test_moment_about_axis_equals_direct_sum_over_point_masses():
    # Independent of the parallel-axis theorem: I = Σ m_i |r_i⊥|² summed directly (1e-14 relative).
    rng = np.random.default_rng(3)
    masses, pos = rng.uniform(0.1, 2.0, 7), rng.normal(size=(7, 3))
    pivot, axis = np.array([0.4, -0.2, 1.5]), np.array([0.3, 1.0, -0.2])
    pend = PhysicalPendulum(point_masses(masses, pos), pivot, axis)
    n = axis / np.linalg.norm(axis)
    d = pos - pivot
    d_perp = d - np.outer(d @ n, n)
    assert pend.moment_of_inertia == pytest.approx(np.sum(masses * np.sum(d_perp**2, axis=1)), rel=1e-14)


def test_only_gravity_in_the_swing_plane_acts():
    # Axis tilted by β from the vertical: g⊥ = g sin β, so the small period grows by 1/sqrt(sin β).
    beta = 0.4
    axis = [np.sin(beta), 0.0, np.cos(beta)]
    body = rod(M, L)
    pivot = body.center_of_mass + np.array([0.0, L / 2, 0.0])  # a⊥ along y, perpendicular to the axis
    body = body.transformed(Rotation.from_rotvec([np.pi / 2, 0, 0]).as_matrix())  # rod along y
    pend = PhysicalPendulum(body, pivot, axis)
    assert pend.gravity_in_plane == pytest.approx(G * np.sin(beta), rel=1e-15)
    assert pend.small_oscillation_period == pytest.approx(
        2 * np.pi * np.sqrt(2 * L / (3 * G * np.sin(beta))), rel=1e-14
    )


def test_vertical_axis_has_no_restoring_torque_but_can_be_struck():
    # A door on vertical hinges: uniform rotation, infinite periods, the percussion geometry unchanged.
    door = box(20.0, [0.8, 0.04, 2.0])
    pend = PhysicalPendulum(door, pivot=[-0.4, 0.0, 0.0], axis=[0.0, 0.0, 1.0])
    assert pend.gravity_in_plane == 0.0 and pend.omega0 == 0.0
    assert pend.small_oscillation_period == np.inf
    assert np.all(pend.period([0.1, 1.0]) == np.inf)
    t = np.linspace(-2.0, 3.0, 7)
    theta, rate = pend.solve(0.2, 0.7, t)
    np.testing.assert_allclose(theta, 0.2 + 0.7 * t, rtol=0, atol=1e-15)
    np.testing.assert_array_equal(rate, 0.7)
    assert pend.regime(0.2, 0.7) == UNIFORM
    # door: I = M (0.8² + 0.04²)/12 + M 0.4², ℓ = k²/0.4; struck there the hinge feels nothing
    assert pend.effective_length == pytest.approx((20 * (0.64 + 0.0016) / 12 + 20 * 0.16) / (20 * 0.4), rel=1e-14)
    result = pend.strike([0.0, 3.0, 0.0], pend.center_of_percussion())
    np.testing.assert_allclose(result.reaction_impulse, 0.0, atol=1e-14)  # round-off of ~3 N s


def test_pivot_on_the_centre_of_mass_is_balanced_with_infinite_length():
    wheel = solid_sphere(1.0, 0.2)
    pend = PhysicalPendulum(wheel, pivot=[0.0, 0.0, 0.0], axis=[1.0, 0.0, 0.0])
    assert pend.a_perp == 0.0
    assert pend.effective_length == np.inf
    assert pend.small_oscillation_period == np.inf
    with pytest.raises(ValueError, match="centre of percussion is at infinity"):
        pend.center_of_percussion()
    theta, _ = pend.solve(1.0, 2.0, [0.0, 1.5])
    np.testing.assert_allclose(theta, [1.0, 4.0], rtol=0, atol=1e-15)
    # Any blow: the axis takes the whole momentum (the centre of mass cannot move).
    result = pend.strike([0.0, 1.0, 0.0], [0.0, 0.0, -0.2])
    np.testing.assert_allclose(result.reaction_impulse, [0.0, -1.0, 0.0], atol=1e-15)
    assert result.delta_omega == pytest.approx(0.2 / (0.4 * 0.04), rel=1e-14)


@pytest.mark.parametrize(
    "kwargs, message",
    [
        (dict(pivot=[0.0, np.nan, 0.0], axis=[1.0, 0.0, 0.0]), "pivot must be finite"),
        (dict(pivot=[0.0, 0.0, 0.0], axis=[np.inf, 0.0, 0.0]), "axis must be finite"),
        (dict(pivot=[0.0, 0.0, 0.0], axis=[0.0, 0.0, 0.0]), "axis must be a non-zero vector"),
        (dict(pivot=[0.0, 0.0], axis=[1.0, 0.0, 0.0]), r"pivot must have shape \(3,\)"),
        (dict(pivot=[0.0, 0.0, 0.5], axis=[1.0, 0.0, 0.0], g=-9.81), "g must not be negative"),
        (dict(pivot=[0.0, 0.0, 0.5], axis=[1.0, 0.0, 0.0], g=np.nan), "g must be finite"),
        (dict(pivot=[0.0, 0.0, 0.5], axis=[0.0, 0.0, 1.0]), "no moment of inertia about this axis"),
    ],
)
def test_bad_input_is_refused_with_a_clear_message(kwargs, message):
    with pytest.raises(ValueError, match=message):
        PhysicalPendulum(rod(1.0, 1.0), **kwargs)


def test_bad_bodies_and_states_are_refused(bat):
    with pytest.raises(ValueError, match="mass must be positive"):
        PhysicalPendulum(MassProperties(0.0, np.zeros(3), np.eye(3)), [0, 0, 1.0], [1.0, 0, 0])
    with pytest.raises(ValueError, match="must be a physics.inertia.MassProperties"):
        PhysicalPendulum({"mass": 1.0}, [0, 0, 1.0], [1.0, 0, 0])
    with pytest.raises(ValueError, match="theta0 must be finite"):
        bat.solve(np.nan, 0.0, [0.0])
    with pytest.raises(ValueError, match="t must be finite"):
        bat.solve(0.1, 0.0, [0.0, np.inf])
    with pytest.raises(ValueError, match="amplitude lies in"):
        bat.period(3.2)
    with pytest.raises(ValueError, match="impulse must be finite"):
        bat.strike([np.nan, 0, 0], [0, 0, 0])


@settings(max_examples=150, deadline=None)
@given(
    extents=st.tuples(*[st.floats(0.0, 2.0)] * 3).filter(lambda e: sorted(e)[1] > 1e-3),
    rotvec=st.tuples(*[st.floats(-3.0, 3.0)] * 3),
    pivot=st.tuples(*[st.floats(-2.0, 2.0)] * 3),
    axis=st.tuples(*[st.floats(-1.0, 1.0)] * 3).filter(lambda a: np.linalg.norm(a) > 0.1),
    mass=st.floats(1e-3, 1e3),
)
def test_lecture_inequalities_hold_for_any_body_and_pivot(extents, rotvec, pivot, axis, mass):
    # ℓ > k > |a⊥| (lecture): strict because a box with at least two non-zero extents has I_cm,nn > 0
    # about every axis (even a plate about an in-plane axis). The equality case (a point mass) is
    # tested above. The parallel-axis sum to 1e-12 relative: round-off of the rotated tensor.
    body = box(mass, extents).transformed(Rotation.from_rotvec(rotvec).as_matrix())
    pend = PhysicalPendulum(body, pivot, axis)
    i_cm = body.moment_about(axis)
    if pend.a_perp < 1e-6:
        return  # balanced on its centre of mass: ℓ infinite (tested above)
    assert pend.moment_of_inertia == pytest.approx(i_cm + mass * pend.a_perp**2, rel=1e-12)
    assert pend.effective_length > pend.radius_of_gyration > pend.a_perp
    # and ℓ |a⊥| = k², the definition (round-off: 1e-13 relative)
    assert pend.effective_length * pend.a_perp == pytest.approx(pend.radius_of_gyration**2, rel=1e-13)


# -- the period -------------------------------------------------------------------------------

AMPLITUDES = [1e-3, 0.3, 1.0, 2.0, 3.0, 3.1, np.pi * (1 - 1e-3), np.pi * (1 - 1e-6)]


def test_period_matches_high_precision_quadrature(bat):
    # 30-digit quadrature of the period integral; ellipkm1 is good to a few ulps, so 1e-14 relative.
    w = bat.omega0
    ours = bat.period(AMPLITUDES)
    ref = np.array([quadrature_period(w, a) for a in AMPLITUDES])
    np.testing.assert_allclose(ours, ref, rtol=1e-14, atol=0)


@pytest.mark.parametrize("amplitude", [0.5, 2.0, 3.0])
def test_period_matches_direct_integration(bat, amplitude):
    # DOP853 at rtol 1e-13 over one swing: its global error is ~1e-12 relative; allow 1e-11.
    assert bat.period(amplitude) == pytest.approx(integrated_period(bat.omega0, amplitude), rel=1e-11)


def test_period_small_amplitude_limit_and_separatrix(bat):
    t0 = bat.small_oscillation_period
    assert bat.period(0.0) == pytest.approx(t0, rel=1e-15)
    # T = T0 (1 + A²/16 + 11 A⁴/3072 + 173 A⁶/737280 + ...): with A = 0.01 the first omitted term is
    # ~2e-14 · A² ≈ 1e-18, so the three-term series is exact to round-off (1e-15).
    a = 0.01
    assert bat.period(a) / t0 == pytest.approx(1 + a**2 / 16 + 11 * a**4 / 3072 + 173 * a**6 / 737280, rel=1e-15)
    assert bat.period(np.pi) == np.inf
    # Near π the period diverges like (4/ω0) ln(4 / cos(A/2)); the next term is O(cos² ln) ~ 1e-11.
    big = np.pi * (1 - 1e-6)
    assert bat.period(big) == pytest.approx(4 / bat.omega0 * np.log(4 / np.cos(big / 2)), rel=1e-10)


# -- the exact swing --------------------------------------------------------------------------

CASES = [
    # (theta0, thetadot0 in units of ω0, regime)
    (0.3, 0.0, LIBRATION),
    (-1.2, 0.7, LIBRATION),
    (2.9, -0.1, LIBRATION),
    (np.pi * (1 - 1e-6), 0.0, LIBRATION),  # amplitude 0.999999 π
    (0.0, 2.0 * (1 - 1e-9), LIBRATION),  # just below the separatrix, from the bottom
    (0.0, 2.0, SEPARATRIX),
    (0.0, 2.0 * (1 + 1e-9), ROTATION),
    (1.0, 3.0, ROTATION),
    (-2.5, -2.2, ROTATION),
    (7.0, 0.1, LIBRATION),  # one turn on: swings about 2π
]


@pytest.mark.parametrize("theta0, rate, regime", CASES)
def test_exact_swing_matches_40_digit_closed_form(bat, theta0, rate, regime):
    # The same formulas evaluated in mpmath at 40 digits from the same float inputs: only this
    # module's float arithmetic is tested (the AGM, the complementary parameter, the reductions).
    # 5e-13 absolute over ~3 periods: phase round-off eps·ω0 t ≈ 1e-14 per radian of phase, plus
    # the float ω0 t products; separatrix-adjacent cases included.
    w = bat.omega0
    t = np.linspace(-3.0, 9.0, 41) / w * 2.0
    theta, _ = bat.solve(theta0, rate * w, t)
    assert bat.regime(theta0, rate * w) == regime
    if regime == SEPARATRIX:
        ref = 4 * np.arctan(np.exp(w * t)) - np.pi  # from the bottom with θ̇ = 2ω0: exact
    else:
        turns = np.round(theta0 / (2 * np.pi))
        ref = reference_swing(w, theta0 - 2 * np.pi * turns, rate * w, t) + 2 * np.pi * turns
    np.testing.assert_allclose(theta, ref, rtol=0, atol=5e-13)


@pytest.mark.parametrize("theta0, rate, regime", CASES)
def test_energy_of_exact_swing_is_constant(bat, theta0, rate, regime):
    # E = ½ I θ̇² − M g⊥ a⊥ cos θ constant to 1e-12 relative to the energy scale M g⊥ a⊥ + ½ I θ̇0².
    w = bat.omega0
    t = np.linspace(0.0, 200.0, 2001) / w
    theta, rate_t = bat.solve(theta0, rate * w, t)
    e = bat.energy(theta, rate_t)
    scale = bat.mass * bat.gravity_in_plane * bat.a_perp + 0.5 * bat.moment_of_inertia * (rate * w) ** 2
    assert np.max(np.abs(e - bat.energy(theta0, rate * w))) <= 1e-12 * scale


@pytest.mark.parametrize("theta0, rate", [(1.0, 0.0), (2.9, -0.4), (-2.5, -2.2), (0.0, 2.0)])
def test_rate_is_the_time_derivative_of_the_angle(bat, theta0, rate):
    # With energy conserved this pins down θ̈ = −ω0² sin θ. Fourth-order central differences with
    # h = 1e-3/ω0: truncation ~h⁴ θ⁽⁵⁾/30 ≈ 1e-13 ω0, round-off ~eps/h ≈ 1e-13 ω0; allow 1e-10 ω0.
    w = bat.omega0
    t = np.linspace(0.0, 12.0, 37) / w
    h = 1e-3 / w
    th = [bat.solve(theta0, rate * w, t + k * h).theta for k in (-2, -1, 1, 2)]
    derivative = (th[0] - 8 * th[1] + 8 * th[2] - th[3]) / (12 * h)
    np.testing.assert_allclose(derivative, bat.solve(theta0, rate * w, t).theta_dot, rtol=0, atol=1e-10 * w)


@pytest.mark.parametrize("theta0, rate", [(0.6, 0.0), (2.5, 0.9), (1.0, 3.0), (-0.4, -2.6)])
def test_exact_swing_matches_dop853(bat, theta0, rate):
    # Independent check of the physics: DOP853 at rtol 1e-13 over ~3 periods is good to ~1e-11 rad.
    w = bat.omega0
    t = np.linspace(0.0, 20.0, 50) / w
    sol = solve_ivp(
        lambda _t, y: [y[1], -(w**2) * np.sin(y[0])],
        (0, t[-1]),
        [theta0, rate * w],
        method="DOP853",
        rtol=1e-13,
        atol=1e-14,
        t_eval=t,
    )
    theta, theta_dot = bat.solve(theta0, rate * w, t)
    np.testing.assert_allclose(theta, sol.y[0], rtol=0, atol=1e-10)
    np.testing.assert_allclose(theta_dot, sol.y[1], rtol=0, atol=1e-10 * w)


def test_libration_repeats_and_reaches_its_amplitude(bat):
    # Released at rest at A: θ(T/2) = −A, θ(T) = A exactly (to round-off, 1e-13 rad near the top).
    for amp in [0.2, 2.0, np.pi * (1 - 1e-6)]:
        period = float(bat.period(amp))
        theta, rate = bat.solve(amp, 0.0, np.array([0.25, 0.5, 1.0, 50.0]) * period)
        np.testing.assert_allclose(theta, [0.0, -amp, amp, amp], rtol=0, atol=1e-12)
        assert np.max(np.abs(bat.solve(amp, 0.0, np.linspace(0, period, 999)).theta)) <= amp
        assert bat.motion_period(amp, 0.0) == pytest.approx(period, rel=1e-15)


def test_rotation_advances_one_turn_per_period(bat):
    w = bat.omega0
    for rate in [2.0 * (1 + 1e-8), 2.5, -6.0]:
        period = float(bat.motion_period(0.4, rate * w))
        t = np.linspace(0.0, period, 201)
        theta, theta_dot = bat.solve(0.4, rate * w, t)
        assert theta[-1] - theta[0] == pytest.approx(2 * np.pi * np.sign(rate), rel=1e-12)
        assert np.all(np.sign(np.diff(theta)) == np.sign(rate))  # never turns back
        assert np.all(np.abs(theta_dot) > 0)


def test_separatrix_creeps_to_the_top_and_never_passes(bat):
    w = bat.omega0
    # Up to ω0 t = 30, where π − θ = 4 e^{−30} ≈ 4e-13 is still resolved in floats.
    t = np.linspace(0.0, 30.0, 400) / w
    theta, theta_dot = bat.solve(0.0, 2.0 * w, t)
    assert bat.regime(0.0, 2.0 * w) == SEPARATRIX
    assert np.all(np.diff(theta) > 0) and np.all(theta < np.pi) and np.all(theta_dot > 0)
    assert np.pi - theta[-1] == pytest.approx(4 * np.exp(-30.0), rel=1e-3)  # 1e-3: ulps of π at 4e-13
    assert bat.motion_period(0.0, 2.0 * w) == np.inf


def test_symmetries_of_the_swing(bat):
    # Mirror (θ → −θ), time reversal, and whole turns: exact symmetries of θ̈ = −ω0² sin θ, held to
    # 1e-13 rad (round-off of the phase reduction).
    w = bat.omega0
    t = np.linspace(-7.0, 7.0, 29) / w
    for theta0, rate in [(0.5, 1.0), (2.0, -0.3), (1.0, 3.1), (0.0, 2.0)]:
        theta, theta_dot = bat.solve(theta0, rate * w, t)
        mirrored = bat.solve(-theta0, -rate * w, t)
        np.testing.assert_allclose(mirrored.theta, -theta, atol=1e-13)
        reversed_ = bat.solve(theta0, -rate * w, -t)
        np.testing.assert_allclose(reversed_.theta, theta, atol=1e-13)
        np.testing.assert_allclose(reversed_.theta_dot, -theta_dot, atol=1e-13 * w)
        shifted = bat.solve(theta0 - 4 * np.pi, rate * w, t)
        np.testing.assert_allclose(shifted.theta, theta - 4 * np.pi, atol=1e-13)


def test_small_swing_is_harmonic(bat):
    # A = 1e-6: θ = A cos ω0 t up to the anharmonic shift O(A³) ≈ 1e-18 and the period change
    # A²/16 · ω0 t ≈ 1e-12 relative over 20 rad of phase: 1e-17 absolute, so 1e-20 + round-off.
    w, amp = bat.omega0, 1e-6
    t = np.linspace(0.0, 20.0, 101) / w
    np.testing.assert_allclose(bat.solve(amp, 0.0, t).theta, amp * np.cos(w * t), rtol=0, atol=1e-16)


def test_solve_broadcasts_initial_states_against_times(bat):
    w = bat.omega0
    theta0 = np.array([[0.3], [2.0], [0.0]])
    rate0 = np.array([[0.0], [5.0 * w], [2.0 * w]])
    t = np.linspace(0.0, 3.0, 5)
    theta, theta_dot = bat.solve(theta0, rate0, t)
    assert theta.shape == theta_dot.shape == (3, 5)
    for i in range(3):
        np.testing.assert_array_equal(theta[i], bat.solve(theta0[i, 0], rate0[i, 0], t).theta)
    np.testing.assert_array_equal(bat.regime(theta0, rate0)[:, 0], [LIBRATION, ROTATION, SEPARATRIX])


def test_configuration_follows_the_angle():
    # A rod modelled lying horizontally along +y from a pivot at the origin: θ = −π/2 about +x
    # (right-hand rule: +x rotates −z into +y at θ = +π/2 ... so +y is at θ = +π/2).
    body = rod(1.0, 1.0).transformed(Rotation.from_rotvec([np.pi / 2, 0, 0]).as_matrix(), [0.0, 0.5, 0.0])
    pend = PhysicalPendulum(body, pivot=[0.0, 0.0, 0.0], axis=[1.0, 0.0, 0.0])
    assert pend.model_angle == pytest.approx(np.pi / 2, rel=1e-15)
    np.testing.assert_allclose(pend.center_of_mass_at(pend.model_angle), body.center_of_mass, atol=1e-15)
    np.testing.assert_allclose(pend.center_of_mass_at(0.0), [0.0, 0.0, -0.5], atol=1e-15)
    np.testing.assert_allclose(pend.center_of_mass_at(np.pi), [0.0, 0.0, 0.5], atol=1e-15)
    rot = pend.attitude(np.linspace(0, 3, 4))
    np.testing.assert_allclose(np.swapaxes(rot, 1, 2) @ rot, np.broadcast_to(np.eye(3), rot.shape), atol=1e-15)


# -- percussion -------------------------------------------------------------------------------


def test_no_pivot_reaction_at_the_centre_of_percussion(bat):
    # Erratum 2: struck at ℓ = k²/a⊥ perpendicular to (axis, a⊥) the pivot gives nothing (round-off).
    cp = bat.center_of_percussion()
    for j in ([0.0, 2.5, 0.0], [0.0, -0.01, 0.0]):
        result = bat.strike(j, cp)
        np.testing.assert_allclose(result.reaction_impulse, 0.0, atol=4 * np.finfo(float).eps * np.linalg.norm(j))
        np.testing.assert_allclose(result.reaction_angular_impulse, 0.0, atol=1e-15 * np.linalg.norm(j))
        # ... and the centre of mass takes the whole momentum: M Δv = J
        np.testing.assert_allclose(bat.mass * result.delta_velocity_cm, j, rtol=1e-15, atol=1e-17)
    # A point on the line through it parallel to the axis does the same for the force.
    off = bat.strike([0.0, 1.0, 0.0], cp + [0.3, 0.0, 0.0])
    np.testing.assert_allclose(off.reaction_impulse, 0.0, atol=1e-15)


@pytest.mark.parametrize("s", [0.0, 0.1, 0.45, 0.9])
def test_reaction_elsewhere_is_lectures_delta_p_minus_f_dt(bat, s):
    # Struck at distance s below the pivot with F Δt along y: Δφ̇ = F s Δt/(M k²), ΔP = F s a⊥/k² Δt,
    # and the pivot supplies ΔP − F Δt (lecture). Round-off 1e-15 relative.
    f_dt = 0.8
    k2 = bat.radius_of_gyration**2
    result = bat.strike([0.0, f_dt, 0.0], bat.pivot + [0.0, 0.0, -s])
    assert result.delta_omega == pytest.approx(f_dt * s / (M * k2), rel=1e-15, abs=1e-18)
    delta_p = f_dt * s * bat.a_perp / k2
    np.testing.assert_allclose(result.reaction_impulse, [0.0, delta_p - f_dt, 0.0], rtol=1e-14, atol=1e-16)


@settings(max_examples=100, deadline=None)
@given(
    masses=st.lists(st.floats(0.1, 3.0), min_size=2, max_size=6),
    seed=st.integers(0, 2**31),
    impulse=st.tuples(*[st.floats(-5.0, 5.0)] * 3),
)
def test_strike_conserves_momentum_and_angular_momentum_balance(masses, seed, impulse):
    # For any rigid body and any blow: M Δv = J + R, and about the pivot I_pivot Δω n̂ = (r−p) × J + C
    # with C ⊥ n̂; at the centre of percussion R = 0 for a blow ⊥ (n̂, a⊥). Tolerances: round-off of
    # sums of O(10) terms of size O(10): 1e-12.
    rng = np.random.default_rng(seed)
    body = point_masses(masses, rng.normal(size=(len(masses), 3)))
    axis = rng.normal(size=3)
    pend = PhysicalPendulum(body, rng.normal(size=3), axis)
    if pend.a_perp < 1e-3:
        return
    j, r = np.array(impulse), rng.normal(size=3)
    res = pend.strike(j, r)
    n = pend.axis
    # Rigid rotation about the fixed axis: Δv_cm = Δω n̂ × (r_cm − pivot), computed here, not by the code.
    dv = res.delta_omega * np.cross(n, pend.mass_properties.center_of_mass - pend.pivot)
    np.testing.assert_allclose(res.delta_velocity_cm, dv, atol=1e-12)
    angular = pend.mass_properties.tensor_about(pend.pivot) @ (res.delta_omega * n)
    np.testing.assert_allclose(angular, np.cross(r - pend.pivot, j) + res.reaction_angular_impulse, atol=1e-12)
    assert abs(res.reaction_angular_impulse @ n) < 1e-12
    ehat = np.cross(n, pend.a_perp_vector / pend.a_perp)
    at_cp = pend.strike(np.linalg.norm(j) * ehat, pend.center_of_percussion())
    np.testing.assert_allclose(at_cp.reaction_impulse, 0.0, atol=1e-12 * (1 + pend.effective_length))


def test_strike_while_swung_equals_striking_the_rotated_body():
    # Covariance: striking the body at angle θ is striking a body modelled in that pose. The couple
    # is non-zero here (an oblique box), so all four outputs are compared, to round-off (1e-13).
    body = box(2.0, [0.3, 0.1, 1.2]).transformed(Rotation.from_rotvec([0.4, 0.2, -0.3]).as_matrix(), [0, 0, -0.6])
    pivot, axis = np.array([0.05, 0.0, 0.0]), np.array([1.0, 0.2, 0.0])
    pend = PhysicalPendulum(body, pivot, axis)
    j, point = np.array([0.3, -1.0, 0.7]), np.array([0.1, 0.4, -0.9])
    for theta in [-2.0, 0.7, 3.0]:
        rot = pend.attitude(theta)
        posed = PhysicalPendulum(body.transformed(rot, pivot - rot @ pivot), pivot, axis)
        assert posed.model_angle == pytest.approx(theta, abs=1e-14)
        a, b = pend.strike(j, point, theta=theta), posed.strike(j, point)
        assert a.delta_omega == pytest.approx(b.delta_omega, rel=1e-13)
        for field in ("delta_velocity_cm", "reaction_impulse", "reaction_angular_impulse"):
            np.testing.assert_allclose(getattr(a, field), getattr(b, field), rtol=0, atol=1e-13)
        assert np.linalg.norm(a.reaction_angular_impulse) > 1e-3  # the hinge couple is really there
        np.testing.assert_allclose(pend.center_of_percussion(theta), posed.center_of_percussion(), atol=1e-13)
        ehat = np.cross(pend.axis, posed.a_perp_vector / posed.a_perp)
        at_cp = pend.strike(ehat, pend.center_of_percussion(theta), theta=theta)
        np.testing.assert_allclose(at_cp.reaction_impulse, 0.0, atol=1e-15)


def test_a_rate_whose_square_overflows_is_refused():
    pend = PhysicalPendulum(rod(1.0, 1.0), [0.0, 0.0, 0.5], [1.0, 0.0, 0.0])
    with pytest.raises(ValueError, match="at most 1e\\+100 rad/s"):
        pend.solve(0.0, 1e160, [0.0, 1.0])
