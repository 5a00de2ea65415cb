"""What every method shares: validation, the step on arrays, torque sub-flows, and the splitting machinery."""

from __future__ import annotations

import math

import numpy as np
from numpy.typing import ArrayLike, NDArray

from physics.integrators._state import (
    _check_dt,
    _check_shapes,
    _check_state,
    _from_state,
    _inverse_moments,
    _moments,
    _rot_x,
    _rot_y,
    _rot_z,
    _State,
    _to_state,
    kinetic_energy,
)
from physics.integrators.torques import GravityTorque, _torque_flows, _torque_list


class _Method:
    """Common machinery: validation, the step on arrays, the component step."""

    name = "?"
    order = 0
    symplectic = False
    conserves: tuple = ()

    def __init__(self, moments: ArrayLike, torque=None) -> None:
        self.moments = _moments(moments)
        self._inv = _inverse_moments(self.moments)
        self.torques = _torque_list(torque)
        self._kicks, self._others = _torque_flows(self.torques)
        self._zero_axes = tuple(int(i) for i in np.nonzero(self.moments == 0.0)[0])

    def __repr__(self) -> str:
        return f"{type(self).__name__}(moments={self.moments.tolist()}, torques={len(self.torques)})"

    # -- arrays in, arrays out ------------------------------------------------------------------------
    def step(self, R: ArrayLike, L_body: ArrayLike, dt: float) -> tuple[NDArray[np.float64], NDArray[np.float64]]:
        """Advance one step of ``dt`` seconds.

        Parameters
        ----------
        R : array_like, shape (3, 3) or (n, 3, 3)
            Attitudes, body to space.
        L_body : array_like, shape (3,) or (n, 3)
            Body-frame angular momenta, kg m²/s.
        dt : float
            Step, s (negative steps integrate backwards).

        Returns
        -------
        (R, L_body) : ndarrays of the input shapes
        """
        from physics.integrators.drivers import _interpreted, _refuse_unstable  # (drivers imports this module)

        R, L, batched = _check_state(R, L_body, ("R", "L_body"))
        dt = _check_dt(dt)
        _refuse_unstable(self, L, dt, "L_body")
        xp = np if batched else math
        s = _interpreted(self._step, _to_state(R, L), dt, xp, 1, self, 0)
        return _from_state(s, batched)

    def energy(self, R: ArrayLike, L_body: ArrayLike) -> NDArray[np.float64]:
        """Kinetic plus potential energy of the conservative torques that define one, J.

        ``R`` (3, 3) and ``L_body`` (3,) give a number, (n, 3, 3) and (n, 3) one per body; any other shape is
        refused with a ValueError that names the argument. ``R`` need not be a rotation (classical RK4's
        leaves SO(3)).
        """
        R, L_body = _check_shapes(R, L_body, ("R", "L_body"))
        e = kinetic_energy(self.moments, L_body)
        for t in self.torques:
            if getattr(t, "conservative", False) and hasattr(t, "potential"):
                e = e + t.potential(R)
        return e

    # -- internals ------------------------------------------------------------------------------------
    def _project(self, s: _State) -> _State:
        """Hold L at 0 along a zero-moment (rod) axis."""
        if not self._zero_axes:
            return s
        held = list(s)
        for i in self._zero_axes:
            held[9 + i] = 0.0 * held[9 + i]
        return tuple(held)

    def _torque_half(self, s, h, xp, first: bool):
        """Torque sub-flows for a time h, nested symmetrically (kicks outside, others inside)."""
        if first:
            for k in self._kicks:
                s = k(s, h, xp)
            for f in self._others:
                s = f(s, h, xp)
        else:
            for f in reversed(self._others):
                s = f(s, h, xp)
            for k in reversed(self._kicks):
                s = k(s, h, xp)
        return self._project(s) if self._zero_axes else s

    def _step(self, s: _State, dt: float, xp) -> _State:  # pragma: no cover - abstract
        raise NotImplementedError


class _Splitting(_Method):
    """Compositions of a symmetric base step ``T(h/2) F(h) T(h/2)`` with weights ``_weights``."""

    symplectic = True
    # What the free rotation keeps (the class's declaration); an instance narrows it to its torques.
    conserves: tuple = ("orthonormality of R", "|L|", "L_space", "symplectic form")
    _weights: tuple[float, ...] = (1.0,)
    _sym: tuple[int, float, float] | None = None  # (axis, 1/I⊥, 1/I_s − 1/I⊥) of a symmetric body

    def __init__(self, moments: ArrayLike, torque=None) -> None:
        super().__init__(moments, torque)
        self._program = self._build_program()
        conserves = ["orthonormality of R", "|L| (Casimir) of each free sub-step"]
        if not self.torques:
            conserves = ["orthonormality of R", "|L|", "L_space", "symplectic form"]
        else:
            if all(isinstance(t, GravityTorque) for t in self.torques):
                conserves = ["orthonormality of R", "L_z (space)", "symplectic form"]
            elif all(getattr(t, "conservative", False) for t in self.torques):
                conserves = ["orthonormality of R", "symplectic form"]
            else:
                conserves = ["orthonormality of R"]
        self.conserves = tuple(conserves)
        if any(not getattr(t, "conservative", False) for t in self.torques):
            self.symplectic = False

    def _free_ops(self, w: float) -> list:
        """Operations of the free flow for a fraction w of the step."""
        raise NotImplementedError

    def _build_program(self) -> list:
        """A flat list of (kind, fraction) with adjacent compatible operations merged."""
        ops: list = []
        has_torque = bool(self.torques)
        for w in self._weights:
            if has_torque:
                ops.append(("T0", 0.5 * w))
            ops.extend(self._free_ops(w))
            if has_torque:
                ops.append(("T1", 0.5 * w))
        merged: list = []
        for kind, frac in ops:
            if merged and kind[0] in "XYZ" and merged[-1][0] == kind:
                merged[-1] = (kind, merged[-1][1] + frac)
            elif merged and kind in ("T0", "T1") and merged[-1][0] in ("T0", "T1") and not self._others:
                # kicks of conservative torques commute: merge the half kicks between two stages
                merged[-1] = ("T0", merged[-1][1] + frac)
            else:
                merged.append((kind, frac))
        return [op for op in merged if op[1] != 0.0]

    def _step(self, s, dt, xp):
        inv = self._inv
        for kind, frac in self._program:
            h = frac * dt
            if kind == "X":
                s = _rot_x(s, h * inv[0] * s[9], xp)
            elif kind == "Y":
                s = _rot_y(s, h * inv[1] * s[10], xp)
            elif kind == "Z":
                s = _rot_z(s, h * inv[2] * s[11], xp)
            elif kind == "T0":
                s = self._torque_half(s, h, xp, True)
            elif kind == "T1":
                s = self._torque_half(s, h, xp, False)
            else:
                s = self._exact_free(s, h, xp)
        return s

    def _exact_free(self, s, h, xp):  # pragma: no cover - only in ExactFreeSplitting
        raise NotImplementedError
