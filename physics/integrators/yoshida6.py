"""Yoshida's seven-stage composition of the Strang step: order 6."""

from __future__ import annotations

from physics.integrators.compositions import YOSHIDA6
from physics.integrators.lie_poisson import LiePoissonStrang


class Yoshida6(LiePoissonStrang):
    """Seven-stage sixth-order composition of :class:`LiePoissonStrang` (Yoshida 1990, solution A): order 6.

    With a non-conservative torque that has no exact sub-flow (a generic callable; not
    :class:`SpinFriction`) the order drops to 4, because that sub-flow is one RK4 step.
    """

    name = "Yoshida 6 (Strang)"
    order = 6
    _weights = YOSHIDA6
