"""Yoshida's fifteen-stage composition of the Strang step: order 8."""

from __future__ import annotations

from physics.integrators.compositions import YOSHIDA8
from physics.integrators.lie_poisson import LiePoissonStrang


class Yoshida8(LiePoissonStrang):
    """Fifteen-stage eighth-order composition of :class:`LiePoissonStrang` (Yoshida 1990, solution D): order 8.

    Pays at errors below about 1e-9. With a torque whose sub-flow is neither a kick nor exact (a generic
    non-conservative callable) the order drops to 4.
    """

    name = "Yoshida 8 (Strang)"
    order = 8
    _weights = YOSHIDA8
