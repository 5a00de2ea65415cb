"""Free body and pendulum solved once, evaluated often: ``FreeBody.trajectory(ω0, R0).at(t)`` and
``PhysicalPendulum.trajectory(θ0, θ̇0).at(t)``.

One time is evaluated on Python floats (a frame of an animation), many times vectorised. They are the
same closed forms; the free body's one-time path multiplies its 3×3 matrices in another order than the
batched one, so the two agree to a few roundings (16 ulp of the largest entry is asserted), the pendulum's
to the bit. The wrappers (``motion``, ``omega``, ``attitude``, ``solve``) are the trajectories.
"""

from __future__ import annotations

import math

import numpy as np
import pytest
from hypothesis import given, settings
from hypothesis import strategies as st

from physics.free_body import FreeBody, FreeBodyState, FreeBodyTrajectory
from physics.inertia import box
from physics.pendulum import PendulumTrajectory, PhysicalPendulum
from tests.physics.test_free_body import ALL, R_TILT

EPS = np.finfo(float).eps
TIMES = np.concatenate([np.linspace(-300.0, 300.0, 61), [1e-9, -1e-9]])


def _close(one: FreeBodyState, many: FreeBodyState, i: int) -> None:
    scale = np.max(np.abs(many.omega[i]))
    assert np.max(np.abs(one.omega - many.omega[i])) <= 16 * EPS * scale
    assert np.max(np.abs(one.attitude - many.attitude[i])) <= 16 * EPS


@pytest.mark.parametrize("name", list(ALL))
def test_free_body_one_time_is_the_vectorised_value(name):
    moments, omega0 = ALL[name]
    motion = FreeBody(moments).trajectory(omega0, R_TILT)
    many = motion.at(TIMES)
    for i, t in enumerate(TIMES):
        one = motion.at(float(t))
        assert one.t == t and one.omega.shape == (3,) and one.attitude.shape == (3, 3)
        _close(one, many, i)


@settings(max_examples=60, deadline=None)
@given(
    moments=st.tuples(st.floats(0.1, 1.0), st.floats(0.1, 1.0), st.floats(0.1, 1.0)).filter(
        lambda m: max(m) <= sum(m) - max(m)  # the triangle inequality of a rigid body
    ),
    omega0=st.tuples(*(st.floats(-10.0, 10.0),) * 3).filter(lambda w: max(map(abs, w)) > 1e-3),
    t=st.floats(-1e3, 1e3),
)
def test_random_free_bodies_agree_one_time_and_many(moments, omega0, t):
    motion = FreeBody(moments).trajectory(omega0)
    _close(motion.at(t), motion.at(np.array([0.0, t])), 1)


def test_free_body_wrappers_are_the_trajectory():
    moments, omega0 = ALL["generic_L2_above_2EI2"]
    body = FreeBody(moments)
    motion = body.trajectory(omega0, R_TILT)
    assert isinstance(motion, FreeBodyTrajectory)
    state = motion.at(TIMES)
    omega, attitude = body.motion(omega0, TIMES, R_TILT)
    np.testing.assert_array_equal(omega, state.omega)
    np.testing.assert_array_equal(attitude, state.attitude)
    np.testing.assert_array_equal(body.omega(omega0, TIMES), state.omega)
    np.testing.assert_array_equal(body.attitude(omega0, TIMES, R_TILT), state.attitude)
    np.testing.assert_allclose(motion.angular_momentum, R_TILT @ (body.moments * np.asarray(omega0)), rtol=1e-15)
    assert motion.energy == pytest.approx(body.energy(omega0), rel=1e-15)


def test_free_body_trajectory_refuses_bad_input():
    body = FreeBody([1.0, 2.0, 3.0])
    with pytest.raises(ValueError, match="shape"):
        body.trajectory([1.0, 2.0])
    with pytest.raises(ValueError, match="rotation"):
        body.trajectory([1.0, 2.0, 3.0], np.diag([1.0, 1.0, -1.0]))
    with pytest.raises(ValueError, match="finite"):
        body.trajectory([1.0, 2.0, 3.0]).at(math.nan)


PENDULUM = PhysicalPendulum(box(1.0, [0.1, 0.2, 0.3]), [0.0, 0.0, 0.15], [1.0, 0.0, 0.0])
W0 = PENDULUM.omega0
SWINGS = {
    "small libration": (0.1, 0.0),
    "large libration": (3.0, 0.0),
    "near the top": (math.pi - 1e-9, 0.0),
    "separatrix": (0.0, 2.0 * W0),
    "just over the top": (0.0, 2.0 * W0 * (1.0 + 1e-12)),
    "rotation backwards": (0.0, -5.0 * W0),
    "whole turns kept": (2.0 * math.pi + 0.3, 0.2),
}


@pytest.mark.parametrize("name", list(SWINGS))
def test_pendulum_one_time_is_the_vectorised_value_to_roundoff(name):
    # The same expressions; numpy's SIMD kernels for arrays (AVX-512 where present) and the C library for
    # floats may round a transcendental function differently by one ulp: 2 ulps of max(|value|, 1)
    # (measured: at most 0.8).
    motion = PENDULUM.trajectory(*SWINGS[name])
    assert isinstance(motion, PendulumTrajectory)
    many = motion.at(TIMES)
    eps = float(np.finfo(float).eps)
    for i, t in enumerate(TIMES):
        theta, theta_dot = motion.at(float(t))
        assert theta.shape == ()
        for one, vectorised in ((theta, many.theta[i]), (theta_dot, many.theta_dot[i])):
            assert abs(one - vectorised) <= 2.0 * eps * max(abs(one), abs(vectorised), 1.0), (name, t)


def test_pendulum_solve_is_the_trajectory_and_broadcasts_as_before():
    theta0 = np.array([0.1, 3.0, 0.0])
    thetadot0 = np.array([0.0, 0.0, -5.0 * W0])
    swing = PENDULUM.solve(theta0[:, None], thetadot0[:, None], TIMES[None, :])
    assert swing.theta.shape == (3, TIMES.size)
    for k in range(3):
        row = PENDULUM.trajectory(theta0[k], thetadot0[k]).at(TIMES)
        np.testing.assert_array_equal(swing.theta[k], row.theta)
        np.testing.assert_array_equal(swing.theta_dot[k], row.theta_dot)
    # One time per swing (paired), as solve did before the trajectories.
    paired = PENDULUM.solve(theta0, thetadot0, TIMES[:3])
    np.testing.assert_array_equal(paired.theta, [swing.theta[k, k] for k in range(3)])
    with pytest.raises(ValueError, match="finite"):
        PENDULUM.trajectory(0.1, 0.0).at(math.inf)


@settings(max_examples=40, deadline=None)
@given(theta0=st.floats(-7.0, 7.0), rate=st.floats(-4.0, 4.0), t=st.floats(-6.0, 6.0))
def test_random_swings_match_an_independent_integration(theta0, rate, t):
    # θ̈ = −ω0² sin θ by DOP853 at rtol 1e-13 over at most 6 s (≈ 10 small periods): its global error is
    # ~1e-11 rad there; the closed form must agree to that.
    from scipy.integrate import solve_ivp

    thetadot0 = rate * W0
    sol = solve_ivp(
        lambda _, y: [y[1], -(W0**2) * math.sin(y[0])],
        (0.0, t),
        [theta0, thetadot0],
        method="DOP853",
        rtol=1e-13,
        atol=1e-14,
    )
    theta, theta_dot = PENDULUM.trajectory(theta0, thetadot0).at(t)
    assert abs(theta - sol.y[0, -1]) < 1e-9
    assert abs(theta_dot - sol.y[1, -1]) < 1e-9 * max(W0, abs(thetadot0))
    # The energy is the initial one (the closed form is exact: a few roundings of ω0² and θ̇²).
    energy = 0.5 * theta_dot**2 - W0**2 * math.cos(theta)
    assert energy == pytest.approx(0.5 * thetadot0**2 - W0**2 * math.cos(theta0), abs=1e-13 * (W0**2 + thetadot0**2))
