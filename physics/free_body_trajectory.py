"""The free body's motion from one initial state, solved once and evaluated at any times.

:class:`FreeBodyTrajectory` keeps the constants of the motion (:func:`physics.free_body_motion.motion_constants`:
modulus, rate, phase, pole, the frame of L at t = 0); :meth:`FreeBodyTrajectory.at` evaluates an array
of times with the vectorised closed form of :mod:`physics.free_body`, and one time (a frame of an
animation) with the same formulas on Python floats (:meth:`FreeBodyTrajectory._one`).
"""

from __future__ import annotations

import math
from dataclasses import dataclass, fields
from typing import TYPE_CHECKING, Any

import numpy as np
from numpy.typing import ArrayLike, NDArray

from physics.elliptic import carlson_rj_one, reduced_jacobi_one
from physics.free_body_motion import check_attitude0, check_omega0, check_times, evaluate
from physics.validation import finite_phase, finite_scalar

if TYPE_CHECKING:
    from physics.free_body import FreeBody

Floats = NDArray[np.float64]

__all__ = ["FreeBodyState", "FreeBodyTrajectory"]


@dataclass(frozen=True)
class FreeBodyState:
    """The free body at given times (what :meth:`FreeBodyTrajectory.at` returns).

    Attributes
    ----------
    t : ndarray (n,), or float for one time
        Times, s.
    omega : ndarray (n, 3), or (3,)
        Body-frame angular velocity, rad/s.
    attitude : ndarray (n, 3, 3), or (3, 3)
        Body-to-space rotations.
    """

    t: Any
    omega: NDArray[np.float64]
    attitude: NDArray[np.float64]


@dataclass(frozen=True)
class EllipticFloats:
    """The constants of one elliptic motion as floats (one time is evaluated on floats): the entries of
    :class:`physics.free_body_motion.MotionConstants` of the same names."""

    m: float
    mc: float
    kp: float
    K: float
    lam: float
    u0: float
    n: float
    Jc: float
    L: float
    rate0: float
    coef: float
    P0: float
    ia: float
    ib: float
    ic: float


class FreeBodyTrajectory:
    """One motion of a :class:`FreeBody`, ready to be evaluated at any times.

    Made by :meth:`FreeBody.trajectory`: the constants of the motion (modulus, rate, phase, the frame
    of the angular momentum at t = 0) are computed once here.

    Attributes
    ----------
    body : FreeBody
    omega0 : ndarray (3,)
        ``ω(0)``, rad/s.
    attitude0 : ndarray (3, 3)
        ``R(0)``.
    energy : float
        Kinetic energy, J.
    angular_momentum : ndarray (3,)
        ``L`` in space, kg m²/s (constant).
    """

    def __init__(self, body: FreeBody, omega0: ArrayLike, attitude0: ArrayLike | None = None) -> None:
        self.body = body
        self.omega0 = check_omega0(omega0)
        self.attitude0 = check_attitude0(attitude0)
        self.energy = float(0.5 * np.sum(body.moments * self.omega0 * self.omega0))
        self.angular_momentum = np.einsum("ij,j->i", self.attitude0, body.moments * self.omega0)
        self._w = self.omega0[None, :]
        self._r0 = self.attitude0[None]
        self._setup = body.constants(self._w)
        self._kind = int(self._setup.kind[0])
        moments = body.moments
        # A bound on every phase per second of t (see physics.free_body_motion.evaluate), to refuse overflowing times.
        self._reach = 4.0 * float(np.max(moments) / np.min(moments[moments > 0.0])) * float(np.max(np.abs(self.omega0)))
        if self._kind == 2:
            self._prepare_elliptic()

    def _prepare_elliptic(self) -> None:
        """The floats one time needs, and ``M0 = R0 Qᵀ B(0)`` (see :func:`physics.free_body_motion.evaluate`)."""
        p = self._setup
        self._constants = EllipticFloats(
            *(float(getattr(p, f.name)[0]) for f in fields(EllipticFloats))  # the same names as MotionConstants'
        )
        self._deep = bool(p.deep[0])
        self._pole_c = bool(p.pole_c[0])
        self._amp = [float(a) for a in p.amp[0]]
        roots, scale = p.ladder
        self._roots, self._scale = [float(q[0]) for q in roots], float(scale[0])
        self._q = p.q_can[0]
        self._qt = self._q.T.copy()
        c = self._constants
        wc0 = self._q @ self.omega0
        frame_0 = _frame_one(wc0, c.ia, c.ib, c.ic, self._pole_c)
        self._m0 = self.attitude0 @ self._qt @ frame_0

    def __repr__(self) -> str:
        return f"FreeBodyTrajectory({self.body.moments.tolist()}, omega0={self.omega0.tolist()})"

    def at(self, t: ArrayLike) -> FreeBodyState:
        """ω and R at the times ``t`` (s, any sign): arrays (n, 3) and (n, 3, 3) for an array of times,
        (3,) and (3, 3) for one time."""
        if isinstance(t, (float, int)) and not isinstance(t, bool):
            tf = finite_scalar(t, "t")
            with np.errstate(over="ignore"):
                finite_phase(self._reach * abs(tf))
            return self._one(tf)
        tt = check_times(t)
        body = self.body
        which = np.zeros(tt.shape, dtype=int)
        omega, attitude = evaluate(
            self._setup, body.moments, body.symmetry_axis, self._w, tt, self._r0, which, want_attitude=True
        )
        if np.ndim(t) == 0:
            return FreeBodyState(float(tt[0]), omega[0], attitude[0])
        return FreeBodyState(tt, omega, attitude)

    def _one(self, t: float) -> FreeBodyState:
        """One time, on floats: the closed form of :func:`physics.free_body_motion.evaluate`."""
        w, r0 = self.omega0, self.attitude0
        if self._kind == 0:  # uniform rotation about a principal axis
            return FreeBodyState(t, w.copy(), r0 @ _expm_one(t * w[0], t * w[1], t * w[2]))
        if self._kind == 1:  # symmetric body: ω⊥ turns by −Ω t about e_s; R = exp(t hat(L)/I⊥) R0 exp(Ω t hat e_s)
            p, body = self._setup, self.body
            s = body.symmetry_axis
            ang = float(p.Omega[0]) * t
            cs, sn = math.cos(ang), math.sin(ang)
            b, c = (s + 1) % 3, (s + 2) % 3
            omega = w.copy()
            omega[b] = w[b] * cs + w[c] * sn
            omega[c] = w[c] * cs - w[b] * sn
            l_space = t * self.angular_momentum / p.i_perp
            axis = [0.0, 0.0, 0.0]
            axis[s] = ang
            attitude = _expm_one(*l_space) @ r0 @ _expm_one(*axis)
            return FreeBodyState(t, omega, attitude)
        k = self._constants
        u = k.lam * t + k.u0
        j, v, s_, c_, d_ = reduced_jacobi_one(u, k.m, k.mc, k.K, self._roots, self._scale, k.kp)
        sign = 1.0 - 2.0 * (j % 2.0)
        a0, a1, a2 = self._amp
        wc = np.array([a0 * d_, a1 * sign * s_, a2 * sign * c_])
        omega = self._qt @ wc
        # Angle turned about L: ψ − ψ0 = L t / I_c + C [P(u) − P(u0)], P = Π(n; am u|m) − u.
        excess = _excess_one(k, u, j, v, s_, c_, d_, self._deep)
        dpsi = k.L * t * k.rate0 + k.coef * (excess - k.P0)
        b1, b2, b3 = _frame_rows_one(a0 * d_, a1 * sign * s_, a2 * sign * c_, k.ia, k.ib, k.ic, self._pole_c)
        cp, sp = math.cos(dpsi), math.sin(dpsi)
        rot_bt = np.array(
            [[cp * x - sp * y for x, y in zip(b1, b2)], [sp * x + cp * y for x, y in zip(b1, b2)], list(b3)]
        )
        return FreeBodyState(t, omega, self._m0 @ rot_bt @ self._q)


def _expm_one(x: float, y: float, z: float) -> Floats:
    """:func:`physics.rotations.expm_so3` of one rotation vector, on floats (Rodrigues)."""
    a2 = (x * x + z * z) + y * y  # numpy's einsum adds three terms in this order: the same angle, to the bit
    a = math.sqrt(a2)
    if a < 1e-4:
        s, c = 1.0 - a2 / 6.0 + a2 * a2 / 120.0, 0.5 - a2 / 24.0 + a2 * a2 / 720.0
    else:
        s, c = math.sin(a) / a, (1.0 - math.cos(a)) / (a * a)
    # exp(hat v) = I + s hat v + c hat v², with hat v²'s diagonal −(y² + z²), ... (no cancellation).
    return np.array(
        [
            [1.0 - c * (z * z + y * y), -s * z + c * x * y, s * y + c * x * z],
            [s * z + c * x * y, 1.0 - c * (z * z + x * x), -s * x + c * y * z],
            [-s * y + c * x * z, s * x + c * y * z, 1.0 - c * (y * y + x * x)],
        ]
    )


def _sep_excess_one(a: float, n: float) -> float:
    """:func:`physics.free_body_motion.sep_excess` of one ``a ≥ 0``."""
    rn = math.sqrt(-n)
    th = math.tanh(a)
    x = rn * th
    atan_over = th * (1.0 - x * x / 3.0) if abs(x) < 1e-8 else math.atan(x) / rn
    return (a - atan_over) / (1.0 - n)


def _excess_one(k: EllipticFloats, u: float, j: float, v: float, s: float, c: float, d: float, deep: bool) -> float:
    """:func:`physics.free_body_motion.third_kind_excess` at one phase."""
    n = k.n
    if k.K == math.inf:  # separatrix: the elementary form
        return math.copysign(_sep_excess_one(abs(u), n), u)
    if deep:  # within 1 − m < 1e-40 of it: the separatrix's pulses 2K apart
        a, kk = abs(v), k.K
        local = k.Jc / 3.0 - (kk - a) / (1.0 - n) if a > 0.5 * kk else _sep_excess_one(a, n)
        return 2.0 * j * k.Jc / 3.0 + math.copysign(local, v)
    x2, y2, p = c * c, d * d, 1.0 - n * s * s
    rj = carlson_rj_one(x2, y2, p)
    return (2.0 * j * k.Jc + s**3 * rj) / 3.0


def _frame_rows_one(
    wa: float, wb: float, wc: float, ia: float, ib: float, ic: float, pole_c: bool
) -> tuple[tuple[float, float, float], ...]:
    """:func:`physics.free_body_motion.frame_from_momentum` for one state: its columns b1, b2, L̂ (floats)."""
    la, lb, lc = ia * wa, ib * wb, ic * wc
    big = max(abs(la), abs(lb), abs(lc))  # no underflow in the norm for tiny ω
    la, lb, lc = la / big, lb / big, lc / big
    norm = math.sqrt(la * la + lb * lb + lc * lc)
    la, lb, lc = la / norm, lb / norm, lc / norm
    if pole_c:
        rho = math.hypot(la, lb)
        return (-lb / rho, la / rho, 0.0), (-lc * la / rho, -lc * lb / rho, rho), (la, lb, lc)
    rho = math.hypot(lb, lc)
    return (0.0, -lc / rho, lb / rho), (rho, -la * lb / rho, -la * lc / rho), (la, lb, lc)


def _frame_one(wc: Floats, ia: float, ib: float, ic: float, pole_c: bool) -> Floats:
    """The frame B (columns b1, b2, L̂) of one state, shape (3, 3)."""
    return np.array(_frame_rows_one(float(wc[0]), float(wc[1]), float(wc[2]), ia, ib, ic, pole_c)).T
