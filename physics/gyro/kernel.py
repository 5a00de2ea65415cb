"""Euler's equations with a linear air drag on each principal axis, stepped by a compiled classical RK4
(numba): the fit's inner loop, evaluated hundreds of times per toss.

``I_i ω̇_i = (I_j − I_k) ω_j ω_k − c_i ω_i`` (cyclic i, j, k; c_i ≥ 0). The stepping is at most
:data:`MAX_STEP` s, which keeps the error below 1e-6 of |ω| for the rates a phone's gyroscope measures
(|ω| ≤ 35 rad/s: ``h |ω| ≤ 0.07``, RK4's global error ~ (h |ω|)⁴); tests/physics/test_gyro_model.py checks it
against the exact free solution and the project's splitting integrators.
"""

from __future__ import annotations

import math
from typing import Any

import numpy as np
from numba import njit
from numpy.typing import NDArray

Floats = NDArray[np.float64]

MAX_STEP = 0.002
"""s: the largest RK4 step."""

__all__ = ["MAX_STEP", "drag_omega"]


@njit(cache=True)
def _rates(w0: float, w1: float, w2: float, inv: Any, d: Any, ab: Any) -> tuple[float, float, float]:
    return (
        (ab[0] * w1 * w2 - d[0] * w0) * inv[0],
        (ab[1] * w2 * w0 - d[1] * w1) * inv[1],
        (ab[2] * w0 * w1 - d[2] * w2) * inv[2],
    )


@njit(cache=True)
def _run(moments: Any, drag: Any, w: Any, t: Any, max_step: float, out: Any) -> None:
    inv = 1.0 / moments
    ab = np.array([moments[1] - moments[2], moments[2] - moments[0], moments[0] - moments[1]])
    w0, w1, w2 = w[0], w[1], w[2]
    now = 0.0
    for k in range(t.shape[0]):
        span = t[k] - now
        n = int(math.ceil(abs(span) / max_step)) if span != 0.0 else 0
        if n > 0:
            h = span / n
            for _ in range(n):
                k1 = _rates(w0, w1, w2, inv, drag, ab)
                k2 = _rates(w0 + 0.5 * h * k1[0], w1 + 0.5 * h * k1[1], w2 + 0.5 * h * k1[2], inv, drag, ab)
                k3 = _rates(w0 + 0.5 * h * k2[0], w1 + 0.5 * h * k2[1], w2 + 0.5 * h * k2[2], inv, drag, ab)
                k4 = _rates(w0 + h * k3[0], w1 + h * k3[1], w2 + h * k3[2], inv, drag, ab)
                w0 += h / 6.0 * (k1[0] + 2.0 * k2[0] + 2.0 * k3[0] + k4[0])
                w1 += h / 6.0 * (k1[1] + 2.0 * k2[1] + 2.0 * k3[1] + k4[1])
                w2 += h / 6.0 * (k1[2] + 2.0 * k2[2] + 2.0 * k3[2] + k4[2])
        now = t[k]
        out[k, 0], out[k, 1], out[k, 2] = w0, w1, w2


def drag_omega(moments: Floats, drag: Floats, omega0: Floats, t: Floats, max_step: float = MAX_STEP) -> Floats:
    """ω (n, 3) in principal axes with linear drag, from ``ω(0) = omega0``.

    Parameters
    ----------
    moments : ndarray (3,)
        Principal moments (any positive scale), kg m².
    drag : ndarray (3,)
        ``c_i`` ≥ 0 on the same scale as the moments per second (N m s when the moments are in kg m²).
    omega0 : ndarray (3,)
        ω at t = 0, rad/s.
    t : ndarray (n,)
        Times, s, increasing from 0 or decreasing from 0 (stepped in that order).
    max_step : float
        Largest step, s.
    """
    out = np.empty((t.shape[0], 3))
    _run(
        np.ascontiguousarray(moments, dtype=float),
        np.ascontiguousarray(drag, dtype=float),
        np.ascontiguousarray(omega0, dtype=float),
        np.ascontiguousarray(t, dtype=float),
        float(max_step),
        out,
    )
    return out
