"""What every method shares: validation, the step on arrays, torque sub-flows, and the splitting machinery."""

from __future__ import annotations

import math
from typing import Any

import numpy as np
from numpy.typing import ArrayLike, NDArray

from physics.integrators._state import (
    State,
    check_dt,
    check_moments,
    check_shapes,
    check_state,
    from_state,
    inverse_moments,
    kinetic_energy,
    rot_x,
    rot_y,
    rot_z,
    to_state,
)
from physics.integrators.torques import GravityTorque, compiles, torque_flows, torque_list


class Method:
    """Common machinery: validation, the step on arrays, the component step."""

    name = "?"
    order = 0
    symplectic = False
    conserves: tuple = ()

    def __init__(self, moments: ArrayLike, torque=None) -> None:
        self.moments = check_moments(moments)
        self.inverse_moments = inverse_moments(self.moments)
        self.torques = torque_list(torque)
        self._kicks, self._others = torque_flows(self.torques)
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
        R, L, batched = check_state(R, L_body, ("R", "L_body"))
        dt = check_dt(dt)
        refuse_unstable(self, L, dt, "L_body")
        xp = np if batched else math
        s = interpreted(self.step_state, to_state(R, L), dt, xp, 1, self, 0)
        return from_state(s, batched)

    def energy(self, R: ArrayLike, L_body: ArrayLike) -> NDArray[np.float64]:
        """Kinetic plus potential energy of the conservative torques that define one, J.

        ``R`` (3, 3) and ``L_body`` (3,) give a number, (n, 3, 3) and (n, 3) one per body; any other shape is
        refused with a ValueError that names the argument. ``R`` need not be a rotation (classical RK4's
        leaves SO(3)).
        """
        R, L_body = check_shapes(R, L_body, ("R", "L_body"))
        e = kinetic_energy(self.moments, L_body)
        for t in self.torques:
            if getattr(t, "conservative", False) and hasattr(t, "potential"):
                e = e + t.potential(R)
        return e

    # -- on the component state (the drivers run these) -----------------------------------------------
    def project(self, s: State) -> State:
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
        return self.project(s) if self._zero_axes else s

    def step_state(self, s: State, dt: float, xp) -> State:  # pragma: no cover - abstract
        """One step of ``dt`` on the component state (:mod:`._state`); ``xp`` is :mod:`math` for one body,
        numpy for a batch."""
        raise NotImplementedError


class Splitting(Method):
    """Compositions of a symmetric base step ``T(h/2) F(h) T(h/2)`` with weights ``_weights``.

    ``compensated=True`` (keyword-only) carries ``L_body`` in double-double arithmetic through the axis
    rotations of the compiled steps (:mod:`.kernels`): the same method, with round-off 1e-16 times smaller in
    ``L``, for motions that amplify it (near the separatrix, docs/physics-notes.md), at about 1.1 times the
    CPU. It needs the compiled torques (gravity, spin friction, the transverse air drag); ``step``, one
    interpreted step, rounds as the plain method.
    """

    symplectic = True
    # What the free rotation keeps (the class's declaration); an instance narrows it to its torques.
    conserves: tuple = ("orthonormality of R", "|L|", "L_space", "symplectic form")
    _weights: tuple[float, ...] = (1.0,)
    symmetric: tuple[int, float, float] | None = None  # (axis, 1/I⊥, 1/I_s − 1/I⊥) of a symmetric body

    def __init__(self, moments: ArrayLike, torque=None, *, compensated: bool = False) -> None:
        super().__init__(moments, torque)
        if not isinstance(compensated, (bool, np.bool_)):
            raise ValueError(f"compensated must be True or False, got {compensated!r:.60}")
        if compensated and not all(compiles(t) for t in self.torques):
            raise ValueError(
                "compensated=True runs only in the compiled steps, whose torques are GravityTorque, SpinFriction "
                f"and TransverseAirDrag; got {[type(t).__name__ for t in self.torques]}"
            )
        self.compensated = bool(compensated)
        if self.compensated:
            self.name = f"{self.name}, compensated"
        self.program = self._build_program()
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

    def step_state(self, s, dt, xp):
        inv = self.inverse_moments
        for kind, frac in self.program:
            h = frac * dt
            if kind == "X":
                s = rot_x(s, h * inv[0] * s[9], xp)
            elif kind == "Y":
                s = rot_y(s, h * inv[1] * s[10], xp)
            elif kind == "Z":
                s = rot_z(s, h * inv[2] * s[11], xp)
            elif kind == "T0":
                s = self._torque_half(s, h, xp, True)
            elif kind == "T1":
                s = self._torque_half(s, h, xp, False)
            else:
                s = self._exact_free(s, h, xp)
        return s

    def _exact_free(self, s, h, xp):  # pragma: no cover - only in ExactFreeSplitting
        raise NotImplementedError


def refuse_unstable(method: Method, L: NDArray[np.float64], dt: float, name: str) -> None:
    """Refuse up front a step beyond the method's stability (its ``max_rate_step``, if it states one) and an
    angular momentum whose rate of change ``L × ω`` is beyond the float range.

    The rate is the largest ``|ω|`` of the torque-free motion from ``L``, ``sqrt(2E / I_min)``
    (``|ω|² ≤ Σ (I_i / I_min) ω_i²``), taken over the batch; a torque may speed the body up later, which the
    check after each chunk catches (:func:`check_finite`).
    """
    limit = getattr(method, "max_rate_step", None)
    if limit is None:
        return
    inv = np.asarray(method.inverse_moments, dtype=float)
    big, top = float(np.max(np.abs(L), initial=0.0)), float(np.max(inv))
    if big == 0.0:
        return
    # sqrt(Σ L_i² / I_i · max 1/I) with L and 1/I scaled to 1 first: no overflow or underflow on the way.
    with np.errstate(over="ignore"):
        rate = big * top * math.sqrt(float(np.max(np.sum((L / big) ** 2 * (inv / top), axis=-1))))
    if math.isfinite(rate) and rate * abs(dt) > limit:
        raise ValueError(
            f"dt = {dt:g} s is too large for {method.name} with the initial momentum {name} = "
            f"{np.asarray(L).tolist()!s:.80}: the body turns at up to |ω| = {rate:.4g} rad/s (sqrt(2E/I_min)), and "
            f"|ω|·|dt| = {rate * abs(dt):.3g} is beyond {limit:g}, the method's stability limit (RK4 diverges beyond "
            f"2√2 ≈ 2.83 on the imaginary axis); take |dt| ≤ {limit / rate:.3g} s"
        )
    if not math.isfinite(rate) or big * rate > 1e306:
        raise ValueError(
            f"{name} = {np.asarray(L).tolist()!s:.80} is too large for these moments {method.moments.tolist()}: "
            f"the body turns at up to |ω| = {rate:.3g} rad/s and L × ω overflows the float range; the motion "
            "is the same with the moments and L scaled down together"
        )


def diverged(method: Method, dt: float, done: int, chunk: int) -> ValueError:
    return ValueError(
        f"the integration diverged: {method.name} with dt = {dt:g} s reached a state that is not finite "
        f"between step {done} and step {done + chunk} (finite at step {done}); take a smaller dt"
    )


CHECK_EVERY = 1000
"""Steps between two checks that the saved states are finite (at least; and at the end): often enough to
stop a diverged run early, rarely enough that the check costs nothing per step, even saving every step."""


def check_finite(rows: NDArray[np.float64], method: Method, dt: float, done: int, chunk: int) -> None:
    """After a chunk (not each step: the compiled loop stays as fast): no NaN or inf in the state."""
    if not np.all(np.isfinite(rows)):
        raise diverged(method, dt, done, chunk)


def interpreted(
    step: Any, s: Any, dt: float, xp: Any, chunk: int, method: Method, done: int, check: bool = True
) -> Any:
    """``chunk`` interpreted steps; an overflow on the way (math's domain errors, numpy's warnings) is the
    divergence the check after the chunk (``check``, or the caller's) reports."""
    try:
        with np.errstate(all="ignore"):
            for _ in range(chunk):
                s = step(s, dt, xp)
    except (ValueError, OverflowError, ZeroDivisionError):
        raise diverged(method, dt, done, chunk) from None
    if check:
        check_finite(np.asarray(s, dtype=float), method, dt, done, chunk)
    return s
