"""A method instance as the arrays its compiled step runs on (:mod:`.kernels`), or None when it has a
torque the kernels do not know (it then runs interpreted) or a triaxial exact free flow (Jacobi
functions: :meth:`physics.free_body.FreeBody.flow`, not compiled)."""

from __future__ import annotations

from typing import Any

import numpy as np

from physics.integrators import kernels
from physics.integrators._base import Method, Splitting
from physics.integrators.classical_rk4 import ClassicalRK4
from physics.integrators.exact_free import ExactFreeSplitting
from physics.integrators.lie_rk4 import LieRK4
from physics.integrators.torques import GravityTorque, SpinFriction, compiles

_OPS = {"X": kernels.OP_X, "Y": kernels.OP_Y, "Z": kernels.OP_Z, "T0": kernels.OP_T0, "T1": kernels.OP_T1}


def torque_arrays(method: Method) -> tuple[np.ndarray, np.ndarray, np.ndarray] | None:
    """(gravity (g, 3), friction (f, 8), drag (d, 3)) of the method's torques, or None for another torque."""
    if not all(compiles(t) for t in method.torques):
        return None
    gravity, friction, drag = [], [], []
    for t in method.torques:
        if isinstance(t, GravityTorque):
            gravity.append(np.asarray(t.weight_moment, dtype=float))
        elif isinstance(t, SpinFriction):
            friction.append([t.coefficient, t.axis_inverse_moment, *t.axis_body, *t.inverse_moments])
        else:
            inv = np.where(t.moments > 0.0, 1.0 / np.where(t.moments > 0.0, t.moments, 1.0), 0.0)
            drag.append([t.coefficient, inv[0], inv[1]])
    return (
        np.array(gravity, dtype=float).reshape(-1, 3),
        np.array(friction, dtype=float).reshape(-1, 8),
        np.array(drag, dtype=float).reshape(-1, 3),
    )


class CompiledStep:
    """``run(states (k, 12), dt, n)``: n compiled steps for every body, in place; ``None``-free by
    construction (use :func:`compile_method`)."""

    def __init__(self, method: Method, torques: tuple[np.ndarray, np.ndarray, np.ndarray]) -> None:
        self.method = method
        self.gravity, self.friction, self.drag = torques
        self.inv = np.asarray(method.inverse_moments, dtype=float)
        self.zero = np.asarray(method.moments == 0.0, dtype=np.bool_)
        self.splitting = isinstance(method, Splitting)
        self.classical = isinstance(method, ClassicalRK4)
        if self.splitting:
            program: list[Any] = method.program  # type: ignore[attr-defined]
            self.ops = np.array([_OPS.get(kind, kernels.OP_E) for kind, _ in program], dtype=np.int64)
            self.fracs = np.array([frac for _, frac in program], dtype=float)
            sym = getattr(method, "symmetric", None)
            self.sym = np.array(sym if sym is not None else (2, 0.0, 0.0), dtype=float)
            self.compensated = bool(getattr(method, "compensated", False))

    def run(self, states: np.ndarray, dt: float, n: int) -> np.ndarray:
        if self.splitting:
            return kernels.run_splitting(
                states,
                dt,
                n,
                self.ops,
                self.fracs,
                self.inv,
                self.zero,
                self.gravity,
                self.friction,
                self.drag,
                self.sym,
                self.compensated,
            )
        run = kernels.run_classical_rk4 if self.classical else kernels.run_lie_rk4
        return run(states, dt, n, self.inv, self.zero, self.gravity, self.friction, self.drag)


def compile_method(method: Method) -> CompiledStep | None:
    """The compiled step of a method instance, or None when it must run interpreted (see the module)."""
    if not isinstance(method, (Splitting, LieRK4, ClassicalRK4)):
        return None
    if isinstance(method, ExactFreeSplitting) and method.symmetric is None:
        return None
    torques = torque_arrays(method)
    return None if torques is None else CompiledStep(method, torques)
