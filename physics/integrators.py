"""Geometric integrators for a rigid body about a fixed point (or its centre of mass) under a torque.

State: the attitude ``R`` (body to space, ``x_space = R @ x_body``, ``Ṙ = R hat(ω)``) and the body-frame
angular momentum ``L_body = I ω`` (principal axes, so ``I`` is the diagonal ``moments``). The equations are
Euler's equations with a torque (lecture, "Euler's equations")

    dL_body/dt = L_body × ω + τ_body(R, L_body),    Ṙ = R hat(ω),    ω = L_body / I.

Methods (each declares ``name``, ``order``, ``symplectic`` and ``conserves``):

* :class:`LiePoissonStrang` — the free rotation ``H = Σ L_i²/(2 I_i)`` is split into the three exactly
  solvable flows of ``L_i²/(2 I_i)``, each a rotation about the principal axis ``e_i`` by the angle
  ``h L_i / I_i`` (of ``R`` forwards, of ``L_body`` backwards) (McLachlan 1993; Touma & Wisdom 1994;
  Dullweber, Leimkuhler & McLachlan 1997, "NO_SQUISH"); a torque enters as a kick with ``R`` frozen.
  Symmetric (Strang) composition ``K(h/2) X(h/2) Y(h/2) Z(h) Y(h/2) X(h/2) K(h/2)``: order 2.
* :class:`Yoshida4`, :class:`Yoshida6`, :class:`Yoshida8` — symmetric compositions of that Strang step
  (Yoshida 1990: triple jump, "solution A", "solution D"), orders 4, 6 and 8; :class:`Suzuki4` — Suzuki's five-stage fourth-order
  composition (smaller error constant than the triple jump).
* :class:`ExactFreeSplitting` — the free rotation is taken whole from its exact flow
  (:meth:`physics.free_body.FreeBody.flow`; for a body with two equal moments the lecture's closed form
  ``R ← R exp(h hat(L_body)/I⊥) exp(h Ω_s hat(e_s))`` is evaluated inline, which is the same formula and
  much cheaper per step), plus torque kicks; order 2 (``composition="yoshida4"``, ``"yoshida6"``,
  ``"yoshida8"`` give 4, 6, 8).
  Without torque it is exact for any step.
* :class:`ClassicalRK4` — classical RK4 on the components of ``(R, L_body)``: order 4, conserves nothing,
  ``R`` leaves SO(3) (stepped by :func:`advance`); the careless baseline the app shows beside the exact motion.
* :class:`LieRK4` — Runge–Kutta–Munthe-Kaas of order 4 with the classical RK4 tableau (the attitude is
  advanced by the exponential map, so it stays on SO(3)); the non-symplectic baseline.

Torques. A torque is a callable ``torque(R (n,3,3), L_body (n,3)) -> τ_body (n,3)`` (N m) with an attribute
``conservative`` (True when it depends on the attitude only, i.e. comes from a potential ``V(R)``: its
sub-flow is the symplectic kick ``L ← L + h τ(R)``). A non-conservative torque (friction) is advanced with
``R`` frozen by its exact flow when it provides one (:class:`SpinFriction` does: the flow is linear in
``L``), else by one classical RK4 step (which keeps the Strang and fourth-order compositions at their
order; :class:`Yoshida6` then drops to order 4).

A zero principal moment (a rod, lecture: "a rod has one moment 0") is allowed: the rod cannot carry
angular momentum about its own axis, so ``L_body`` along that axis is held at 0 (any torque component
along it is dropped), its angular velocity component is taken as 0, and its axis rotation sub-flow is
the identity. Nothing is divided by the zero moment.

Speed. A step works on the twelve scalar components of ``(R, L_body)``. For one body they are Python floats
and the step is hand-unrolled scalar arithmetic with :mod:`math` (measured here: about 4 to 8 times faster
than numpy on 3x3 arrays, whose per-call overhead dominates); for a batch ``(n, 3, 3)``, ``(n, 3)`` the very
same code runs on numpy arrays of shape ``(n,)``.
"""

from __future__ import annotations

import math
from collections.abc import Callable
from dataclasses import dataclass
from typing import Any, cast

import numpy as np
from numpy.typing import ArrayLike, NDArray

from physics import G
from physics.validation import rotation_array, vector_array

__all__ = [
    "GravityTorque",
    "SpinFriction",
    "LiePoissonStrang",
    "Yoshida4",
    "Suzuki4",
    "Yoshida6",
    "Yoshida8",
    "ExactFreeSplitting",
    "LieRK4",
    "ClassicalRK4",
    "advance",
    "Trajectory",
    "integrate",
    "kinetic_energy",
]

# A state is a tuple of 12 scalars (or (n,) arrays): R row-major r00..r22, then L0, L1, L2.
_State = tuple


# --------------------------------------------------------------------------------------------------
# Torques
# --------------------------------------------------------------------------------------------------


def _vec3(value: ArrayLike, name: str) -> NDArray[np.float64]:
    v = np.asarray(value, dtype=float)
    if v.shape != (3,) or not np.all(np.isfinite(v)):
        raise ValueError(f"{name} must be 3 finite numbers, got {np.asarray(value).tolist()}")
    return v


class GravityTorque:
    """Gravity ``-g ẑ`` (space) acting at the centre of mass; the pivot is the body origin.

    ``τ_body = c × (Rᵀ (−M g ẑ))`` with ``c`` the centre of mass in body axes. Conservative: it comes
    from ``V(R) = M g (R c)_z`` (lecture, heavy top: ``V = M g ℓ cos θ``).

    Parameters
    ----------
    mass : float
        Mass M, kg (> 0).
    center_of_mass_body : array_like, shape (3,)
        Centre of mass in body (principal) axes relative to the pivot, m.
    g : float, optional
        Gravitational acceleration, m/s², default :data:`physics.G`.
    """

    conservative = True

    def __init__(self, mass: float, center_of_mass_body: ArrayLike, g: float = G) -> None:
        if not (np.isfinite(mass) and mass > 0.0):
            raise ValueError(f"mass must be a positive number of kg, got {mass}")
        if not (np.isfinite(g) and g >= 0.0):
            raise ValueError(f"g must be a non-negative acceleration in m/s², got {g}")
        self.mass = float(mass)
        self.g = float(g)
        self.center_of_mass_body = _vec3(center_of_mass_body, "center_of_mass_body")
        self._w = self.mass * self.g * self.center_of_mass_body  # M g c, N m

    def __call__(self, R: ArrayLike, L_body: ArrayLike) -> NDArray[np.float64]:
        """Body-frame torque, N m: ``R`` (n,3,3) or (3,3) -> (n,3) or (3,)."""
        R = np.asarray(R, dtype=float)
        up = R[..., 2, :]  # Rᵀ ẑ: the space vertical in body axes
        return -np.cross(self._w, up)

    def potential(self, R: ArrayLike) -> NDArray[np.float64]:
        """``V = M g (R c)_z``, J: ``R`` (n,3,3) or (3,3) -> (n,) or ()."""
        R = np.asarray(R, dtype=float)
        return R[..., 2, :] @ self._w

    def _kick(self, s: _State, h: float, xp) -> _State:
        r00, r01, r02, r10, r11, r12, r20, r21, r22, l0, l1, l2 = s
        w0, w1, w2 = self._w
        return (
            r00,
            r01,
            r02,
            r10,
            r11,
            r12,
            r20,
            r21,
            r22,
            l0 - h * (w1 * r22 - w2 * r21),
            l1 - h * (w2 * r20 - w0 * r22),
            l2 - h * (w0 * r21 - w1 * r20),
        )


class SpinFriction:
    """Viscous friction about a body axis: ``τ = −c (ω · a) a``, N m (``c`` in N m s).

    Dissipates energy at the rate ``c (ω · a)² ≥ 0``. Its flow with ``R`` frozen is linear in ``L``,
    ``dL/dt = −c a aᵀ I⁻¹ L``, and is solved exactly (``(a aᵀ I⁻¹)² = s a aᵀ I⁻¹`` with
    ``s = aᵀ I⁻¹ a``): ``L ← L + (e^{−c s h} − 1)/s · a (a · ω)``, so each sub-step loses energy
    monotonically and never overshoots (no sign flip of the spin however large ``c h``).

    Parameters
    ----------
    coefficient : float
        c ≥ 0, N m s.
    moments : array_like, shape (3,)
        Principal moments of the body, kg m² (to form ω = L / I; a zero moment gives ω = 0 there).
    axis_body : array_like, shape (3,), optional
        The friction axis in body axes (normalised here), default the body z axis.
    """

    conservative = False

    def __init__(self, coefficient: float, moments: ArrayLike, axis_body: ArrayLike = (0.0, 0.0, 1.0)) -> None:
        if not (np.isfinite(coefficient) and coefficient >= 0.0):
            raise ValueError(f"the friction coefficient must be a non-negative number of N m s, got {coefficient}")
        self.coefficient = float(coefficient)
        self.moments = _moments(moments)
        a = _vec3(axis_body, "axis_body")
        norm = np.linalg.norm(a)
        if norm == 0.0:
            raise ValueError("axis_body must be a non-zero vector")
        self.axis_body = a / norm
        self._inv = _inverse_moments(self.moments)
        self._s = float(np.sum(self.axis_body**2 * self._inv))

    def __call__(self, R: ArrayLike, L_body: ArrayLike) -> NDArray[np.float64]:
        """Body-frame torque, N m: ``L_body`` (n,3) or (3,) -> same shape."""
        L = np.asarray(L_body, dtype=float)
        wa = (L * self._inv) @ self.axis_body
        return -self.coefficient * wa[..., None] * self.axis_body

    def _flow(self, s: _State, h: float, xp) -> _State:
        if self._s == 0.0 or self.coefficient == 0.0:
            return s
        a0, a1, a2 = self.axis_body
        i0, i1, i2 = self._inv
        l0, l1, l2 = s[9], s[10], s[11]
        wa = a0 * i0 * l0 + a1 * i1 * l1 + a2 * i2 * l2
        f = xp.expm1(-self.coefficient * self._s * h) / self._s * wa
        return s[:9] + (l0 + f * a0, l1 + f * a1, l2 + f * a2)


# --------------------------------------------------------------------------------------------------
# Helpers on moments and on the component state
# --------------------------------------------------------------------------------------------------


def _moments(moments: ArrayLike) -> NDArray[np.float64]:
    m = np.asarray(moments, dtype=float)
    if m.shape != (3,) or not np.all(np.isfinite(m)):
        raise ValueError(f"moments must be 3 finite principal moments in kg m², got {np.asarray(moments).tolist()}")
    if np.any(m < 0.0) or np.all(m == 0.0):
        raise ValueError(f"no rigid body has these moments: {m.tolist()} (negative, or all zero)")
    tol = 1e-12 * float(np.max(m))
    for i in range(3):
        if m[i] > m[(i + 1) % 3] + m[(i + 2) % 3] + tol:
            raise ValueError(
                f"no rigid body has these moments: {m.tolist()} (each moment must be at most the sum of the other two)"
            )
    return m


def _inverse_moments(m: NDArray[np.float64]) -> NDArray[np.float64]:
    """1/I, with 0 on a zero moment (a rod: no angular velocity component is carried there)."""
    return np.where(m > 0.0, 1.0 / np.where(m > 0.0, m, 1.0), 0.0)


def kinetic_energy(moments: ArrayLike, L_body: ArrayLike) -> NDArray[np.float64]:
    """``T = Σ L_i² / (2 I_i)``, J (zero moments contribute 0): ``L_body`` (n,3) or (3,) -> (n,) or ()."""
    inv = _inverse_moments(np.asarray(moments, dtype=float))
    L = np.asarray(L_body, dtype=float)
    return 0.5 * np.sum(L * L * inv, axis=-1)


def _to_state(R, L) -> _State:
    """Arrays to the component tuple; floats for one body, (n,) arrays for a batch."""
    if R.ndim == 2:
        r = R.ravel().tolist()
        return tuple(r) + tuple(L.tolist())
    return tuple(R[:, i, j].copy() for i in range(3) for j in range(3)) + tuple(L[:, i].copy() for i in range(3))


def _from_state(s: _State, batched: bool):
    if not batched:
        return np.array(s[:9], dtype=float).reshape(3, 3), np.array(s[9:], dtype=float)
    n = np.broadcast(*s).shape[0]
    R = np.empty((n, 3, 3))
    L = np.empty((n, 3))
    for k in range(9):
        R[:, k // 3, k % 3] = s[k]
    for k in range(3):
        L[:, k] = s[9 + k]
    return R, L


def _rot_x(s: _State, th, xp) -> _State:
    """R ← R exp(θ ê_x), L ← exp(−θ ê_x) L (the exact flow of L_x²/(2 I_x) for θ = h L_x / I_x)."""
    r00, r01, r02, r10, r11, r12, r20, r21, r22, l0, l1, l2 = s
    c, sn = xp.cos(th), xp.sin(th)
    return (
        r00,
        c * r01 + sn * r02,
        c * r02 - sn * r01,
        r10,
        c * r11 + sn * r12,
        c * r12 - sn * r11,
        r20,
        c * r21 + sn * r22,
        c * r22 - sn * r21,
        l0,
        c * l1 + sn * l2,
        c * l2 - sn * l1,
    )


def _rot_y(s: _State, th, xp) -> _State:
    r00, r01, r02, r10, r11, r12, r20, r21, r22, l0, l1, l2 = s
    c, sn = xp.cos(th), xp.sin(th)
    return (
        c * r00 - sn * r02,
        r01,
        c * r02 + sn * r00,
        c * r10 - sn * r12,
        r11,
        c * r12 + sn * r10,
        c * r20 - sn * r22,
        r21,
        c * r22 + sn * r20,
        c * l0 - sn * l2,
        l1,
        c * l2 + sn * l0,
    )


def _rot_z(s: _State, th, xp) -> _State:
    r00, r01, r02, r10, r11, r12, r20, r21, r22, l0, l1, l2 = s
    c, sn = xp.cos(th), xp.sin(th)
    return (
        c * r00 + sn * r01,
        c * r01 - sn * r00,
        r02,
        c * r10 + sn * r11,
        c * r11 - sn * r10,
        r12,
        c * r20 + sn * r21,
        c * r21 - sn * r20,
        r22,
        c * l0 + sn * l1,
        c * l1 - sn * l0,
        l2,
    )


_ROT = (_rot_x, _rot_y, _rot_z)


def _expm_coeffs(u0, u1, u2, xp):
    """Rodrigues coefficients sin(a)/a and (1 − cos a)/a² (Taylor below a = 1e-4 rad)."""
    a2 = u0 * u0 + u1 * u1 + u2 * u2
    if xp is math:
        if a2 < 1e-8:
            return 1.0 - a2 / 6.0 + a2 * a2 / 120.0, 0.5 - a2 / 24.0 + a2 * a2 / 720.0
        a = math.sqrt(a2)
        return math.sin(a) / a, (1.0 - math.cos(a)) / a2
    small = a2 < 1e-8
    angle = np.sqrt(np.where(small, 1.0, a2))
    sa = np.where(small, 1.0 - a2 / 6.0 + a2 * a2 / 120.0, np.sin(angle) / angle)
    # 2 sin²(a/2) avoids the cancellation of 1 − cos a.
    ca = np.where(small, 0.5 - a2 / 24.0 + a2 * a2 / 720.0, 2.0 * np.sin(0.5 * angle) ** 2 / (angle * angle))
    return sa, ca


def _right_exp(s: _State, u0, u1, u2, xp) -> tuple:
    """The attitude part ``R exp(hat u)`` of a state (9 components), by Rodrigues' formula."""
    sa, ca = _expm_coeffs(u0, u1, u2, xp)
    # E = I + sa K + ca K², K = hat(u)
    e00 = 1.0 - ca * (u1 * u1 + u2 * u2)
    e11 = 1.0 - ca * (u0 * u0 + u2 * u2)
    e22 = 1.0 - ca * (u0 * u0 + u1 * u1)
    p01, p02, p12 = ca * u0 * u1, ca * u0 * u2, ca * u1 * u2
    q0, q1, q2 = sa * u0, sa * u1, sa * u2
    e01, e10 = p01 - q2, p01 + q2
    e02, e20 = p02 + q1, p02 - q1
    e12, e21 = p12 - q0, p12 + q0
    r00, r01, r02, r10, r11, r12, r20, r21, r22 = s[:9]
    return (
        r00 * e00 + r01 * e10 + r02 * e20,
        r00 * e01 + r01 * e11 + r02 * e21,
        r00 * e02 + r01 * e12 + r02 * e22,
        r10 * e00 + r11 * e10 + r12 * e20,
        r10 * e01 + r11 * e11 + r12 * e21,
        r10 * e02 + r11 * e12 + r12 * e22,
        r20 * e00 + r21 * e10 + r22 * e20,
        r20 * e01 + r21 * e11 + r22 * e21,
        r20 * e02 + r21 * e12 + r22 * e22,
    )


# --------------------------------------------------------------------------------------------------
# Torque sub-flows on the component state
# --------------------------------------------------------------------------------------------------


def _torque_list(torque) -> list:
    if torque is None:
        return []
    items = list(torque) if isinstance(torque, (list, tuple)) else [torque]
    for t in items:
        if not callable(t) or not hasattr(t, "conservative"):
            raise ValueError(
                "a torque must be callable as torque(R (n,3,3), L_body (n,3)) -> (n,3) and have an attribute "
                f"'conservative' (bool); got {t!r}"
            )
    return items


class _GenericTorque:
    """Sub-flow of a user torque on the component state (arrays built per call: slower)."""

    def __init__(self, torque, zero_axes) -> None:
        self.torque = torque
        self.conservative = bool(torque.conservative)

    def _tau(self, s, xp):
        batched = xp is not math
        R, L = _from_state(s, batched)
        tau = np.asarray(self.torque(R, L), dtype=float)
        if batched:
            return tau[..., 0], tau[..., 1], tau[..., 2]
        tau = tau.reshape(3)
        return float(tau[0]), float(tau[1]), float(tau[2])

    def __call__(self, s, h, xp):
        if self.conservative:
            t0, t1, t2 = self._tau(s, xp)
            return s[:9] + (s[9] + h * t0, s[10] + h * t1, s[11] + h * t2)

        # One classical RK4 step in L with R frozen (order 4 sub-flow).
        def f(l):
            return self._tau(s[:9] + l, xp)

        l = s[9:]
        k1 = f(l)
        k2 = f(tuple(l[i] + 0.5 * h * k1[i] for i in range(3)))
        k3 = f(tuple(l[i] + 0.5 * h * k2[i] for i in range(3)))
        k4 = f(tuple(l[i] + h * k3[i] for i in range(3)))
        return s[:9] + tuple(l[i] + h / 6.0 * (k1[i] + 2.0 * k2[i] + 2.0 * k3[i] + k4[i]) for i in range(3))


def _torque_flows(torques) -> tuple[list, list]:
    """(kicks of the conservative torques, sub-flows of the others) as functions (s, h, xp) -> s."""
    kicks, others = [], []
    for t in torques:
        if isinstance(t, GravityTorque):
            kicks.append(t._kick)
        elif isinstance(t, SpinFriction):
            others.append(t._flow)
        else:
            g = _GenericTorque(t, None)
            (kicks if g.conservative else others).append(g)
    return kicks, others


# --------------------------------------------------------------------------------------------------
# Methods
# --------------------------------------------------------------------------------------------------

_CBRT2 = 2.0 ** (1.0 / 3.0)
_YOSHIDA4 = (1.0 / (2.0 - _CBRT2), -_CBRT2 / (2.0 - _CBRT2), 1.0 / (2.0 - _CBRT2))
_P_SUZUKI = 1.0 / (4.0 - 4.0 ** (1.0 / 3.0))
_SUZUKI4 = (_P_SUZUKI, _P_SUZUKI, 1.0 - 4.0 * _P_SUZUKI, _P_SUZUKI, _P_SUZUKI)
# Yoshida (1990) sixth order, "solution A": w1, w2, w3 and w0 = 1 − 2 (w1 + w2 + w3).
_W6 = (-1.17767998417887, 0.235573213359357, 0.784513610477560)
_W6_0 = 1.0 - 2.0 * sum(_W6)
_YOSHIDA6 = (_W6[2], _W6[1], _W6[0], _W6_0, _W6[0], _W6[1], _W6[2])
# Yoshida (1990) eighth order, "solution D" (15 stages), w1..w7 and w0 = 1 − 2 Σ w.
_W8 = (
    0.102799849391985,
    -1.96061023297549,
    1.93813913762276,
    -0.158240635368243,
    -1.44485223686048,
    0.253693336566229,
    0.914844246229740,
)
_YOSHIDA8 = tuple(reversed(_W8)) + (1.0 - 2.0 * sum(_W8),) + _W8


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
        R, L, batched = _check_state(R, L_body)
        dt = _check_dt(dt)
        xp = np if batched else math
        s = self._step(_to_state(R, L), dt, xp)
        return _from_state(s, batched)

    def energy(self, R: ArrayLike, L_body: ArrayLike) -> NDArray[np.float64]:
        """Kinetic plus potential energy of the conservative torques that define one, J."""
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


def _check_state(R, L_body):
    R = rotation_array(R, "R0")
    L = vector_array(L_body, "L0_body")
    if R.shape == (3, 3) and L.shape == (3,):
        batched = False
    elif R.ndim == 3 and R.shape[1:] == (3, 3) and L.ndim == 2 and L.shape[1] == 3 and R.shape[0] == L.shape[0]:
        batched = True
    else:
        raise ValueError(
            f"R must have shape (3, 3) or (n, 3, 3) and L_body (3,) or (n, 3) with the same n; got {R.shape}, {L.shape}"
        )
    if not (np.all(np.isfinite(R)) and np.all(np.isfinite(L))):
        raise ValueError("the attitude R and the angular momentum L_body must be finite")
    return R, L, batched


def _check_dt(dt) -> float:
    if isinstance(dt, bool) or not isinstance(dt, (int, float, np.integer, np.floating)):
        raise ValueError(f"the time step dt must be one number of seconds, got {dt!r}")
    dt = float(dt)
    if not math.isfinite(dt):
        raise ValueError(f"the time step dt must be a finite number of seconds, got {dt}")
    return dt


class _Splitting(_Method):
    """Compositions of a symmetric base step ``T(h/2) F(h) T(h/2)`` with weights ``_weights``."""

    symplectic = True
    _weights: tuple[float, ...] = (1.0,)
    _sym: tuple[int, float, float] | None = None  # (axis, 1/I⊥, 1/I_s − 1/I⊥) of a symmetric body

    def __init__(self, moments: ArrayLike, torque=None) -> None:
        super().__init__(moments, torque)
        self._program = self._build_program()
        self._compiled: _CompiledRun | None = None  # generated scalar code for one body, built on first use
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


class LiePoissonStrang(_Splitting):
    """Lie–Poisson splitting of the free rotation into exact axis rotations (NO_SQUISH), Strang, order 2.

    One step: ``K(h/2) X(h/2) Y(h/2) Z(h) Y(h/2) X(h/2) K(h/2)`` where ``X`` is the exact flow of
    ``L_x²/(2 I_x)`` (a rotation about ``e_x`` by ``h L_x/I_x``) and ``K`` the torque sub-flow. Axes with a
    zero moment are skipped. Symplectic (with conservative torques), time-symmetric; conserves ``|L|``
    to round-off without torque, and ``L_z`` (space) to round-off under gravity. The energy error stays
    bounded (no drift) for a conservative torque.

    Parameters
    ----------
    moments : array_like, shape (3,)
        Principal moments about the pivot (or centre of mass), kg m², in body-axis order.
    torque : None, a torque, or a list of torques
        See the module docstring.
    """

    name = "Lie-Poisson Strang"
    order = 2
    _weights: tuple[float, ...] = (1.0,)

    def _free_ops(self, w):
        ops = [("X", 0.5 * w), ("Y", 0.5 * w), ("Z", w), ("Y", 0.5 * w), ("X", 0.5 * w)]
        # A rod's axis carries no angular momentum: its sub-flow is the identity.
        return [op for op in ops if self.moments["XYZ".index(op[0])] > 0.0]


class Yoshida4(LiePoissonStrang):
    """Triple-jump composition of :class:`LiePoissonStrang` (Yoshida 1990): order 4, symplectic, symmetric.

    Weights ``w1 = 1/(2 − 2^{1/3})``, ``w0 = −2^{1/3} w1``; conserves what the Strang step conserves.
    """

    name = "Yoshida 4 (Strang)"
    order = 4
    _weights = _YOSHIDA4


class Suzuki4(LiePoissonStrang):
    """Suzuki's five-stage fourth-order composition of :class:`LiePoissonStrang` (Suzuki 1990): order 4.

    Weights ``p, p, 1 − 4p, p, p`` with ``p = 1/(4 − 4^{1/3})``; smaller error constant than
    :class:`Yoshida4` at 5/3 of its cost.
    """

    name = "Suzuki 4 (Strang)"
    order = 4
    _weights = _SUZUKI4


class Yoshida6(LiePoissonStrang):
    """Seven-stage sixth-order composition of :class:`LiePoissonStrang` (Yoshida 1990, solution A): order 6.

    With a non-conservative torque that has no exact sub-flow (a generic callable; not
    :class:`SpinFriction`) the order drops to 4, because that sub-flow is one RK4 step.
    """

    name = "Yoshida 6 (Strang)"
    order = 6
    _weights = _YOSHIDA6


class Yoshida8(LiePoissonStrang):
    """Fifteen-stage eighth-order composition of :class:`LiePoissonStrang` (Yoshida 1990, solution D): order 8.

    Pays at errors below about 1e-9. With a torque whose sub-flow is neither a kick nor exact (a generic
    non-conservative callable) the order drops to 4.
    """

    name = "Yoshida 8 (Strang)"
    order = 8
    _weights = _YOSHIDA8


class ExactFreeSplitting(_Splitting):
    """Torque kicks around the exact free-body flow: ``K(h/2) Φ_free(h) K(h/2)``, order 2.

    ``Φ_free`` is the exact torque-free motion (:meth:`physics.free_body.FreeBody.flow`; for a body with
    two equal moments the lecture's closed form is evaluated inline for speed). Without torque the method
    is exact for any ``dt``. ``composition="yoshida4"`` or ``"yoshida6"`` composes the step to order 4 or 6.

    Parameters
    ----------
    moments : array_like, shape (3,)
        Principal moments, kg m².
    torque : None, a torque, or a list of torques
    composition : {"strang", "yoshida4", "yoshida6", "yoshida8"}
    """

    name = "exact free + kicks"
    order = 2

    def __init__(self, moments: ArrayLike, torque=None, composition: str = "strang") -> None:
        weights = {"strang": (1.0,), "yoshida4": _YOSHIDA4, "yoshida6": _YOSHIDA6, "yoshida8": _YOSHIDA8}
        if composition not in weights:
            raise ValueError(f"composition must be one of {sorted(weights)}, got {composition!r}")
        self._weights = weights[composition]
        self.order = {"strang": 2, "yoshida4": 4, "yoshida6": 6, "yoshida8": 8}[composition]
        if composition != "strang":
            self.name = f"exact free + kicks, {composition}"
        super().__init__(moments, torque)
        m = self.moments
        # Symmetric body: s = the odd axis, I⊥ the common moment of the other two (sphere: s = 2).
        self._sym = None
        for s_ax in (2, 0, 1):
            b, c = (s_ax + 1) % 3, (s_ax + 2) % 3
            if m[b] == m[c] and m[b] > 0.0:
                self._sym = (s_ax, 1.0 / m[b], (1.0 / m[s_ax] if m[s_ax] > 0.0 else 1.0 / m[b]) - 1.0 / m[b])
                break
        self._free_body = None
        if self._sym is None:
            from physics.free_body import FreeBody  # the triaxial closed form (Jacobi elliptic functions)

            self._free_body = FreeBody(m)
        self.conserves = self.conserves + ("energy and L_space of the free sub-flow (exact)",)

    def _free_ops(self, w):
        return [("E", w)]

    def _exact_free(self, s, h, xp):
        if self._sym is not None:
            ax, inv_perp, dinv = self._sym
            l0, l1, l2 = s[9], s[10], s[11]
            # H = |L|²/(2 I⊥) + L_s² (1/I_s − 1/I⊥)/2: two commuting exact flows. A rod (I_s = 0) carries
            # no L_s, so its second flow is the identity.
            r9 = _right_exp(s, h * inv_perp * l0, h * inv_perp * l1, h * inv_perp * l2, xp)
            s = r9 + (l0, l1, l2)
            return _ROT[ax](s, h * dinv * s[9 + ax], xp)
        batched = xp is not math
        R, L = _from_state(s, batched)
        assert self._free_body is not None  # set in __init__ whenever this flow is used
        R2, L2 = self._free_body.flow(R, L, h)
        if not batched:
            return _to_state(R2[0], L2[0])
        return _to_state(R2, L2)


class LieRK4(_Method):
    """Runge–Kutta–Munthe-Kaas with the classical RK4 tableau: order 4, not symplectic.

    ``L`` is advanced by classical RK4; the attitude by ``R ← R exp(hat u)`` with ``u`` the RK4
    combination of ``u̇ = dexp⁻¹_{−u}(ω) ≈ ω + ½ u × ω + (1/12) u × (u × ω)`` at the stages (the right
    trivialisation of ``Ṙ = R hat(ω)``; the series to this term is enough for order 4).
    ``R`` stays orthonormal to round-off; ``|L|`` and the energy drift at the order of the method.
    """

    name = "Lie RK4 (RKMK)"
    order = 4
    symplectic = False
    conserves: tuple[str, ...] = ("orthonormality of R",)

    def _rhs(self, s, xp):
        i0, i1, i2 = self._inv
        l0, l1, l2 = s[9], s[10], s[11]
        w0, w1, w2 = i0 * l0, i1 * l1, i2 * l2
        d0, d1, d2 = l1 * w2 - l2 * w1, l2 * w0 - l0 * w2, l0 * w1 - l1 * w0
        if self.torques:
            t0, t1, t2 = self._torque_value(s, xp)
            d0, d1, d2 = d0 + t0, d1 + t1, d2 + t2
        return (w0, w1, w2), (d0, d1, d2)

    def _torque_value(self, s, xp):
        t0 = t1 = t2 = 0.0
        for t in self._fast:
            a, b, c = t(s, xp)
            t0, t1, t2 = t0 + a, t1 + b, t2 + c
        return t0, t1, t2

    def __init__(self, moments: ArrayLike, torque=None) -> None:
        super().__init__(moments, torque)
        self._fast: list[Callable[..., Any]] = []
        for t in self.torques:
            if isinstance(t, GravityTorque):
                w0, w1, w2 = t._w
                self._fast.append(
                    lambda s, xp, w0=w0, w1=w1, w2=w2: (
                        -(w1 * s[8] - w2 * s[7]),
                        -(w2 * s[6] - w0 * s[8]),
                        -(w0 * s[7] - w1 * s[6]),
                    )
                )
            elif isinstance(t, SpinFriction):
                a0, a1, a2 = t.axis_body
                i0, i1, i2 = t._inv
                c = t.coefficient

                def fr(s, xp, a0=a0, a1=a1, a2=a2, i0=i0, i1=i1, i2=i2, c=c):
                    wa = c * (a0 * i0 * s[9] + a1 * i1 * s[10] + a2 * i2 * s[11])
                    return -wa * a0, -wa * a1, -wa * a2

                self._fast.append(fr)
            else:
                self._fast.append(lambda s, xp, g=_GenericTorque(t, None): g._tau(s, xp))  # noqa: B008 - one per torque, bound at definition
        self._needs_attitude = any(not isinstance(t, SpinFriction) for t in self.torques)

    def _step(self, s, dt, xp):
        h = dt
        l0, l1, l2 = s[9], s[10], s[11]
        r = s[:9]

        def dexpinv(u, w):
            u0, u1, u2 = u
            w0, w1, w2 = w
            c0, c1, c2 = u1 * w2 - u2 * w1, u2 * w0 - u0 * w2, u0 * w1 - u1 * w0
            d0, d1, d2 = u1 * c2 - u2 * c1, u2 * c0 - u0 * c2, u0 * c1 - u1 * c0
            return (w0 + 0.5 * c0 + d0 / 12.0, w1 + 0.5 * c1 + d1 / 12.0, w2 + 0.5 * c2 + d2 / 12.0)

        k1, m1 = self._rhs(s, xp)
        u = (0.5 * h * k1[0], 0.5 * h * k1[1], 0.5 * h * k1[2])
        lb = (l0 + 0.5 * h * m1[0], l1 + 0.5 * h * m1[1], l2 + 0.5 * h * m1[2])
        st = (_right_exp(s, *u, xp) if self._needs_attitude else r) + lb
        w, m2 = self._rhs(st, xp)
        k2 = dexpinv(u, w)
        u = (0.5 * h * k2[0], 0.5 * h * k2[1], 0.5 * h * k2[2])
        lb = (l0 + 0.5 * h * m2[0], l1 + 0.5 * h * m2[1], l2 + 0.5 * h * m2[2])
        st = (_right_exp(s, *u, xp) if self._needs_attitude else r) + lb
        w, m3 = self._rhs(st, xp)
        k3 = dexpinv(u, w)
        u = (h * k3[0], h * k3[1], h * k3[2])
        lb = (l0 + h * m3[0], l1 + h * m3[1], l2 + h * m3[2])
        st = (_right_exp(s, *u, xp) if self._needs_attitude else r) + lb
        w, m4 = self._rhs(st, xp)
        k4 = dexpinv(u, w)
        h6 = h / 6.0
        u = tuple(h6 * (k1[i] + 2.0 * k2[i] + 2.0 * k3[i] + k4[i]) for i in range(3))
        lnew = tuple(s[9 + i] + h6 * (m1[i] + 2.0 * m2[i] + 2.0 * m3[i] + m4[i]) for i in range(3))
        out = _right_exp(s, *u, xp) + lnew
        return self._project(out) if self._zero_axes else out


class ClassicalRK4(LieRK4):
    """Classical Runge–Kutta of order 4 on the twelve components of ``(R, L_body)``: not geometric.

    ``Ṙ = R hat(ω)`` is integrated as any linear ODE in the nine entries of ``R``, so ``R`` leaves the
    rotations (``|RᵀR − I|`` grows like the error, order 4 per unit time) and the energy and ``|L|``
    drift: the careless integrator that the app's "Compare with integrator" shows beside the exact
    solution. Its state is not projected back onto SO(3) (use :func:`advance` to step it; :func:`integrate`
    accepts only rotations as a start).
    """

    name = "classical RK4"
    order = 4
    symplectic = False
    conserves: tuple[str, ...] = ()

    def _rates(self, s, xp):
        (w0, w1, w2), dl = self._rhs(s, xp)
        # (R hat(ω)) row i = r_i × ω.
        dr = []
        for i in (0, 3, 6):
            a, b, c = s[i], s[i + 1], s[i + 2]
            dr += [b * w2 - c * w1, c * w0 - a * w2, a * w1 - b * w0]
        return tuple(dr) + dl

    def _step(self, s, dt, xp):
        h = dt
        k1 = self._rates(s, xp)
        k2 = self._rates(tuple(x + 0.5 * h * k for x, k in zip(s, k1)), xp)
        k3 = self._rates(tuple(x + 0.5 * h * k for x, k in zip(s, k2)), xp)
        k4 = self._rates(tuple(x + h * k for x, k in zip(s, k3)), xp)
        h6 = h / 6.0
        out = tuple(x + h6 * (a + 2.0 * b + 2.0 * c + d) for x, a, b, c, d in zip(s, k1, k2, k3, k4))
        return self._project(out) if self._zero_axes else out


def advance(method: _Method, state: ArrayLike, dt: float, n_steps: int) -> NDArray[np.float64]:
    """Take ``n_steps`` steps of ``dt`` from one body's state, without requiring ``R`` to be a rotation.

    For stepping a motion frame by frame (the app's integrator "ghost"), and for :class:`ClassicalRK4`,
    whose ``R`` leaves SO(3) as it goes: the state is carried as it is, never projected.

    Parameters
    ----------
    method : a method instance
    state : array_like, shape (12,)
        ``R`` row-major (nine entries), then ``L_body`` (kg m²/s).
    dt : float
        Step, s.
    n_steps : int
        Number of steps (≥ 0).

    Returns
    -------
    ndarray, shape (12,)
    """
    if not isinstance(method, _Method):
        raise ValueError(f"method must be an integrator instance such as LiePoissonStrang(moments), got {method!r}")
    try:
        values = np.asarray(state, dtype=float)
    except (TypeError, ValueError):
        raise ValueError(f"state must be twelve numbers (R row-major, then L_body), got {state!r:.60}") from None
    if values.shape != (12,) or not np.all(np.isfinite(values)):
        raise ValueError(f"state must be twelve finite numbers (R row-major, then L_body), got shape {values.shape}")
    dt = _check_dt(dt)
    if int(n_steps) != n_steps or n_steps < 0:
        raise ValueError(f"n_steps must be a non-negative integer, got {n_steps}")
    s = tuple(float(x) for x in values)
    step = method._step
    for _ in range(int(n_steps)):
        s = step(s, dt, math)
    return np.array(s)


# --------------------------------------------------------------------------------------------------
# Driver
# --------------------------------------------------------------------------------------------------


@dataclass(frozen=True)
class Trajectory:
    """Sampled motion.

    Attributes
    ----------
    t : ndarray, shape (k,)
        Times, s.
    attitude : ndarray, shape (k, 3, 3) (or (k, n, 3, 3) for a batch)
        Body-to-space rotations.
    L_body : ndarray, shape (k, 3) (or (k, n, 3))
        Body-frame angular momenta, kg m²/s.
    """

    t: NDArray[np.float64]
    attitude: NDArray[np.float64]
    L_body: NDArray[np.float64]


def integrate(
    method: _Method, R0: ArrayLike, L0_body: ArrayLike, dt: float, n_steps: int, *, save_every: int = 1
) -> Trajectory:
    """Take ``n_steps`` steps of ``dt`` from ``(R0, L0_body)``, saving every ``save_every`` steps.

    Parameters
    ----------
    method : a method instance (:class:`LiePoissonStrang`, :class:`Yoshida4`, ...)
    R0 : array_like, shape (3, 3) or (n, 3, 3)
        Initial attitude(s), body to space.
    L0_body : array_like, shape (3,) or (n, 3)
        Initial body-frame angular momentum, kg m²/s.
    dt : float
        Step, s.
    n_steps : int
        Number of steps (≥ 0).
    save_every : int, keyword-only
        Save the state every this many steps (the initial state is always saved, and the final one).

    Returns
    -------
    Trajectory
        ``t`` (k,), ``attitude`` (k, 3, 3) or (k, n, 3, 3), ``L_body`` (k, 3) or (k, n, 3).
    """
    if not isinstance(method, _Method):
        raise ValueError(f"method must be an integrator instance such as LiePoissonStrang(moments), got {method!r}")
    R, L, batched = _check_state(R0, L0_body)
    dt = _check_dt(dt)
    if int(n_steps) != n_steps or n_steps < 0:
        raise ValueError(f"n_steps must be a non-negative integer, got {n_steps}")
    if int(save_every) != save_every or save_every < 1:
        raise ValueError(f"save_every must be a positive integer, got {save_every}")
    n_steps, save_every = int(n_steps), int(save_every)
    xp = np if batched else math
    s = method._project(_to_state(R, L))
    states = [s]
    steps = [0]
    step = method._step
    run: _CompiledRun | None = None
    if not batched and isinstance(method, _Splitting):
        if method._compiled is None:
            method._compiled = _CompiledRun(method)
        run = method._compiled if method._compiled.ok else None
    done = 0
    while done < n_steps:
        chunk = min(save_every, n_steps - done)
        if run is not None:
            s = run(s, dt, chunk)
        else:
            for _ in range(chunk):
                s = step(s, dt, xp)
        done += chunk
        states.append(s)
        steps.append(done)
    t = np.asarray(steps, dtype=float) * dt
    if batched:
        Rs, Ls = zip(*(_from_state(x, True) for x in states))
        return Trajectory(t=t, attitude=np.stack(Rs), L_body=np.stack(Ls))
    arr = np.array(states, dtype=float)
    return Trajectory(t=t, attitude=arr[:, :9].reshape(-1, 3, 3), L_body=arr[:, 9:].copy())


# --------------------------------------------------------------------------------------------------
# Straight-line scalar code for one body (generated once per method and step size)
# --------------------------------------------------------------------------------------------------
# The program of a splitting is a fixed sequence of sub-flows, so for one body we write it out as
# Python source: local variables instead of tuples, constants folded per step size, no dispatch, the
# step loop inside the function, and the last sub-flow of a step fused with the first of the next when
# they are of the same kind (X…X, or kick…kick). Measured: 2-3x faster than interpreting the program.

_R = ("r00", "r01", "r02", "r10", "r11", "r12", "r20", "r21", "r22")
_L = ("l0", "l1", "l2")
_STATE = ", ".join(_R + _L)
# For a rotation about axis i: the pairs (j, k) of R columns and L components that turn.
_PAIRS = {0: (1, 2), 1: (2, 0), 2: (0, 1)}


def _src_rotation(i: int, coef: str, ind: str) -> list[str]:
    j, k = _PAIRS[i]
    out = [f"{ind}th = {coef} * l{i}", f"{ind}c = cos(th); sn = sin(th)"]
    for row in range(3):
        a, b = f"r{row}{j}", f"r{row}{k}"
        out.append(f"{ind}{a}, {b} = c * {a} + sn * {b}, c * {b} - sn * {a}")
    out.append(f"{ind}l{j}, l{k} = c * l{j} + sn * l{k}, c * l{k} - sn * l{j}")
    return out


def _src_gravity(name: str, ind: str) -> list[str]:
    # L += h τ with τ = −(M g c) × (third row of R); {name}0..2 = h M g c folded per op.
    return [
        f"{ind}l0, l1, l2 = l0 - ({name}1 * r22 - {name}2 * r21), l1 - ({name}2 * r20 - {name}0 * r22), "
        f"l2 - ({name}0 * r21 - {name}1 * r20)"
    ]


def _src_friction(name: str, ind: str) -> list[str]:
    # L += f a (a·ω): {name}b0..2 = a_i / I_i, {name}f0..2 = f a_i folded per op.
    return [
        f"{ind}wa = {name}b0 * l0 + {name}b1 * l1 + {name}b2 * l2",
        f"{ind}l0, l1, l2 = l0 + {name}f0 * wa, l1 + {name}f1 * wa, l2 + {name}f2 * wa",
    ]


def _src_symmetric_free(coef: str, ax: int, coef_ax: str, ind: str) -> list[str]:
    # R ← R exp(h hat(L)/I⊥) (Rodrigues, Taylor below 1e-4 rad), then the e_s rotation by h L_s (1/I_s − 1/I⊥).
    out = [
        f"{ind}u0 = {coef} * l0; u1 = {coef} * l1; u2 = {coef} * l2",
        f"{ind}a2 = u0 * u0 + u1 * u1 + u2 * u2",
        f"{ind}if a2 < 1e-8:",
        f"{ind}    sa = 1.0 - a2 / 6.0 + a2 * a2 / 120.0; ca = 0.5 - a2 / 24.0 + a2 * a2 / 720.0",
        f"{ind}else:",
        f"{ind}    a = sqrt(a2); sa = sin(a) / a; ca = (1.0 - cos(a)) / a2",
        f"{ind}e00 = 1.0 - ca * (u1 * u1 + u2 * u2); e11 = 1.0 - ca * (u0 * u0 + u2 * u2); "
        f"e22 = 1.0 - ca * (u0 * u0 + u1 * u1)",
        f"{ind}p01 = ca * u0 * u1; p02 = ca * u0 * u2; p12 = ca * u1 * u2",
        f"{ind}e01 = p01 - sa * u2; e10 = p01 + sa * u2; e02 = p02 + sa * u1; e20 = p02 - sa * u1; "
        f"e12 = p12 - sa * u0; e21 = p12 + sa * u0",
    ]
    for row in range(3):
        a, b, c = f"r{row}0", f"r{row}1", f"r{row}2"
        out.append(
            f"{ind}{a}, {b}, {c} = {a} * e00 + {b} * e10 + {c} * e20, {a} * e01 + {b} * e11 + {c} * e21, "
            f"{a} * e02 + {b} * e12 + {c} * e22"
        )
    return out + _src_rotation(ax, coef_ax, ind)


def _compile_splitting(method: _Splitting):
    """Python source and constants of ``run(state, dt, n)`` for one body, or None if not compilable."""
    for t in method.torques:
        if not isinstance(t, (GravityTorque, SpinFriction)):
            return None
    if isinstance(method, ExactFreeSplitting) and method._sym is None:
        return None
    gravity = [t for t in method.torques if isinstance(t, GravityTorque)]
    friction = [t for t in method.torques if isinstance(t, SpinFriction) and t._s > 0.0 and t.coefficient > 0.0]
    prog = list(method._program)
    # Fuse the last sub-flow of a step with the first of the next when both are of one kind.
    fusable = len(prog) > 1 and prog[0][0] == prog[-1][0] and prog[0][0] in "XYZ"
    if prog and prog[0][0] in ("T0", "T1") and prog[-1][0] in ("T0", "T1") and not friction and len(prog) > 1:
        fusable = True
    ops_first = prog[:-1] if fusable else prog
    # Each op gets its own folded constants (names k<index>...).
    const_specs: list = []  # (name, kind, data) evaluated per dt

    def op_source(idx, kind, frac, ind):
        name = f"k{idx}"
        lines = []
        if kind in ("X", "Y", "Z"):
            i = "XYZ".index(kind)
            const_specs.append((name, "rot", (frac, i)))
            lines += _src_rotation(i, name, ind)
        elif kind in ("T0", "T1"):
            seq = [("g", gi, t) for gi, t in enumerate(gravity)] + [("f", fi, t) for fi, t in enumerate(friction)]
            if kind == "T1":
                seq = seq[::-1]
            for typ, j, t in seq:
                nm = f"{name}{typ}{j}_"
                const_specs.append((nm, typ, (frac, t)))
                lines += _src_gravity(nm, ind) if typ == "g" else _src_friction(nm, ind)
            for z in method._zero_axes:
                lines.append(f"{ind}l{z} = 0.0")
        elif kind == "E":
            assert method._sym is not None  # only symmetric bodies take this branch
            ax, inv_perp, dinv = method._sym
            const_specs.append((name, "sym", (frac, inv_perp, dinv)))
            lines += _src_symmetric_free(name + "a", ax, name + "b", ind)
        return lines

    body: list[str] = []
    if fusable:
        # first op alone once, then the middle ops and the fused (last + first) n − 1 times, then the rest
        head = op_source("h", prog[0][0], prog[0][1], "    ")
        mid = []
        for idx, (kind, frac) in enumerate(prog[1:-1]):
            mid += op_source(idx + 1, kind, frac, "        ")
        fused = op_source("f", prog[0][0], prog[0][1] + prog[-1][1], "        ")
        tail_mid = []
        for idx, (kind, frac) in enumerate(prog[1:-1]):
            tail_mid += [ln[4:] for ln in op_source(idx + 1, kind, frac, "        ")]
        tail = op_source("t", prog[-1][0], prog[-1][1], "    ")
        body = ["    if n <= 0:", f"        return ({_STATE})"] + head
        body += ["    for _ in range(n - 1):"] + mid + fused + (tail_mid or []) + tail
    else:
        inner = []
        for idx, (kind, frac) in enumerate(ops_first):
            inner += op_source(idx, kind, frac, "        ")
        body = ["    for _ in range(n):"] + (inner or ["        pass"])
    # Remove duplicate constant specs (the same op rendered twice).
    seen, specs = set(), []
    for sp in const_specs:
        if sp[0] not in seen:
            seen.add(sp[0])
            specs.append(sp)
    src = ["def run(state, n):", f"    {_STATE} = state"] + body + [f"    return ({_STATE})"]
    return "\n".join(src), specs


def _constants(method, specs, dt: float) -> dict:
    inv = method._inv
    env: dict = {}
    for name, typ, data in specs:
        if typ == "rot":
            frac, i = data
            env[name] = frac * dt * inv[i]
        elif typ == "g":
            frac, t = data
            w = frac * dt * t._w
            env[name + "0"], env[name + "1"], env[name + "2"] = (float(x) for x in w)
        elif typ == "f":
            frac, t = data
            b = t.axis_body * t._inv
            f = math.expm1(-t.coefficient * t._s * frac * dt) / t._s
            for i in range(3):
                env[f"{name}b{i}"] = float(b[i])
                env[f"{name}f{i}"] = float(f * t.axis_body[i])
        elif typ == "sym":
            frac, inv_perp, dinv = data
            env[name + "a"] = frac * dt * inv_perp
            env[name + "b"] = frac * dt * dinv
    return env


class _CompiledRun:
    """``run(state, n)`` for one body and one step size, built from generated source."""

    def __init__(self, method) -> None:
        res = _compile_splitting(method)
        self.ok = res is not None
        if self.ok:
            self.source, self.specs = res
            self.method = method
            self._cache: dict = {}

    def __call__(self, state, dt: float, n: int):
        fn = self._cache.get(dt)
        if fn is None:
            env = {"cos": math.cos, "sin": math.sin, "sqrt": math.sqrt}
            env.update(_constants(self.method, self.specs, dt))
            exec(compile(self.source, f"<{self.method.name} step>", "exec"), env)
            fn = cast(Callable[[Any, int], Any], env["run"])
            if len(self._cache) > 64:
                self._cache.clear()
            self._cache[dt] = fn
        return fn(state, n)
