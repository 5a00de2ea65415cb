"""Elliptic pieces of the heavy top's closed form (Carlson forms, scipy.special).

``u = cos θ = u1 + (u2 − u1) sn²(τ | m)`` with ``τ = λ t + c``; φ and ψ are sums of elliptic integrals of
the third kind, one per pole (:class:`_PoleTerm`). Each function has an array form (vectorised over τ)
and the evaluation of one time in :mod:`physics.top_trajectory` uses the ``*_one`` forms, which compute
the same expressions on Python floats (a frame of an animation asks for one time).
"""

from __future__ import annotations

import math
from dataclasses import dataclass

import numpy as np
from numpy.typing import ArrayLike, NDArray
from scipy.special import ellipj, elliprf, elliprj

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


def _jacobi_one(r: float, m: float, one_m: float, K: float) -> tuple[float, float, float]:
    """:func:`_jacobi` for one r (floats)."""
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
    rj = float(elliprj(cn2, dn2, 1.0, p))  # scipy.special reports domain errors by value, not by warning
    return r + n / 3.0 * sn**3 * rj


def _complete_q(one_n: float, one_m: float) -> float:
    """``Q(n|m) = ∫₀^K sn²/(1 − n sn²) dτ = (Π(n|m) − K)/n = R_J(0, 1 − m, 1, 1 − n)/3`` (DLMF 19.25.2):
    no division by n, so it stays accurate as n → 0."""
    return float(elliprj(0.0, one_m, 1.0, one_n)) / 3.0


def _q_integral(k: Floats, sn: Floats, cn2: Floats, dn2: Floats, n: float, one_n: float, qc: float) -> Floats:
    """``Q(n; τ) = ∫₀^τ sn²/(1 − n sn²)`` for ``τ = 2K k + r``, given sn, cn², dn² at r:
    ``2 k Q(n|m) + sn³ R_J(cn², dn², 1, 1 − n sn²)/3`` (DLMF 19.25.14 without the factor n)."""
    p = one_n + n * cn2 if n > 0.0 else 1.0 - n * sn * sn
    with np.errstate(invalid="ignore"):
        rj = elliprj(cn2, dn2, 1.0, p)
    return 2.0 * k * qc + np.where(sn == 0.0, 0.0, sn**3 * rj / 3.0)


def _q_integral_one(k: float, sn: float, cn2: float, dn2: float, n: float, one_n: float, qc: float) -> float:
    """:func:`_q_integral` for one τ (floats)."""
    if sn == 0.0:
        return 2.0 * k * qc
    p = one_n + n * cn2 if n > 0.0 else 1.0 - n * sn * sn
    return 2.0 * k * qc + sn**3 * float(elliprj(cn2, dn2, 1.0, p)) / 3.0
