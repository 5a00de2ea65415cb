"""Tests of the step-by-step heavy top (friction, asymmetric body) through physics.integrators.

The exact solution of physics.heavy_top is the reference without friction; with spin friction the
model's own exact consequence L3(t) = L3(0) exp(−c t / I3) is; the lecture's story (a sleeping top
falls once L3 < 2 sqrt(M g ℓ I1)) is checked against the threshold.
"""

from __future__ import annotations

import math

import numpy as np
import pytest
from scipy.integrate import solve_ivp

from physics import integrators
from physics.heavy_top import FrictionRun, HeavyTop, TransverseAirDrag, simulate_heavy_body
from physics.rotations import hat, orthonormality_error, rotation_angle

TOP = HeavyTop(I1=0.02, I3=0.015, mgl=0.3)
METHODS = ["LieRK4", "Yoshida4", "Suzuki4", "Yoshida6", "LiePoissonStrang", "ExactFreeSplitting"]


def _order(name: str) -> int:
    return int(getattr(integrators, name).order)


def _error_vs_exact(name: str, ic, t_final: float, n: int) -> float:
    run = TOP.simulate(*ic, t_final, t_final / n, method=name, save_every=n)
    exact = TOP.solve(*ic, run.t)
    return float(np.max(rotation_angle(run.attitude, exact.attitude)))


@pytest.mark.parametrize("name", METHODS)
@pytest.mark.parametrize(
    "ic",
    [(0.6, 0.0, 0.0, 40.0), (0.0, 2.0, 0.0, 30.0), (1.2, 0.0, 0.0, 6.0)],
    ids=["cusps", "through θ = 0", "through θ = π/2"],
)
def test_without_friction_converges_to_the_exact_solution_at_the_method_s_order(name, ic):
    T = TOP.nutation_period(*ic)
    e1 = _error_vs_exact(name, ic, 2.0 * T, 80)
    e2 = _error_vs_exact(name, ic, 2.0 * T, 160)
    p = _order(name)
    # Halving dt divides the error by 2^p; measured orders are within 0.13 of p for all 18
    # combinations (both errors are well above rounding, see the e2 check).
    assert e2 > 1e-12
    observed = math.log2(e1 / e2)
    assert abs(observed - p) < 0.25, (name, observed)


def test_passes_the_pole_and_the_horizontal_without_singularity():
    for ic in [(0.0, 2.0, 0.0, 30.0), (1.2, 0.0, 0.0, 6.0)]:
        T = TOP.nutation_period(*ic)
        run = TOP.simulate(*ic, 3.0 * T, T / 400)
        assert np.all(np.isfinite(run.attitude))
        assert np.max(orthonormality_error(run.attitude)) < 1e-12
        exact = TOP.solve(*ic, run.t)
        # Order 4 at 400 steps a period: ≈ 1e-8 rad; the θ range includes 0 or π/2.
        assert np.max(rotation_angle(run.attitude, exact.attitude)) < 1e-6
    assert run.theta.max() > math.pi / 2 > run.theta.min()


def test_spin_friction_loses_energy_monotonically_and_L3_decays_exponentially():
    c = 2e-3
    ic = (0.6, 0.3, 1.0, 40.0)
    run = TOP.simulate(*ic, 3.0, 2e-3, spin_friction=c, air_drag=1e-4)
    assert isinstance(run, FrictionRun)
    dE = np.diff(run.energy)
    # Energy only leaves: every step loses some (up to rounding of E ≈ 10 J).
    assert np.all(dE < 1e-12 * np.abs(run.energy).max())
    assert run.energy[-1] < run.energy[0]
    # Without air drag, I3 dω3/dt = −c ω3 exactly for a symmetric top: L3 = L3(0) exp(−c t/I3).
    run = TOP.simulate(*ic, 3.0, 2e-3, spin_friction=c)
    L30 = run.L3[0]
    assert np.allclose(run.L3, L30 * np.exp(-c * run.t / TOP.I3), rtol=1e-9, atol=0)


def test_a_sleeping_top_wobbles_and_falls_once_L3_is_below_the_threshold():
    """The lecture's story: stable while L3 > 2 sqrt(M g ℓ I1), falls after friction takes it below."""
    thr = TOP.sleeping_threshold()
    c = 2e-3
    ic = (1e-3, 0.0, 0.0, 1.5 * thr / TOP.I3)
    run = TOP.simulate(*ic, 7.0, 4e-3, spin_friction=c, save_every=5)
    ratio = run.L3 / thr
    above = ratio > 1.05
    below = ratio < 0.85
    assert above.any() and below.any()
    # Above the threshold (with margin for the slow drift) the axis stays within a few times its start.
    assert run.theta[above].max() < 1e-2
    # Below it the vertical is a maximum of U and the top falls far.
    assert run.theta[below].max() > 1.0
    # Energy leaves all the way through the fall (the method's own error is far below the loss).
    assert np.all(np.diff(run.energy) < 0.0)
    # Without friction the same top sleeps on.
    calm = TOP.simulate(*ic, 7.0, 4e-3, save_every=5)
    assert calm.theta.max() < 2e-3
    # U''(0) changes sign where the fall begins: the axis has not left before the crossing, whose time
    # is the model's (I3/c) ln(L3/threshold), and the simulated L3 crosses there.
    t_cross = TOP.threshold_crossing_time(1.5 * thr, c)
    assert t_cross == pytest.approx(TOP.I3 / c * math.log(1.5), rel=1e-15)
    assert run.theta[run.t < t_cross].max() < 1e-2
    assert np.interp(t_cross, run.t, run.L3) == pytest.approx(thr, rel=1e-4)  # linear interpolation
    assert TOP.threshold_crossing_time(0.5 * thr, c) == 0.0 and TOP.threshold_crossing_time(thr * 2, 0.0) == math.inf


def _dop853_body(moments, mass, com, R0, w0, t, g=9.81):
    I = np.asarray(moments, float)

    def rhs(_, y):
        R, L = y[:9].reshape(3, 3), y[9:]
        w = L / I
        tau = np.cross(com, -mass * g * R[2, :])
        return np.concatenate([(R @ hat(w)).ravel(), np.cross(L, w) + tau])

    sol = solve_ivp(
        rhs, (0, t[-1]), np.concatenate([np.ravel(R0), I * w0]), method="DOP853", rtol=1e-12, atol=1e-14, t_eval=t
    )
    return sol.y[:9].T.reshape(-1, 3, 3), sol.y[9:].T


@pytest.mark.parametrize("name", ["Yoshida4", "LieRK4"])
def test_asymmetric_heavy_top(name):
    moments = (0.05, 0.04, 0.02)
    com = (0.01, -0.02, 0.1)
    R0 = np.eye(3)
    w0 = np.array([0.5, -1.0, 30.0])
    errs, lz, de = [], [], []
    for n in (200, 400):
        run = simulate_heavy_body(moments, 0.5, com, R0, w0, 1.0, 1.0 / n, method=name, save_every=n // 10)
        R_ref, _ = _dop853_body(moments, 0.5, np.array(com), R0, w0, run.t)
        errs.append(np.max(rotation_angle(run.attitude, R_ref)))
        lz.append(np.ptp(run.Lz) / np.abs(run.L_body).max())
        de.append(np.ptp(run.energy) / np.abs(run.energy).max())
    p = _order(name)
    assert abs(math.log2(errs[0] / errs[1]) - p) < 0.6
    assert abs(math.log2(de[0] / de[1]) - p) < 0.6  # the energy error is of the method's order
    if getattr(integrators, name).symplectic:
        # Gravity's torque is horizontal and the free sub-flows keep L_space: Lz to rounding.
        assert max(lz) < 1e-13
    else:
        assert abs(math.log2(lz[0] / lz[1]) - p) < 0.6


def test_symmetric_body_through_the_general_function_is_the_top():
    ic = (0.6, 0.0, 0.0, 40.0)
    run = TOP.simulate(*ic, 0.2, 1e-3)
    from physics.heavy_top import euler_attitude, omega_body_from_euler

    gen = simulate_heavy_body(
        (TOP.I1, TOP.I1, TOP.I3),
        TOP.mgl / 9.81 / 0.25,
        (0, 0, 0.25),
        euler_attitude(0, 0.6, 0),
        omega_body_from_euler(0.6, 0, 0, 0, 40.0),
        0.2,
        1e-3,
    )
    # Same M g ℓ, different split into M and ℓ: the same motion up to rounding.
    assert np.max(np.abs(run.attitude - gen.attitude)) < 1e-12


def test_air_drag_torque_and_bad_input():
    drag = TransverseAirDrag(0.1, (1.0, 2.0, 3.0))
    tau = drag(np.eye(3)[None], np.array([[1.0, 2.0, 3.0]]))
    assert np.allclose(tau, [[-0.1, -0.1, 0.0]]) and drag.conservative is False
    with pytest.raises(ValueError, match="spin_friction must be >= 0"):
        TOP.simulate(0.5, 0.0, 0.0, 30.0, 1.0, 0.01, spin_friction=-1.0)
    with pytest.raises(ValueError, match="unknown method"):
        TOP.simulate(0.5, 0.0, 0.0, 30.0, 1.0, 0.01, method="Euler")
    with pytest.raises(ValueError, match="rotation matrix"):
        simulate_heavy_body((1, 1, 1), 1.0, (0, 0, 1), 2 * np.eye(3), (0, 0, 1), 1.0, 0.1)
    with pytest.raises(ValueError, match="t_final and dt must be positive"):
        TOP.simulate(0.5, 0.0, 0.0, 30.0, 1.0, 0.0)


if __name__ == "__main__":  # the order table of the closing note: python -m tests.physics.test_heavy_top_simulated
    print("| method | order | case | error (T/80) | error (T/160) | observed order |")
    print("| --- | --- | --- | --- | --- | --- |")
    for ic, label in [
        ((0.6, 0.0, 0.0, 40.0), "cusps"),
        ((0.0, 2.0, 0.0, 30.0), "through θ = 0"),
        ((1.2, 0.0, 0.0, 6.0), "through θ = π/2"),
    ]:
        T = TOP.nutation_period(*ic)
        for name in METHODS:
            e1, e2 = (_error_vs_exact(name, ic, 2.0 * T, n) for n in (80, 160))
            print(f"| {name} | {_order(name)} | {label} | {e1:.2e} | {e2:.2e} | {math.log2(e1 / e2):.2f} |")
