"""The columns of an export's CSV: named quantities with their units, from a scene's state.

A scene's :meth:`app.scenes.Scene.columns` composes these; the header of each column is its symbol and
its SI unit in brackets (``theta (rad)``, ``L_x (kg m^2/s)``), the order is the dict's order.
"""

from __future__ import annotations

import math
from typing import Any

import numpy as np

__all__ = ["euler_columns", "vector_columns"]


def euler_columns(R: Any) -> dict[str, float]:
    """The z-x-z Euler angles of an attitude ``R = Rz(φ) Rx(θ) Rz(ψ)`` (shape (3, 3), body to space), rad.

    φ and ψ are in (−π, π] (undefined when θ = 0 or π, where only φ + ψ is: ψ is then 0); θ in [0, π].
    The convention of :func:`physics.euler_angles.euler_attitude`.
    """
    R = np.asarray(R, dtype=float)
    sin_theta = math.hypot(R[0, 2], R[1, 2])
    theta = math.atan2(sin_theta, R[2, 2])
    if sin_theta < 1e-12:
        phi, psi = math.atan2(R[1, 0], R[0, 0]), 0.0  # R = Rz(φ ± ψ) Rx(θ): all the turn in φ
    else:
        phi, psi = math.atan2(R[0, 2], -R[1, 2]), math.atan2(R[2, 0], R[2, 1])
    return {"phi (rad)": phi, "theta (rad)": theta, "psi (rad)": psi}


def vector_columns(symbol: str, vector: Any, unit: str, suffixes: str = "xyz") -> dict[str, float]:
    """One column per component: ``{symbol}_{x|y|z} ({unit})`` (or the given suffixes, e.g. "123")."""
    return {f"{symbol}_{s} ({unit})": float(v) for s, v in zip(suffixes, np.asarray(vector, dtype=float), strict=True)}
