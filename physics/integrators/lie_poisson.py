"""Lie–Poisson (NO_SQUISH) Strang splitting: order 2, symplectic."""

from __future__ import annotations

from physics.integrators._base import Splitting


class LiePoissonStrang(Splitting):
    """Lie–Poisson splitting of the free rotation into exact axis rotations (NO_SQUISH), Strang, order 2.

    One step: ``K(h/2) X(h/2) Y(h/2) Z(h) Y(h/2) X(h/2) K(h/2)`` where ``X`` is the exact flow of
    ``L_x²/(2 I_x)`` (a rotation about ``e_x`` by ``h L_x/I_x``) and ``K`` the torque sub-flow. Axes with a
    zero moment are skipped. Symplectic (with conservative torques), time-symmetric; conserves ``|L|``
    to round-off without torque, and ``L_z`` (space) to round-off under gravity. The energy error stays
    bounded (no drift) for a conservative torque.

    Parameters
    ----------
    moments : array_like, shape (3,)
        Principal moments about the pivot (or centre of mass), kg m², in body-axis order.
    torque : None, a torque, or a list of torques
        See the module docstring.
    compensated : bool, keyword-only
        Carry ``L_body`` in double-double through the rotations (:class:`._base.Splitting`); default False.
    """

    name = "Lie-Poisson Strang"
    order = 2
    _weights: tuple[float, ...] = (1.0,)

    def _free_ops(self, w):
        ops = [("X", 0.5 * w), ("Y", 0.5 * w), ("Z", w), ("Y", 0.5 * w), ("X", 0.5 * w)]
        # A rod's axis carries no angular momentum: its sub-flow is the identity.
        return [op for op in ops if self.moments["XYZ".index(op[0])] > 0.0]
