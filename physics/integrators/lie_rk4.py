"""Runge–Kutta–Munthe-Kaas with the classical tableau: order 4 on SO(3), not symplectic."""

from __future__ import annotations

from collections.abc import Callable
from typing import Any

from numpy.typing import ArrayLike

from physics.integrators._base import Method
from physics.integrators._state import right_exp
from physics.integrators.torques import GenericTorque, GravityTorque, SpinFriction


class LieRK4(Method):
    """Runge–Kutta–Munthe-Kaas with the classical RK4 tableau: order 4, not symplectic.

    ``L`` is advanced by classical RK4; the attitude by ``R ← R exp(hat u)`` with ``u`` the RK4
    combination of ``u̇ = dexp⁻¹_{−u}(ω) ≈ ω + ½ u × ω + (1/12) u × (u × ω)`` at the stages (the right
    trivialisation of ``Ṙ = R hat(ω)``; the series to this term is enough for order 4).
    ``R`` stays orthonormal to round-off; ``|L|`` and the energy drift at the order of the method.
    """

    name = "Lie RK4 (RKMK)"
    order = 4
    symplectic = False
    conserves: tuple[str, ...] = ("orthonormality of R",)
    max_rate_step = 2.8
    """Largest ``|ω|·|dt|`` accepted (``|ω| = sqrt(2E/I_min)``, the fastest rate of the torque-free motion):
    just inside 2√2, where classical RK4's stability region meets the imaginary axis. Beyond it the iteration
    grows without bound (``L = (50, 100, 150)``, moments (2, 1.5, 1), ``dt = 0.1`` reached NaN), so
    :func:`integrate` and :func:`advance` refuse such a step up front."""

    def _rhs(self, s, xp):
        i0, i1, i2 = self.inverse_moments
        l0, l1, l2 = s[9], s[10], s[11]
        w0, w1, w2 = i0 * l0, i1 * l1, i2 * l2
        d0, d1, d2 = l1 * w2 - l2 * w1, l2 * w0 - l0 * w2, l0 * w1 - l1 * w0
        if self.torques:
            t0, t1, t2 = self._torque_value(s, xp)
            d0, d1, d2 = d0 + t0, d1 + t1, d2 + t2
        return (w0, w1, w2), (d0, d1, d2)

    def _torque_value(self, s, xp):
        t0 = t1 = t2 = 0.0
        for t in self._fast:
            a, b, c = t(s, xp)
            t0, t1, t2 = t0 + a, t1 + b, t2 + c
        return t0, t1, t2

    def __init__(self, moments: ArrayLike, torque=None) -> None:
        super().__init__(moments, torque)
        self._fast: list[Callable[..., Any]] = []
        for t in self.torques:
            if isinstance(t, GravityTorque):
                w0, w1, w2 = t.weight_moment
                self._fast.append(
                    lambda s, xp, w0=w0, w1=w1, w2=w2: (
                        -(w1 * s[8] - w2 * s[7]),
                        -(w2 * s[6] - w0 * s[8]),
                        -(w0 * s[7] - w1 * s[6]),
                    )
                )
            elif isinstance(t, SpinFriction):
                a0, a1, a2 = t.axis_body
                i0, i1, i2 = t.inverse_moments
                c = t.coefficient

                def fr(s, xp, a0=a0, a1=a1, a2=a2, i0=i0, i1=i1, i2=i2, c=c):
                    wa = c * (a0 * i0 * s[9] + a1 * i1 * s[10] + a2 * i2 * s[11])
                    return -wa * a0, -wa * a1, -wa * a2

                self._fast.append(fr)
            else:
                self._fast.append(lambda s, xp, g=GenericTorque(t, None): g._tau(s, xp))  # noqa: B008 - one per torque, bound at definition
        self._needs_attitude = any(not isinstance(t, SpinFriction) for t in self.torques)

    def step_state(self, s, dt, xp):
        h = dt
        l0, l1, l2 = s[9], s[10], s[11]
        r = s[:9]

        def dexpinv(u, w):
            u0, u1, u2 = u
            w0, w1, w2 = w
            c0, c1, c2 = u1 * w2 - u2 * w1, u2 * w0 - u0 * w2, u0 * w1 - u1 * w0
            d0, d1, d2 = u1 * c2 - u2 * c1, u2 * c0 - u0 * c2, u0 * c1 - u1 * c0
            return (w0 + 0.5 * c0 + d0 / 12.0, w1 + 0.5 * c1 + d1 / 12.0, w2 + 0.5 * c2 + d2 / 12.0)

        k1, m1 = self._rhs(s, xp)
        u = (0.5 * h * k1[0], 0.5 * h * k1[1], 0.5 * h * k1[2])
        lb = (l0 + 0.5 * h * m1[0], l1 + 0.5 * h * m1[1], l2 + 0.5 * h * m1[2])
        st = (right_exp(s, *u, xp) if self._needs_attitude else r) + lb
        w, m2 = self._rhs(st, xp)
        k2 = dexpinv(u, w)
        u = (0.5 * h * k2[0], 0.5 * h * k2[1], 0.5 * h * k2[2])
        lb = (l0 + 0.5 * h * m2[0], l1 + 0.5 * h * m2[1], l2 + 0.5 * h * m2[2])
        st = (right_exp(s, *u, xp) if self._needs_attitude else r) + lb
        w, m3 = self._rhs(st, xp)
        k3 = dexpinv(u, w)
        u = (h * k3[0], h * k3[1], h * k3[2])
        lb = (l0 + h * m3[0], l1 + h * m3[1], l2 + h * m3[2])
        st = (right_exp(s, *u, xp) if self._needs_attitude else r) + lb
        w, m4 = self._rhs(st, xp)
        k4 = dexpinv(u, w)
        h6 = h / 6.0
        u = tuple(h6 * (k1[i] + 2.0 * k2[i] + 2.0 * k3[i] + k4[i]) for i in range(3))
        lnew = tuple(s[9 + i] + h6 * (m1[i] + 2.0 * m2[i] + 2.0 * m3[i] + m4[i]) for i in range(3))
        out = right_exp(s, *u, xp) + lnew
        return self.project(out) if self._zero_axes else out
