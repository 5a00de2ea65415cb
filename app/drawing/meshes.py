"""Meshes and attitudes: viser's quaternion from physics' rotations, and the meshes scenes draw.

Attitudes come from ``physics/`` as rotation matrices (body to space) or scipy quaternions ``(x, y, z, w)``;
:func:`wxyz` is the one place where they become viser's ``(w, x, y, z)``.
"""

from __future__ import annotations

import math

import numpy as np
import trimesh
from numpy.typing import ArrayLike, NDArray
from scipy.spatial.transform import Rotation

__all__ = ["wxyz", "rotation_z_to", "top_mesh", "cylinder_mesh"]


def wxyz(attitude: ArrayLike) -> NDArray[np.float64]:
    """viser's ``(w, x, y, z)`` quaternion from a rotation matrix or a scipy ``(x, y, z, w)`` quaternion.

    The only conversion between the physics convention (scipy, scalar last) and viser's (scalar first).

    Parameters
    ----------
    attitude : array_like, shape (3, 3) or (4,), or batched (n, 3, 3) / (n, 4)
        Body-to-space rotation matrix, or scipy quaternion ``(x, y, z, w)``.

    Returns
    -------
    ndarray, shape (4,) or (n, 4)
        ``(w, x, y, z)``, unit norm.
    """
    a = np.asarray(attitude, dtype=float)
    if a.shape == (3, 3):
        return _wxyz_of_matrix(a)
    if a.shape[-2:] == (3, 3):
        q = Rotation.from_matrix(a.reshape(-1, 3, 3)).as_quat()
        q = q.reshape(a.shape[:-2] + (4,))
    elif a.shape[-1] == 4:
        q = a / np.linalg.norm(a, axis=-1, keepdims=True)
    else:
        raise ValueError(f"an attitude is a (3, 3) rotation matrix or an (x, y, z, w) quaternion, got shape {a.shape}")
    return np.concatenate([q[..., 3:4], q[..., :3]], axis=-1)


def _wxyz_of_matrix(r: NDArray[np.float64]) -> NDArray[np.float64]:
    """Shepperd's method for one matrix (about 20x faster than a scipy call per frame); same result as
    ``Rotation.from_matrix(r).as_quat()`` reordered, up to the sign of the quaternion."""
    (m00, m01, m02), (m10, m11, m12), (m20, m21, m22) = r.tolist()
    tr = m00 + m11 + m22
    # Divide by the largest of 4w², 4x², 4y², 4z² for accuracy.
    if tr >= m00 and tr >= m11 and tr >= m22:
        s = 2.0 * math.sqrt(max(1.0 + tr, 0.0))
        q = (0.25 * s, (m21 - m12) / s, (m02 - m20) / s, (m10 - m01) / s)
    elif m00 >= m11 and m00 >= m22:
        s = 2.0 * math.sqrt(max(1.0 + m00 - m11 - m22, 0.0))
        q = ((m21 - m12) / s, 0.25 * s, (m01 + m10) / s, (m02 + m20) / s)
    elif m11 >= m22:
        s = 2.0 * math.sqrt(max(1.0 + m11 - m00 - m22, 0.0))
        q = ((m02 - m20) / s, (m01 + m10) / s, 0.25 * s, (m12 + m21) / s)
    else:
        s = 2.0 * math.sqrt(max(1.0 + m22 - m00 - m11, 0.0))
        q = ((m10 - m01) / s, (m02 + m20) / s, (m12 + m21) / s, 0.25 * s)
    out = np.array(q)
    return out / math.sqrt(float(out @ out))


def rotation_z_to(direction: NDArray[np.float64]) -> NDArray[np.float64]:
    """The shortest rotation taking +z to the unit vector ``direction`` (a half turn about x at -z).

    Rodrigues' formula with v = z × d, c = z · d: ``R = I + hat(v) + hat(v)² / (1 + c)``.
    """
    x, y, z = direction.tolist()
    if z < -1.0 + 1e-12:
        return np.diag([1.0, -1.0, -1.0])
    k = 1.0 / (1.0 + z)
    # v = (-y, x, 0)
    return np.array(
        [
            [1.0 - x * x * k, -x * y * k, x],
            [-x * y * k, 1.0 - y * y * k, y],
            [-x, -y, z],
        ]
    )


# ---------------------------------------------------------------------------------------------------
# Meshes
# ---------------------------------------------------------------------------------------------------


def top_mesh(length: float = 1.0, radius: float = 0.3, sections: int = 48) -> trimesh.Trimesh:
    """A spinning top: a cone on its tip at the origin, a disc body and a short stem, axis +z.

    A painted stripe is not possible on one mesh colour, so the disc is made slightly faceted
    (``sections``) to let the eye see the spin.
    """
    cone_h = 0.55 * length
    cone = trimesh.creation.cone(radius=radius, height=cone_h, sections=sections)
    # trimesh's cone has its base at z = 0 and its apex at +z: flip so the apex (the tip) is at the origin.
    cone.apply_transform(np.diag([1.0, -1.0, -1.0, 1.0]))  # a half turn about x
    cone.apply_translation([0, 0, cone_h])
    disc = trimesh.creation.cylinder(radius=radius, height=0.12 * length, sections=12)
    disc.apply_translation([0, 0, cone_h + 0.06 * length])
    stem = trimesh.creation.cylinder(radius=0.05 * length, height=0.33 * length, sections=16)
    stem.apply_translation([0, 0, cone_h + 0.12 * length + 0.165 * length])
    top = trimesh.util.concatenate([cone, disc, stem])
    assert isinstance(top, trimesh.Trimesh)  # concatenating meshes gives a mesh
    return top


def cylinder_mesh(radius: float, length: float, sections: int = 40) -> trimesh.Trimesh:
    """A solid cylinder centred at the origin, axis +z, with a notch-free but faceted rim."""
    cylinder: trimesh.Trimesh = trimesh.creation.cylinder(radius=radius, height=length, sections=sections)
    return cylinder
