"""The heavy symmetric (Lagrange) top: exact motion, rates, sleeping threshold, friction.

A body symmetric about its axis 3 spins with its tip fixed at the origin; gravity ``-g ẑ`` acts at the
centre of mass a distance ``ℓ`` up the axis. Conventions (docs/conventions.md, with errata 3-5 applied):

* Euler angles z-x-z: attitude ``R = Rz(φ) Rx(θ) Rz(ψ)``; θ is the angle of the symmetry axis from +z,
  φ the precession (azimuth), ψ the spin. The symmetry axis in space is
  ``R[:, 2] = (sin θ sin φ, −sin θ cos φ, cos θ)`` and ``Ṙ = R hat(ω_body)`` with
  ``ω_body = (φ̇ sin θ sin ψ + θ̇ cos ψ, φ̇ sin θ cos ψ − θ̇ sin ψ, φ̇ cos θ + ψ̇)``.
* ``V = + M g ℓ cos θ``; ``L3 = I3 (ψ̇ + φ̇ cos θ)`` and ``Lz = I1 sin²θ φ̇ + L3 cos θ`` are conserved;
  the lecture's effective potential (per I1) is
  ``U(θ) = (Lz − L3 cos θ)² / (2 I1² sin²θ) + (M g ℓ / I1) cos θ`` and ``ℰ = θ̇²/2 + U`` is conserved,
  ``E = I1 ℰ + L3² / (2 I3)``.

Exact solution. With ``u = cos θ``, ``u̇² = f(u) = 2 (ℰ − a u)(1 − u²) − (α − β u)²`` (``a = Mgℓ/I1``,
``α = Lz/I1``, ``β = L3/I1``), a cubic with roots ``−1 ≤ u1 ≤ u2 ≤ 1 ≤ u3``, so
``u = u1 + (u2 − u1) sn²(λ t + c | m)``, ``m = (u2 − u1)/(u3 − u1)``, ``λ = sqrt(a (u3 − u1)/2)``.
By partial fractions ``φ̇ = (α−β)/(2(1−u)) + (α+β)/(2(1+u))`` and
``ψ̇ = L3/I3 − β − (α−β)/(2(1−u)) + (α+β)/(2(1+u))``; each ``∫ dt/(1 ∓ u)`` is an incomplete elliptic
integral of the third kind, evaluated through Carlson's ``R_J`` (scipy.special.elliprj).

Digits. The roots are found from Taylor expansions of f about three points where f is known exactly
from the initial data (u0: ``f = sin²θ0 θ̇0²``; ±1: ``f = −(α ∓ β)²``, with ``α ∓ β`` formed without
cancellation), then polished by Newton in the nearest expansion. A root known exactly (a start at a
turning point, or the axis passing through a pole) is deflated, so no digits are lost.

Poles. When the axis passes exactly through θ = 0 (``Lz = L3``) φ jumps by +π and ψ by −π (φ + ψ and
the attitude are continuous); through θ = π (``Lz = −L3``) both jump by +π. Near (not through) a pole
the same turn happens smoothly and fast; the closed form handles it without a special case.

Limits. Right at a pole φ̇ and ψ̇ are each huge and only their combination is well conditioned; the
attitude, the axis and ``omega_body`` are returned accurately there. The phase error of φ, ψ is about
eps × (nutation period) × |φ̇|, which only matters when the period itself is astronomically long (a top
exactly at the sleeping threshold nudged by 1e-80 rad/s). Near a separatrix (m → 1) the motion itself
amplifies any rounding of the data exponentially.

Step by step. :meth:`HeavyTop.simulate` (spin friction, air drag) and :func:`simulate_heavy_body` (any
body, e.g. an asymmetric top) integrate (R, L_body) with :mod:`physics.integrators`: no Euler angles, so
θ = 0 and θ = π/2 are ordinary points.
"""

from __future__ import annotations

import math
from collections.abc import Callable, Sequence
from dataclasses import dataclass, field
from typing import TYPE_CHECKING, Any

import numpy as np
from numpy.typing import ArrayLike, NDArray
from scipy.special import ellipj, ellipkm1, elliprf, elliprj

from physics import G
from physics.validation import finite_array, finite_scalar, rotation_array, vector_array

if TYPE_CHECKING:
    from physics.inertia import MassProperties

Floats = NDArray[np.float64]

MAX_RATE = 1e100
"""Largest angular rate accepted, rad/s: far beyond any body, well inside the float range of its square."""

MAX_STEPS = 100_000_000
"""Most steps :meth:`HeavyTop.simulate` / :func:`simulate_heavy_body` will take (t_final / dt)."""

__all__ = [
    "HeavyTop",
    "HeavyTopSolution",
    "NutationCubic",
    "FrictionRun",
    "euler_attitude",
    "symmetry_axis",
    "omega_body_from_euler",
    "simulate_heavy_body",
    "TransverseAirDrag",
]

_EPS = np.finfo(float).eps


# --------------------------------------------------------------------------------------------------
# Euler angles <-> attitude
# --------------------------------------------------------------------------------------------------


def euler_attitude(phi: ArrayLike, theta: ArrayLike, psi: ArrayLike) -> NDArray[np.float64]:
    """Attitude ``R = Rz(φ) Rx(θ) Rz(ψ)`` (z-x-z Euler angles, body to space).

    Parameters
    ----------
    phi, theta, psi : array_like, shape (n,) or scalars
        Precession, nutation (from +z) and spin angles, rad.

    Returns
    -------
    ndarray, shape (n, 3, 3) (or (3, 3) for scalars)
    """
    phi, theta, psi = np.broadcast_arrays(*(np.asarray(x, dtype=float) for x in (phi, theta, psi)))
    cf, sf = np.cos(phi), np.sin(phi)
    ct, st = np.cos(theta), np.sin(theta)
    cp, sp = np.cos(psi), np.sin(psi)
    return _attitude_from_trig(cf, sf, ct, st, cp, sp)


def _attitude_from_trig(cf: Floats, sf: Floats, ct: Floats, st: Floats, cp: Floats, sp: Floats) -> Floats:
    r = np.empty(np.shape(cf) + (3, 3))
    r[..., 0, 0] = cf * cp - sf * ct * sp
    r[..., 0, 1] = -cf * sp - sf * ct * cp
    r[..., 0, 2] = sf * st
    r[..., 1, 0] = sf * cp + cf * ct * sp
    r[..., 1, 1] = -sf * sp + cf * ct * cp
    r[..., 1, 2] = -cf * st
    r[..., 2, 0] = st * sp
    r[..., 2, 1] = st * cp
    r[..., 2, 2] = ct
    return r


def symmetry_axis(phi: ArrayLike, theta: ArrayLike) -> NDArray[np.float64]:
    """Unit symmetry axis in space ``(sin θ sin φ, −sin θ cos φ, cos θ)``, shape (n, 3)."""
    phi, theta = np.broadcast_arrays(np.asarray(phi, dtype=float), np.asarray(theta, dtype=float))
    st = np.sin(theta)
    return np.stack([st * np.sin(phi), -st * np.cos(phi), np.cos(theta)], axis=-1)


def omega_body_from_euler(
    theta: ArrayLike, psi: ArrayLike, thetadot: ArrayLike, phidot: ArrayLike, psidot: ArrayLike
) -> NDArray[np.float64]:
    """Body-frame angular velocity of ``R = Rz(φ) Rx(θ) Rz(ψ)``, rad/s, shape (n, 3).

    ``ω_body = (φ̇ sin θ sin ψ + θ̇ cos ψ, φ̇ sin θ cos ψ − θ̇ sin ψ, φ̇ cos θ + ψ̇)``, so that
    ``Ṙ = R hat(ω_body)``.
    """
    theta, psi, td, fd, pd = np.broadcast_arrays(
        *(np.asarray(x, dtype=float) for x in (theta, psi, thetadot, phidot, psidot))
    )
    st, ct, sp, cp = np.sin(theta), np.cos(theta), np.sin(psi), np.cos(psi)
    return np.stack([fd * st * sp + td * cp, fd * st * cp - td * sp, fd * ct + pd], axis=-1)


# --------------------------------------------------------------------------------------------------
# The nutation cubic
# --------------------------------------------------------------------------------------------------


def _horner(c: Sequence[float], x: float) -> tuple[float, float]:
    """Value and derivative of c0 + c1 x + c2 x² + c3 x³."""
    p = ((c[3] * x + c[2]) * x + c[1]) * x + c[0]
    dp = (3.0 * c[3] * x + 2.0 * c[2]) * x + c[1]
    return p, dp


def _polish(c: Sequence[float], x: float) -> float:
    """Newton on a local cubic; stops as soon as a step no longer lowers |p| (double roots stay put)."""
    p, dp = _horner(c, x)
    for _ in range(8):
        if p == 0.0 or dp == 0.0:
            break
        xn = x - p / dp
        pn, dpn = _horner(c, xn)
        if abs(pn) >= abs(p):
            break
        x, p, dp = xn, pn, dpn
    return x


def _quadratic_roots(a2: float, a1: float, a0: float) -> list[float]:
    """Real roots of a2 x² + a1 x + a0 (a2 > 0) without cancellation; a negative discriminant
    (a double root blurred by rounding) gives the double root twice."""
    disc = a1 * a1 - 4.0 * a2 * a0
    if disc <= 0.0:
        x = -a1 / (2.0 * a2)
        return [x, x]
    q = -0.5 * (a1 + math.copysign(math.sqrt(disc), a1 if a1 != 0.0 else 1.0))
    return [q / a2, a0 / q] if q != 0.0 else [0.0, 0.0]


@dataclass(frozen=True)
class _Root:
    """One root of f, held three ways so differences can be formed without cancellation:
    ``v = u − u0``, ``p = 1 − u``, ``q = 1 + u``."""

    v: float
    p: float
    q: float

    @property
    def u(self) -> float:
        return 1.0 - self.p if abs(self.p) < abs(self.q) else self.q - 1.0


def _diff(hi: _Root, lo: _Root) -> float:
    """``u_hi − u_lo`` from whichever representation has the smallest operands."""
    cands = [
        (max(abs(hi.v), abs(lo.v)), hi.v - lo.v),
        (max(abs(hi.p), abs(lo.p)), lo.p - hi.p),
        (max(abs(hi.q), abs(lo.q)), hi.q - lo.q),
    ]
    return min(cands)[1]


@dataclass(frozen=True)
class NutationCubic:
    """The cubic ``f(u) = u̇²`` of one motion and its roots ``u1 ≤ u2 ≤ u3`` (``u = cos θ``).

    Attributes
    ----------
    u1, u2, u3 : float
        Roots; θ moves between ``arccos(u2)`` (highest) and ``arccos(u1)`` (lowest); ``u3 ≥ 1``.
    one_minus_u1, one_minus_u2, one_plus_u1, one_plus_u2 : float
        ``1 ∓ u`` at the roots, formed without cancellation (the pole distances).
    u2_minus_u1, u3_minus_u1, u3_minus_u2, u0_minus_u1, u2_minus_u0 : float
        Root differences formed without cancellation.
    """

    u0: float
    u1: float
    u2: float
    u3: float
    one_minus_u1: float
    one_minus_u2: float
    one_plus_u1: float
    one_plus_u2: float
    u2_minus_u1: float
    u3_minus_u1: float
    u3_minus_u2: float
    u0_minus_u1: float
    u2_minus_u0: float


# --------------------------------------------------------------------------------------------------
# Results
# --------------------------------------------------------------------------------------------------


@dataclass(frozen=True)
class HeavyTopSolution:
    """Exact motion of the heavy symmetric top sampled at times ``t``.

    Attributes
    ----------
    t : ndarray (n,)
        Times, s.
    theta, phi, psi : ndarray (n,)
        Euler angles, rad (φ, ψ unwrapped; jumps of ±π only where the axis passes exactly through a pole).
    thetadot, phidot, psidot : ndarray (n,)
        Their rates, rad/s.
    axis : ndarray (n, 3)
        Unit symmetry axis in space.
    attitude : ndarray (n, 3, 3)
        Body-to-space rotation ``R = Rz(φ) Rx(θ) Rz(ψ)``.
    omega_body : ndarray (n, 3)
        Body-frame angular velocity, rad/s (``Ṙ = R hat(ω_body)``).
    L3, Lz : float
        Conserved angular momenta about the symmetry axis and about +z, kg m²/s.
    energy : float
        Conserved total energy from the initial data, J.
    nutation_period : float
        Period of θ, s (``inf`` for a vertical top that cannot leave the vertical in finite time).
    precession_rate : float
        Mean φ̇ over a nutation period, rad/s.
    theta_min, theta_max : float
        Turning points of θ, rad.
    """

    t: NDArray[np.float64]
    theta: NDArray[np.float64]
    phi: NDArray[np.float64]
    psi: NDArray[np.float64]
    thetadot: NDArray[np.float64]
    phidot: NDArray[np.float64]
    psidot: NDArray[np.float64]
    axis: NDArray[np.float64]
    attitude: NDArray[np.float64]
    omega_body: NDArray[np.float64]
    L3: float
    Lz: float
    energy: float
    nutation_period: float
    precession_rate: float
    theta_min: float
    theta_max: float

    def energy_along(self, top: HeavyTop) -> NDArray[np.float64]:
        """Total energy evaluated from the sampled state (a check of the solution), J, shape (n,)."""
        return top.energy_of(self.theta, self.thetadot, self.phidot, self.psidot)

    def angular_momenta_along(self, top: HeavyTop) -> tuple[NDArray[np.float64], NDArray[np.float64]]:
        """``(L3, Lz)`` evaluated from the sampled state, kg m²/s, each shape (n,)."""
        return top.angular_momenta(self.theta, self.phidot, self.psidot)


@dataclass(frozen=True)
class _PoleTerm:
    """One pole's share of φ: ``φ̇ ⊃ half_d / (1 ∓ u)`` (pole = ±1), integrated in closed form.

    As a function of τ = λ t + c the integral is ``a0 x + a1 Π(n; x)`` with ``x = τ − shift``,
    ``Π(n; x) = ∫₀ˣ dτ'/(1 − n sn²τ')`` (quasi-periodic: + 2 Π(n|m) per 2K). If the axis passes exactly
    through the pole (``1 − n = 0``) the term is the limit: ``±π`` at each passage (x = K mod 2K).
    ψ gets the same term times ``−pole``.
    """

    pole: int
    half_d: float
    jump: float
    shift: float
    a0: float
    a1: float
    n: float
    one_n: float
    pic: float

    def integral(
        self, tau: ArrayLike, K: float, m: float, one_m: float, jac: tuple[Floats, ...] | None = None
    ) -> Floats:
        x = np.asarray(tau, dtype=float) - self.shift
        if self.jump:
            return self.jump * math.pi * np.floor((x + K) / (2.0 * K))
        if self.a0 == 0.0 and self.a1 == 0.0:
            return np.zeros_like(x)
        if jac is None or self.shift != 0.0:
            k, r = _reduce(x, K)
            sn, cn, dn = _jacobi(r, m, one_m, K)
            cn2, dn2 = cn * cn, dn * dn
        else:
            k, r, sn, cn2, dn2 = jac
        return self.a0 * x + self.a1 * (
            2.0 * k * self.pic + _incomplete_third_kind(r, sn, cn2, dn2, self.n, self.one_n)
        )


@dataclass
class _Motion:
    """Everything the closed form needs, computed once per initial condition."""

    kind: str  # "vertical", "steady" or "nutating"
    theta0: float
    phi0: float
    psi0: float
    phidot0: float
    psidot0: float
    L3: float
    Lz: float
    energy: float
    cubic: NutationCubic | None = None
    m: float = 0.0
    lam: float = 0.0
    K: float = 0.0
    one_m: float = 1.0
    c: float = 0.0
    spin_rate: float = 0.0  # L3/I3 − L3/I1: the constant part of ψ̇
    terms: list[_PoleTerm] = field(default_factory=list)  # two of them
    period: float = math.inf
    precession_rate: float = 0.0


# --------------------------------------------------------------------------------------------------
# The top
# --------------------------------------------------------------------------------------------------


def _times(t: ArrayLike) -> NDArray[np.float64]:
    tt = np.atleast_1d(np.asarray(t, dtype=float))
    if tt.ndim != 1:
        raise ValueError(f"t must be a scalar or a 1-D array of times, got shape {tt.shape}")
    if not np.all(np.isfinite(tt)):
        raise ValueError("t must contain only finite times (no NaN or inf)")
    return tt


class HeavyTop:
    """A heavy symmetric top with its tip fixed at the origin (the Lagrange top).

    Parameters
    ----------
    I1 : float
        Moment of inertia about the pivot, perpendicular to the symmetry axis, kg m².
    I3 : float
        Moment of inertia about the symmetry axis, kg m².
    mgl : float
        ``M g ℓ``, weight times pivot-to-centre-of-mass distance, J (> 0: the centre of mass is up the axis).

    Raises
    ------
    ValueError
        If a value is not positive and finite, or ``I3 > 2 I1`` (no rigid body: about the pivot
        ``I1 = I1_cm + M ℓ²`` and the triangle inequality of the moments gives ``I3 ≤ 2 I1``).
    """

    def __init__(self, I1: float, I3: float, mgl: float) -> None:
        self.I1 = finite_scalar(I1, "I1")
        self.I3 = finite_scalar(I3, "I3")
        self.mgl = finite_scalar(mgl, "mgl")
        if self.I3 == 0.0:
            raise ValueError(
                "I3 = 0 is a thin rod on a pivot (a spherical pendulum), not a top: its spin carries no "
                "angular momentum, so the Lagrange top's solution does not apply; use simulate_heavy_body"
            )
        for name, v in (("I1", self.I1), ("I3", self.I3), ("mgl", self.mgl)):
            if v <= 0.0:
                raise ValueError(f"{name} must be positive, got {v}")
        if self.I3 > 2.0 * self.I1 * (1.0 + 4.0 * _EPS):
            raise ValueError(
                f"no rigid body has these moments: I3 = {self.I3} > 2 I1 = {2 * self.I1} "
                "(the moment about the symmetry axis cannot exceed the sum of the other two)"
            )

    def __repr__(self) -> str:
        return f"HeavyTop(I1={self.I1!r}, I3={self.I3!r}, mgl={self.mgl!r})"

    @classmethod
    def from_mass_properties(
        cls, body: MassProperties, tip: ArrayLike, *, g: float = G, rtol: float = 1e-9
    ) -> HeavyTop:
        """The top made of ``body`` (a :class:`physics.inertia.MassProperties`) spinning on ``tip``.

        The symmetry axis is the line from the tip to the centre of mass; the inertia tensor about the tip
        (parallel-axis theorem) must have that line as an axis with moment I3 and equal moments I1 about
        every perpendicular line.

        Parameters
        ----------
        body : MassProperties
            Mass, centre of mass and inertia tensor, modelling frame.
        tip : array_like (3,)
            The fixed point, modelling frame, m.
        g : float
            Gravitational acceleration, m/s².
        rtol : float
            Relative tolerance for the symmetry check.

        Raises
        ------
        ValueError
            If the tip is at the centre of mass, or the body is not symmetric about the tip–centre line.
        """
        tip = np.asarray(tip, dtype=float).reshape(3)
        if not np.all(np.isfinite(tip)):
            raise ValueError("tip must be finite")
        d = np.asarray(body.center_of_mass, dtype=float) - tip
        ell = float(np.linalg.norm(d))
        if ell == 0.0:
            raise ValueError("the tip is at the centre of mass: gravity exerts no torque (use physics.free_body)")
        e3 = d / ell
        tensor = np.asarray(body.tensor_about(tip), dtype=float)
        I3 = float(e3 @ tensor @ e3)
        P = np.eye(3) - np.outer(e3, e3)
        I1 = float(np.trace(P @ tensor @ P)) / 2.0
        scale = float(np.max(np.abs(tensor)))
        if (
            np.max(np.abs(tensor @ e3 - I3 * e3)) > rtol * scale
            or np.max(np.abs(P @ tensor @ P - I1 * P)) > rtol * scale
        ):
            raise ValueError(
                "the body is not symmetric about the line from the tip to its centre of mass "
                f"(tensor about the tip: {tensor.tolist()})"
            )
        return cls(I1, I3, finite_scalar(body.mass, "mass") * finite_scalar(g, "g") * ell)

    def threshold_crossing_time(self, L3: float, spin_friction: float) -> float:
        """When spin friction ``−c ω3`` (see :meth:`simulate`) takes ``L3`` down to :meth:`sleeping_threshold`,
        s: ``L3(t) = L3 exp(−c t / I3)`` gives ``t* = (I3 / c) ln(L3 / L3_threshold)``
        (0 if already below, inf without friction)."""
        L3 = abs(finite_scalar(L3, "L3"))
        c = finite_scalar(spin_friction, "spin_friction")
        if c < 0.0:
            raise ValueError(f"spin_friction must be >= 0 (it removes energy), got {c}")
        thr = self.sleeping_threshold()
        if L3 <= thr:
            return 0.0
        return math.inf if c == 0.0 else self.I3 / c * math.log(L3 / thr)

    # ------------------------------------------------------------------ conserved quantities
    def angular_momenta(
        self, theta: ArrayLike, phidot: ArrayLike, psidot: ArrayLike
    ) -> tuple[NDArray[np.float64], NDArray[np.float64]]:
        """``L3 = I3 (ψ̇ + φ̇ cos θ)`` and ``Lz = I1 sin²θ φ̇ + L3 cos θ`` (docs/conventions.md, erratum 3), kg m²/s.

        Parameters
        ----------
        theta, phidot, psidot : array_like (n,) or scalars
            Angle from +z (rad) and the precession and spin rates (rad/s).
        """
        theta = np.asarray(theta, dtype=float)
        phidot = np.asarray(phidot, dtype=float)
        L3 = self.I3 * (np.asarray(psidot, dtype=float) + phidot * np.cos(theta))
        return L3, self.I1 * np.sin(theta) ** 2 * phidot + L3 * np.cos(theta)

    def energy_of(
        self, theta: ArrayLike, thetadot: ArrayLike, phidot: ArrayLike, psidot: ArrayLike
    ) -> NDArray[np.float64]:
        """Total energy ``½ I1 (θ̇² + sin²θ φ̇²) + ½ I3 ω3² + M g ℓ cos θ``, J (shapes broadcast)."""
        theta = np.asarray(theta, dtype=float)
        phidot = np.asarray(phidot, dtype=float)
        w3 = np.asarray(psidot, dtype=float) + phidot * np.cos(theta)
        td = np.asarray(thetadot, dtype=float)
        energy: Floats = (
            0.5 * self.I1 * (td**2 + np.sin(theta) ** 2 * phidot**2) + 0.5 * self.I3 * w3**2 + self.mgl * np.cos(theta)
        )
        return energy

    @staticmethod
    def _potential_arguments(theta: ArrayLike, Lz: float, L3: float) -> tuple[NDArray[np.float64], float, float]:
        theta = finite_array(theta, "theta")
        if np.any((theta < 0.0) | (theta > math.pi)):
            raise ValueError("theta is the angle of the axis from +z and must lie in [0, pi]")
        return theta, finite_scalar(Lz, "Lz"), finite_scalar(L3, "L3")

    def effective_potential(self, theta: ArrayLike, Lz: float, L3: float) -> NDArray[np.float64]:
        """The lecture's effective potential per I1,
        ``U(θ) = (Lz − L3 cos θ)² / (2 I1² sin²θ) + (M g ℓ / I1) cos θ``, 1/s² (θ̈ = −dU/dθ).

        Parameters
        ----------
        theta : array_like (n,)
            Angle of the axis from +z, rad. At θ = 0 (π) the limit is returned when ``Lz = L3``
            (``Lz = −L3``); otherwise U is +inf there.
        Lz, L3 : float
            Conserved angular momenta, kg m²/s.
        """
        theta, Lz, L3 = self._potential_arguments(theta, Lz, L3)
        i1 = self.I1
        half_lo = np.sin(0.5 * theta) ** 2  # (1 − cos θ)/2 without cancellation
        half_hi = np.cos(0.5 * theta) ** 2
        # Lz − L3 cos θ = (Lz − L3) + 2 L3 sin²(θ/2); partial fractions remove the 0/0 at the poles.
        dm, dp = Lz - L3, Lz + L3
        with np.errstate(divide="ignore", invalid="ignore"):
            t1 = np.where(dm == 0.0, 0.0, dm**2 / (8.0 * i1**2 * half_lo))
            t2 = np.where(dp == 0.0, 0.0, dp**2 / (8.0 * i1**2 * half_hi))
        # (Lz − L3 u)²/(1 − u²) = dm²/(2(1−u)) + dp²/(2(1+u)) − ... exactly:
        # (Lz − L3 u)² / (1 − u²) = dm²/(2(1−u)) + dp²/(2(1+u)) − L3², dm, dp = Lz ∓ L3.
        return t1 + t2 - L3**2 / (2.0 * i1**2) + (self.mgl / i1) * np.cos(theta)

    def effective_potential_derivative(self, theta: ArrayLike, Lz: float, L3: float) -> NDArray[np.float64]:
        """``dU/dθ`` of :meth:`effective_potential`, 1/s²; ``θ̈ = −dU/dθ`` (lecture's θ equation).

        ``dU/dθ = (Lz − L3 cos θ)(L3 sin²θ − cos θ (Lz − L3 cos θ)) / (I1² sin³θ) − (Mgℓ/I1) sin θ``.
        """
        theta, Lz, L3 = self._potential_arguments(theta, Lz, L3)
        i1 = self.I1
        s2, c2 = np.sin(0.5 * theta) ** 2, np.cos(0.5 * theta) ** 2
        dm, dp = Lz - L3, Lz + L3
        # From the partial-fraction form U = dm²/(8 I1² s2) + dp²/(8 I1² c2) + const + a cos θ:
        # d(s2)/dθ = sin θ / 2, d(c2)/dθ = −sin θ / 2.
        st = np.sin(theta)
        with np.errstate(divide="ignore", invalid="ignore"):
            d1 = np.where(dm == 0.0, 0.0, -(dm**2) * st / (16.0 * i1**2 * s2**2))
            d2 = np.where(dp == 0.0, 0.0, dp**2 * st / (16.0 * i1**2 * c2**2))
        return d1 + d2 - (self.mgl / i1) * st

    def sleeping_threshold(self) -> float:
        """Least spin angular momentum ``L3 = 2 sqrt(M g ℓ I1)`` for which the vertical spin is stable,
        kg m²/s (lecture: U''(0) = L3²/(4 I1²) − Mgℓ/I1 changes sign there)."""
        return 2.0 * math.sqrt(self.mgl * self.I1)

    def vertical_curvature(self, L3: float) -> float:
        """``U''(0) = L3²/(4 I1²) − M g ℓ / I1`` for a top spinning about the vertical (Lz = L3), 1/s²."""
        return L3**2 / (4.0 * self.I1**2) - self.mgl / self.I1

    def steady_precession_rates(self, theta: float, L3: float) -> tuple[float, float]:
        """The slow and the fast rate φ̇ of steady precession at angle θ, rad/s.

        With θ̇ = θ̈ = 0 the θ equation gives ``I1 cos θ φ̇² − L3 φ̇ + M g ℓ = 0``. The slow root tends to
        ``M g ℓ / L3`` for a fast top. For θ = π/2 only the slow rate exists (the fast one is returned as
        ±inf); for θ > π/2 the second root is negative. Start a steady precession with
        ``thetadot0 = 0, phidot0 = rate, psidot0 = L3/I3 − rate cos θ``.

        Raises
        ------
        ValueError
            If the spin is too slow: ``L3² < 4 I1 M g ℓ cos θ`` (no steady precession at that θ).
        """
        theta = finite_scalar(theta, "theta")
        L3 = finite_scalar(L3, "L3")
        if not 0.0 < theta < math.pi:
            raise ValueError(f"steady precession needs 0 < theta < pi, got theta = {theta}")
        ct = math.cos(theta)
        disc = L3 * L3 - 4.0 * self.I1 * self.mgl * ct
        if disc < 0.0:
            raise ValueError(
                f"no steady precession at theta = {theta}: L3 = {L3} is below 2 sqrt(I1 M g l cos theta) = "
                f"{2 * math.sqrt(self.I1 * self.mgl * ct)}"
            )
        q = 0.5 * (L3 + math.copysign(math.sqrt(disc), L3 if L3 != 0.0 else 1.0))
        slow = self.mgl / q
        fast = q / (self.I1 * ct) if ct != 0.0 else math.copysign(math.inf, q)
        return (slow, fast) if abs(slow) <= abs(fast) else (fast, slow)

    # ------------------------------------------------------------------ the exact motion
    def _motion(
        self,
        theta0: float,
        thetadot0: float,
        phidot0: float,
        psidot0: float,
        phi0: float = 0.0,
        psi0: float = 0.0,
    ) -> _Motion:
        th0 = finite_scalar(theta0, "theta0")
        thd0 = finite_scalar(thetadot0, "thetadot0")
        phd0 = finite_scalar(phidot0, "phidot0")
        psd0 = finite_scalar(psidot0, "psidot0")
        phi0 = finite_scalar(phi0, "phi0")
        psi0 = finite_scalar(psi0, "psi0")
        if not 0.0 <= th0 <= math.pi:
            raise ValueError(f"theta0 is the angle of the axis from +z and must lie in [0, pi], got {th0}")
        if max(abs(thd0), abs(phd0), abs(psd0)) > MAX_RATE:
            raise ValueError(
                f"angular rates must be at most {MAX_RATE:g} rad/s (their squares would overflow); got "
                f"thetadot0 = {thd0:g}, phidot0 = {phd0:g}, psidot0 = {psd0:g}"
            )
        # Squares of these would underflow: to every digit the cubic can see they are 0 (a pole, no rate).
        th0 = 0.0 if th0 < 1e-150 else th0
        thd0, phd0, psd0 = (0.0 if abs(x) < 1e-150 else x for x in (thd0, phd0, psd0))
        # At a pole θ̇ < 0 means leaving towards the opposite azimuth: same state, θ̇ > 0.
        if th0 == 0.0 and thd0 < 0.0:
            thd0, phi0, psi0 = -thd0, phi0 + math.pi, psi0 - math.pi
        if th0 == math.pi and thd0 > 0.0:
            thd0, phi0, psi0 = -thd0, phi0 + math.pi, psi0 + math.pi
        at_pole = th0 == 0.0 or th0 == math.pi
        s0 = 0.0 if at_pole else math.sin(th0)
        u0 = 1.0 if th0 == 0.0 else (-1.0 if th0 == math.pi else math.cos(th0))
        w0 = 2.0 * math.sin(0.5 * th0) ** 2 if th0 != math.pi else 2.0  # 1 − u0
        z0 = 2.0 * math.cos(0.5 * th0) ** 2 if th0 != math.pi else 0.0  # 1 + u0
        I1, I3 = self.I1, self.I3
        L3 = I3 * (psd0 + phd0 * u0)
        Lz = I1 * s0 * s0 * phd0 + L3 * u0
        K0 = 0.5 * thd0 * thd0 + 0.5 * s0 * s0 * phd0 * phd0  # ℰ − a u0
        energy = I1 * K0 + L3 * L3 / (2.0 * I3) + self.mgl * u0
        base: dict[str, Any] = dict(
            theta0=th0, phi0=phi0, psi0=psi0, phidot0=phd0, psidot0=psd0, L3=L3, Lz=Lz, energy=energy
        )
        if at_pole and thd0 == 0.0:
            # Sleeping (or hanging) top exactly vertical: an equilibrium of θ, stable or not.
            mo = _Motion(kind="vertical", **base)
            mo.precession_rate = phd0
            mo.period = self._vertical_period(L3, u0)
            return mo

        a = self.mgl / I1
        beta = L3 / I1
        dm = (I1 * s0 * s0 * phd0 - L3 * w0) / I1  # α − β = (Lz − L3)/I1 without cancellation
        dp = (I1 * s0 * s0 * phd0 + L3 * z0) / I1  # α + β
        c3 = 2.0 * a
        loc0 = [
            s0 * s0 * thd0 * thd0,
            -4.0 * u0 * K0 - 2.0 * a * s0 * s0 + 2.0 * beta * s0 * s0 * phd0,
            -2.0 * K0 + 4.0 * a * u0 - beta * beta,
            c3,
        ]
        k1 = K0 - a * w0  # ℰ − a
        loc_p = [-dm * dm, -4.0 * k1 + 2.0 * beta * dm, -2.0 * k1 + 4.0 * a - beta * beta, c3]
        k2 = K0 + a * z0  # ℰ + a
        loc_m = [-dp * dp, 4.0 * k2 + 2.0 * beta * dp, -2.0 * k2 - 4.0 * a - beta * beta, c3]

        if loc0[0] == 0.0:  # start at a turning point: v = 0 is an exact root, deflate it
            vs = [0.0] + _quadratic_roots(c3, loc0[2], loc0[1])
        else:
            r = np.roots([loc0[3], loc0[2], loc0[1], loc0[0]])
            vs = sorted(float(x.real) for x in r)
        vs = sorted(vs)
        # Snap exactly known roots, polish the others in the expansion about the nearest anchor.
        roots = []
        near = {
            "1": int(np.argmin([abs(v - w0) for v in vs])),
            "-1": int(np.argmin([abs(v + z0) for v in vs])),
            "0": int(np.argmin([abs(v) for v in vs])),
        }
        for i, v in enumerate(vs):
            if loc0[0] == 0.0 and i == near["0"]:
                roots.append(_Root(0.0, w0, z0))
            elif dm == 0.0 and i == near["1"]:
                roots.append(_Root(w0, 0.0, 2.0))
            elif dp == 0.0 and i == near["-1"]:
                roots.append(_Root(-z0, 2.0, 0.0))
            else:
                # Polish in the expansion about the nearest anchor; a root that lands closer to another
                # anchor (e.g. 1e-64 from a pole, 1e-31 from u0) is polished again there.
                anchor = ""
                for _ in range(3):
                    offs = {"0": abs(v), "1": abs(v - w0), "-1": abs(v + z0)}
                    best = min(offs, key=lambda name: offs[name])
                    if best == anchor:
                        break
                    anchor = best
                    if best == "0":
                        v = _polish(loc0, v)
                        root = _Root(v, w0 - v, z0 + v)
                    elif best == "1":
                        x = _polish(loc_p, v - w0)
                        root = _Root(w0 + x, -x, 2.0 + x)
                    else:
                        y = _polish(loc_m, v + z0)
                        root = _Root(y - z0, 2.0 - y, y)
                    v = root.v
                roots.append(root)
        roots.sort(key=lambda r_: r_.u)
        r1, r2, r3 = roots
        # Rounding may push a root across u0 or a pole by an ulp; the motion lies in [u1, u2] ∋ u0.
        if r1.v > 0.0:
            r1 = _Root(0.0, w0, z0)
        if r2.v < 0.0:
            r2 = _Root(0.0, w0, z0)
        if r2.p < 0.0:
            r2 = _Root(w0, 0.0, 2.0)
        if r1.q < 0.0:
            r1 = _Root(-z0, 2.0, 0.0)
        u21, u31, u32 = _diff(r2, r1), _diff(r3, r1), _diff(r3, r2)
        r0 = _Root(0.0, w0, z0)
        cubic = NutationCubic(
            u0=u0,
            u1=r1.u,
            u2=r2.u,
            u3=r3.u,
            one_minus_u1=r1.p,
            one_minus_u2=r2.p,
            one_plus_u1=r1.q,
            one_plus_u2=r2.q,
            u2_minus_u1=u21,
            u3_minus_u1=u31,
            u3_minus_u2=u32,
            u0_minus_u1=_diff(r0, r1),
            u2_minus_u0=_diff(r2, r0),
        )
        if u21 <= 0.0:
            mo = _Motion(kind="steady", cubic=cubic, **base)
            mo.precession_rate = phd0
            mo.lam = math.sqrt(a * u31 / 2.0)
            mo.period = math.pi / mo.lam if mo.lam > 0 else math.inf
            return mo

        mo = _Motion(kind="nutating", cubic=cubic, **base)
        m = u21 / u31
        # Exactly on a separatrix (u2 = u3: the axis creeps up to an unstable position for ever) K = inf;
        # with 1 − m = 1e-300 instead the approach takes ~350/λ and differs by e^-350: invisible.
        one_m = max(u32 / u31, 1e-300)
        mo.one_m = one_m
        mo.m = m
        mo.lam = lam = math.sqrt(a * u31 / 2.0)
        mo.K = K = float(ellipkm1(one_m))  # accurate even as m → 1 (near a separatrix)
        # Phase: sn²(c) = (u0 − u1)/(u2 − u1), cn²(c) = (u2 − u0)/(u2 − u1), sign from u̇0 = −sin θ0 θ̇0.
        sn2 = cubic.u0_minus_u1 / u21
        cn2 = cubic.u2_minus_u0 / u21
        if cn2 <= 0.0:
            c = K
        elif sn2 <= 0.0:
            c = 0.0
        else:
            c = _incomplete_first_kind(sn2, cn2, m)
        udot0 = -s0 * thd0
        mo.c = -c if udot0 < 0.0 else c
        mo.spin_rate = L3 / I3 - beta
        mo.period = 2.0 * K / lam
        # The two pole terms of φ̇: (α ∓ β) / (2 (1 ∓ u)); their time integrals are elliptic integrals of
        # the third kind (Carlson R_J). See _PoleTerm.
        terms = []
        for pole, d in ((+1, dm), (-1, dp)):
            half_d = 0.5 * d
            if pole == +1:
                # 1 − u = (1 − u1)(1 − n sn²τ), n = (u2 − u1)/(1 − u1) ≤ 1.
                d1, d2 = r1.p, r2.p
                n, one_n, shift = u21 / d1, d2 / d1, 0.0
                a0, a1 = 0.0, half_d / (lam * d1)
            elif u21 <= r1.q:
                # 1 + u = (1 + u1)(1 − n sn²τ), n = −(u2 − u1)/(1 + u1) ∈ [−1, 0].
                n = -u21 / r1.q
                one_n, shift = 1.0 - n, 0.0
                a0, a1 = 0.0, half_d / (lam * r1.q)
            else:
                # Near the bottom pole n → −∞ and Π(n) cancels; instead 1 + u = (1 + u2)(1 − n' cn²τ) and with
                # x = τ − K, ∫ dτ/(1 − n' cn²) = (m/N) x + (1 − m/N) Π(N; x), N = m + n'(1 − m) ∈ [m, 1]:
                # the same well-conditioned form as the top pole.
                npr = u21 / r2.q
                n = m + npr * (1.0 - m)
                one_n = one_m * r1.q / r2.q
                shift = K
                scale = half_d / (lam * r2.q)
                a0, a1 = scale * m / n, scale * npr * one_m / n
            through = one_n == 0.0  # the axis passes exactly through this pole
            jump = (math.copysign(1.0, d) if d != 0.0 else 1.0) if through else 0.0
            pic = 0.0 if through else _complete_third_kind(n, one_n, m, one_m, K)
            terms.append(_PoleTerm(pole, half_d, jump, shift, a0, a1, n, one_n, pic))
        mo.terms = terms
        # Mean φ̇ over one period: each pole term advances by 2K a0 + 2 a1 Π(n|m), or by ±π per passage.
        adv = sum(tm.jump * math.pi if tm.jump else 2.0 * K * tm.a0 + 2.0 * tm.a1 * tm.pic for tm in terms)
        mo.precession_rate = adv / mo.period
        return mo

    def _vertical_period(self, L3: float, u0: float) -> float:
        # Limit of the nutation period of motions with Lz = ±L3 close to the vertical: π/λ with the
        # remaining root of the cubic; infinite when the vertical is unstable (separatrix).
        a, beta = self.mgl / self.I1, L3 / self.I1
        if u0 > 0:  # sleeping top: roots 1, 1, β²/(2a) − 1
            u31 = beta * beta / (2.0 * a) - 2.0
        else:  # hanging: roots −1, −1, 1 + ... always stable
            u31 = beta * beta / (2.0 * a) + 2.0
        if u31 <= 0.0:
            return math.inf
        return math.pi / math.sqrt(a * u31 / 2.0)

    def nutation_cubic(self, theta0: float, thetadot0: float, phidot0: float, psidot0: float) -> NutationCubic | None:
        """Roots of ``f(u) = u̇²`` (u = cos θ) for these initial data (None for a top exactly vertical
        at rest in θ, whose θ never moves)."""
        return self._motion(theta0, thetadot0, phidot0, psidot0).cubic

    def turning_points(self, theta0: float, thetadot0: float, phidot0: float, psidot0: float) -> tuple[float, float]:
        """``(θ_min, θ_max)``: the turning points of θ, rad (roots u2, u1 of the cubic in u = cos θ).

        Starting at a turning point (``thetadot0 = 0``) the known root is deflated, so θ0 is returned
        exactly.
        """
        mo = self._motion(theta0, thetadot0, phidot0, psidot0)
        if mo.kind == "vertical":
            return mo.theta0, mo.theta0
        cu = mo.cubic
        if mo.kind == "steady" or cu is None:
            return mo.theta0, mo.theta0
        return _theta_from(cu.one_minus_u2, cu.one_plus_u2), _theta_from(cu.one_minus_u1, cu.one_plus_u1)

    def conserved_quantities(self, theta0: float, thetadot0: float, phidot0: float, psidot0: float) -> dict[str, float]:
        """``{"L3", "Lz", "energy"}`` from the initial data (kg m²/s, kg m²/s, J)."""
        mo = self._motion(theta0, thetadot0, phidot0, psidot0)
        return {"L3": mo.L3, "Lz": mo.Lz, "energy": mo.energy}

    def nutation_period(self, theta0: float, thetadot0: float, phidot0: float, psidot0: float) -> float:
        """Period of θ(t), ``2 K(m) / λ``, s. For a steady precession the limit ``π/λ`` (the period of
        small nutations about it); for a top exactly vertical the same limit for nearby motions with
        ``Lz = ±L3`` (inf below the sleeping threshold, where the vertical is unstable)."""
        return self._motion(theta0, thetadot0, phidot0, psidot0).period

    def precession_rate(self, theta0: float, thetadot0: float, phidot0: float, psidot0: float) -> float:
        """Mean precession rate ``⟨φ̇⟩`` over one nutation period, rad/s (exact, complete Π).

        For a fast top it tends to the pseudo-regular ``M g ℓ / (I3 ω3)``."""
        return self._motion(theta0, thetadot0, phidot0, psidot0).precession_rate

    def solve(
        self,
        theta0: float,
        thetadot0: float,
        phidot0: float,
        psidot0: float,
        t: ArrayLike,
        *,
        phi0: float = 0.0,
        psi0: float = 0.0,
    ) -> HeavyTopSolution:
        """Exact motion of the top from the given initial Euler angles and rates.

        ``u = cos θ = u1 + (u2 − u1) sn²(λ t + c | m)``; φ(t), ψ(t) in closed form through the incomplete
        elliptic integral of the third kind (Carlson R_J). Vectorised over t; negative t allowed.

        Parameters
        ----------
        theta0 : float
            Initial angle of the axis from +z, rad, in [0, π].
        thetadot0, phidot0, psidot0 : float
            Initial θ̇, φ̇, ψ̇, rad/s. At θ0 = 0 only ``phidot0 + psidot0`` matters (the spin ω3).
        t : array_like (n,)
            Times, s.
        phi0, psi0 : float, keyword-only
            Initial precession and spin angles, rad.

        Returns
        -------
        HeavyTopSolution
        """
        tt = _times(t)
        mo = self._motion(theta0, thetadot0, phidot0, psidot0, phi0, psi0)
        n = tt.size
        if mo.kind in ("vertical", "steady"):
            th = np.full(n, mo.theta0)
            phi = mo.phi0 + mo.phidot0 * tt
            psi = mo.psi0 + mo.psidot0 * tt
            thd = np.zeros(n)
            fd = np.full(n, mo.phidot0)
            pd = np.full(n, mo.psidot0)
            if mo.theta0 == 0.0:
                ct, st = np.ones(n), np.zeros(n)
            elif mo.theta0 == math.pi:
                ct, st = -np.ones(n), np.zeros(n)
            else:
                ct, st = np.full(n, math.cos(mo.theta0)), np.full(n, math.sin(mo.theta0))
            tmin = tmax = mo.theta0
        else:
            th, phi, psi, thd, fd, pd, ct, st = self._evaluate(mo, tt)
            cu = mo.cubic
            assert cu is not None  # a nutating motion has its cubic
            tmin = _theta_from(cu.one_minus_u2, cu.one_plus_u2)
            tmax = _theta_from(cu.one_minus_u1, cu.one_plus_u1)
        cf, sf, cp, sp = np.cos(phi), np.sin(phi), np.cos(psi), np.sin(psi)
        attitude = _attitude_from_trig(cf, sf, ct, st, cp, sp)
        axis = attitude[:, :, 2].copy()
        omega = np.stack([fd * st * sp + thd * cp, fd * st * cp - thd * sp, np.full(n, mo.L3 / self.I3)], axis=-1)
        return HeavyTopSolution(
            t=tt,
            theta=th,
            phi=phi,
            psi=psi,
            thetadot=thd,
            phidot=fd,
            psidot=pd,
            axis=axis,
            attitude=attitude,
            omega_body=omega,
            L3=mo.L3,
            Lz=mo.Lz,
            energy=mo.energy,
            nutation_period=mo.period,
            precession_rate=mo.precession_rate,
            theta_min=tmin,
            theta_max=tmax,
        )

    def simulate(
        self,
        theta0: float,
        thetadot0: float,
        phidot0: float,
        psidot0: float,
        t_final: float,
        dt: float,
        *,
        spin_friction: float = 0.0,
        air_drag: float = 0.0,
        method: str | type = "LieRK4",
        save_every: int = 1,
        phi0: float = 0.0,
        psi0: float = 0.0,
    ) -> FrictionRun:
        """The top with friction, integrated step by step on (R, L_body) by :mod:`physics.integrators`.

        Friction model (both at the tip, both only remove energy):

        * spin friction at the tip: body torque ``−c ω3 e3`` about the symmetry axis
          (:class:`physics.integrators.SpinFriction`), so ``dL3/dt = −c L3 / I3`` and
          ``dE/dt = −c ω3² ≤ 0``; L3 decays as ``exp(−c t / I3)``;
        * optional air drag on the wobble: ``−c_air (ω1, ω2, 0)`` (:class:`TransverseAirDrag`),
          ``dE/dt = −c_air (ω1² + ω2²)``.

        The lecture's story: a sleeping top (θ0 ≈ 0) with ``L3 > 2 sqrt(M g ℓ I1)`` stays up; as friction
        takes L3 below :meth:`sleeping_threshold` the vertical turns unstable (U''(0) < 0), the top starts
        to wobble and falls. No Euler angles are integrated, so θ = 0 and θ = π/2 are ordinary points.

        Parameters
        ----------
        theta0, thetadot0, phidot0, psidot0 : float
            Initial Euler angle θ (rad, in [0, π]) and rates (rad/s), as in :meth:`solve`.
        t_final, dt : float
            Duration and step, s (the step is shortened to fit a whole number of steps).
        spin_friction : float
            ``c ≥ 0``, N m s.
        air_drag : float
            ``c_air ≥ 0``, N m s.
        method : str or integrator class
            ``"LieRK4"`` (default), ``"Yoshida4"``, ``"LiePoissonStrang"`` or ``"ExactFreeSplitting"``.
        save_every : int
            Keep every this many steps.
        phi0, psi0 : float
            Initial precession and spin angles, rad.

        Returns
        -------
        FrictionRun
        """
        return _simulate_symmetric(
            self,
            theta0,
            thetadot0,
            phidot0,
            psidot0,
            t_final,
            dt,
            spin_friction,
            air_drag,
            method,
            save_every,
            phi0,
            psi0,
        )

    def _evaluate(self, mo: _Motion, t: NDArray[np.float64]) -> tuple[Floats, ...]:
        cu, m, K, lam = mo.cubic, mo.m, mo.K, mo.lam
        assert cu is not None  # only nutating motions are evaluated here
        tau = lam * t + mo.c
        k, r = _reduce(tau, K)
        sn, cn, dn = _jacobi(r, m, mo.one_m, K)
        sn2, cn2 = sn * sn, cn * cn
        u21 = cu.u2_minus_u1
        # 1 ∓ u as sums of non-negative terms: no cancellation near the poles.
        one_mu = cu.one_minus_u2 + u21 * cn2
        one_pu = cu.one_plus_u1 + u21 * sn2
        u = np.where(one_mu < one_pu, 1.0 - one_mu, one_pu - 1.0)
        st = np.sqrt(one_mu * one_pu)
        th = _theta_from(one_mu, one_pu)
        udot = 2.0 * u21 * lam * sn * cn * dn
        with np.errstate(divide="ignore", invalid="ignore"):
            thd = np.where(st > 0.0, -udot / st, 0.0)
        # Exactly at a pole (only when the axis passes through it): the one-sided limit, leaving the pole.
        top, bot = one_mu == 0.0, one_pu == 0.0
        if np.any(top):
            thd[top] = 2.0 * math.sqrt(u21) * lam * np.abs(sn[top]) * dn[top] / np.sqrt(one_pu[top])
        if np.any(bot):
            thd[bot] = -2.0 * math.sqrt(u21) * lam * np.abs(cn[bot]) * dn[bot] / np.sqrt(one_mu[bot])
        fd = np.zeros_like(t)
        phi = np.full_like(t, mo.phi0)
        psi = mo.psi0 + mo.spin_rate * t
        pdd = np.full_like(t, mo.spin_rate)
        one_m = mo.one_m
        for tm in mo.terms:
            dphi = tm.integral(tau, K, m, one_m, (k, r, sn, cn2, dn * dn)) - tm.integral(np.array([mo.c]), K, m, one_m)
            phi = phi + dphi
            psi = psi - tm.pole * dphi
            if tm.half_d != 0.0:
                dist = one_mu if tm.pole == +1 else one_pu
                with np.errstate(divide="ignore", invalid="ignore"):
                    rate = np.where(dist > 0.0, tm.half_d / dist, 0.0)
                fd = fd + rate
                pdd = pdd - tm.pole * rate
        return th, phi, psi, thd, fd, pdd, u, st


# --------------------------------------------------------------------------------------------------
# Elliptic integrals (Carlson forms)
# --------------------------------------------------------------------------------------------------


def _theta_from(one_mu: ArrayLike, one_pu: ArrayLike) -> Any:
    """θ from 1 − cos θ = 2 sin²(θ/2) and 1 + cos θ = 2 cos²(θ/2): accurate at both poles."""
    return 2.0 * np.arctan2(np.sqrt(np.maximum(one_mu, 0.0)), np.sqrt(np.maximum(one_pu, 0.0)))


def _incomplete_first_kind(sn2: float, cn2: float, m: float) -> float:
    """F(φ | m) with sin²φ = sn2, cos²φ = cn2 given separately (so φ near π/2 keeps its digits)."""
    return float(math.sqrt(sn2) * elliprf(cn2, cn2 + (1.0 - m) * sn2, 1.0))


def _complete_third_kind(n: float, one_n: float, m: float, one_m: float, K: float) -> float:
    """Π(n | m) = K(m) + (n/3) R_J(0, 1 − m, 1, 1 − n) (DLMF 19.25.2)."""
    return float(K + n / 3.0 * elliprj(0.0, one_m, 1.0, one_n))


def _incomplete_third_kind(r: Floats, sn: Floats, cn2: Floats, dn2: Floats, n: float, one_n: float) -> Floats:
    """∫₀^r dτ/(1 − n sn²τ) for |r| ≤ K: ``r + (n/3) sn³ R_J(cn², dn², 1, 1 − n sn²)`` (DLMF 19.25.14,
    with s R_F(c², d², 1) = F(am r) = r)."""
    p = one_n + n * cn2 if n > 0.0 else 1.0 - n * sn * sn  # 1 − n sn², both forms free of cancellation
    with np.errstate(invalid="ignore"):
        rj = elliprj(cn2, dn2, 1.0, p)
    term = np.where(sn == 0.0, 0.0, n / 3.0 * sn**3 * rj)
    return r + term


def _jacobi(r: Floats, m: float, one_m: float, K: float) -> tuple[Floats, Floats, Floats]:
    """sn, cn, dn of r in [−K, K) with cn keeping its relative digits near r = ±K (the top turning
    point, where 1 − u ∝ cn² may be all that separates the axis from the pole): there
    ``sn(K − x) = cd x``, ``cn(K − x) = sqrt(1 − m) sd x``, ``dn(K − x) = sqrt(1 − m) nd x``."""
    r = np.asarray(r, dtype=float)
    sn, cn, dn, _ = ellipj(r, m)
    far = np.abs(r) > 0.5 * K
    if np.any(far):
        x = K - np.abs(r[far])  # exact (Sterbenz)
        sx, cx, dx, _ = ellipj(x, m)
        k1 = math.sqrt(one_m)
        sn[far] = np.sign(r[far]) * cx / dx
        cn[far] = k1 * sx / dx
        dn[far] = k1 / dx
    return sn, cn, dn


def _reduce(tau: Floats, K: float) -> tuple[Floats, Floats]:
    """``τ = 2K k + r`` with r in [−K, K): sn² has period 2K. The half-open interval puts τ = K (the
    top turning point) at r = −K, on the side the pole-jump count already counts as passed."""
    k = np.floor((tau + K) / (2.0 * K))
    return k, tau - 2.0 * K * k


class TransverseAirDrag:
    """Air drag on the wobble: body torque ``−c_air (ω1, ω2, 0)`` (opposes the rotation of the symmetry
    axis, not the spin), N m. A torque object for :mod:`physics.integrators`.

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
        out: Floats = -self.coefficient * w
        out[..., 2] = 0.0
        return out


@dataclass(frozen=True)
class FrictionRun:
    """A heavy body integrated step by step (attitude R and body angular momentum L).

    Attributes
    ----------
    t : ndarray (k,)
        Saved times, s.
    attitude : ndarray (k, 3, 3)
        Body-to-space rotations.
    L_body : ndarray (k, 3)
        Angular momentum about the pivot in the body frame, kg m²/s.
    omega_body : ndarray (k, 3)
        Angular velocity in the body frame, rad/s.
    axis : ndarray (k, 3)
        Body axis 3 in space (the symmetry axis of a symmetric top).
    theta : ndarray (k,)
        Angle of that axis from +z, rad (from the axis itself: no Euler-angle singularity).
    energy : ndarray (k,)
        Kinetic plus gravitational energy, J.
    L3 : ndarray (k,)
        Body component 3 of L (the spin angular momentum of a symmetric top), kg m²/s.
    Lz : ndarray (k,)
        Space z component of L, kg m²/s (conserved without friction: gravity's torque is horizontal).
    method : str
        Name of the integrator.
    """

    t: NDArray[np.float64]
    attitude: NDArray[np.float64]
    L_body: NDArray[np.float64]
    omega_body: NDArray[np.float64]
    axis: NDArray[np.float64]
    theta: NDArray[np.float64]
    energy: NDArray[np.float64]
    L3: NDArray[np.float64]
    Lz: NDArray[np.float64]
    method: str


_METHOD_NAMES = ("LiePoissonStrang", "Yoshida4", "Suzuki4", "Yoshida6", "ExactFreeSplitting", "LieRK4")


def _method_class(method: str | type) -> type:
    from physics import integrators

    if isinstance(method, str):
        if method not in _METHOD_NAMES:
            raise ValueError(f"unknown method {method!r}; choose one of {', '.join(_METHOD_NAMES)}")
        cls: type = getattr(integrators, method)
        return cls
    return method


def simulate_heavy_body(
    moments: ArrayLike,
    mass: float,
    center_of_mass_body: ArrayLike,
    attitude0: ArrayLike,
    omega_body0: ArrayLike,
    t_final: float,
    dt: float,
    *,
    torques: Sequence[Callable[..., Any]] = (),
    method: str | type = "LieRK4",
    g: float = G,
    save_every: int = 1,
) -> FrictionRun:
    """Any rigid body with one point (the origin, its pivot) fixed, under gravity ``−g ẑ`` and optional
    extra torques, integrated by :mod:`physics.integrators` on (R, L_body) — no Euler angles.

    Euler's equations with the gravity torque ``τ_body = c × (−M g Rᵀ ẑ)`` (c = centre of mass in the
    body frame) and ``Ṙ = R hat(ω_body)``.

    Parameters
    ----------
    moments : array_like (3,)
        Principal moments about the pivot, kg m²; the body frame is their principal frame.
    mass : float
        kg (> 0).
    center_of_mass_body : array_like (3,)
        Centre of mass relative to the pivot, body frame, m.
    attitude0 : array_like (3, 3)
        Initial body-to-space rotation.
    omega_body0 : array_like (3,)
        Initial angular velocity, body frame, rad/s.
    t_final, dt : float
        Duration and step, s; the step is shortened so that a whole number of steps reaches t_final.
    torques : sequence of torque objects
        Extra torques (e.g. :class:`physics.integrators.SpinFriction`, :class:`TransverseAirDrag`).
    method : str or integrator class
        ``"LieRK4"`` (default, order 4), ``"Yoshida4"``, ``"LiePoissonStrang"``, ``"ExactFreeSplitting"``.
    g : float
        Gravitational acceleration, m/s².
    save_every : int
        Keep every this many steps.

    Returns
    -------
    FrictionRun
    """
    from physics import integrators
    from physics.inertia import validate_moments

    I = validate_moments(moments)
    mass = finite_scalar(mass, "mass")
    if mass <= 0.0:
        raise ValueError(f"mass must be positive, got {mass}")
    com = vector_array(center_of_mass_body, "center_of_mass_body", batched=False)
    R0 = rotation_array(attitude0, "attitude0", batched=False)
    w0 = vector_array(omega_body0, "omega_body0", batched=False)
    t_final, dt = finite_scalar(t_final, "t_final"), finite_scalar(dt, "dt")
    if t_final <= 0.0 or dt <= 0.0:
        raise ValueError(f"t_final and dt must be positive, got t_final = {t_final}, dt = {dt}")
    if t_final / dt > MAX_STEPS:
        raise ValueError(
            f"t_final / dt = {t_final / dt:.3g} steps is more than {MAX_STEPS:,}: take a larger dt or a shorter run"
        )
    if np.max(np.abs(w0)) > MAX_RATE:
        raise ValueError(f"omega_body0 must be at most {MAX_RATE:g} rad/s in each component, got {w0.tolist()}")
    n_steps = max(1, int(math.ceil(t_final / dt - 1e-9)))
    h = t_final / n_steps
    g = finite_scalar(g, "g")
    all_torques = [integrators.GravityTorque(mass, com, g=g), *torques]
    stepper = _method_class(method)(I, all_torques)
    traj = integrators.integrate(stepper, R0, I * w0, h, n_steps, save_every=save_every)
    R = np.asarray(traj.attitude)
    L = np.asarray(traj.L_body)
    w = L / I
    axis = R[:, :, 2].copy()
    height = np.einsum("kij,j->ki", R, com)[:, 2]
    energy = 0.5 * np.sum(L * w, axis=1) + mass * g * height
    Lz = np.einsum("kij,kj->ki", R, L)[:, 2]
    theta = np.arctan2(np.hypot(axis[:, 0], axis[:, 1]), axis[:, 2])
    return FrictionRun(
        t=np.asarray(traj.t, dtype=float),
        attitude=R,
        L_body=L,
        omega_body=w,
        axis=axis,
        theta=theta,
        energy=energy,
        L3=L[:, 2].copy(),
        Lz=Lz,
        method=getattr(stepper, "name", type(stepper).__name__),
    )


def _simulate_symmetric(
    top: HeavyTop,
    theta0: float,
    thetadot0: float,
    phidot0: float,
    psidot0: float,
    t_final: float,
    dt: float,
    spin_friction: float,
    air_drag: float,
    method: str | type,
    save_every: int,
    phi0: float,
    psi0: float,
) -> FrictionRun:
    from physics import integrators

    vals = [
        finite_scalar(v, n)
        for v, n in (
            (theta0, "theta0"),
            (thetadot0, "thetadot0"),
            (phidot0, "phidot0"),
            (psidot0, "psidot0"),
            (phi0, "phi0"),
            (psi0, "psi0"),
        )
    ]
    if not 0.0 <= vals[0] <= math.pi:
        raise ValueError(f"theta0 is the angle of the axis from +z and must lie in [0, pi], got {vals[0]}")
    c = finite_scalar(spin_friction, "spin_friction")
    if c < 0.0:
        raise ValueError(f"spin_friction must be >= 0 (it removes energy), got {c}")
    moments = np.array([top.I1, top.I1, top.I3])
    R0 = euler_attitude(vals[4], vals[0], vals[5])
    w0 = omega_body_from_euler(vals[0], vals[5], vals[1], vals[2], vals[3])
    torques: list[Any] = []
    if c > 0.0:
        torques.append(integrators.SpinFriction(c, moments, axis_body=(0.0, 0.0, 1.0)))
    if air_drag:
        torques.append(TransverseAirDrag(air_drag, moments))
    # M g ℓ = mgl with a unit lever: the torque (and the energy) only depend on the product.
    return simulate_heavy_body(
        moments,
        top.mgl / G,
        (0.0, 0.0, 1.0),
        R0,
        w0,
        t_final,
        dt,
        torques=torques,
        method=method,
        g=G,
        save_every=save_every,
    )
