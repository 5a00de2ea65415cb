"""Weights of the symmetric compositions of a second-order step (Yoshida 1990; Suzuki 1990)."""

from __future__ import annotations

_CBRT2 = 2.0 ** (1.0 / 3.0)
YOSHIDA4 = (1.0 / (2.0 - _CBRT2), -_CBRT2 / (2.0 - _CBRT2), 1.0 / (2.0 - _CBRT2))
_P_SUZUKI = 1.0 / (4.0 - 4.0 ** (1.0 / 3.0))
SUZUKI4 = (_P_SUZUKI, _P_SUZUKI, 1.0 - 4.0 * _P_SUZUKI, _P_SUZUKI, _P_SUZUKI)
# Yoshida (1990) sixth order, "solution A": w1, w2, w3 and w0 = 1 − 2 (w1 + w2 + w3).
_W6 = (-1.17767998417887, 0.235573213359357, 0.784513610477560)
_W6_0 = 1.0 - 2.0 * sum(_W6)
YOSHIDA6 = (_W6[2], _W6[1], _W6[0], _W6_0, _W6[0], _W6[1], _W6[2])
# Yoshida (1990) eighth order, "solution D" (15 stages), w1..w7 and w0 = 1 − 2 Σ w.
_W8 = (
    0.102799849391985,
    -1.96061023297549,
    1.93813913762276,
    -0.158240635368243,
    -1.44485223686048,
    0.253693336566229,
    0.914844246229740,
)
YOSHIDA8 = tuple(reversed(_W8)) + (1.0 - 2.0 * sum(_W8),) + _W8
