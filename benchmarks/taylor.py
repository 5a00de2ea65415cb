"""Reference solutions for the benchmark cases without a closed form: Taylor series on the whole span.

The equations of a body about a fixed point with the project's torques (docs/conventions.md, "Signs"),
in the attitude ``R`` (body to space) and the body angular momentum ``L``, ``ω = L / I``:

    Ṙ = R hat(ω),    L̇ = L × ω − w × (third row of R) − c (ω · a) a − c_air (ω1, ω2, 0)

(``w = M g c_body``: gravity at the centre of mass; spin friction ``c`` about the body axis ``a``; transverse
air drag ``c_air``). The right-hand side is a polynomial of degree two in ``(R, L)``, so its Taylor
coefficients follow from their own recurrence (Cauchy products), to any order, without differentiating
anything numerically: :func:`taylor_flow` does this in ``numpy.longdouble`` (80-bit extended precision on
x86: 18 digits, unit round-off 5.4e-20) with the step chosen from the last two coefficients (Jorba & Zou
2005). This method shares nothing with the benchmarked integrators (splittings, Runge–Kutta) or with
scipy's; :func:`mpmath_flow` runs mpmath's own Taylor integrator (``mpmath.odefun``) on the same equations
at 20 digits as an independent check.
"""

from __future__ import annotations

from dataclasses import dataclass, field

import numpy as np
from numpy.typing import ArrayLike, NDArray

LD = np.longdouble


@dataclass(frozen=True)
class Body:
    """The equations' constants: moments (kg m²), ``w = M g c_body`` (N m), spin friction ``c`` (N m s) about
    the unit body axis ``axis``, transverse air drag ``c_air`` (N m s)."""

    moments: NDArray[np.float64]
    w: NDArray[np.float64]
    friction: float = 0.0
    axis: NDArray[np.float64] = field(default_factory=lambda: np.array([0.0, 0.0, 1.0]))
    drag: float = 0.0


def taylor_flow(
    body: Body, R0: ArrayLike, L0: ArrayLike, t_end: float, order: int = 30, tol: float = 1e-21
) -> tuple[NDArray[np.longdouble], NDArray[np.longdouble], int]:
    """``(R (3,3), L (3,), steps)`` at ``t_end`` in long double, from the Taylor series of ``order``.

    Each step takes ``h = min((tol s/|y_{K−1}|)^{1/(K−1)}, (tol s/|y_K|)^{1/K})`` (``s = max(1, |L|)``), so
    the first neglected terms are about ``tol`` relative; the last step ends at ``t_end`` exactly.
    """
    K = int(order)
    inv = np.array([1.0 / m for m in body.moments], dtype=LD)
    w = np.asarray(body.w, dtype=LD)
    a = np.asarray(body.axis, dtype=LD)
    fc, dc = LD(body.friction), LD(body.drag)
    R = np.array(R0, dtype=LD)
    L = np.array(L0, dtype=LD)
    Rc = np.zeros((K + 1, 3, 3), dtype=LD)
    Lc = np.zeros((K + 1, 3), dtype=LD)
    Wc = np.zeros((K + 1, 3), dtype=LD)
    recip = LD(1) / np.arange(1, K + 1, dtype=LD)
    t, T, steps = LD(0), LD(t_end), 0
    while t < T:
        Rc[0], Lc[0] = R, L
        for k in range(K):
            Wc[k] = Lc[k] * inv
            wr = Wc[k::-1]
            # k-th coefficients of R hat(ω) and L × ω: Cauchy sums S[a, b, c] = Σ_j R_j[a, b] ω_{k−j}[c].
            S = np.einsum("jab,jc->abc", Rc[: k + 1], wr)
            P = np.einsum("ja,jb->ab", Lc[: k + 1], wr)
            u = Rc[k][2]
            dR = np.stack([S[:, 1, 2] - S[:, 2, 1], S[:, 2, 0] - S[:, 0, 2], S[:, 0, 1] - S[:, 1, 0]], axis=1)
            dL = np.array(
                [
                    P[1, 2] - P[2, 1] - (w[1] * u[2] - w[2] * u[1]),
                    P[2, 0] - P[0, 2] - (w[2] * u[0] - w[0] * u[2]),
                    P[0, 1] - P[1, 0] - (w[0] * u[1] - w[1] * u[0]),
                ],
                dtype=LD,
            )
            dL -= fc * (Wc[k] @ a) * a
            dL[:2] -= dc * Wc[k][:2]
            Rc[k + 1] = dR * recip[k]
            Lc[k + 1] = dL * recip[k]
        scale = max(LD(1), np.max(np.abs(L)))
        n1 = max(np.max(np.abs(Rc[K - 1])), np.max(np.abs(Lc[K - 1])) / scale)
        n2 = max(np.max(np.abs(Rc[K])), np.max(np.abs(Lc[K])) / scale)
        h = min((LD(tol) / n1) ** (LD(1) / (K - 1)), (LD(tol) / n2) ** (LD(1) / K), T - t)
        R, L = Rc[K].copy(), Lc[K].copy()
        for k in range(K - 1, -1, -1):  # Horner
            R = R * h + Rc[k]
            L = L * h + Lc[k]
        t += h
        steps += 1
    return R, L, steps


def mpmath_flow(body: Body, R0: ArrayLike, L0: ArrayLike, t_end: float, dps: int = 20):
    """``(R (3,3), L (3,))`` at ``t_end`` from ``mpmath.odefun`` (its Taylor method) at ``dps`` digits, rounded
    to float64. Slow (about a second of CPU per radian-second of motion at 20 digits)."""
    import mpmath

    with mpmath.workdps(dps):
        mpf = mpmath.mpf
        inv = [1 / mpf(float(m)) for m in body.moments]
        w = [mpf(float(x)) for x in body.w]
        a = [mpf(float(x)) for x in body.axis]
        fc, dc = mpf(float(body.friction)), mpf(float(body.drag))

        def rhs(t, y):
            o = [y[9 + i] * inv[i] for i in range(3)]
            out = []
            for r in range(3):
                r0, r1, r2 = y[3 * r : 3 * r + 3]
                out += [r1 * o[2] - r2 * o[1], r2 * o[0] - r0 * o[2], r0 * o[1] - r1 * o[0]]
            l0, l1, l2 = y[9:]
            u0, u1, u2 = y[6:9]
            wa = fc * (o[0] * a[0] + o[1] * a[1] + o[2] * a[2])
            out += [
                l1 * o[2] - l2 * o[1] - (w[1] * u2 - w[2] * u1) - wa * a[0] - dc * o[0],
                l2 * o[0] - l0 * o[2] - (w[2] * u0 - w[0] * u2) - wa * a[1] - dc * o[1],
                l0 * o[1] - l1 * o[0] - (w[0] * u1 - w[1] * u0) - wa * a[2],
            ]
            return out

        y0 = [mpf(float(x)) for x in np.concatenate([np.ravel(R0), np.ravel(L0)])]
        y = mpmath.odefun(rhs, 0, y0)(mpf(float(t_end)))
        out = np.array([float(v) for v in y])
    return out[:9].reshape(3, 3), out[9:]
