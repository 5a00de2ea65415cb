"""Elliptic pieces of the heavy top's closed form (Carlson forms, scipy.special).

``u = cos θ = u1 + (u2 − u1) sn²(τ | m)`` with ``τ = λ t + c``; φ and ψ are sums of elliptic integrals of
the third kind, one per pole (:class:`_PoleTerm`). Each function has an array form (vectorised over τ)
and the evaluation of one time in :mod:`physics.top_trajectory` uses the ``*_one`` forms, which compute
the same expressions on Python floats (a frame of an animation asks for one time).
"""

from __future__ import annotations

import math
from dataclasses import dataclass
from functools import lru_cache

import numpy as np
from numpy.typing import ArrayLike, NDArray
from scipy.special import ellipj, elliprc, elliprf, elliprj

from physics.free_body import _landen_ladder
from physics.free_body_trajectory import _jacobi_one as _jacobi_one_from_ladder

Floats = NDArray[np.float64]


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

    def integral_one(
        self, tau: float, K: float, m: float, one_m: float, k: float, r: float, sn: float, cn2: float, dn2: float
    ) -> float:
        """:meth:`integral` at one τ, given its reduction ``τ = 2K k + r`` and sn, cn², dn² at r."""
        x = tau - self.shift
        if self.jump:
            return self.jump * math.pi * math.floor((x + K) / (2.0 * K))
        if self.a0 == 0.0 and self.a1 == 0.0:
            return 0.0
        if self.shift != 0.0:
            k = math.floor((x + K) / (2.0 * K))
            r = x - 2.0 * K * k
            sn, cn, dn = _jacobi_one(r, m, one_m, K)
            cn2, dn2 = cn * cn, dn * dn
        return self.a0 * x + self.a1 * (
            2.0 * k * self.pic + _incomplete_third_kind_one(r, sn, cn2, dn2, self.n, self.one_n)
        )


def _incomplete_first_kind(sn2: float, cn2: float, m: float, one_m: float) -> float:
    """F(φ | m) with sin²φ = sn2, cos²φ = cn2 and 1 − m given separately (so φ near π/2 keeps its digits,
    and so does 1 − m sin²φ = cos²φ + (1 − m) sin²φ near the separatrix, where the float 1 − m of m
    rounding to 1 would have none)."""
    return float(math.sqrt(sn2) * elliprf(cn2, cn2 + one_m * sn2, 1.0))


def _complete_third_kind(n: float, one_n: float, m: float, one_m: float, K: float) -> float:
    """Π(n | m) = K(m) + (n/3) R_J(0, 1 − m, 1, 1 − n) (DLMF 19.25.2)."""
    return float(K + n / 3.0 * _rj_one(0.0, one_m, one_n))


def _incomplete_third_kind(r: Floats, sn: Floats, cn2: Floats, dn2: Floats, n: float, one_n: float) -> Floats:
    """∫₀^r dτ/(1 − n sn²τ) for |r| ≤ K: ``r + (n/3) sn³ R_J(cn², dn², 1, 1 − n sn²)`` (DLMF 19.25.14,
    with s R_F(c², d², 1) = F(am r) = r)."""
    p = one_n + n * cn2 if n > 0.0 else 1.0 - n * sn * sn  # 1 − n sn², both forms free of cancellation
    with np.errstate(invalid="ignore"):
        rj = _rj(cn2, dn2, p)
    term = np.where(sn == 0.0, 0.0, n / 3.0 * sn**3 * rj)
    return r + term


def _jacobi(r: Floats, m: float, one_m: float, K: float) -> tuple[Floats, Floats, Floats]:
    """sn, cn, dn of r in [−K, K) with cn keeping its relative digits near r = ±K (the top turning
    point, where 1 − u ∝ cn² may be all that separates the axis from the pole): there
    ``sn(K − x) = cd x``, ``cn(K − x) = sqrt(1 − m) sd x``, ``dn(K − x) = sqrt(1 − m) nd x``.

    Near the separatrix (``1 − m < 1e-4``: a top started near the vertical below the sleeping threshold)
    scipy's ``ellipj``, which sees only the float m, loses ``eps/(1 − m)`` of relative accuracy in cn and
    dn (2.5e-10 at 1 − m = 7e-16); there the free body's Landen ladder driven by m and 1 − m (and its
    expansion about m = 1 below 1 − m = 1e-15) keeps every digit (:func:`_jacobi_one`)."""
    r = np.asarray(r, dtype=float)
    if one_m < _NEAR_SEPARATRIX:
        # Element by element on floats (1.3 µs each): one time and many get the same numbers, which numpy's
        # own sin, cosh, ... (SIMD kernels on some CPUs) would not guarantee.
        values = np.array([_jacobi_one(x, m, one_m, K) for x in r.tolist()]).reshape(-1, 3)
        return values[:, 0], values[:, 1], values[:, 2]
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


_NEAR_SEPARATRIX = 1e-4
"""Below this 1 − m the Jacobi functions come from m and 1 − m (measured: scipy's ``ellipj`` is within
3e-15 relative down to 1 − m = 1e-4, 4e-14 at 1e-6, 5e-13 at 1e-8)."""


@lru_cache(maxsize=64)
def _ladder(m: float, one_m: float) -> tuple[list[float], float]:
    """The descending Landen ladder of (m, 1 − m) as floats: ``√μ`` of each step and the argument scale."""
    roots, scale = _landen_ladder(np.array(min(m, 1.0)), np.array(one_m))
    return [float(q) for q in roots], float(scale)


def _reduce(tau: Floats, K: float) -> tuple[Floats, Floats]:
    """``τ = 2K k + r`` with r in [−K, K): sn² has period 2K. The half-open interval puts τ = K (the
    top turning point) at r = −K, on the side the pole-jump count already counts as passed."""
    k = np.floor((tau + K) / (2.0 * K))
    return k, tau - 2.0 * K * k


def _jacobi_one(r: float, m: float, one_m: float, K: float) -> tuple[float, float, float]:
    """:func:`_jacobi` for one r (floats)."""
    if one_m < _NEAR_SEPARATRIX:  # the free body's Landen ladder on floats (its ladder computed once)
        roots, scale = _ladder(m, one_m)
        j, _, sn, cn, dn = _jacobi_one_from_ladder(r, min(m, 1.0), one_m, K, roots, scale, math.sqrt(one_m))
        # It reduces r by 2K j (j = ±1 when rounding has put r a hair beyond ±K): sn, cn change sign.
        return (-sn, -cn, dn) if j % 2.0 else (sn, cn, dn)
    if abs(r) > 0.5 * K:
        sx, cx, dx, _ = ellipj(K - abs(r), m)
        k1 = math.sqrt(one_m)
        sign = 1.0 if r > 0.0 else -1.0
        return float(sign * cx / dx), float(k1 * sx / dx), float(k1 / dx)
    sn, cn, dn, _ = ellipj(r, m)
    return float(sn), float(cn), float(dn)


def _incomplete_third_kind_one(r: float, sn: float, cn2: float, dn2: float, n: float, one_n: float) -> float:
    """:func:`_incomplete_third_kind` for one r (floats)."""
    if sn == 0.0:
        return r
    p = one_n + n * cn2 if n > 0.0 else 1.0 - n * sn * sn
    rj = _rj_one(cn2, dn2, p)
    return r + n / 3.0 * sn**3 * rj


def _complete_q(one_n: float, one_m: float) -> float:
    """``Q(n|m) = ∫₀^K sn²/(1 − n sn²) dτ = (Π(n|m) − K)/n = R_J(0, 1 − m, 1, 1 − n)/3`` (DLMF 19.25.2):
    no division by n, so it stays accurate as n → 0."""
    return _rj_one(0.0, one_m, one_n) / 3.0


def _q_integral(k: Floats, sn: Floats, cn2: Floats, dn2: Floats, n: float, one_n: float, qc: float) -> Floats:
    """``Q(n; τ) = ∫₀^τ sn²/(1 − n sn²)`` for ``τ = 2K k + r``, given sn, cn², dn² at r:
    ``2 k Q(n|m) + sn³ R_J(cn², dn², 1, 1 − n sn²)/3`` (DLMF 19.25.14 without the factor n)."""
    p = one_n + n * cn2 if n > 0.0 else 1.0 - n * sn * sn
    with np.errstate(invalid="ignore"):
        rj = _rj(cn2, dn2, p)
    return 2.0 * k * qc + np.where(sn == 0.0, 0.0, sn**3 * rj / 3.0)


def _q_integral_one(k: float, sn: float, cn2: float, dn2: float, n: float, one_n: float, qc: float) -> float:
    """:func:`_q_integral` for one τ (floats)."""
    if sn == 0.0:
        return 2.0 * k * qc
    p = one_n + n * cn2 if n > 0.0 else 1.0 - n * sn * sn
    return 2.0 * k * qc + sn**3 * _rj_one(cn2, dn2, p) / 3.0


_RJ_SMALL = 1e-100
"""Below this an argument of scipy's ``elliprj`` (other than x = 0) is lifted first (see :func:`_rj`)."""


def _rj(x: ArrayLike, y: ArrayLike, p: ArrayLike) -> Floats:
    """Carlson's ``R_J(x, y, 1, p)`` for ``0 ≤ x``, ``0 < y, p ≤ 1``, accurate down to the smallest
    normal arguments.

    A start near the vertical puts ``cn²``, ``dn²``, ``1 − m`` and ``1 − n`` at ~θ0², and scipy's
    ``elliprj`` returns NaN once two of its arguments are below ~1e-155 (and may lose digits before).
    Each duplication step (DLMF 19.26.9) ``R_J(x, y, z, p) = 2 R_J(x + λ, y + λ, z + λ, p + λ)
    + (6/d) R_C(1, 1 + e)``, ``λ = √x√y + √x√z + √y√z``, ``d = (√p + √x)(√p + √y)(√p + √z)``, lifts the
    small arguments to at least ``√(y z)``; two steps bring anything above 1e-308 beyond 1e-77. The
    ratio is formed as ``1 + e = 2 √p (p + λ) / d`` (a product of ratios below 1, with no cancellation and
    no underflow), and ``6/d`` as a product of reciprocals.
    """
    xs, ys, ps = np.broadcast_arrays(*(np.asarray(a, dtype=float) for a in (x, y, p)))
    zs = np.ones(xs.shape)
    total = np.zeros(xs.shape)
    weight = np.ones(xs.shape)
    for _ in range(3):
        small = np.minimum(np.where(xs > 0.0, xs, 1.0), np.minimum(ys, ps)) < _RJ_SMALL
        if not np.any(small):
            break
        sx, sy, sz, sp = np.sqrt(xs), np.sqrt(ys), np.sqrt(zs), np.sqrt(ps)
        lam = sx * sy + sx * sz + sy * sz
        ax, ay, az = sp + sx, sp + sy, sp + sz
        one_plus_e = 2.0 * (sp / ax) * ((ps + lam) / (ay * az))
        term = 6.0 / ax / ay / az * elliprc(1.0, one_plus_e)
        total = np.where(small, total + weight * term, total)
        weight = np.where(small, 2.0 * weight, weight)
        xs, ys, zs, ps = (np.where(small, a + lam, a) for a in (xs, ys, zs, ps))
    result: Floats = total + weight * elliprj(xs, ys, zs, ps)
    return result


def _rj_one(x: float, y: float, p: float) -> float:
    """:func:`_rj` for one set of floats (the same operations, so the same numbers)."""
    z, total, weight = 1.0, 0.0, 1.0
    for _ in range(3):
        if min(x if x > 0.0 else 1.0, y, p) >= _RJ_SMALL:
            break
        sx, sy, sz, sp = math.sqrt(x), math.sqrt(y), math.sqrt(z), math.sqrt(p)
        lam = sx * sy + sx * sz + sy * sz
        ax, ay, az = sp + sx, sp + sy, sp + sz
        total += weight * (6.0 / ax / ay / az * float(elliprc(1.0, 2.0 * (sp / ax) * ((p + lam) / (ay * az)))))
        weight *= 2.0
        x, y, z, p = x + lam, y + lam, z + lam, p + lam
    # scipy.special reports domain errors by value, not by warning
    return total + weight * float(elliprj(x, y, z, p))
