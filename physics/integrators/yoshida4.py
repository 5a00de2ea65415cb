"""Yoshida's triple jump of the Strang step: order 4."""

from __future__ import annotations

from physics.integrators.compositions import YOSHIDA4
from physics.integrators.lie_poisson import LiePoissonStrang


class Yoshida4(LiePoissonStrang):
    """Triple-jump composition of :class:`LiePoissonStrang` (Yoshida 1990): order 4, symplectic, symmetric.

    Weights ``w1 = 1/(2 − 2^{1/3})``, ``w0 = −2^{1/3} w1``; conserves what the Strang step conserves.
    """

    name = "Yoshida 4 (Strang)"
    order = 4
    _weights = YOSHIDA4
