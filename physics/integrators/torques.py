"""Torques for the integrators: gravity at the centre of mass, spin friction about the symmetry axis, and
any callable; and their sub-flows on the component state (a kick, an exact flow, or one RK4 step)."""

from __future__ import annotations

import math

import numpy as np
from numpy.typing import ArrayLike, NDArray

from physics.constants import G
from physics.integrators._state import State, check_moments, from_state, inverse_moments, vec3
from physics.validation import finite_scalar

__all__ = ["GravityTorque", "SpinFriction", "TransverseAirDrag"]


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
        self.center_of_mass_body = vec3(center_of_mass_body, "center_of_mass_body")
        self.weight_moment = self.mass * self.g * self.center_of_mass_body  # M g c, N m

    def __call__(self, R: ArrayLike, L_body: ArrayLike) -> NDArray[np.float64]:
        """Body-frame torque, N m: ``R`` (n,3,3) or (3,3) -> (n,3) or (3,)."""
        R = np.asarray(R, dtype=float)
        up = R[..., 2, :]  # Rᵀ ẑ: the space vertical in body axes
        return -np.cross(self.weight_moment, up)

    def potential(self, R: ArrayLike) -> NDArray[np.float64]:
        """``V = M g (R c)_z``, J: ``R`` (n,3,3) or (3,3) -> (n,) or ()."""
        R = np.asarray(R, dtype=float)
        return R[..., 2, :] @ self.weight_moment

    def _kick(self, s: State, h: float, xp) -> State:
        r00, r01, r02, r10, r11, r12, r20, r21, r22, l0, l1, l2 = s
        w0, w1, w2 = self.weight_moment
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
        self.moments = check_moments(moments)
        a = vec3(axis_body, "axis_body")
        norm = np.linalg.norm(a)
        if norm == 0.0:
            raise ValueError("axis_body must be a non-zero vector")
        self.axis_body = a / norm
        self.inverse_moments = inverse_moments(self.moments)
        self.axis_inverse_moment = float(np.sum(self.axis_body**2 * self.inverse_moments))

    def __call__(self, R: ArrayLike, L_body: ArrayLike) -> NDArray[np.float64]:
        """Body-frame torque, N m: ``L_body`` (n,3) or (3,) -> same shape."""
        L = np.asarray(L_body, dtype=float)
        wa = (L * self.inverse_moments) @ self.axis_body
        return -self.coefficient * wa[..., None] * self.axis_body

    def _flow(self, s: State, h: float, xp) -> State:
        if self.axis_inverse_moment == 0.0 or self.coefficient == 0.0:
            return s
        a0, a1, a2 = self.axis_body
        i0, i1, i2 = self.inverse_moments
        l0, l1, l2 = s[9], s[10], s[11]
        wa = a0 * i0 * l0 + a1 * i1 * l1 + a2 * i2 * l2
        f = xp.expm1(-self.coefficient * self.axis_inverse_moment * h) / self.axis_inverse_moment * wa
        return s[:9] + (l0 + f * a0, l1 + f * a1, l2 + f * a2)


class TransverseAirDrag:
    """Air drag on the wobble: body torque ``−c_air (ω1, ω2, 0)`` (opposes the rotation of the symmetry
    axis, not the spin), N m.

    Its flow with ``R`` frozen is ``L_i ← L_i e^{−c h / I_i}`` (i = 1, 2); the compiled steps run it
    (:mod:`.kernels`), the interpreted ones take it as a generic torque.

    Parameters
    ----------
    coefficient : float
        ``c_air ≥ 0``, N m s.
    moments : array_like (3,)
        Principal moments about the pivot, kg m² (to get ω = L / I).
    """

    conservative = False

    def __init__(self, coefficient: float, moments: ArrayLike) -> None:
        self.coefficient = finite_scalar(coefficient, "air_drag")
        if self.coefficient < 0.0:
            raise ValueError(f"air_drag must be >= 0 (it removes energy), got {self.coefficient}")
        self.moments = np.asarray(moments, dtype=float).reshape(3)

    def __call__(self, R: NDArray[np.float64], L_body: NDArray[np.float64]) -> NDArray[np.float64]:
        w = np.asarray(L_body, dtype=float) / self.moments
        out: NDArray[np.float64] = -self.coefficient * w
        out[..., 2] = 0.0
        return out


def compiles(torque: object) -> bool:
    """Whether the compiled steps (:mod:`.kernels`) know this torque: gravity, spin friction and the
    transverse air drag itself (a subclass of it may change its torque: it runs interpreted)."""
    return isinstance(torque, (GravityTorque, SpinFriction)) or type(torque) is TransverseAirDrag


def torque_list(torque) -> list:
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


class GenericTorque:
    """Sub-flow of a user torque on the component state (arrays built per call: slower)."""

    def __init__(self, torque, zero_axes) -> None:
        self.torque = torque
        self.conservative = bool(torque.conservative)

    def _tau(self, s, xp):
        batched = xp is not math
        R, L = from_state(s, batched)
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


def torque_flows(torques) -> tuple[list, list]:
    """(kicks of the conservative torques, sub-flows of the others) as functions (s, h, xp) -> s."""
    kicks, others = [], []
    for t in torques:
        if isinstance(t, GravityTorque):
            kicks.append(t._kick)
        elif isinstance(t, SpinFriction):
            others.append(t._flow)
        else:
            g = GenericTorque(t, None)
            (kicks if g.conservative else others).append(g)
    return kicks, others
