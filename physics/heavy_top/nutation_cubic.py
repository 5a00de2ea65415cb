"""The nutation cubic of the heavy top, ``f(u) = u̇²`` in ``u = cos θ``, and its roots found without
cancellation.

The roots are found in Taylor expansions of f about three points where f is known exactly from the
initial data (u0, and the poles ±1), each root at its own scale (:func:`local_roots`), and each is taken
from the expansion in which it is smallest (:func:`physics.heavy_top.motion.motion_constants` builds the
expansions). Each root is held three ways
(``u − u0``, ``1 − u``, ``1 + u``) so that the differences the closed form needs keep their digits.
"""

from __future__ import annotations

import math
from collections.abc import Sequence
from dataclasses import dataclass

import numpy as np


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


def local_roots(sign: float, d: float, c1: float, c2: float, c3: float) -> list[float]:
    """The real roots of ``sign d² + c1 x + c2 x² + c3 x³`` (as many as its degree: three, or two when
    ``c3 = 0``), ascending, each to full relative precision however different their sizes, without forming
    ``d²`` (near the vertical ``d`` is ~θ0² and its square underflows) and without overflow.

    The Newton polygon of the coefficients (the upper hull of the points ``(k, log2 |c_k|)``) gives the
    roots' sizes: an edge from k = i to j holds ``j − i`` roots of size ``2^r``, ``−r`` its slope. Edges
    whose sizes lie within a factor 2^6 form one group; each group is solved at its own scale,
    ``x = 2^r σ`` with the coefficients scaled by powers of two (exactly) so that the largest term at
    ``|σ| = 1`` is of order 1: its own terms give estimates, Newton on the whole scaled polynomial the
    digits. ``d = 0`` gives the exact root 0. A complex pair (two roots that coincide to rounding) gives its
    real part twice.
    """
    logs: dict[int, float] = {}
    if d != 0.0:
        logs[0] = 2.0 * math.log2(abs(d))
    for k, c in ((1, c1), (2, c2), (3, c3)):
        if c != 0.0:
            logs[k] = math.log2(abs(c))
    first = min(logs)
    roots = [0.0] * first  # x^first divides the polynomial: exact roots at the anchor
    # Upper convex hull of the points (k, log2 |c_k|), left to right.
    hull: list[int] = []
    for k in sorted(logs):
        while len(hull) >= 2:
            i, j = hull[-2], hull[-1]
            # j lies on or below the line from i to k: not a vertex of the upper hull.
            if (logs[j] - logs[i]) * (k - i) <= (logs[k] - logs[i]) * (j - i):
                hull.pop()
            else:
                break
        hull.append(k)
    # Edges whose root sizes lie within a factor 2^6 of each other are solved together, at one scale.
    groups: list[tuple[int, int]] = []  # (first k, last k) of each group of edges
    previous = -math.inf
    for i, j in zip(hull, hull[1:]):
        size = (logs[i] - logs[j]) / (j - i)  # log2 of the size of this edge's roots
        if groups and size - previous < 6.0:
            groups[-1] = (groups[-1][0], j)
        else:
            groups.append((i, j))
        previous = size
    md, ed = math.frexp(d)
    for first, last in groups:
        # All of this group's roots have sizes near 2^r; the terms of lower and higher degree are, at that
        # size, at least 2^6 below the group's: the group's own terms give the estimates, and Newton on the
        # whole (scaled) polynomial the digits.
        r = round((logs[first] - logs[last]) / (last - first))
        n = math.floor(max(logs[k] + k * r for k in logs))
        scaled = [
            sign * math.ldexp(md * md, 2 * ed - n) if d != 0.0 else 0.0,
            math.ldexp(c1, r - n),
            math.ldexp(c2, 2 * r - n),
            math.ldexp(c3, 3 * r - n),
        ]
        own = scaled[first : last + 1]
        if len(own) == 2:
            estimates = [-own[0] / own[1]]
        else:
            estimates = [complex(z).real for z in np.roots(own[::-1])]
        for z in estimates:
            roots.append(math.ldexp(_polish(scaled, z), r))
    return sorted(roots)


@dataclass(frozen=True)
class Root:
    """One root of f, held three ways so differences can be formed without cancellation:
    ``v = u − u0``, ``p = 1 − u``, ``q = 1 + u``."""

    v: float
    p: float
    q: float

    @property
    def u(self) -> float:
        return 1.0 - self.p if abs(self.p) < abs(self.q) else self.q - 1.0


def root_gap(hi: Root, lo: Root) -> float:
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
