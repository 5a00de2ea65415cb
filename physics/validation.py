"""Checks of user input shared by the physics modules: one wording for every bad number.

Every check raises :class:`ValueError` with a message that names the argument, so a student (or the
app's notification) sees which input was wrong and why.
"""

from __future__ import annotations

import math
from typing import Any

import numpy as np
from numpy.typing import ArrayLike, NDArray

__all__ = [
    "MAX_RATE",
    "MAX_STEPS",
    "ROTATION_TOLERANCE",
    "bounded_scalar",
    "broadcast",
    "finite_array",
    "finite_result",
    "finite_phase",
    "finite_scalar",
    "rotation_array",
    "vector_array",
]

MAX_RATE = 1e100
"""Largest angular rate accepted, rad/s: far beyond any body, well inside the float range of its square."""

MAX_STEPS = 100_000_000
"""Most steps a step-by-step simulation will take (t_final / dt)."""

ROTATION_TOLERANCE = 1e-9
"""Largest ``|RᵀR − I|`` entry accepted for an attitude (rounding of a stored matrix is far below it)."""


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
    except OverflowError:  # an integer beyond the float range (e.g. 10**400)
        raise ValueError(f"{name} must be within the float range (|x| < 1.8e308), got {_short(value)}") from None
    except (TypeError, ValueError) as exc:
        raise ValueError(f"{name} must be numeric, got {_short(value)}") from exc
    if shape is not None and arr.shape != shape:
        raise ValueError(f"{name} must have shape {shape}, got shape {arr.shape}")
    if not np.all(np.isfinite(arr)):
        raise ValueError(f"{name} must be finite (no NaN or inf), got {arr.tolist()}")
    return arr


def finite_scalar(value: Any, name: str) -> float:
    """``value`` as a Python float, refusing non-numbers, NaN and inf (same messages as above)."""
    if isinstance(value, np.ndarray) and value.ndim:
        raise ValueError(f"{name} must be a single number, got an array of shape {value.shape}")
    try:
        v = float(value)
    except OverflowError:
        raise ValueError(f"{name} must be within the float range (|x| < 1.8e308), got {_short(value)}") from None
    except (TypeError, ValueError):
        raise ValueError(f"{name} must be a real number, got {_short(value)}") from None
    if not math.isfinite(v):
        raise ValueError(f"{name} must be finite (no NaN or inf), got {v}")
    return v


def bounded_scalar(value: Any, name: str, limit: float = 1e150) -> float:
    """:func:`finite_scalar` that also refuses ``|value| > limit`` (default 1e150: its square and its
    products with any other accepted number stay inside the float range)."""
    v = finite_scalar(value, name)
    if abs(v) > limit:
        raise ValueError(f"{name} must be at most {limit:g} in magnitude (its square would overflow), got {v:g}")
    return v


def finite_phase(phase: ArrayLike, name: str = "t") -> None:
    """Refuse times so large that the phase of the motion (rate × time) is no longer a finite number."""
    if not np.all(np.isfinite(phase)):
        raise ValueError(
            f"{name} is too far from 0: the phase of the motion (its rate times {name}) overflows the float range"
        )


def broadcast(**arrays: NDArray[np.float64]) -> tuple[int, ...]:
    """The common shape of ``arrays`` (keyword: argument name), or ValueError naming their shapes."""
    try:
        return tuple(np.broadcast_shapes(*(a.shape for a in arrays.values())))
    except ValueError:
        shapes = ", ".join(f"{name} {a.shape}" for name, a in arrays.items())
        raise ValueError(f"{' and '.join(arrays)} must have shapes that broadcast together, got {shapes}") from None


def finite_result(value: ArrayLike, what: str, inputs: str) -> None:
    """Refuse a result that left the float range (it overflowed, though every input was finite).

    ``what`` names the result and ``inputs`` the arguments that set its size, for the message.
    """
    if not np.all(np.isfinite(value)):
        raise ValueError(f"{what} overflows the float range (|x| > 1.8e308) for these {inputs}: scale them down")


def _short(value: object) -> str:
    text = repr(value)
    return text if len(text) <= 60 else text[:57] + "..."


def rotation_array(value: ArrayLike, name: str, *, batched: bool = True) -> NDArray[np.float64]:
    """``value`` as rotation matrices, shape (3, 3) or, when ``batched``, (n, 3, 3).

    Raises
    ------
    ValueError
        Not numeric, another shape (the message names the shapes accepted and the one given), NaN or
        inf, not orthogonal beyond :data:`ROTATION_TOLERANCE` (e.g. ``2 I``), or a reflection
        (determinant −1): an attitude maps body to space and keeps handedness.
    """
    arr = finite_array(value, name)
    if not (arr.shape == (3, 3) or (batched and arr.ndim == 3 and arr.shape[1:] == (3, 3))):
        accepted = "(3, 3) or (n, 3, 3)" if batched else "(3, 3)"
        raise ValueError(f"{name} must have shape {accepted}, got shape {arr.shape}")
    error = np.max(np.abs(np.swapaxes(arr, -1, -2) @ arr - np.eye(3)), initial=0.0)
    if error > ROTATION_TOLERANCE:
        raise ValueError(f"{name} must be a rotation matrix (orthonormal): |RᵀR − I| is {error:.3g}")
    if np.any(np.linalg.det(arr) < 0.0):
        raise ValueError(f"{name} must be a rotation (determinant +1), not a reflection (determinant −1)")
    return arr


def vector_array(value: ArrayLike, name: str, *, batched: bool = True) -> NDArray[np.float64]:
    """``value`` as 3-vectors, shape (3,) or, when ``batched``, (n, 3); ValueError names the shapes."""
    arr = finite_array(value, name)
    if not (arr.shape == (3,) or (batched and arr.ndim == 2 and arr.shape[1] == 3)):
        accepted = "(3,) or (n, 3)" if batched else "(3,)"
        raise ValueError(f"{name} must have shape {accepted}, got shape {arr.shape}")
    return arr
