"""Suzuki's five-stage composition of the Strang step: order 4."""

from __future__ import annotations

from physics.integrators.compositions import SUZUKI4
from physics.integrators.lie_poisson import LiePoissonStrang


class Suzuki4(LiePoissonStrang):
    """Suzuki's five-stage fourth-order composition of :class:`LiePoissonStrang` (Suzuki 1990): order 4.

    Weights ``p, p, 1 − 4p, p, p`` with ``p = 1/(4 − 4^{1/3})``; smaller error constant than
    :class:`Yoshida4` at 5/3 of its cost.
    """

    name = "Suzuki 4 (Strang)"
    order = 4
    _weights = SUZUKI4
