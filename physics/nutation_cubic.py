"""The nutation cubic of the heavy top, ``f(u) = u̇²`` in ``u = cos θ``, and its roots found without
cancellation.

The roots are found from Taylor expansions of f about three points where f is known exactly from the
initial data (u0, and the poles ±1), then polished by Newton in the nearest expansion
(:func:`physics.top_motion.motion_constants` builds the expansions). Each root is held three ways
(``u − u0``, ``1 − u``, ``1 + u``) so that the differences the closed form needs keep their digits.
"""

from __future__ import annotations

import math
from collections.abc import Sequence
from dataclasses import dataclass


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
