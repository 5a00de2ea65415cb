"""Double-double arithmetic (Dekker 1971; Knuth, TAOCP vol. 2, 4.2.2): error-free transformations that
carry a sum or a product as (high part, low part), vectorised over numpy arrays or on floats.

Used where a physical quantity is the small difference of large ones that the float inputs define
exactly: L² − 2 E I2 near the free body's separatrix, 4 M g ℓ I1 − L3² at the top's sleeping threshold.
"""

from __future__ import annotations

from typing import Any

DD = tuple[Any, Any]
"""A double-double number: (high part, low part), arrays or scalars."""

# ---------------------------------------------------------------------------------------------------
_SPLIT = 134217729.0  # 2**27 + 1


def two_sum(a: Any, b: Any) -> DD:
    s = a + b
    bb = s - a
    return s, (a - (s - bb)) + (b - bb)


def _split(a: Any) -> DD:
    c = _SPLIT * a
    hi = c - (c - a)
    return hi, a - hi


def two_prod(a: Any, b: Any) -> DD:
    p = a * b
    ah, al = _split(a)
    bh, bl = _split(b)
    return p, ((ah * bh - p) + ah * bl + al * bh) + al * bl


def dd_mul(x: DD, y: DD) -> DD:
    p, e = two_prod(x[0], y[0])
    e = e + (x[0] * y[1] + x[1] * y[0])
    s = p + e
    return s, e - (s - p)


def dd_add(x: DD, y: DD) -> DD:
    s, e = two_sum(x[0], y[0])
    e = e + (x[1] + y[1])
    t = s + e
    return t, e - (t - s)


def dd_term(moment: Any, diff: DD, w: Any) -> DD:
    """``moment · diff · w²`` in double-double; ``diff`` is a double-double."""
    return dd_mul(dd_mul((moment, 0.0 * moment), diff), two_prod(w, w))
