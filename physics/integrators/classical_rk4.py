"""Classical RK4 on the twelve components: order 4, conserves nothing (the careless baseline)."""

from __future__ import annotations

from physics.integrators.lie_rk4 import LieRK4


class ClassicalRK4(LieRK4):
    """Classical Runge–Kutta of order 4 on the twelve components of ``(R, L_body)``: not geometric.

    ``Ṙ = R hat(ω)`` is integrated as any linear ODE in the nine entries of ``R``, so ``R`` leaves the
    rotations (``|RᵀR − I|`` grows like the error, order 4 per unit time) and the energy and ``|L|``
    drift: the careless integrator that the app's "Compare with integrator" shows beside the exact
    solution. Its state is not projected back onto SO(3) (use :func:`advance` to step it; :func:`integrate`
    accepts only rotations as a start).
    """

    name = "classical RK4"
    order = 4
    symplectic = False
    conserves: tuple[str, ...] = ()

    def _rates(self, s, xp):
        (w0, w1, w2), dl = self._rhs(s, xp)
        # (R hat(ω)) row i = r_i × ω.
        dr = []
        for i in (0, 3, 6):
            a, b, c = s[i], s[i + 1], s[i + 2]
            dr += [b * w2 - c * w1, c * w0 - a * w2, a * w1 - b * w0]
        return tuple(dr) + dl

    def step_state(self, s, dt, xp):
        h = dt
        k1 = self._rates(s, xp)
        k2 = self._rates(tuple(x + 0.5 * h * k for x, k in zip(s, k1)), xp)
        k3 = self._rates(tuple(x + 0.5 * h * k for x, k in zip(s, k2)), xp)
        k4 = self._rates(tuple(x + h * k for x, k in zip(s, k3)), xp)
        h6 = h / 6.0
        out = tuple(x + h6 * (a + 2.0 * b + 2.0 * c + d) for x, a, b, c, d in zip(s, k1, k2, k3, k4))
        return self.project(out) if self._zero_axes else out
