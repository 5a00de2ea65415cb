"""Checks of user input shared by the physics modules: one wording for every bad number.

Every check raises :class:`ValueError` with a message that names the argument, so a student (or the
app's notification) sees which input was wrong and why.
"""

from __future__ import annotations

import math

import numpy as np
from numpy.typing import ArrayLike, NDArray

__all__ = ["finite_array", "finite_scalar"]


def finite_array(value: ArrayLike, name: str, shape: tuple[int, ...] | None = None) -> NDArray[np.float64]:
    """``value`` as a float64 array, refusing non-numbers, a wrong shape, NaN and inf.

    Parameters
    ----------
    value : array_like
    name : str
        The argument's name, used in the message.
    shape : tuple of int, optional
        Required shape, e.g. ``(3,)``.

    Raises
    ------
    ValueError
        "<name> must be numeric", "<name> must have shape ...", "<name> must be finite ...".
    """
    try:
        arr = np.asarray(value, dtype=float)
    except (TypeError, ValueError) as exc:
        raise ValueError(f"{name} must be numeric, got {value!r}") from exc
    if shape is not None and arr.shape != shape:
        raise ValueError(f"{name} must have shape {shape}, got shape {arr.shape}")
    if not np.all(np.isfinite(arr)):
        raise ValueError(f"{name} must be finite (no NaN or inf), got {arr.tolist()}")
    return arr


def finite_scalar(value: float, name: str) -> float:
    """``value`` as a Python float, refusing non-numbers, NaN and inf (same messages as above)."""
    try:
        v = float(value)
    except (TypeError, ValueError):
        raise ValueError(f"{name} must be a real number, got {value!r}") from None
    if not math.isfinite(v):
        raise ValueError(f"{name} must be finite (no NaN or inf), got {v}")
    return v
