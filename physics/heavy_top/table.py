"""A top standing on its tip on a table (the plane z = 0 through the tip): the tilt at which its body first
touches the table, and the contact rule that lays it there at rest.

The tip is at the origin and the body's axis ê₃ = R[:, 2] makes the angle θ with +z (docs/conventions.md).
The table is a one-sided constraint the stepped top (:func:`physics.heavy_top.friction_stepper`) does not
know: after each step the rule below puts the body back on the table and stops it, a perfectly inelastic,
rough contact (no bounce, no rolling on the rim).
"""

from __future__ import annotations

import math

import numpy as np
from numpy.typing import ArrayLike, NDArray
from scipy.spatial.transform import Rotation

__all__ = ["on_the_table", "touch_angle"]

ON_AXIS = 1e-9
"""m: a vertex within this distance of the axis is on it (the tip itself), always on the table."""


def touch_angle(vertices: ArrayLike) -> float:
    """The tilt θ, rad, at which a body standing on its tip at the origin first touches the table z = 0.

    A point at height z on the axis and distance ρ from it reaches the table when ρ sin θ = z cos θ, i.e. at
    θ = atan2(z, ρ); the body touches at the smallest such angle over its points (a convex body's vertices
    suffice, and any body's, to the mesh's resolution).

    Parameters
    ----------
    vertices : array_like (n, 3)
        Points of the body in its own frame (axis +z, tip at the origin), m; e.g. ``trimesh.Trimesh.vertices``.

    Raises
    ------
    ValueError
        If the array is not (n, 3), not finite, or has no point off the axis.
    """
    v = np.asarray(vertices, dtype=float)
    if v.ndim != 2 or v.shape[1] != 3:
        raise ValueError(f"vertices must have shape (n, 3), got {v.shape}")
    if not np.all(np.isfinite(v)):
        raise ValueError("vertices must be finite")
    rho, z = np.hypot(v[:, 0], v[:, 1]), v[:, 2]
    away = rho > ON_AXIS  # the tip itself, on the axis, is always on the table
    if not np.any(away):
        raise ValueError("vertices must include a point off the axis (a body on the axis never touches the table)")
    return float(np.min(np.arctan2(z[away], rho[away])))


def on_the_table(
    R: NDArray[np.float64], L_body: NDArray[np.float64], landed: bool, touch: float
) -> tuple[NDArray[np.float64], NDArray[np.float64], bool]:
    """The contact rule of a top on a table: once its rim reaches the table (θ ≥ ``touch``) it lies there at
    rest, its axis turned back up to θ = ``touch`` about the horizontal line through the tip.

    Parameters
    ----------
    R : ndarray (3, 3)
        Body-to-space rotation after a free step.
    L_body : ndarray (3,)
        Body angular momentum about the tip after that step, kg m²/s.
    landed : bool
        Whether the top already lies on the table (it stays there: nothing lifts it).
    touch : float
        The tilt at which the body touches the table, rad (:func:`touch_angle`).

    Returns
    -------
    R : ndarray (3, 3)
        The attitude, unchanged while the top is off the table, else with θ = ``touch`` (φ kept).
    L_body : ndarray (3,)
        Unchanged off the table, zero on it, kg m²/s.
    landed : bool
        True once the top lies on the table.
    """
    axis = R[:, 2]
    theta = math.atan2(math.hypot(axis[0], axis[1]), axis[2])
    if theta < touch and not landed:
        return R, L_body, False
    if theta > touch:
        n = np.cross([0.0, 0.0, 1.0], axis)
        n /= np.linalg.norm(n)
        R = Rotation.from_rotvec(-(theta - touch) * n).as_matrix() @ R
    return R, np.zeros(3), True
