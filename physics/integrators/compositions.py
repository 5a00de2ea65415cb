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


def _palindrome(half: tuple[float, ...], middle: float) -> tuple[float, ...]:
    return half + (middle,) + tuple(reversed(half))


# Kahan & Li (1997), "Composition constants for raising the orders of unconventional schemes for ordinary
# differential equations", Math. Comp. 66, 1089-1099: method s17odr8a, order 8 from 17 symmetric stages
# (also in Hairer, Lubich & Wanner, Geometric Numerical Integration, 2nd ed., Sect. V.3.2); γ1..γ8, γ9 the middle.
KAHAN_LI_8 = _palindrome(
    (
        0.13020248308889008087881763,
        0.56116298177510838456196441,
        -0.38947496264484728640807860,
        0.15884190655515560089621075,
        -0.39590389413323757733623154,
        0.18453964097831570709183254,
        0.25837438768632204729397911,
        0.29501172360931029887096624,
    ),
    -0.60550853383003451169892108,
)
"""Weights of the 17 Strang stages of Kahan and Li's s17odr8a: order 8."""

# Sofroniou & Spaletta (2005), "Derivation of symmetric composition constants for symmetric integrators",
# Optim. Methods Softw. 20, 597-613: order 10 from 35 symmetric stages (s35odr10); γ1..γ17, γ18 the middle.
SOFRONIOU_SPALETTA_10 = _palindrome(
    (
        0.07879572252168641926390768,
        0.31309610341510852776481247,
        0.02791838323507806610952027,
        -0.22959284159390709415121340,
        0.13096206107716486317465686,
        -0.26973340565451071434460973,
        0.07497334315589143566613711,
        0.11199342399981020488957508,
        0.36613344954622675119314812,
        -0.39910563013603589787862981,
        0.10308739852747107731580277,
        0.41143087395589023782070412,
        -0.00486636058313526176219566,
        -0.39203335370863990644808194,
        0.05194250296244964703718290,
        0.05066509075992449633587434,
        0.04967437063972987905456880,
    ),
    0.04931773575959453791768001,
)
"""Weights of the 35 Strang stages of Sofroniou and Spaletta's s35odr10: order 10."""

# Blanes & Moan (2002), "Practical symplectic partitioned Runge-Kutta and Runge-Kutta-Nyström methods",
# J. Comput. Appl. Math. 142, 313-330, Table 2, method S6: the splitting e^{a1 h A} e^{b1 h B} e^{a2 h A} ...
# e^{b10 h B} e^{a11 h A} of order 6 for any A + B (a6 = 1 − 2 Σ a_i, b5 = b6 = 1/2 − Σ b_i; the paper's
# 15 digits, with which its order conditions hold to about 1e-16).
_BM6_A = (0.0502627644003922, 0.413514300428344, 0.0450798897943977, -0.188054853819569, 0.541960678450780)
_BM6_B = (0.148816447901042, -0.132385865767784, 0.067307604692185, 0.432666402578175)
BLANES_MOAN_6_A = _palindrome(_BM6_A, 1.0 - 2.0 * sum(_BM6_A))
"""The eleven coefficients ``a_i`` of Blanes and Moan's S6 (the outer flow ``A``)."""
BLANES_MOAN_6_B = _BM6_B + (0.5 - sum(_BM6_B), 0.5 - sum(_BM6_B)) + tuple(reversed(_BM6_B))
"""The ten coefficients ``b_i`` of Blanes and Moan's S6 (the inner flow ``B``)."""
