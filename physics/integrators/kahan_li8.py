"""Kahan and Li's seventeen-stage composition of the Strang step: order 8."""

from __future__ import annotations

from physics.integrators.compositions import KAHAN_LI_8
from physics.integrators.lie_poisson import LiePoissonStrang


class KahanLi8(LiePoissonStrang):
    """Kahan and Li's s17odr8a: seventeen :class:`LiePoissonStrang` stages, order 8.

    Source: W. Kahan and R.-C. Li, Math. Comp. 66 (1997) 1089-1099 (weights :data:`.compositions.KAHAN_LI_8`).
    Its weights are all below 0.61 in size (Yoshida 8's reach 1.96), so its error constant is far smaller:
    at the same step its error is 1/5000 to 1/9000 of :class:`Yoshida8`'s (benchmarks/cases.py, free_generic,
    asym_top_slow, body_air_drag), so a given error takes about a third of the steps. Symmetric and
    symplectic like the Strang step; with a non-conservative torque that has no exact sub-flow (a generic
    callable) the order drops to 4.
    """

    name = "Kahan-Li 8 (Strang)"
    order = 8
    _weights = KAHAN_LI_8
