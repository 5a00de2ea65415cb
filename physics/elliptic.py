"""Jacobi elliptic functions and the elliptic integrals of the closed-form motions (free body, heavy top,
pendulum), accurate up to and near the separatrix ``m → 1``.

Every function takes the parameter ``m`` together with its complement ``1 − m`` (``mc``, ``one_m``,
``m1``), which the models compute without cancellation; array forms are vectorised over the argument,
``*_one`` forms compute the same expressions on Python floats (a frame asks for one time).
docs/physics-notes.md explains the algorithms and the accuracy measured.
"""

from __future__ import annotations

import math
from functools import lru_cache
from typing import Any

import numpy as np
from numpy.typing import ArrayLike, NDArray
from scipy.special import ellipj, ellipkm1, elliprc, elliprf, elliprj

from physics.validation import finite_array, finite_scalar

Floats = NDArray[np.float64]
Ladder = tuple[list[Floats], Floats]
"""The descending Landen ladder: the ``√μ`` of each step, and the total argument scale."""

_EPS = np.finfo(float).eps

__all__ = [
    "MC_NEAR_ONE",
    "NEAR_SEPARATRIX",
    "RJ_SMALL",
    "Ladder",
    "carlson_rj",
    "carlson_rj_one",
    "complete_q",
    "complete_third_kind",
    "incomplete_first_kind",
    "incomplete_first_kind_one",
    "incomplete_third_kind",
    "incomplete_third_kind_one",
    "jacobi_amplitude",
    "jacobi_amplitude_one",
    "jacobi_half_period",
    "jacobi_half_period_one",
    "jacobi_sn_cn_dn",
    "ladder_of",
    "landen_ladder",
    "q_integral",
    "q_integral_one",
    "reduce_half_period",
    "reduced_jacobi",
    "reduced_jacobi_one",
]


# ---------------------------------------------------------------------------------------------------
# Jacobi sn, cn, dn from m and its complement mc = 1 − m (the free body's reduction to [−K, K]).
# ---------------------------------------------------------------------------------------------------
def landen_ladder(m: Floats, mc: Floats) -> Ladder:
    """Descending Landen ladder: the ``√μ`` of each step and the total argument scale.

    Each step maps ``(m, mc)`` to ``μ = ((1 − √mc)/(1 + √mc))²`` (A&S 16.12) computed as
    ``√μ = m / (1 + √mc)²`` and ``1 − μ = 4 √mc / (1 + √mc)²``, without cancellation; it stops when every
    ``μ`` is below 1e-17, where ``sn = sin`` to double precision.
    """
    roots: list[Floats] = []
    scale = np.ones_like(m)
    while np.any(m > 1e-17) and len(roots) < 40:
        r = np.sqrt(mc)
        one_r2 = (1.0 + r) ** 2
        q = m / one_r2
        roots.append(q)
        scale = scale * (1.0 + q)
        m, mc = q * q, 4.0 * r / one_r2
    return roots, scale


# Below this 1 − m the ascending Landen pass loses cn's relative accuracy (its dn cancels) and, below
# about 1e-130, underflows; the first-order expansion about m = 1 is exact to rounding there (below).
MC_NEAR_ONE = 1e-15


def _sn_cn_dn_near_one(w: Floats, mc: Floats) -> tuple[Floats, Floats, Floats]:
    """``sn, cn, dn`` for ``0 ≤ w ≤ K/2`` and ``1 − m = mc ≤ 1e-15`` (A&S 16.15.1-3).

    ``sn = tanh w + (mc/4)(sinh w cosh w − w) sech²w``, ``cn = sech w − (mc/4)(sinh w cosh w − w) tanh w
    sech w``, ``dn = sech w + (mc/4)(sinh w cosh w + w) tanh w sech w``. The neglected terms are of
    relative order ``(mc e^{2w})²``, and ``e^{2w} ≤ e^K ≈ 4/√mc`` for ``w ≤ K/2``, so they are below
    ``16 mc ≤ 2e-14`` relative to the first-order term and below rounding in the result: every value keeps
    its full relative precision however small ``mc`` is (down to the smallest double), with no underflow
    (``sech w ≥ sech(K/2) ≈ (√mc/4)^{1/2}``).
    """
    # For mc > 0, w ≤ K/2 < 373 (K < 745 down to the smallest 1 − m, see _LOG_KP_DEEP); the cap only keeps the
    # separatrix's own (mc = 0, w unbounded) entries finite until reduced_jacobi replaces them with tanh
    # and sech. mc · sinh · cosh is taken as (mc sinh) cosh: sinh · cosh alone overflows above w ≈ 355.
    w = np.clip(w, 0.0, 700.0)
    ch = np.cosh(w)
    sh = np.sinh(w)
    th = np.tanh(w)
    se = 1.0 / ch
    quarter = 0.25 * mc
    shch = (quarter * sh) * ch
    s = th + (shch - quarter * w) * se * se
    c = se * (1.0 - (shch - quarter * w) * th)
    d = se * (1.0 + (shch + quarter * w) * th)
    return s, c, d


def _sn_cn_dn_small(w: Floats, m: Floats, mc: Floats, ladder: Ladder) -> tuple[Floats, Floats, Floats]:
    """``sn, cn, dn`` for ``0 ≤ w ≤ K/2``: the ascending pass of the Landen ladder, or the expansion
    about ``m = 1`` where ``1 − m ≤ 1e-15``."""
    near_one = mc <= MC_NEAR_ONE
    if np.all(near_one):
        return _sn_cn_dn_near_one(w, mc)
    s, c, d = _sn_cn_dn_landen(w, m, mc, ladder)
    if np.any(near_one):
        with np.errstate(all="ignore"):
            s1, c1, d1 = _sn_cn_dn_near_one(np.where(near_one, w, 0.0), mc)
        s, c, d = np.where(near_one, s1, s), np.where(near_one, c1, c), np.where(near_one, d1, d)
    return s, c, d


def _sn_cn_dn_landen(w: Floats, m: Floats, mc: Floats, ladder: Ladder) -> tuple[Floats, Floats, Floats]:
    """``sn, cn, dn`` for ``0 ≤ w ≤ K/2`` by the ascending pass of the Landen ladder."""
    roots, scale = ladder
    v = w / scale
    s, c = np.sin(v), np.cos(v)
    d = np.ones_like(v)
    # Walk back up: each level keeps the relative accuracy of s, c and d (products and quotients only).
    for q in reversed(roots):
        den = 1.0 + q * s * s
        s, c, d = (1.0 + q) * s / den, c * d / den, (1.0 - q * s * s) / den
    # dn from cn without cancellation (the ladder's own dn formula cancels near m = 1).
    d = np.sqrt(mc + m * c * c)
    return s, c, d


def reduced_jacobi(
    u: Floats, m: Floats, mc: Floats, kk: Any, ladder: Ladder, kp: Any = None
) -> tuple[Floats, Floats, Floats, Floats, Floats]:
    """Jacobi functions of ``u`` reduced to ``v = u − 2 K j`` in ``[−K, K]``.

    Returns ``(j, v, sn(v), cn(v), dn(v))``; ``sn(u) = (−1)^j sn(v)``, ``cn(u) = (−1)^j cn(v)``,
    ``dn(u) = dn(v)``. On the separatrix (``K = ∞``) ``j = 0`` and tanh/sech are used. ``kp`` is the
    complementary modulus ``√(1 − m)`` (default ``√mc``); pass it when ``mc`` underflows (below 1e-308 it
    is 0 while ``kp`` is not, and only ``K`` then says that the motion is not on the separatrix).
    """
    sep = ~np.isfinite(kk)
    kfin = np.where(sep, 1.0, kk)
    j = np.where(sep, 0.0, np.rint(u / (2.0 * kfin)))
    v = u - 2.0 * kfin * j
    a = np.abs(v)
    flip = a > 0.5 * kfin
    w = np.where(flip, kfin - a, a)
    s, c, d = _sn_cn_dn_small(w, m, mc, ladder)
    # Quarter-period shift sn(K − w) = cd w, cn(K − w) = √mc sd w, dn(K − w) = √mc nd w keeps cn's
    # relative accuracy near its zero.
    r = np.sqrt(mc) if kp is None else kp
    s, c, d = np.where(flip, c / d, s), np.where(flip, r * (s / d), c), np.where(flip, r / d, d)
    if np.any(sep):
        th, sh = np.tanh(a), 1.0 / np.cosh(np.minimum(a, 710.0))
        s, c, d = np.where(sep, th, s), np.where(sep, sh, c), np.where(sep, sh, d)
    s = np.copysign(s, v)
    return j, v, s, c, d


def jacobi_sn_cn_dn(u: ArrayLike, m: float, mc: float | None = None) -> tuple[Floats, Floats, Floats]:
    """Jacobi elliptic functions ``sn, cn, dn (u | m)`` accurate up to and on ``m = 1``.

    Parameters
    ----------
    u : array_like, shape (n,)
        Arguments (any size: reduced modulo the period ``4K`` first).
    m : float
        Parameter, ``0 ≤ m ≤ 1``.
    mc : float, optional
        Complementary parameter ``1 − m``; pass it when it is known more accurately than ``1 − m``
        (near ``m = 1``). Default ``1 − m``.

    Returns
    -------
    sn, cn, dn : ndarray, shape (n,)
    """
    uu = finite_array(u, "u")
    mm = np.asarray(finite_scalar(m, "m"))
    mmc = np.asarray(1.0 - float(mm) if mc is None else finite_scalar(mc, "mc"))
    if not (0.0 <= mm <= 1.0 and 0.0 <= mmc <= 1.0):
        raise ValueError(f"the elliptic parameter must lie in [0, 1], got m = {float(mm)}, 1 - m = {float(mmc)}")
    kk = ellipkm1(mmc) if mmc > 0 else np.inf
    j, _, s, c, d = reduced_jacobi(uu, mm, mmc, kk, landen_ladder(mm, mmc))
    sign = 1.0 - 2.0 * np.mod(j, 2.0)
    return sign * s, sign * c, d


def reduced_jacobi_one(
    u: float, m: float, mc: float, kk: float, roots: list[float], scale: float, kp: float
) -> tuple[float, ...]:
    """:func:`physics.free_body.reduced_jacobi` for one phase: ``(j, v, sn v, cn v, dn v)``."""
    if kk == math.inf:  # the separatrix: K = ∞, tanh and sech
        a = abs(u)
        th, sh = math.tanh(a), 1.0 / math.cosh(min(a, 710.0))
        return 0.0, u, math.copysign(th, u), sh, sh
    j = float(round(u / (2.0 * kk)))
    v = u - 2.0 * kk * j
    a = abs(v)
    flip = a > 0.5 * kk
    w = kk - a if flip else a
    if mc <= MC_NEAR_ONE:  # first order about m = 1 (see _sn_cn_dn_near_one)
        w = min(max(w, 0.0), 700.0)
        ch, sh, th = math.cosh(w), math.sinh(w), math.tanh(w)
        se = 1.0 / ch
        quarter = 0.25 * mc
        shch = (quarter * sh) * ch
        s = th + (shch - quarter * w) * se * se
        c = se * (1.0 - (shch - quarter * w) * th)
        d = se * (1.0 + (shch + quarter * w) * th)
    else:  # the ascending pass of the Landen ladder
        x = w / scale
        s, c, d = math.sin(x), math.cos(x), 1.0
        for q in reversed(roots):
            den = 1.0 + q * s * s
            s, c, d = (1.0 + q) * s / den, c * d / den, (1.0 - q * s * s) / den
        d = math.sqrt(mc + m * c * c)
    if flip:
        s, c, d = c / d, kp * (s / d), kp / d
    return j, v, math.copysign(s, v), c, d


def incomplete_first_kind_one(sn2: float, cn2: float, m: float, one_m: float) -> float:
    """F(φ | m) with sin²φ = sn2, cos²φ = cn2 and 1 − m given separately (so φ near π/2 keeps its digits,
    and so does 1 − m sin²φ = cos²φ + (1 − m) sin²φ near the separatrix, where the float 1 − m of m
    rounding to 1 would have none)."""
    return float(math.sqrt(sn2) * elliprf(cn2, cn2 + one_m * sn2, 1.0))


def complete_third_kind(n: float, one_n: float, m: float, one_m: float, K: float) -> float:
    """Π(n | m) = K(m) + (n/3) R_J(0, 1 − m, 1, 1 − n) (DLMF 19.25.2)."""
    return float(K + n / 3.0 * carlson_rj_one(0.0, one_m, one_n))


def incomplete_third_kind(r: Floats, sn: Floats, cn2: Floats, dn2: Floats, n: float, one_n: float) -> Floats:
    """∫₀^r dτ/(1 − n sn²τ) for |r| ≤ K: ``r + (n/3) sn³ R_J(cn², dn², 1, 1 − n sn²)`` (DLMF 19.25.14,
    with s R_F(c², d², 1) = F(am r) = r)."""
    p = one_n + n * cn2 if n > 0.0 else 1.0 - n * sn * sn  # 1 − n sn², both forms free of cancellation
    with np.errstate(invalid="ignore"):
        rj = carlson_rj(cn2, dn2, p)
    term = np.where(sn == 0.0, 0.0, n / 3.0 * sn**3 * rj)
    return r + term


def jacobi_half_period(r: Floats, m: float, one_m: float, K: float) -> tuple[Floats, Floats, Floats]:
    """sn, cn, dn of r in [−K, K) with cn keeping its relative digits near r = ±K (the top turning
    point, where 1 − u ∝ cn² may be all that separates the axis from the pole): there
    ``sn(K − x) = cd x``, ``cn(K − x) = sqrt(1 − m) sd x``, ``dn(K − x) = sqrt(1 − m) nd x``.

    Near the separatrix (``1 − m < 1e-4``: a top started near the vertical below the sleeping threshold)
    scipy's ``ellipj``, which sees only the float m, loses ``eps/(1 − m)`` of relative accuracy in cn and
    dn (2.5e-10 at 1 − m = 7e-16); there the free body's Landen ladder driven by m and 1 − m (and its
    expansion about m = 1 below 1 − m = 1e-15) keeps every digit (:func:`jacobi_half_period_one`)."""
    r = np.asarray(r, dtype=float)
    if one_m < NEAR_SEPARATRIX:
        # Element by element on floats (1.3 µs each): one time and many get the same numbers, which numpy's
        # own sin, cosh, ... (SIMD kernels on some CPUs) would not guarantee.
        values = np.array([jacobi_half_period_one(x, m, one_m, K) for x in r.tolist()]).reshape(-1, 3)
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


NEAR_SEPARATRIX = 1e-4
"""Below this 1 − m the Jacobi functions come from m and 1 − m (measured: scipy's ``ellipj`` is within
3e-15 relative down to 1 − m = 1e-4, 4e-14 at 1e-6, 5e-13 at 1e-8)."""


@lru_cache(maxsize=64)
def ladder_of(m: float, one_m: float) -> tuple[list[float], float]:
    """The descending Landen ladder of (m, 1 − m) as floats: ``√μ`` of each step and the argument scale."""
    roots, scale = landen_ladder(np.array(min(m, 1.0)), np.array(one_m))
    return [float(q) for q in roots], float(scale)


def reduce_half_period(tau: Floats, K: float) -> tuple[Floats, Floats]:
    """``τ = 2K k + r`` with r in [−K, K): sn² has period 2K. The half-open interval puts τ = K (the
    top turning point) at r = −K, on the side the pole-jump count already counts as passed."""
    k = np.floor((tau + K) / (2.0 * K))
    return k, tau - 2.0 * K * k


def jacobi_half_period_one(r: float, m: float, one_m: float, K: float) -> tuple[float, float, float]:
    """:func:`jacobi_half_period` for one r (floats)."""
    if one_m < NEAR_SEPARATRIX:  # the free body's Landen ladder on floats (its ladder computed once)
        roots, scale = ladder_of(m, one_m)
        j, _, sn, cn, dn = reduced_jacobi_one(r, min(m, 1.0), one_m, K, roots, scale, math.sqrt(one_m))
        # It reduces r by 2K j (j = ±1 when rounding has put r a hair beyond ±K): sn, cn change sign.
        return (-sn, -cn, dn) if j % 2.0 else (sn, cn, dn)
    if abs(r) > 0.5 * K:
        sx, cx, dx, _ = ellipj(K - abs(r), m)
        k1 = math.sqrt(one_m)
        sign = 1.0 if r > 0.0 else -1.0
        return float(sign * cx / dx), float(k1 * sx / dx), float(k1 / dx)
    sn, cn, dn, _ = ellipj(r, m)
    return float(sn), float(cn), float(dn)


def incomplete_third_kind_one(r: float, sn: float, cn2: float, dn2: float, n: float, one_n: float) -> float:
    """:func:`incomplete_third_kind` for one r (floats)."""
    if sn == 0.0:
        return r
    p = one_n + n * cn2 if n > 0.0 else 1.0 - n * sn * sn
    rj = carlson_rj_one(cn2, dn2, p)
    return r + n / 3.0 * sn**3 * rj


def complete_q(one_n: float, one_m: float) -> float:
    """``Q(n|m) = ∫₀^K sn²/(1 − n sn²) dτ = (Π(n|m) − K)/n = R_J(0, 1 − m, 1, 1 − n)/3`` (DLMF 19.25.2):
    no division by n, so it stays accurate as n → 0."""
    return carlson_rj_one(0.0, one_m, one_n) / 3.0


def q_integral(k: Floats, sn: Floats, cn2: Floats, dn2: Floats, n: float, one_n: float, qc: float) -> Floats:
    """``Q(n; τ) = ∫₀^τ sn²/(1 − n sn²)`` for ``τ = 2K k + r``, given sn, cn², dn² at r:
    ``2 k Q(n|m) + sn³ R_J(cn², dn², 1, 1 − n sn²)/3`` (DLMF 19.25.14 without the factor n)."""
    p = one_n + n * cn2 if n > 0.0 else 1.0 - n * sn * sn
    with np.errstate(invalid="ignore"):
        rj = carlson_rj(cn2, dn2, p)
    return 2.0 * k * qc + np.where(sn == 0.0, 0.0, sn**3 * rj / 3.0)


def q_integral_one(k: float, sn: float, cn2: float, dn2: float, n: float, one_n: float, qc: float) -> float:
    """:func:`q_integral` for one τ (floats)."""
    if sn == 0.0:
        return 2.0 * k * qc
    p = one_n + n * cn2 if n > 0.0 else 1.0 - n * sn * sn
    return 2.0 * k * qc + sn**3 * carlson_rj_one(cn2, dn2, p) / 3.0


RJ_SMALL = 1e-100
"""Below this an argument of scipy's ``elliprj`` (other than x = 0) is lifted first (see :func:`carlson_rj`)."""


def carlson_rj(x: ArrayLike, y: ArrayLike, p: ArrayLike) -> Floats:
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
        small = np.minimum(np.where(xs > 0.0, xs, 1.0), np.minimum(ys, ps)) < RJ_SMALL
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


def carlson_rj_one(x: float, y: float, p: float) -> float:
    """:func:`carlson_rj` for one set of floats (the same operations, so the same numbers)."""
    z, total, weight = 1.0, 0.0, 1.0
    for _ in range(3):
        if min(x if x > 0.0 else 1.0, y, p) >= RJ_SMALL:
            break
        sx, sy, sz, sp = math.sqrt(x), math.sqrt(y), math.sqrt(z), math.sqrt(p)
        lam = sx * sy + sx * sz + sy * sz
        ax, ay, az = sp + sx, sp + sy, sp + sz
        total += weight * (6.0 / ax / ay / az * float(elliprc(1.0, 2.0 * (sp / ax) * ((p + lam) / (ay * az)))))
        weight *= 2.0
        x, y, z, p = x + lam, y + lam, z + lam, p + lam
    # scipy.special reports domain errors by value, not by warning
    return total + weight * float(elliprj(x, y, z, p))


def jacobi_amplitude(u: NDArray[np.float64], m: NDArray[np.float64], m1: NDArray[np.float64]) -> NDArray[np.float64]:
    """Jacobi amplitude ``am(u | m)`` by the arithmetic-geometric mean, given ``m`` and ``m1 = 1 − m``.

    Abramowitz & Stegun 16.4 (descending Landen), with two changes for accuracy near ``m = 1``:
    ``b0 = sqrt(m1)`` from the separately known complement, and ``c_{n+1} = c_n² / (4 a_{n+1})`` with
    the back-substitution ``asin(r sin φ)`` written as ``atan2(r sin φ, sqrt(cos²φ + (b/a)² sin²φ))``
    (``1 − r² = b²/a²``), so nothing cancels. Needs ``0 <= m <= 1``, ``m1 > 0``; keep ``|u| <= 2 K``.
    """
    a = np.ones_like(u)
    b = np.sqrt(m1)
    c = np.sqrt(m)
    ratios: list[tuple[NDArray[np.float64], NDArray[np.float64]]] = []
    for _ in range(64):  # quadratic convergence: ~12 steps even for m1 ~ 1e-300
        if np.all(c <= _EPS * a):
            break
        a_next = 0.5 * (a + b)
        b = np.sqrt(a * b)
        c = c * c / (4.0 * a_next)
        a = a_next
        ratios.append((c / a, b / a))
    phi = np.ldexp(a * u, len(ratios))
    for r, q in reversed(ratios):
        s, co = np.sin(phi), np.cos(phi)
        phi = 0.5 * (phi + np.arctan2(r * s, np.sqrt(co * co + (q * s) ** 2)))
    return phi


def jacobi_amplitude_one(u: float, m: float, m1: float) -> float:
    """:func:`jacobi_amplitude` for one u (Python floats, same steps)."""
    a, b, c = 1.0, math.sqrt(m1), math.sqrt(m)
    ratios: list[tuple[float, float]] = []
    for _ in range(64):
        if c <= _EPS * a:
            break
        a_next = 0.5 * (a + b)
        b = math.sqrt(a * b)
        c = c * c / (4.0 * a_next)
        a = a_next
        ratios.append((c / a, b / a))
    phi = math.ldexp(a * u, len(ratios))
    for r, q in reversed(ratios):
        s, co = math.sin(phi), math.cos(phi)
        phi = 0.5 * (phi + math.atan2(r * s, math.sqrt(co * co + (q * s) ** 2)))
    return phi


def incomplete_first_kind(
    sin_phi: NDArray[np.float64], cos_phi: NDArray[np.float64], m1: NDArray[np.float64]
) -> NDArray[np.float64]:
    """``F(φ | m)`` for ``|φ| <= π/2`` as ``sin φ R_F(cos²φ, cos²φ + m1 sin²φ, 1)`` (Carlson)."""
    c2 = cos_phi * cos_phi
    out: NDArray[np.float64] = sin_phi * elliprf(c2, c2 + m1 * sin_phi * sin_phi, 1.0)
    return out
