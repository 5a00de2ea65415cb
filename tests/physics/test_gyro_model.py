"""The gyroscope fit's model (physics.gyro.model, physics.gyro.kernel) against the project's exact free body
and its compiled integrators."""

from __future__ import annotations

import numpy as np

from physics.free_body import FreeBody
from physics.gyro.kernel import drag_omega
from physics.gyro.model import euler_ratios, free_omega, model_omega, rotation_from_vector
from physics.integrators import BlanesMoan6, SpinFriction, integrate


def random_bodies(count: int, seed: int) -> list[np.ndarray]:
    rng = np.random.default_rng(seed)
    bodies = []
    while len(bodies) < count:
        moments = rng.uniform(0.05, 1.0, 3)
        if 2.0 * moments.max() <= moments.sum():  # a rigid body (triangle inequality)
            bodies.append(moments)
    return bodies


def test_closed_form_matches_the_exact_free_body_on_both_sides_of_the_separatrix() -> None:
    """scipy's Jacobi functions (Cephes) keep ~1e-15 of relative accuracy in sn, cn, dn for m away from 1 and
    the phase grows to ~60 rad here, so 1e-11 of |ω| leaves a margin of 100 over the 1.4e-13 measured; the
    exact free body is at the round-off floor."""
    t = np.linspace(-1.0, 2.0, 301)
    rng = np.random.default_rng(3)
    sides = set()
    for moments in random_bodies(60, 1):
        w0 = rng.normal(size=3) * 10.0
        got, want = free_omega(moments, w0, t), FreeBody(moments).omega(w0, t)
        assert np.max(np.abs(got - want)) <= 1e-11 * np.linalg.norm(w0)
        big_l2, two_e = np.sum((moments * w0) ** 2), np.sum(moments * w0**2)
        sides.add(bool(big_l2 > two_e * np.median(moments)))
    assert sides == {True, False}  # tumbling about the largest and about the smallest axis both seen


def test_phone_toss_near_the_separatrix() -> None:
    """A phone's toss about its intermediate axis: 1 − m ~ 1e-4, the flip's case."""
    moments = np.array([0.8, 0.21, 1.0])
    w0 = np.array([20.0, 0.3, -0.2])
    t = np.linspace(0.0, 1.2, 121)
    assert np.max(np.abs(free_omega(moments, w0, t) - FreeBody(moments).omega(w0, t))) <= 1e-11 * 20.0


def test_stepped_without_drag_is_the_exact_solution_to_rk4s_error() -> None:
    """RK4 at 2 ms: global error ~ (h |ω| s)^4 with s the moments' spread ~ 1, below 1e-6 of |ω| at 25 rad/s."""
    moments = np.array([0.8, 0.21, 1.0])
    w0 = np.array([25.0, 0.5, -0.4])
    t = np.linspace(0.0, 1.0, 101)
    error = np.max(np.abs(drag_omega(moments, np.zeros(3), w0, t) - FreeBody(moments).omega(w0, t)))
    assert error <= 1e-6 * 25.0
    back = -t[::-1]
    assert (
        np.max(np.abs(drag_omega(moments, np.zeros(3), w0, back[::-1]) - FreeBody(moments).omega(w0, back[::-1])))
        <= 1e-6 * 25.0
    )


def test_stepped_drag_matches_the_projects_compiled_integrator() -> None:
    """The same linear drag, three SpinFriction flows (exact) in a sixth-order splitting at 0.1 ms: the two
    agree to the RK4's 1e-6 of |ω|, and the drag takes the 5-15% of |L| a real toss loses."""
    moments = np.array([0.8, 0.21, 1.0])
    drag = np.array([0.1, 0.02, 0.05])
    w0 = np.array([22.0, 0.4, -0.3])
    method = BlanesMoan6(moments, [SpinFriction(drag[i], moments, np.eye(3)[i]) for i in range(3)])
    run = integrate(method, np.eye(3), moments * w0, 1e-4, 10_000, save_every=100)
    stepped = drag_omega(moments, drag, w0, run.t)
    assert np.max(np.abs(stepped - run.L_body / moments)) <= 1e-6 * 22.0
    loss = 1.0 - np.linalg.norm(run.L_body[-1]) / np.linalg.norm(run.L_body[0])
    assert 0.05 < loss < 0.15


def test_model_in_phone_axes_turns_the_principal_frame() -> None:
    moments = np.array([0.8, 0.21, 1.0])
    rot = rotation_from_vector(np.array([0.02, -0.01, 0.03]))
    assert np.allclose(rot.T @ rot, np.eye(3), atol=1e-15, rtol=0) and np.isclose(np.linalg.det(rot), 1.0)
    w0 = np.array([20.0, 0.3, -0.2])
    t = np.linspace(-0.2, 0.5, 71)
    assert np.allclose(
        model_omega(moments, rot, None, w0, t), FreeBody(moments).omega(w0, t) @ rot.T, atol=1e-10, rtol=0
    )
    # With drag, stepped both ways from t = 0, where ω is ω0 turned into the phone's axes.
    drag = np.array([0.1, 0.0, 0.0])
    both = model_omega(moments, rot, drag, w0, np.array([-0.1, 0.0, 0.1]))
    assert np.allclose(both[1], rot @ w0, atol=1e-14, rtol=0)
    for k, t1 in ((0, -0.1), (2, 0.1)):
        assert np.allclose(both[k], drag_omega(moments, drag, w0, np.array([t1]))[0] @ rot.T, atol=1e-14, rtol=0)


def test_eulers_equations_read_as_a_linear_system_give_the_ratios() -> None:
    """From exact samples at 100 Hz the central differences' error (h² ω⃛/6 ~ 1e-3 of ω̇) sets the guess's
    error: within 0.01 of the true ratios."""
    moments = np.array([0.8, 0.21, 1.0])
    t = np.arange(0.0, 0.8, 0.01)
    omega = FreeBody(moments).omega(np.array([20.0, 0.3, -0.2]), t)
    assert np.max(np.abs(euler_ratios([(t, omega)]) - moments)) < 0.01
