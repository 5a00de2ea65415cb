"""Every public physics function, given a bad argument, either returns finite values or raises a
ValueError: never a TypeError, IndexError or OverflowError from numpy, never a NaN, never a warning.

Bad values: NaN, ±inf, a string, None, a wrong shape, ±1e308 (squares overflow), 1e-320 (subnormal),
an integer beyond the float range, a bool, an arbitrary object. Times so large that the phase of the
motion overflows are refused too ("too far from 0").
"""

from __future__ import annotations

import inspect
import math
import warnings

import numpy as np
import pytest

from physics.free_body import FreeBody, jacobi_sn_cn_dn
from physics.heavy_top import HeavyTop, euler_attitude, omega_body_from_euler, simulate_heavy_body, symmetry_axis
from physics.inertia import box
from physics.integrators import LieRK4, advance, integrate
from physics.pendulum import PhysicalPendulum

BAD = {
    "nan": math.nan,
    "inf": math.inf,
    "-inf": -math.inf,
    "text": "x",
    "None": None,
    "wrong shape": [1.0, 2.0],
    "matrix": np.zeros((2, 2)),
    "1e308": 1e308,
    "-1e308": -1e308,
    "subnormal": 1e-320,
    "10**400": 10**400,
    "object": object(),
}
TOP = HeavyTop(1.0, 0.5, 2.0)
BODY = FreeBody([1.0, 2.0, 3.0])
PENDULUM = PhysicalPendulum(box(1.0, [0.1, 0.2, 0.3]), [0.0, 0.0, 0.15], [1.0, 0.0, 0.0])
RK4 = LieRK4([1.0, 2.0, 3.0])
CALLS = {
    "HeavyTop": (HeavyTop, (1.0, 0.5, 2.0)),
    "HeavyTop.solve": (TOP.solve, (0.5, 0.1, 0.2, 10.0, [0.0, 1.0])),
    "HeavyTop.trajectory": (TOP.trajectory, (0.5, 0.1, 0.2, 10.0)),
    "HeavyTopTrajectory.at": (TOP.trajectory(0.5, 0.1, 0.2, 10.0).at, (1.0,)),
    "HeavyTop.steady_precession_rates": (TOP.steady_precession_rates, (0.5, 10.0)),
    "HeavyTop.simulate": (TOP.simulate, (0.5, 0.1, 0.2, 10.0, 0.1, 0.01)),
    "HeavyTop.threshold_crossing_time": (TOP.threshold_crossing_time, (10.0, 0.1)),
    "FreeBody": (FreeBody, ([1.0, 2.0, 3.0],)),
    "FreeBody.motion": (BODY.motion, ([0.1, 1.0, 0.2], [0.0, 1.0])),
    "FreeBodyTrajectory.at": (BODY.trajectory([0.1, 1.0, 0.2]).at, (1.0,)),
    "FreeBody.flow": (BODY.flow, (np.eye(3), [0.1, 1.0, 0.2], 0.1)),
    "FreeBody.stability": (BODY.stability, (1, 2.0)),
    "FreeBody.period": (BODY.period, ([0.1, 1.0, 0.2],)),
    "jacobi_sn_cn_dn": (jacobi_sn_cn_dn, ([0.1], 0.5)),
    "PhysicalPendulum.solve": (PENDULUM.solve, (0.5, 0.1, [0.0, 1.0])),
    "PendulumTrajectory.at": (PENDULUM.trajectory(0.5, 0.1).at, (1.0,)),
    "PhysicalPendulum.period": (PENDULUM.period, (0.5,)),
    "PhysicalPendulum.strike": (PENDULUM.strike, ([0.0, 1.0, 0.0], [0.0, 0.0, -0.1])),
    "box": (box, (1.0, [0.1, 0.2, 0.3])),
    "euler_attitude": (euler_attitude, (0.1, 0.2, 0.3)),
    "symmetry_axis": (symmetry_axis, (0.1, 0.2)),
    "omega_body_from_euler": (omega_body_from_euler, (0.1, 0.2, 0.3, 0.4, 0.5)),
    "simulate_heavy_body": (
        simulate_heavy_body,
        ([1.0, 1.0, 0.5], 1.0, [0.0, 0.0, 0.1], np.eye(3), [0.0, 0.0, 10.0], 0.05, 0.01),
    ),
    "LieRK4": (LieRK4, ([1.0, 2.0, 3.0],)),
    "LieRK4.step": (RK4.step, (np.eye(3), [0.1, 1.0, 0.2], 0.01)),
    "LieRK4.energy": (RK4.energy, (np.eye(3), [0.1, 1.0, 0.2])),
    "integrate": (integrate, (RK4, np.eye(3), [0.1, 1.0, 0.2], 0.01, 10)),
    "advance": (advance, (RK4, [1.0, 0.0, 0.0, 0.0, 1.0, 0.0, 0.0, 0.0, 1.0, 0.1, 1.0, 0.2], 0.01, 10)),
}
# The argument's name as each message must say it. HeavyTop.simulate checks the Euler rates after turning
# them into the body's angular velocity, and names that (physics/heavy_top.py, not this test's to change).
NAMED_AS = {("HeavyTop.simulate", rate): ("omega_body0", rate) for rate in ("thetadot0", "phidot0", "psidot0")}
# A time that is longer than the float range is returned as +inf, as the docstring says.
DOCUMENTED_INFINITY = {"HeavyTop.threshold_crossing_time"}
CASES = [
    (name, i, bad)
    for name, (_, good) in CALLS.items()
    for i in range(len(good))
    for bad in BAD
    if not (name == "FreeBody.stability" and i == 0)  # the axis index: an int, checked by its own test
]


def _floats(value) -> list[float]:
    if isinstance(value, (float, np.floating)):
        return [float(value)]
    if isinstance(value, np.ndarray) and value.dtype.kind == "f":
        return value.ravel().tolist()
    if isinstance(value, tuple):
        return [x for v in value for x in _floats(v)]
    if hasattr(value, "__dataclass_fields__"):
        return [x for f in value.__dataclass_fields__ for x in _floats(getattr(value, f))]
    return []


def _argument_name(call, index: int) -> str:
    return list(inspect.signature(call).parameters)[index]


@pytest.mark.parametrize("name, index, bad", CASES)
def test_a_bad_argument_gives_finite_values_or_a_value_error(name, index, bad):
    call, good = CALLS[name]
    args = list(good)
    args[index] = BAD[bad]
    with warnings.catch_warnings():
        warnings.simplefilter("error")  # a numpy overflow warning is a silent inf on its way
        try:
            result = call(*args)
        except ValueError as exc:
            # The message names the argument that was wrong (a student sees which input to fix).
            argument = _argument_name(call, index)
            names = NAMED_AS.get((name, argument), (argument,))
            assert any(n.lower() in str(exc).lower() for n in names), (argument, str(exc))
            return
    values = _floats(result)
    if name in DOCUMENTED_INFINITY:
        values = [v for v in values if v != math.inf]
    assert all(math.isfinite(v) for v in values), f"{name} returned non-finite values for {bad}"


def test_times_whose_phase_overflows_are_refused_by_name():
    for at in (
        TOP.trajectory(0.5, 0.1, 0.2, 10.0).at,
        BODY.trajectory([0.1, 1.0, 0.2]).at,
        PENDULUM.trajectory(0.5, 0.1).at,
    ):
        for t in (1e308, [0.0, -1e308]):
            with pytest.raises(ValueError, match="t is too far from 0"):
                at(t)


@pytest.mark.parametrize("attitude", [2.0 * np.eye(3), np.diag([1.0, 1.0, -1.0]), np.eye(3)[:2]])
def test_simulate_heavy_body_refuses_an_attitude_that_is_not_a_rotation(attitude):
    """Issue 15, item 6: 2·I (not orthonormal), a reflection, or a wrong shape as attitude0."""
    with pytest.raises(ValueError, match="attitude0"):
        simulate_heavy_body([1.0, 1.0, 0.5], 1.0, [0.0, 0.0, 0.1], attitude, [0.0, 0.0, 10.0], 0.05, 0.01)


@pytest.mark.parametrize(
    "call, argument, expected",
    [
        (lambda: BODY.flow(np.eye(3), [0.1, 1.0, 0.2], [0.1, 0.2]), "dt", r"one number, or shape \(k,\)"),
        (lambda: BODY.flow(np.eye(3), [0.1, 1.0, 0.2], np.zeros((2, 2))), "dt", r"shape \(k,\)"),
        (lambda: BODY.flow(np.stack([np.eye(3)] * 3), np.ones((2, 3)), 0.1), "attitude", "same number k"),
        (lambda: BODY.flow(np.stack([np.eye(3)] * 2), np.ones((2, 3)), [0.1, 0.2, 0.3]), "dt", "same number k"),
        (lambda: integrate(RK4, np.eye(3), [0.1, 1.0, 0.2], 0.01, [1, 2]), "n_steps", "non-negative integer"),
        (lambda: integrate(RK4, np.eye(3), [0.1, 1.0, 0.2], 0.01, math.nan), "n_steps", "non-negative integer"),
        (lambda: integrate(RK4, np.eye(3), [0.1, 1.0, 0.2], 0.01, math.inf), "n_steps", "non-negative integer"),
        (lambda: integrate(RK4, np.eye(3), [0.1, 1.0, 0.2], 0.01, 2.5), "n_steps", "non-negative integer"),
        (
            lambda: integrate(RK4, np.eye(3), [0.1, 1.0, 0.2], 0.01, 10, save_every=[1, 2]),
            "save_every",
            "positive integer",
        ),
        (
            lambda: integrate(RK4, np.eye(3), [0.1, 1.0, 0.2], 0.01, 10, save_every=math.nan),
            "save_every",
            "positive integer",
        ),
        (lambda: integrate(RK4, np.eye(3), [0.1, 1.0, 0.2], 0.01, 10, save_every=0), "save_every", "positive integer"),
        (lambda: integrate(RK4, np.eye(3), [0.1, 1.0, 0.2], [0.1, 0.2], 10), "dt", "one number"),
        (lambda: advance(RK4, np.zeros(12), 0.01, [1, 2]), "n_steps", "non-negative integer"),
        (lambda: RK4.energy(np.eye(3), [1.0, 2.0]), "L_body", r"\(3,\) or \(n, 3\)"),
        (lambda: RK4.energy(np.zeros((2, 3, 3)), [1.0, 2.0, 3.0]), "L_body", "same n"),
        (lambda: RK4.step(np.eye(3), np.ones((2, 3)), 0.01), "L_body", "same n"),
    ],
)
def test_wrong_shapes_and_counts_name_the_argument_and_what_it_must_be(call, argument, expected):
    """Audit of issue 15, item 6: these leaked numpy's broadcast messages, a TypeError from int(), or
    "cannot convert float NaN to integer"."""
    with pytest.raises(ValueError, match=expected) as info:
        call()
    assert argument in str(info.value)
