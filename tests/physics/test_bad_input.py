"""Every public physics function, given a bad argument, either returns finite values or raises a
ValueError: never a TypeError, IndexError or OverflowError from numpy, never a NaN, never a warning.

Bad values: NaN, ±inf, a string, None, a wrong shape, ±1e308 (squares overflow), 1e-320 (subnormal),
an integer beyond the float range, a bool, an arbitrary object. Times so large that the phase of the
motion overflows are refused too ("too far from 0").
"""

from __future__ import annotations

import math
import warnings

import numpy as np
import pytest

from physics.free_body import FreeBody, jacobi_sn_cn_dn
from physics.heavy_top import HeavyTop, euler_attitude, omega_body_from_euler, simulate_heavy_body, symmetry_axis
from physics.inertia import box
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
}
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
            assert str(exc), "the message says what was expected"
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
