"""Torque kicks around the exact torque-free flow: order 2 (4, 6, 8 composed)."""

from __future__ import annotations

import math

from numpy.typing import ArrayLike

from physics.free_body import FreeBody
from physics.integrators._base import Splitting
from physics.integrators._state import ROT, from_state, right_exp, to_state
from physics.integrators.compositions import YOSHIDA4, YOSHIDA6, YOSHIDA8


class ExactFreeSplitting(Splitting):
    """Torque kicks around the exact free-body flow: ``K(h/2) Φ_free(h) K(h/2)``, order 2.

    ``Φ_free`` is the exact torque-free motion (:meth:`physics.free_body.FreeBody.flow`; for a body with
    two equal moments the lecture's closed form is evaluated inline for speed). Without torque the method
    is exact for any ``dt``. ``composition="yoshida4"`` or ``"yoshida6"`` composes the step to order 4 or 6.

    Parameters
    ----------
    moments : array_like, shape (3,)
        Principal moments, kg m².
    torque : None, a torque, or a list of torques
    composition : {"strang", "yoshida4", "yoshida6", "yoshida8"}
    """

    name = "exact free + kicks"
    order = 2

    def __init__(self, moments: ArrayLike, torque=None, composition: str = "strang") -> None:
        weights = {"strang": (1.0,), "yoshida4": YOSHIDA4, "yoshida6": YOSHIDA6, "yoshida8": YOSHIDA8}
        if composition not in weights:
            raise ValueError(f"composition must be one of {sorted(weights)}, got {composition!r}")
        self._weights = weights[composition]
        self.order = {"strang": 2, "yoshida4": 4, "yoshida6": 6, "yoshida8": 8}[composition]
        if composition != "strang":
            self.name = f"exact free + kicks, {composition}"
        super().__init__(moments, torque)
        m = self.moments
        # Symmetric body: s = the odd axis, I⊥ the common moment of the other two (sphere: s = 2).
        self.symmetric = None
        for s_ax in (2, 0, 1):
            b, c = (s_ax + 1) % 3, (s_ax + 2) % 3
            if m[b] == m[c] and m[b] > 0.0:
                self.symmetric = (s_ax, 1.0 / m[b], (1.0 / m[s_ax] if m[s_ax] > 0.0 else 1.0 / m[b]) - 1.0 / m[b])
                break
        self._free_body = None
        if self.symmetric is None:
            self._free_body = FreeBody(m)
        self.conserves = self.conserves + ("energy and L_space of the free sub-flow (exact)",)

    def _free_ops(self, w):
        return [("E", w)]

    def _exact_free(self, s, h, xp):
        if self.symmetric is not None:
            ax, inv_perp, dinv = self.symmetric
            l0, l1, l2 = s[9], s[10], s[11]
            # H = |L|²/(2 I⊥) + L_s² (1/I_s − 1/I⊥)/2: two commuting exact flows. A rod (I_s = 0) carries
            # no L_s, so its second flow is the identity.
            r9 = right_exp(s, h * inv_perp * l0, h * inv_perp * l1, h * inv_perp * l2, xp)
            s = r9 + (l0, l1, l2)
            return ROT[ax](s, h * dinv * s[9 + ax], xp)
        batched = xp is not math
        R, L = from_state(s, batched)
        assert self._free_body is not None  # set in __init__ whenever this flow is used
        R2, L2 = self._free_body.flow(R, L, h)
        if not batched:
            return to_state(R2[0], L2[0])
        return to_state(R2, L2)
