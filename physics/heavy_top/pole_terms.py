"""The pole terms of the heavy top's φ and ψ: each an elliptic integral of the third kind in closed form.

``u = cos θ = u1 + (u2 − u1) sn²(τ | m)`` with ``τ = λ t + c``; φ and ψ are sums of elliptic integrals of
the third kind, one per pole (:class:`PoleTerm`), with an array form (vectorised over τ) and a form for one
time on Python floats (:meth:`PoleTerm.integral_one`; a frame of an animation asks for one time).
"""

from __future__ import annotations

import math
from dataclasses import dataclass

import numpy as np
from numpy.typing import ArrayLike, NDArray

from physics.elliptic import (
    incomplete_third_kind,
    incomplete_third_kind_one,
    jacobi_half_period,
    jacobi_half_period_one,
    reduce_half_period,
)

Floats = NDArray[np.float64]


@dataclass(frozen=True)
class PoleTerm:
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
            k, r = reduce_half_period(x, K)
            sn, cn, dn = jacobi_half_period(r, m, one_m, K)
            cn2, dn2 = cn * cn, dn * dn
        else:
            k, r, sn, cn2, dn2 = jac
        return self.a0 * x + self.a1 * (2.0 * k * self.pic + incomplete_third_kind(r, sn, cn2, dn2, self.n, self.one_n))

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
            sn, cn, dn = jacobi_half_period_one(r, m, one_m, K)
            cn2, dn2 = cn * cn, dn * dn
        return self.a0 * x + self.a1 * (
            2.0 * k * self.pic + incomplete_third_kind_one(r, sn, cn2, dn2, self.n, self.one_n)
        )
