"""Blanes and Moan's optimised sixth-order splitting S6, applied to the Lie–Poisson sub-flows: order 6."""

from __future__ import annotations

from physics.integrators.compositions import BLANES_MOAN_6_A, BLANES_MOAN_6_B
from physics.integrators.lie_poisson import LiePoissonStrang


def adjoint_pair_fractions(a: tuple[float, ...], b: tuple[float, ...]) -> tuple[list[float], list[float]]:
    """The fractions ``(α, β)`` of ``Ψ = φ(α_s) ∘ φ*(β_s) ∘ … ∘ φ(α_1) ∘ φ*(β_1)`` equal to the splitting
    ``A(a_1) B(b_1) A(a_2) … B(b_s) A(a_{s+1})`` (in time order) when ``φ`` is the Lie–Trotter step
    ``B`` then ``A`` (so ``φ*`` is ``A`` then ``B``): ``a_1 = β_1``, ``b_i = β_i + α_i``,
    ``a_{i+1} = α_i + β_{i+1}``, ``a_{s+1} = α_s`` (McLachlan 1995; Hairer, Lubich & Wanner, Sect. III.5).

    Raises ValueError when the coefficients do not close (``a_{s+1} ≠ α_s``: not a consistent splitting).
    """
    alpha: list[float] = []
    beta = [a[0]]
    for i, b_i in enumerate(b):
        alpha.append(b_i - beta[i])
        if i + 1 < len(b):
            beta.append(a[i + 1] - alpha[i])
    if len(a) != len(b) + 1 or abs(alpha[-1] - a[-1]) > 1e-14:
        raise ValueError(f"the splitting coefficients a {a} and b {b} do not close: α_s = {alpha[-1]!r} ≠ a_(s+1)")
    return alpha, beta


class BlanesMoan6(LiePoissonStrang):
    """Blanes and Moan's S6 on the Lie–Poisson splitting: order 6, ten stages, symmetric and symplectic.

    Source: S. Blanes and P. C. Moan, "Practical symplectic partitioned Runge–Kutta and Runge–Kutta–Nyström
    methods", J. Comput. Appl. Math. 142 (2002) 313-330, Table 2, method S6: the splitting
    ``A(a_1) B(b_1) … B(b_10) A(a_11)`` of order 6 for any two flows (coefficients
    :data:`.compositions.BLANES_MOAN_6_A`, ``_B``), optimised for a small error constant. Written as
    ``φ(α_10) φ*(β_10) … φ(α_1) φ*(β_1)`` (:func:`adjoint_pair_fractions`) it is a composition of any
    first-order step ``φ`` and its adjoint ``φ*`` of order 6 (the order conditions are the same; McLachlan
    1995), here ``φ`` = torque ``K`` (dissipation then kick), ``X``, ``Y``, ``Z`` and ``φ*`` the reverse.
    The stages then read ``K X Y Z Y X K`` like the Strang step's and cost the same. At the same step its
    error is 1/36 (free body) to 1/200 (asymmetric heavy top) of :class:`Yoshida6`'s, at the same work
    (0.7 times the steps) 1/4 to 1/24 (benchmarks/cases.py, free_generic, asym_top_slow, body_air_drag).
    With a non-conservative torque that has no exact sub-flow (a generic callable) the order drops to 4.
    """

    name = "Blanes-Moan 6 (PRK)"
    order = 6

    def _build_program(self) -> list:
        alpha, beta = adjoint_pair_fractions(BLANES_MOAN_6_A, BLANES_MOAN_6_B)
        axes = [axis for axis in "XYZ" if self.moments["XYZ".index(axis)] > 0.0]  # a rod's axis: identity
        torque = bool(self.torques)
        ops: list = []
        for a_i, b_i in zip(alpha, beta):
            ops += ([("T0", b_i)] if torque else []) + [(axis, b_i) for axis in axes]  # φ*(β): K, X, Y, Z
            ops += [(axis, a_i) for axis in reversed(axes)] + ([("T1", a_i)] if torque else [])  # φ(α)
        merged: list = []
        for kind, frac in ops:
            if merged and kind in "XYZ" and merged[-1][0] == kind:
                merged[-1] = (kind, merged[-1][1] + frac)
            elif merged and kind == "T0" and merged[-1][0] == "T1" and not self._others:
                merged[-1] = ("T0", merged[-1][1] + frac)  # kicks commute: one kick between two stages
            else:
                merged.append((kind, frac))
        return [op for op in merged if op[1] != 0.0]
