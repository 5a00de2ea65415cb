"""Tests of physics.integrators against exact solutions and conservation laws.

References: the closed-form free body (physics.free_body) and the closed-form Lagrange top
(physics.heavy_top). Orders are measured by step halving; tolerances are explained where they are set.
"""

from __future__ import annotations

import math

import numpy as np
import pytest

from physics.free_body import FreeBody
from physics.heavy_top import HeavyTop
from physics.integrators import (
    ExactFreeSplitting,
    GravityTorque,
    LiePoissonStrang,
    LieRK4,
    SpinFriction,
    Suzuki4,
    Yoshida4,
    Yoshida6,
    Yoshida8,
    integrate,
    kinetic_energy,
)
from physics.rotations import orthonormality_error, rotation_angle

MOMENTS = np.array([2.0, 1.5, 1.0])
OMEGA0 = np.array([1.0, 0.3, 2.0])
SPLITTINGS = [LiePoissonStrang, Yoshida4, Suzuki4, Yoshida6, Yoshida8]
ALL = SPLITTINGS + [LieRK4]


def _free_error(method, n, t_end=5.0):
    body = FreeBody(MOMENTS)
    exact = body.attitude(OMEGA0, t_end)[0]
    tr = integrate(method, np.eye(3), MOMENTS * OMEGA0, t_end / n, n, save_every=n)
    return rotation_angle(tr.attitude[-1], exact)


# Step counts chosen so that the error is well inside the asymptotic range and far above round-off
# (the sixth-order method reaches ~1e-12 at n = 400, so it gets coarser steps; the eighth-order one
# goes 7e-7, 3e-9, 1.3e-11 at n = 40, 80, 160, still a factor 100 above round-off).
@pytest.mark.parametrize(
    "cls, steps",
    [
        (LiePoissonStrang, (100, 200, 400)),
        (Yoshida4, (100, 200, 400)),
        (Suzuki4, (50, 100, 200)),
        (Yoshida6, (40, 80, 160)),
        (Yoshida8, (40, 80, 160)),
        (LieRK4, (100, 200, 400)),
    ],
)
def test_convergence_order_free_body(cls, steps):
    method = cls(MOMENTS)
    errors = np.array([_free_error(method, n) for n in steps])
    orders = np.log2(errors[:-1] / errors[1:])
    # The criterion: measured order within 0.2 of the declared one.
    assert np.all(np.abs(orders - method.order) < 0.2), (method.name, errors, orders)


def _top_setup():
    i1, i3, mass, ell = 1.0, 0.5, 1.0, 0.3
    top = HeavyTop(i1, i3, mass * 9.81 * ell)
    t_end = 2.0
    sol = top.solve(1.0, 0.0, 0.0, 20.0, [0.0, t_end])
    moments = np.array([i1, i1, i3])
    torque = GravityTorque(mass, [0.0, 0.0, ell])
    return moments, torque, sol, t_end


@pytest.mark.parametrize(
    "cls, steps",
    [
        (LiePoissonStrang, (200, 400, 800)),
        (Yoshida4, (200, 400, 800)),
        (Yoshida6, (100, 200, 400)),
        (Yoshida8, (100, 200, 400)),
        (LieRK4, (200, 400, 800)),
        (ExactFreeSplitting, (200, 400, 800)),
    ],
)
def test_convergence_order_heavy_top(cls, steps):
    moments, torque, _, _ = _top_setup()
    _assert_top_order(cls(moments, torque), steps)


def _assert_top_order(method, steps):
    moments, _, sol, t_end = _top_setup()
    L0 = moments * sol.omega_body[0]
    errors = []
    for n in steps:
        tr = integrate(method, sol.attitude[0], L0, t_end / n, n, save_every=n)
        errors.append(rotation_angle(tr.attitude[-1], sol.attitude[-1]))
    errors = np.array(errors)
    orders = np.log2(errors[:-1] / errors[1:])
    assert np.all(np.abs(orders - method.order) < 0.2), (method.name, errors, orders)


# The exact free flow composed to orders 4, 6, 8 (the eighth-order one goes 4.7e-8, 2.1e-10, 8.6e-13 at
# n = 30, 60, 120: still far above round-off).
@pytest.mark.parametrize(
    "composition, steps", [("yoshida4", (100, 200, 400)), ("yoshida6", (50, 100, 200)), ("yoshida8", (30, 60, 120))]
)
def test_convergence_order_exact_free_compositions(composition, steps):
    moments, torque, _, _ = _top_setup()
    method = ExactFreeSplitting(moments, torque, composition=composition)
    assert method.order == int(composition[-1])
    _assert_top_order(method, steps)


def _dissipative_torques(moments):
    from physics.integrators import TransverseAirDrag

    # Friction about an axis off z and the transverse drag: their exact sub-flows do not commute, so a base
    # step that is not symmetric in them (the compiled kernel applied them in the same order on both halves
    # until this test) drops every composition to order 1.
    return [
        GravityTorque(1.0, [0.0, 0.0, 0.3]),
        SpinFriction(0.3, moments, (0.1, 0.0, 1.0)),
        TransverseAirDrag(0.2, moments),
    ]


@pytest.mark.parametrize(
    "cls, composition, base",
    [
        (LiePoissonStrang, None, 100),
        (Yoshida4, None, 100),
        (Suzuki4, None, 100),
        (Yoshida6, None, 100),
        (Yoshida8, None, 100),
        (LieRK4, None, 100),
        (ExactFreeSplitting, "strang", 100),
        (ExactFreeSplitting, "yoshida4", 100),
        (ExactFreeSplitting, "yoshida6", 25),
        (ExactFreeSplitting, "yoshida8", 25),
    ],
)
def test_convergence_order_with_friction_and_drag(cls, composition, base):
    # No closed form: the order is read from successive differences d_n = |x_n − x_2n|, which fall as h^p
    # (measured: the smallest d, at the finest steps, is 2e-12 for Yoshida 8, still far above round-off).
    moments = np.array([1.0, 1.0, 0.5]) if cls is ExactFreeSplitting else np.array([1.0, 0.8, 0.5])
    torques = _dissipative_torques(moments)
    method = cls(moments, torques) if composition is None else cls(moments, torques, composition=composition)
    _, _, sol, t_end = _top_setup()
    R0, L0 = sol.attitude[0], moments * sol.omega_body[0]
    ends = []
    for n in (base, 2 * base, 4 * base, 8 * base):
        tr = integrate(method, R0, L0, t_end / n, n, save_every=n)
        ends.append((tr.attitude[-1], tr.L_body[-1]))
    diffs = np.array(
        [
            max(rotation_angle(a[0], b[0]), np.max(np.abs(a[1] - b[1])) / np.max(np.abs(b[1])))
            for a, b in zip(ends[:-1], ends[1:])
        ]
    )
    orders = np.log2(diffs[:-1] / diffs[1:])
    assert np.all(np.abs(orders - method.order) < 0.2), (method.name, diffs, orders)


def test_exact_free_splitting_is_exact_without_torque():
    body = FreeBody(MOMENTS)
    method = ExactFreeSplitting(MOMENTS)
    R, L = method.step(np.eye(3), MOMENTS * OMEGA0, 7.0)
    # One step of 7 s is the closed form itself: agreement to round-off of the elliptic evaluation.
    assert rotation_angle(R, body.attitude(OMEGA0, 7.0)[0]) < 1e-12
    assert np.allclose(L, MOMENTS * body.omega(OMEGA0, 7.0)[0], rtol=0, atol=1e-12)


@pytest.mark.parametrize("cls", SPLITTINGS)
def test_splittings_conserve_casimir_and_spatial_momentum(cls):
    method = cls(MOMENTS)
    L0 = MOMENTS * OMEGA0
    tr = integrate(method, np.eye(3), L0, 0.05, 4000, save_every=400)
    norms = np.linalg.norm(tr.L_body, axis=1)
    # Every sub-step is an exact rotation of L: |L| changes only by round-off, ~1e-16 per step,
    # a random walk over 4000 x (up to 15 sub-steps) operations stays far below 1e-13.
    assert np.max(np.abs(norms / norms[0] - 1.0)) < 1e-13
    l_space = np.einsum("kij,kj->ki", tr.attitude, tr.L_body)
    assert np.max(np.abs(l_space - l_space[0])) < 1e-12 * norms[0]
    assert np.max(orthonormality_error(tr.attitude)) < 1e-13


def test_gravity_kicks_conserve_vertical_momentum():
    moments, torque, sol, _ = _top_setup()
    method = Yoshida4(moments, torque)
    tr = integrate(method, sol.attitude[0], moments * sol.omega_body[0], 0.01, 3000, save_every=300)
    lz = np.einsum("kj,kj->k", tr.attitude[:, 2, :], tr.L_body)
    # Kicks have no vertical component in space and free rotations keep L_space: L_z to round-off.
    assert np.max(np.abs(lz - lz[0])) < 1e-12 * abs(lz[0])


def test_symplectic_energy_bounded_rk4_drifts():
    # A coarse step (about 1/40 of the rotation period) over 20,000 steps.
    L0 = MOMENTS * OMEGA0
    e0 = kinetic_energy(MOMENTS, L0)
    split = integrate(LiePoissonStrang(MOMENTS), np.eye(3), L0, 0.1, 20000, save_every=100)
    rk = integrate(LieRK4(MOMENTS), np.eye(3), L0, 0.1, 20000, save_every=100)
    err_s = np.abs(kinetic_energy(MOMENTS, split.L_body) / e0 - 1.0)
    err_r = np.abs(kinetic_energy(MOMENTS, rk.L_body) / e0 - 1.0)
    half = err_s.size // 2
    # Bounded, not drifting: the second half never exceeds the first half's maximum by more than 10 %.
    assert np.max(err_s[half:]) <= 1.1 * np.max(err_s[:half])
    # The non-symplectic RK4 drifts: its error keeps growing (the last value is the largest so far,
    # and well above the early error).
    assert err_r[-1] > 5.0 * err_r[len(err_r) // 10]


def test_heavy_top_energy_bounded():
    moments, torque, sol, _ = _top_setup()
    method = LiePoissonStrang(moments, torque)
    R0, L0 = sol.attitude[0], moments * sol.omega_body[0]
    tr = integrate(method, R0, L0, 0.01, 20000, save_every=50)
    e = method.energy(tr.attitude, tr.L_body)
    err = np.abs(e - e[0]) / abs(e[0])
    half = err.size // 2
    assert np.max(err[half:]) <= 1.1 * np.max(err[:half])


def _separatrix_distance(L):
    # Sign and size of L² − 2 E I2 relative to L²: 0 on the separatrix.
    e2 = np.sum(L * L / MOMENTS, axis=-1)
    return (np.sum(L * L, axis=-1) - e2 * MOMENTS[1]) / np.sum(L * L, axis=-1)


def test_intermediate_axis_flip_neither_damped_nor_pumped():
    # Spin about the intermediate axis, perturbed: the body flips periodically (tennis racket).
    omega0 = np.array([0.05, 2.0, 0.05])
    L0 = MOMENTS * omega0
    d0 = _separatrix_distance(L0)
    dt, n = 0.01, 40000  # about 14 flip periods
    ours = integrate(Yoshida4(MOMENTS), np.eye(3), L0, dt, n, save_every=50)
    strang = integrate(LiePoissonStrang(MOMENTS), np.eye(3), L0, dt, n, save_every=50)
    # A scheme that takes an explicit Euler step of Euler's equations and rescales |L| afterwards
    # (vectorised over nothing: a plain loop, 40,000 cheap steps, in floats: np.cross on one 3-vector costs
    # 30 times its arithmetic).
    l1, l2, l3 = L0.tolist()
    i1, i2, i3 = MOMENTS.tolist()
    rescaled = [(l1, l2, l3)]
    norm0 = math.sqrt(l1 * l1 + l2 * l2 + l3 * l3)
    for k in range(n):
        w1, w2, w3 = l1 / i1, l2 / i2, l3 / i3
        n1, n2, n3 = l1 + dt * (l2 * w3 - l3 * w2), l2 + dt * (l3 * w1 - l1 * w3), l3 + dt * (l1 * w2 - l2 * w1)
        scale = norm0 / math.sqrt(n1 * n1 + n2 * n2 + n3 * n3)
        l1, l2, l3 = n1 * scale, n2 * scale, n3 * scale
        if (k + 1) % 50 == 0:
            rescaled.append((l1, l2, l3))
    rel_ours = (_separatrix_distance(ours.L_body) - d0) / abs(d0)
    rel_strang = (_separatrix_distance(strang.L_body) - d0) / abs(d0)
    rel_rescaled = (_separatrix_distance(np.array(rescaled)) - d0) / abs(d0)
    # d0 is only 1.4e-4: the Strang step's O(h²) energy wobble is 20 % of it at this step, but it is a
    # fixed band: each quarter of the run spans the same band (to 2 %, the sampling jitter), no drift.
    quarters = np.array_split(rel_strang, 4)
    assert np.max(np.abs(rel_strang)) < 0.25
    for q in quarters[1:]:
        assert abs(np.max(q) - np.max(quarters[0])) < 0.02 and abs(np.min(q) - np.min(quarters[0])) < 0.02
    # Fourth order: the wobble is 1e-3 of the (tiny) distance to the separatrix.
    assert np.max(np.abs(rel_ours)) < 1e-3
    # The rescaled explicit scheme is driven monotonically onto the separatrix (loses > 50 % of d0; 87 %
    # measured here by the end).
    assert rel_rescaled[-1] < -0.5 and np.all(np.diff(rel_rescaled) < 0.0)
    # The flips keep happening: ω2 changes sign repeatedly in our run.
    signs = np.sign(ours.L_body[:, 1])
    assert np.count_nonzero(np.diff(signs)) >= 10


@pytest.mark.parametrize("cls", [LiePoissonStrang, ExactFreeSplitting, Yoshida4, LieRK4])
def test_friction_loses_energy_monotonically(cls):
    friction = SpinFriction(0.05, MOMENTS, axis_body=(0.2, 0.3, 1.0))
    method = cls(MOMENTS, friction)
    tr = integrate(method, np.eye(3), MOMENTS * OMEGA0, 0.002, 3000, save_every=1)
    e = kinetic_energy(MOMENTS, tr.L_body)
    # Per step the friction loss (~c ω_a² h ≈ 1e-4 E) dominates the splitting's O(h³) energy wobble.
    assert np.all(np.diff(e) < 0.0)
    assert e[-1] < 0.9 * e[0]


def test_spin_friction_flow_is_exact_about_a_principal_axis():
    c, i3 = 0.3, 1.0
    friction = SpinFriction(c, MOMENTS, axis_body=(0.0, 0.0, 1.0))
    method = LiePoissonStrang(MOMENTS, friction)
    # Pure spin about z: the free rotations leave it, friction decays it exactly as exp(−c t / I3).
    R, L = method.step(np.eye(3), np.array([0.0, 0.0, 3.0]), 2.0)
    assert L[2] == pytest.approx(3.0 * math.exp(-c * 2.0 / i3), rel=1e-14)


def test_rod_zero_moment_does_not_divide_by_zero():
    rod = np.array([1.0, 1.0, 0.0])
    for cls in ALL + [ExactFreeSplitting]:
        method = cls(rod, GravityTorque(1.0, [0.0, 0.0, 0.5]))
        tr = integrate(method, np.eye(3), np.array([0.3, 1.0, 0.7]), 0.01, 200, save_every=50)
        assert np.all(np.isfinite(tr.attitude)) and np.all(np.isfinite(tr.L_body)), cls
        # The rod carries no angular momentum about its own axis.
        assert np.all(tr.L_body[:, 2] == 0.0), cls


def test_batched_equals_unbatched():
    method = Yoshida4(MOMENTS, [GravityTorque(2.0, [0.1, 0.0, 0.3]), SpinFriction(0.01, MOMENTS)])
    rng = np.random.default_rng(1)
    from scipy.spatial.transform import Rotation

    R0 = Rotation.random(5, random_state=rng).as_matrix()
    L0 = rng.normal(size=(5, 3))
    Rb, Lb = method.step(R0, L0, 0.03)
    for k in range(5):
        R1, L1 = method.step(R0[k], L0[k], 0.03)
        # Same arithmetic on floats and on arrays: agreement to a few ulps (numpy's sin/cos may differ
        # from math's by an ulp).
        assert np.max(np.abs(R1 - Rb[k])) < 1e-14 and np.max(np.abs(L1 - Lb[k])) < 1e-14


def test_generic_torque_callable_matches_builtin():
    grav = GravityTorque(2.0, [0.1, 0.0, 0.3])

    class MyGravity:
        conservative = True

        def __call__(self, R, L):
            return grav(R, L)

    a = integrate(Yoshida4(MOMENTS, grav), np.eye(3), MOMENTS * OMEGA0, 0.01, 100, save_every=100)
    b = integrate(Yoshida4(MOMENTS, MyGravity()), np.eye(3), MOMENTS * OMEGA0, 0.01, 100, save_every=100)
    assert np.max(np.abs(a.attitude - b.attitude)) < 1e-13


def test_attributes_declared():
    for cls in ALL + [ExactFreeSplitting]:
        m = cls(MOMENTS)
        assert isinstance(m.name, str) and m.order in (2, 4, 6, 8) and isinstance(m.conserves, tuple)
    assert LiePoissonStrang(MOMENTS).symplectic and not LieRK4(MOMENTS).symplectic
    assert not LiePoissonStrang(MOMENTS, SpinFriction(0.1, MOMENTS)).symplectic


def test_the_registry_lists_every_method_once_with_its_declarations():
    import importlib

    from physics.integrators import REGISTRY, BlanesMoan6, ClassicalRK4, KahanLi8, SofroniouSpaletta10

    optimised = [BlanesMoan6, KahanLi8, SofroniouSpaletta10]  # tests/physics/test_optimised_compositions.py
    assert set(REGISTRY.values()) == set(ALL + optimised + [ExactFreeSplitting, ClassicalRK4])
    for name, cls in REGISTRY.items():
        assert cls.name == name and cls.order in (2, 4, 6, 8, 10) and isinstance(cls.symplectic, bool)
        assert isinstance(cls(MOMENTS).conserves, tuple)
        # The class itself declares what the torque-free method keeps (ClassicalRK4: nothing, its R drifts).
        if cls is not ClassicalRK4:
            assert "orthonormality of R" in cls.conserves, name
        if cls.symplectic:
            assert {"|L|", "L_space", "symplectic form"} <= set(cls.conserves), name
            assert set(cls(MOMENTS).conserves) >= set(cls.conserves), name  # torque-free: all of it
        # One method per module: each class lives in its own module of the package.
        module = importlib.import_module(cls.__module__)
        assert module.__name__.startswith("physics.integrators.") and getattr(module, cls.__name__) is cls
    modules = [cls.__module__ for cls in REGISTRY.values()]
    assert len(set(modules)) == len(modules)


@pytest.mark.parametrize("bad", [[1.0, 1.0, 3.0], [-1.0, 1.0, 1.0], [np.nan, 1.0, 1.0], [0.0, 0.0, 0.0]])
def test_impossible_moments_rejected(bad):
    with pytest.raises(ValueError, match="moments"):
        LiePoissonStrang(bad)


def test_bad_input_rejected():
    m = LiePoissonStrang(MOMENTS)
    with pytest.raises(ValueError):
        m.step(np.eye(3), [1.0, 2.0], 0.1)
    with pytest.raises(ValueError):
        m.step(np.eye(3), [1.0, 2.0, np.inf], 0.1)
    with pytest.raises(ValueError):
        integrate(m, np.eye(3), [1.0, 2.0, 3.0], 0.1, -1)
    with pytest.raises(ValueError):
        GravityTorque(-1.0, [0, 0, 1])
    with pytest.raises(ValueError):
        SpinFriction(-0.1, MOMENTS)
    with pytest.raises(ValueError):
        LiePoissonStrang(MOMENTS, torque=lambda R, L: L)  # no 'conservative' attribute


COMPILED = [LiePoissonStrang, Yoshida4, Suzuki4, Yoshida6, Yoshida8, ExactFreeSplitting, LieRK4]


@pytest.mark.parametrize("cls", COMPILED)
def test_the_compiled_step_is_the_interpreted_step(cls):
    from physics.integrators import TransverseAirDrag
    from physics.integrators.drivers import compiled_step

    # Every torque the kernels know except the air drag, whose interpreted sub-flow is one RK4 step
    # (the compiled one is its exact flow): see the next test.
    moments = np.array([1.0, 1.0, 0.5]) if cls is ExactFreeSplitting else MOMENTS
    method = cls(moments, [GravityTorque(1.5, [0.0, 0.0, 0.3]), SpinFriction(0.02, moments, (0.1, 0.0, 1.0))])
    assert compiled_step(method) is not None
    R, L = np.eye(3), moments * OMEGA0
    tr = integrate(method, R, L, 0.01, 50, save_every=50)
    for _ in range(50):
        R, L = method.step(R, L, 0.01)  # interpreted, on arrays
    # The same sub-flows (the compiled loop fuses a step's last one with the next step's first): agreement
    # to a few hundred ulps after 50 steps.
    assert np.max(np.abs(tr.attitude[-1] - R)) < 1e-13 and np.max(np.abs(tr.L_body[-1] - L)) < 1e-13
    assert compiled_step(cls(moments, [TransverseAirDrag(0.1, moments)])) is not None


def test_classical_rk4_compiled_is_its_interpreted_step():
    from physics.integrators import ClassicalRK4, TransverseAirDrag, advance
    from physics.integrators.drivers import compiled_step

    # Gravity, a tilted spin friction and the air drag: ClassicalRK4 treats every torque by its rates, so the
    # compiled loop and the interpreted one do the same arithmetic; R leaves SO(3) in both alike.
    torques = [
        GravityTorque(1.5, [0.0, 0.0, 0.3]),
        SpinFriction(0.02, MOMENTS, (0.1, 0.0, 1.0)),
        TransverseAirDrag(0.1, MOMENTS),
    ]
    method = ClassicalRK4(MOMENTS, torques)
    assert compiled_step(method) is not None
    start = np.r_[np.eye(3).ravel(), MOMENTS * OMEGA0]
    compiled = advance(method, start, 0.05, 200)
    s = tuple(float(x) for x in start)
    for _ in range(200):
        s = method.step_state(s, 0.05, math)
    assert np.max(np.abs(compiled - np.array(s))) < 1e-12
    R = compiled[:9].reshape(3, 3)
    assert np.max(np.abs(R.T @ R - np.eye(3))) > 1e-9  # not projected: the careless baseline stays careless


@pytest.mark.parametrize("dissipative", [False, True])
@pytest.mark.parametrize("cls", COMPILED)
def test_a_batch_and_its_bodies_one_by_one_agree(cls, dissipative):
    moments = np.array([1.0, 1.0, 0.5]) if cls is ExactFreeSplitting else MOMENTS
    torques = _dissipative_torques(moments) if dissipative else GravityTorque(1.0, [0.0, 0.0, 0.4])
    method = cls(moments, torques)
    rng = np.random.default_rng(7)
    from scipy.spatial.transform import Rotation

    R0 = Rotation.random(5, random_state=rng).as_matrix()
    L0 = rng.normal(size=(5, 3)) * 3.0
    batch = integrate(method, R0, L0, 0.02, 40, save_every=20)
    assert batch.attitude.shape == (3, 5, 3, 3) and batch.L_body.shape == (3, 5, 3)
    for b in range(5):
        one = integrate(method, R0[b], L0[b], 0.02, 40, save_every=20)
        assert np.max(np.abs(one.attitude - batch.attitude[:, b])) <= 1e-15
        assert np.max(np.abs(one.L_body - batch.L_body[:, b])) <= 1e-15


def test_a_python_torque_runs_interpreted_and_the_air_drag_compiled_agrees_with_it():
    from physics.integrators import TransverseAirDrag
    from physics.integrators.drivers import compiled_step

    class Drag:  # the same torque as a plain callable: the documented slower path
        conservative = False

        def __call__(self, R, L):
            return TransverseAirDrag(0.1, MOMENTS)(R, L)

    slow, fast = Yoshida4(MOMENTS, Drag()), Yoshida4(MOMENTS, TransverseAirDrag(0.1, MOMENTS))
    assert compiled_step(slow) is None and compiled_step(fast) is not None
    R, L = np.eye(3), MOMENTS * OMEGA0
    a = integrate(slow, R, L, 0.01, 100, save_every=100)
    b = integrate(fast, R, L, 0.01, 100, save_every=100)
    # One RK4 step against the exact flow of the drag, inside an order-4 composition: O(h⁴) apart.
    assert np.max(np.abs(a.L_body[-1] - b.L_body[-1])) < 1e-8


# --------------------------------------------------------------------------------------------------
# Validation: attitudes must be rotations; shapes and steps are named in the message.
# --------------------------------------------------------------------------------------------------
@pytest.mark.parametrize(
    ("attitude", "message"),
    [
        (2 * np.eye(3), "must be a rotation matrix"),
        (np.diag([1.0, 1.0, -1.0]), "not a reflection"),
        (np.eye(4), r"must have shape \(3, 3\) or \(n, 3, 3\), got shape \(4, 4\)"),
        ([[1.0, 0.0, 0.0], [0.0, 1.0, 0.0], [0.0, 0.0, np.nan]], "finite"),
    ],
)
def test_integrate_and_flow_refuse_an_attitude_that_is_not_a_rotation(attitude, message):
    from physics.free_body import FreeBody

    with pytest.raises(ValueError, match=message):
        integrate(LiePoissonStrang([2.0, 1.5, 1.0]), attitude, [1.0, 2.0, 3.0], 0.1, 10)
    with pytest.raises(ValueError, match=message):
        FreeBody([2.0, 1.5, 1.0]).flow(attitude, [1.0, 2.0, 3.0], 0.1)


def test_wrong_shapes_and_steps_name_the_argument():
    from physics.free_body import FreeBody
    from physics.heavy_top import simulate_heavy_body

    with pytest.raises(ValueError, match=r"L0_body must have shape \(3,\) or \(n, 3\), got shape \(2,\)"):
        integrate(LiePoissonStrang([2.0, 1.5, 1.0]), np.eye(3), [1.0, 2.0], 0.1, 10)
    with pytest.raises(ValueError, match=r"L_body must have shape \(3,\) or \(n, 3\), got shape \(2,\)"):
        FreeBody([2.0, 1.5, 1.0]).flow(np.eye(3), [1.0, 2.0], 0.1)
    with pytest.raises(ValueError, match="dt must be one number of seconds"):
        integrate(LiePoissonStrang([2.0, 1.5, 1.0]), np.eye(3), [1.0, 2.0, 3.0], [0.1, 0.2], 10)
    args = ([1.0, 1.0, 0.5], 1.0, [0.0, 0.0, 0.1])
    with pytest.raises(ValueError, match=r"attitude0 must have shape \(3, 3\), got shape \(2, 2\)"):
        simulate_heavy_body(*args, np.eye(2), [0.0, 0.0, 10.0], 1.0, 0.01)
    with pytest.raises(ValueError, match=r"omega_body0 must have shape \(3,\), got shape \(2,\)"):
        simulate_heavy_body(*args, np.eye(3), [0.0, 10.0], 1.0, 0.01)
    with pytest.raises(ValueError, match="not a reflection"):
        simulate_heavy_body(*args, np.diag([1.0, -1.0, -1.0]) @ np.diag([1.0, 1.0, -1.0]), [0.0, 0.0, 10.0], 1.0, 0.01)


# --------------------------------------------------------------------------------------------------
# Classical RK4 (the app's careless comparison) and advance()
# --------------------------------------------------------------------------------------------------


def _chordal(a: np.ndarray, b: np.ndarray) -> float:
    """Chordal angle 2 arcsin(|A − B|_F / √8): the rotation angle between two rotations, and a distance
    that stays defined when one of them has left SO(3)."""
    return float(2.0 * np.arcsin(min(1.0, np.linalg.norm(a - b) / math.sqrt(8.0))))


@pytest.mark.parametrize("with_gravity", [False, True])
def test_classical_rk4_is_order_four_and_not_geometric(with_gravity):
    from physics.integrators import ClassicalRK4, advance

    if with_gravity:
        moments, torque, sol, t_end = _top_setup()
        R0, L0, exact = sol.attitude[0], moments * sol.omega_body[0], sol.attitude[-1]
        steps = (200, 400, 800)
    else:
        moments, torque, t_end = MOMENTS, None, 5.0
        R0, L0, exact = np.eye(3), MOMENTS * OMEGA0, FreeBody(MOMENTS).attitude(OMEGA0, t_end)[0]
        steps = (100, 200, 400)
    method = ClassicalRK4(moments, torque)
    assert (method.order, method.symplectic, method.conserves) == (4, False, ())
    start = np.concatenate([np.asarray(R0).ravel(), L0])
    errors, squish = [], []
    for n in steps:
        end = advance(method, start, t_end / n, n)
        R = end[:9].reshape(3, 3)
        errors.append(_chordal(R, exact))
        squish.append(float(np.abs(R.T @ R - np.eye(3)).max()))
    orders = np.log2(np.array(errors[:-1]) / np.array(errors[1:]))
    assert np.all(np.abs(orders - 4) < 0.2), (errors, orders)
    # Not geometric: R leaves the rotations by an amount of the order of the error (Lie RK4 stays on them).
    assert squish[0] > 1e-10 and squish[0] > 10.0 * squish[-1]
    lie = integrate(LieRK4(moments, torque), R0, L0, t_end / steps[0], steps[0], save_every=steps[0])
    assert orthonormality_error(lie.attitude[-1]) < 1e-14


def test_advance_is_integrate_for_a_splitting():
    from physics.integrators import advance

    method = Yoshida4(MOMENTS)
    tr = integrate(method, np.eye(3), MOMENTS * OMEGA0, 0.01, 50, save_every=50)
    end = advance(method, np.concatenate([np.eye(3).ravel(), MOMENTS * OMEGA0]), 0.01, 50)
    np.testing.assert_allclose(end[:9].reshape(3, 3), tr.attitude[-1], rtol=0, atol=1e-14)
    np.testing.assert_allclose(end[9:], tr.L_body[-1], rtol=0, atol=1e-14)


@pytest.mark.parametrize(
    "state, dt, n, message",
    [
        (np.zeros(11), 0.1, 1, "twelve"),
        (np.full(12, np.nan), 0.1, 1, "finite"),
        ("twelve", 0.1, 1, "twelve"),
        (np.zeros(12), float("inf"), 1, "finite"),
        (np.zeros(12), 0.1, -1, "non-negative"),
        (np.zeros(12), 0.1, 1.5, "integer"),
    ],
)
def test_advance_refuses_bad_input(state, dt, n, message):
    from physics.integrators import advance

    with pytest.raises(ValueError, match=message):
        advance(LieRK4(MOMENTS), state, dt, n)
