"""Rotations: the hat map, the SO(3) exponential, and thin helpers over scipy.

Conventions (docs/conventions.md): an attitude ``R`` maps body to space, ``x_space = R @ x_body``,
and ``Ṙ = R hat(ω_body)``. Quaternions follow :class:`scipy.spatial.transform.Rotation`
(``x, y, z, w``, scalar last).
"""

from __future__ import annotations

import numpy as np
from numpy.typing import ArrayLike, NDArray
from scipy.spatial.transform import Rotation

from physics.validation import broadcast, finite_array

__all__ = [
    "angle_between",
    "hat",
    "vee",
    "expm_so3",
    "rotation_about",
    "rotation_angle",
    "orthonormality_error",
    "as_quaternion",
    "from_quaternion",
    "frame_from_axis",
]


def _vectors(v: ArrayLike, name: str) -> NDArray[np.float64]:
    """``v`` as finite 3-vectors, shape (..., 3); ValueError names ``name`` otherwise."""
    arr = finite_array(v, name)
    if arr.ndim == 0 or arr.shape[-1] != 3:
        raise ValueError(f"{name} must have shape (3,) or (n, 3), got shape {arr.shape}")
    return arr


def _matrices(r: ArrayLike, name: str) -> NDArray[np.float64]:
    """``r`` as finite 3×3 matrices, shape (..., 3, 3); ValueError names ``name`` otherwise."""
    arr = finite_array(r, name)
    if arr.ndim < 2 or arr.shape[-2:] != (3, 3):
        raise ValueError(f"{name} must have shape (3, 3) or (n, 3, 3), got shape {arr.shape}")
    return arr


def _unit_axis(axis: ArrayLike) -> NDArray[np.float64]:
    """``axis`` as a unit vector (scaled first, so a tiny or huge axis neither underflows nor overflows)."""
    a = finite_array(axis, "axis", (3,))
    largest = float(np.max(np.abs(a)))
    if largest == 0.0:
        raise ValueError(f"axis must be a nonzero vector, got {a.tolist()}")
    u = a / largest
    return u / np.linalg.norm(u)


def hat(v: ArrayLike) -> NDArray[np.float64]:
    """Skew-symmetric matrix of a vector: ``hat(v) @ x == cross(v, x)``.

    Parameters
    ----------
    v : array_like, shape (3,) or (n, 3)

    Returns
    -------
    ndarray, shape (3, 3) or (n, 3, 3)
    """
    return _hat(_vectors(v, "v"))


def _hat(v: NDArray[np.float64]) -> NDArray[np.float64]:
    """:func:`hat` without the checks (for callers that have made them)."""
    out = np.zeros(v.shape[:-1] + (3, 3))
    out[..., 0, 1] = -v[..., 2]
    out[..., 0, 2] = v[..., 1]
    out[..., 1, 0] = v[..., 2]
    out[..., 1, 2] = -v[..., 0]
    out[..., 2, 0] = -v[..., 1]
    out[..., 2, 1] = v[..., 0]
    return out


def vee(m: ArrayLike) -> NDArray[np.float64]:
    """Inverse of :func:`hat` (of the skew part): shape (..., 3, 3) -> (..., 3)."""
    m = np.asarray(m, dtype=float)
    return 0.5 * np.stack(
        [m[..., 2, 1] - m[..., 1, 2], m[..., 0, 2] - m[..., 2, 0], m[..., 1, 0] - m[..., 0, 1]],
        axis=-1,
    )


def expm_so3(v: ArrayLike) -> NDArray[np.float64]:
    """The SO(3) exponential ``exp(hat(v))`` by Rodrigues' formula.

    Below an angle of 1e-4 rad the coefficients ``sin(a)/a`` and ``(1-cos a)/a²`` are taken from
    their Taylor series, so small rotations keep full relative precision.

    Parameters
    ----------
    v : array_like, shape (3,) or (n, 3)
        Rotation vectors (axis times angle, rad).

    Returns
    -------
    ndarray, shape (3, 3) or (n, 3, 3)
    """
    return expm_so3_unchecked(_vectors(v, "v"))


def expm_so3_unchecked(v: NDArray[np.float64]) -> NDArray[np.float64]:
    """:func:`expm_so3` without the checks (for callers that have made them: a frame's hot path)."""
    a2 = np.einsum("...i,...i->...", v, v)
    a = np.sqrt(a2)
    small = a < 1e-4
    safe = np.where(small, 1.0, a)
    s = np.where(small, 1.0 - a2 / 6.0 + a2 * a2 / 120.0, np.sin(safe) / safe)
    c = np.where(small, 0.5 - a2 / 24.0 + a2 * a2 / 720.0, (1.0 - np.cos(safe)) / (safe * safe))
    k = _hat(v)
    eye = np.broadcast_to(np.eye(3), k.shape)
    out: NDArray[np.float64] = eye + s[..., None, None] * k + c[..., None, None] * (k @ k)
    return out


def rotation_about(axis: ArrayLike, angle: ArrayLike) -> NDArray[np.float64]:
    """Rotation matrices by ``angle`` (rad) about the unit ``axis``.

    Parameters
    ----------
    axis : array_like, shape (3,)
    angle : array_like, shape () or (n,)

    Returns
    -------
    ndarray, shape (3, 3) or (n, 3, 3)
    """
    axis = _unit_axis(axis)
    angle = finite_array(angle, "angle")
    return expm_so3_unchecked(angle[..., None] * axis)


def rotation_angle(r_a: ArrayLike, r_b: ArrayLike) -> NDArray[np.float64]:
    """Angle (rad) of the relative rotation ``r_a.T @ r_b``, accurate for tiny angles.

    Uses ``2 asin(|R_a - R_b|_F / sqrt(8))``, which has no cancellation near zero, unlike
    ``acos((tr - 1)/2)``.

    Parameters
    ----------
    r_a, r_b : array_like, shape (3, 3) or (n, 3, 3)

    Returns
    -------
    ndarray, shape () or (n,)
    """
    a, b = _matrices(r_a, "r_a"), _matrices(r_b, "r_b")
    broadcast(r_a=a, r_b=b)
    d = a - b
    f = np.sqrt(np.einsum("...ij,...ij->...", d, d))
    out: NDArray[np.float64] = 2.0 * np.arcsin(np.clip(f / np.sqrt(8.0), 0.0, 1.0))
    return out


def orthonormality_error(r: ArrayLike) -> NDArray[np.float64]:
    """Max-abs entry of ``R.T @ R - I``: shape (..., 3, 3) -> (...)."""
    r = np.asarray(r, dtype=float)
    e = np.swapaxes(r, -1, -2) @ r - np.eye(3)
    out: NDArray[np.float64] = np.max(np.abs(e), axis=(-1, -2))
    return out


def as_quaternion(r: ArrayLike) -> NDArray[np.float64]:
    """Rotation matrices (..., 3, 3) to scipy quaternions (..., 4), ``x, y, z, w``."""
    r = np.asarray(r, dtype=float)
    q = Rotation.from_matrix(r.reshape(-1, 3, 3)).as_quat()
    out: NDArray[np.float64] = q.reshape(r.shape[:-2] + (4,))
    return out


def from_quaternion(q: ArrayLike) -> NDArray[np.float64]:
    """Scipy quaternions (..., 4), ``x, y, z, w``, to rotation matrices (..., 3, 3)."""
    q = np.asarray(q, dtype=float)
    r = Rotation.from_quat(q.reshape(-1, 4)).as_matrix()
    out: NDArray[np.float64] = r.reshape(q.shape[:-1] + (3, 3))
    return out


def frame_from_axis(axis: ArrayLike) -> NDArray[np.float64]:
    """A right-handed orthonormal frame whose third column is the unit ``axis``.

    The first column is the coordinate axis least aligned with ``axis``, made orthogonal to it, so
    the frame is continuous except where that choice switches.

    Parameters
    ----------
    axis : array_like, shape (3,)

    Returns
    -------
    ndarray, shape (3, 3)
    """
    e3 = _unit_axis(axis)
    trial = np.eye(3)[int(np.argmin(np.abs(e3)))]
    e1 = trial - e3 * (trial @ e3)
    e1 /= np.linalg.norm(e1)
    e2 = np.cross(e3, e1)
    return np.column_stack([e1, e2, e3])


def angle_between(a: ArrayLike, b: ArrayLike) -> NDArray[np.float64] | float:
    """The angle between two vectors, rad in ``[0, π]``: ``atan2(|a × b|, a · b)``.

    Accurate at every angle (``arccos`` of the normalised dot product loses it near 0 and π: at 1e-12 rad
    its cosine rounds to 1). Each vector is first scaled by its largest component's power of two (exactly),
    so neither overflows nor underflows; the error is a few ulps of π, absolute (about 1e-15 rad).

    Parameters
    ----------
    a, b : array_like, shape (3,) or (n, 3)
        The vectors (L, ω, the symmetry axis, the vertical: any units, each its own); broadcast together.

    Returns
    -------
    float, or ndarray (n,)
        The angle, rad; ``nan`` where either vector is zero (no direction: a body at rest has no ω to
        measure from, which is not an error of the caller).

    Raises
    ------
    ValueError
        Not numeric, NaN or inf, not 3-vectors, or shapes that do not broadcast.
    """
    va, vb = _vectors(a, "a"), _vectors(b, "b")
    broadcast(a=va[..., 0], b=vb[..., 0])
    with np.errstate(divide="ignore", invalid="ignore"):
        sa = np.ldexp(va, -np.frexp(np.max(np.abs(va), axis=-1, keepdims=True))[1])
        sb = np.ldexp(vb, -np.frexp(np.max(np.abs(vb), axis=-1, keepdims=True))[1])
        cross = np.linalg.norm(np.cross(sa, sb), axis=-1)
        dot = np.sum(sa * sb, axis=-1)
        angle = np.arctan2(cross, dot)
    zero = ~np.any(va != 0.0, axis=-1) | ~np.any(vb != 0.0, axis=-1)
    angle = np.where(zero, np.nan, angle)
    if angle.ndim == 0:
        return float(angle)
    out: NDArray[np.float64] = angle
    return out
