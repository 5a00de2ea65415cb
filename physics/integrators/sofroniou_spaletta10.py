"""Sofroniou and Spaletta's thirty-five-stage composition of the Strang step: order 10."""

from __future__ import annotations

from physics.integrators.compositions import SOFRONIOU_SPALETTA_10
from physics.integrators.lie_poisson import LiePoissonStrang


class SofroniouSpaletta10(LiePoissonStrang):
    """Sofroniou and Spaletta's s35odr10: thirty-five :class:`LiePoissonStrang` stages, order 10.

    Source: M. Sofroniou and G. Spaletta, "Derivation of symmetric composition constants for symmetric
    integrators", Optim. Methods Softw. 20 (2005) 597-613 (weights
    :data:`.compositions.SOFRONIOU_SPALETTA_10`, all below 0.42 in size). The cheapest of the project's
    methods at errors of 1e-8 and below on the bodies without a closed form (benchmarks/results/
    work_precision.md). Symmetric and symplectic like the Strang step; with a non-conservative torque that
    has no exact sub-flow (a generic callable) the order drops to 4.
    """

    name = "Sofroniou-Spaletta 10 (Strang)"
    order = 10
    _weights = SOFRONIOU_SPALETTA_10
