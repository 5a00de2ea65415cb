"""Mass properties: inertia tensors, principal axes and the parallel-axis theorem.

The inertia tensor (lecture, "the inertia tensor of the body")

    I^{ab} = Σ_i m_i (r_i² δ^{ab} − r_i^a r_i^b)      or      ∫ d³r ρ(r) (r² δ^{ab} − r^a r^b)

is kept about the centre of mass; :meth:`MassProperties.tensor_about` moves it to any point by the
parallel-axis theorem ``I(a) = I_CM + M (a² δ − a aᵀ)``, with ``a`` measured from the centre of mass.

All quantities are SI: kg, m, kg m².

Examples
--------
>>> from physics.inertia import solid_cylinder
>>> body = solid_cylinder(mass=2.0, radius=0.1, length=0.5)
>>> moments, axes = body.principal()        # I1 >= I2 >= I3
>>> body.tensor_about([0.0, 0.0, 0.25])     # about the centre of one end face
"""

from __future__ import annotations

import math
from dataclasses import dataclass, field
from typing import TYPE_CHECKING

import numpy as np
from numpy.typing import ArrayLike, NDArray

from physics.validation import finite_array, finite_result, finite_scalar

if TYPE_CHECKING:  # trimesh is imported where a mesh is read, not for every import of physics
    import trimesh

__all__ = [
    "MassProperties",
    "validate_moments",
    "parallel_axis",
    "rod",
    "solid_sphere",
    "solid_cylinder",
    "box",
    "point_masses",
    "from_mesh",
]

TRIANGLE_RTOL = 1e-12
"""Relative slack allowed in the triangle inequality ``I_i <= I_j + I_k`` (round-off of sums)."""

DEGENERACY_RTOL = 1e-10
"""Moments closer than this (relative to the largest) are treated as equal by :meth:`principal`."""


def _positive(value: float, name: str) -> float:
    v = float(finite_array(value, name, ()))
    if v <= 0.0:
        raise ValueError(f"{name} must be positive, got {v}")
    return v


def _nonnegative(value: float, name: str) -> float:
    v = float(finite_array(value, name, ()))
    if v < 0.0:
        raise ValueError(f"{name} must not be negative, got {v}")
    return v


def validate_moments(moments: ArrayLike, *, allow_zero: bool = False) -> NDArray[np.float64]:
    """Check that three principal moments can belong to a rigid body.

    A rigid body's moments are finite, non-negative and satisfy the triangle inequality
    ``I_i <= I_j + I_k`` (since ``I_1 + I_2 - I_3 = 2 Σ m z² >= 0``). Equality is a flat lamina; a rod
    has one moment zero and is a legitimate, degenerate case. A slack of
    :data:`TRIANGLE_RTOL` relative to the largest moment absorbs round-off.

    Parameters
    ----------
    moments : array_like, shape (3,)
        Principal moments, kg m², in any order.
    allow_zero : bool
        Accept all three moments zero (a single point mass: it has mass properties but cannot
        rotate). Dynamics refuse it; :class:`MassProperties` accepts it.

    Returns
    -------
    ndarray, shape (3,)
        The moments as float64, in the order given.

    Raises
    ------
    ValueError
        If a moment is not finite or negative, all are zero, or the triangle inequality fails:
        "no rigid body has these moments: ...".
    """
    m = finite_array(moments, "moments of inertia", (3,))
    if np.any(m < 0.0):
        raise ValueError(f"moments of inertia must not be negative, got {m.tolist()}")
    scale = float(np.max(m))
    if scale == 0.0:
        if allow_zero:
            return m
        raise ValueError("moments of inertia are all zero: a point has no rotational inertia")
    for i in range(3):
        j, k = (i + 1) % 3, (i + 2) % 3
        if m[i] > m[j] + m[k] + TRIANGLE_RTOL * scale:
            raise ValueError(
                f"no rigid body has these moments: {m.tolist()} — each moment must be at most the sum of "
                f"the other two, but I{i + 1} = {m[i]:.6g} > I{j + 1} + I{k + 1} = {m[j] + m[k]:.6g} "
                "(equality is a flat plate)"
            )
    return m


def parallel_axis(mass: float, offset: ArrayLike) -> NDArray[np.float64]:
    """The point-mass term ``M (a² δ − a aᵀ)`` of the parallel-axis theorem.

    Parameters
    ----------
    mass : float
        Total mass, kg.
    offset : array_like, shape (3,)
        Vector ``a`` from the centre of mass to the new reference point, m.

    Returns
    -------
    ndarray, shape (3, 3)
        kg m²; add it to the tensor about the centre of mass.
    """
    m = finite_scalar(mass, "mass")
    a = finite_array(offset, "offset", (3,))
    with np.errstate(over="ignore", invalid="ignore"):  # an overflow is refused by name just below
        out: NDArray[np.float64] = m * ((a @ a) * np.eye(3) - np.outer(a, a))
    finite_result(out, "the parallel-axis term", "values of mass and offset")
    return out


def _unit(vector: ArrayLike, name: str) -> NDArray[np.float64]:
    v = finite_array(vector, name, (3,))
    n = np.linalg.norm(v)
    if n == 0.0:
        raise ValueError(f"{name} must be a non-zero vector")
    return v / n


def _canonical_sign(v: NDArray[np.float64]) -> NDArray[np.float64]:
    # Largest-magnitude component positive, so repeated calls give the same axes.
    return v if v[np.argmax(np.abs(v))] >= 0 else -v


def _eigenspace_basis(eigvecs: NDArray[np.float64], dim: int) -> NDArray[np.float64]:
    """An orthonormal basis of a degenerate eigenspace, aligned with the coordinate axes.

    The coordinate axes are projected onto the eigenspace and orthonormalised in the order of how
    much of each projects, so a body whose tensor is diagonal in the coordinate frame gets the
    coordinate axes back, whatever LAPACK returned inside the degenerate space.
    """
    proj = eigvecs @ eigvecs.T
    cols = proj @ np.eye(3)
    order = np.argsort(-np.linalg.norm(cols, axis=0), kind="stable")
    basis: list[NDArray[np.float64]] = []
    for idx in order:
        v = cols[:, idx].copy()
        for b in basis:
            v -= (b @ v) * b
        n = np.linalg.norm(v)
        if n > 1e-8:
            basis.append(v / n)
        if len(basis) == dim:
            break
    return np.column_stack(basis)


@dataclass(frozen=True, eq=False)
class MassProperties:
    """Mass, centre of mass and inertia tensor of a rigid body.

    Parameters
    ----------
    mass : float
        Total mass M, kg (> 0).
    center_of_mass : array_like, shape (3,)
        Centre of mass in the body's modelling frame, m.
    tensor : array_like, shape (3, 3)
        Inertia tensor about the centre of mass, in the modelling frame's axes, kg m². Must be
        symmetric with principal moments that satisfy :func:`validate_moments`.
    """

    mass: float
    center_of_mass: NDArray[np.float64] = field(repr=True)
    tensor: NDArray[np.float64] = field(repr=True)

    def __post_init__(self) -> None:
        mass = _positive(self.mass, "mass")
        com = finite_array(self.center_of_mass, "center_of_mass", (3,)).copy()
        tensor = finite_array(self.tensor, "inertia tensor", (3, 3)).copy()
        scale = max(float(np.max(np.abs(tensor))), np.finfo(float).tiny)
        if np.max(np.abs(tensor - tensor.T)) > 1e-12 * scale:
            raise ValueError(f"an inertia tensor is symmetric; got {tensor.tolist()}")
        tensor = 0.5 * (tensor + tensor.T)
        eig = np.linalg.eigvalsh(tensor)
        # A rod's zero moment comes out of eigvalsh as ±round-off: clip that, refuse real negatives.
        eig[np.abs(eig) <= 1e-12 * scale] = 0.0
        validate_moments(eig, allow_zero=True)
        com.flags.writeable = False
        tensor.flags.writeable = False
        object.__setattr__(self, "mass", mass)
        object.__setattr__(self, "center_of_mass", com)
        object.__setattr__(self, "tensor", tensor)

    # -- principal axes -------------------------------------------------------------------------
    def principal(self) -> tuple[NDArray[np.float64], NDArray[np.float64]]:
        """Principal moments and axes about the centre of mass.

        Returns
        -------
        moments : ndarray, shape (3,)
            ``I1 >= I2 >= I3``, kg m² (the lecture's ordering).
        axes : ndarray, shape (3, 3)
            Columns are the unit principal axes ``1̂, 2̂, 3̂`` in the modelling frame, right-handed
            (``det = +1``), so ``tensor == axes @ diag(moments) @ axes.T``. Where moments repeat
            (within :data:`DEGENERACY_RTOL`), the axes of the degenerate space are the
            coordinate axes projected into it, so a sphere gets the identity. Such moments are
            reported as their mean, exactly equal, so a symmetric body is recognised as one; pass the
            raw moments to :class:`physics.free_body.FreeBody` to study a body that is near-symmetric
            by less than that.
        """
        return principal_frame(self.tensor)

    @property
    def moments(self) -> NDArray[np.float64]:
        """Principal moments ``I1 >= I2 >= I3`` about the centre of mass, shape (3,), kg m²."""
        return self.principal()[0]

    @property
    def principal_axes(self) -> NDArray[np.float64]:
        """Principal axes as columns, shape (3, 3), right-handed."""
        return self.principal()[1]

    # -- other reference points ------------------------------------------------------------------
    def tensor_about(self, point: ArrayLike) -> NDArray[np.float64]:
        """Inertia tensor about ``point`` by the parallel-axis theorem.

        ``I(a) = I_CM + M (a² δ − a aᵀ)`` with ``a = point − center_of_mass``.

        Parameters
        ----------
        point : array_like, shape (3,)
            Reference point in the modelling frame, m.

        Returns
        -------
        ndarray, shape (3, 3)
            kg m².
        """
        p = finite_array(point, "point", (3,))
        return self.tensor + parallel_axis(self.mass, p - self.center_of_mass)

    def moment_about(self, axis: ArrayLike, point: ArrayLike | None = None) -> float:
        """Moment of inertia about the line through ``point`` along ``axis``, kg m².

        Parameters
        ----------
        axis : array_like, shape (3,)
            Direction of the line (need not be unit).
        point : array_like, shape (3,), optional
            A point on the line, m; default the centre of mass.
        """
        n = _unit(axis, "axis")
        tensor = self.tensor if point is None else self.tensor_about(point)
        return float(n @ tensor @ n)

    def radius_of_gyration(self, axis: ArrayLike, point: ArrayLike | None = None) -> float:
        """Radius of gyration ``k = sqrt(I / M)`` about a line (lecture: ``I^{zz} = M k²``), m."""
        return float(np.sqrt(self.moment_about(axis, point) / self.mass))

    # -- composition ---------------------------------------------------------------------------
    def transformed(self, rotation: ArrayLike, translation: ArrayLike = (0.0, 0.0, 0.0)) -> MassProperties:
        """The same body moved rigidly: ``x -> rotation @ x + translation``.

        Parameters
        ----------
        rotation : array_like, shape (3, 3)
            A proper rotation matrix.
        translation : array_like, shape (3,)
            m.
        """
        r = finite_array(rotation, "rotation", (3, 3))
        if np.max(np.abs(r.T @ r - np.eye(3))) > 1e-9 or np.linalg.det(r) < 0:
            raise ValueError("rotation must be a proper rotation matrix (orthonormal, det +1)")
        t = finite_array(translation, "translation", (3,))
        return MassProperties(self.mass, r @ self.center_of_mass + t, r @ self.tensor @ r.T)

    def __add__(self, other: MassProperties) -> MassProperties:
        """Two bodies rigidly joined: masses add, tensors add about the common centre of mass."""
        if not isinstance(other, MassProperties):
            return NotImplemented
        mass = self.mass + other.mass
        com = (self.mass * self.center_of_mass + other.mass * other.center_of_mass) / mass
        return MassProperties(mass, com, self.tensor_about(com) + other.tensor_about(com))


def principal_frame(tensor: ArrayLike) -> tuple[NDArray[np.float64], NDArray[np.float64]]:
    """Principal moments (descending) and right-handed axes of a symmetric (3, 3) tensor.

    See :meth:`MassProperties.principal` for the conventions.
    """
    t = np.asarray(tensor, dtype=float)
    values, vectors = np.linalg.eigh(t)
    values = values[::-1].copy()
    vectors = vectors[:, ::-1].copy()
    scale = max(float(np.max(np.abs(values))), np.finfo(float).tiny)
    values[np.abs(values) < 1e-15 * scale] = 0.0
    # Group numerically equal moments and give each group a canonical basis.
    axes = np.empty((3, 3))
    i = 0
    while i < 3:
        j = i + 1
        while j < 3 and values[i] - values[j] <= DEGENERACY_RTOL * scale:
            j += 1
        block = vectors[:, i:j]
        if j - i == 1:
            axes[:, i] = _canonical_sign(block[:, 0])
        else:
            values[i:j] = np.mean(values[i:j])
            axes[:, i:j] = _eigenspace_basis(block, j - i)
        i = j
    if np.linalg.det(axes) < 0:
        axes[:, 2] = -axes[:, 2]
    return values, axes


# -- constructors (lecture examples and more) -----------------------------------------------------


def rod(mass: float, length: float) -> MassProperties:
    """A thin uniform rod (the lecture's wire) along z, centred at the origin.

    ``I = M ℓ²/12 · diag(1, 1, 0)`` about its centre.

    Parameters
    ----------
    mass : float
        kg.
    length : float
        ℓ, m.
    """
    m = _positive(mass, "mass")
    ell = _positive(length, "length")
    i = m * ell**2 / 12.0
    return MassProperties(m, np.zeros(3), np.diag([i, i, 0.0]))


def solid_sphere(mass: float, radius: float) -> MassProperties:
    """A uniform solid sphere centred at the origin: ``I = (2/5) M a²`` about every axis.

    Parameters
    ----------
    mass : float
        kg.
    radius : float
        a, m.
    """
    m = _positive(mass, "mass")
    a = _positive(radius, "radius")
    return MassProperties(m, np.zeros(3), 0.4 * m * a**2 * np.eye(3))


def solid_cylinder(mass: float, radius: float, length: float) -> MassProperties:
    """A uniform solid cylinder with axis z, centred at the origin.

    ``I_xx = I_yy = M (a²/4 + ℓ²/12)``, ``I_zz = M a²/2`` (lecture, with docs/conventions.md erratum 1).

    Parameters
    ----------
    mass : float
        kg.
    radius : float
        a, m.
    length : float
        ℓ, m (0 gives a disc).
    """
    m = _positive(mass, "mass")
    a = _positive(radius, "radius")
    ell = _nonnegative(length, "length")
    side = m * (a**2 / 4.0 + ell**2 / 12.0)
    return MassProperties(m, np.zeros(3), np.diag([side, side, m * a**2 / 2.0]))


def box(mass: float, extents: ArrayLike) -> MassProperties:
    """A uniform solid box with edge lengths ``extents`` along x, y, z, centred at the origin.

    ``I_xx = M (b² + c²)/12`` and cyclically.

    Parameters
    ----------
    mass : float
        kg.
    extents : array_like, shape (3,)
        Edge lengths, m (one may be 0: a plate).
    """
    m = _positive(mass, "mass")
    e = finite_array(extents, "extents", (3,))
    if np.any(e < 0) or np.count_nonzero(e) < 2:
        raise ValueError(f"a box needs non-negative extents, at most one of them zero; got {e.tolist()}")
    sq = e**2
    return MassProperties(m, np.zeros(3), np.diag([sq[1] + sq[2], sq[0] + sq[2], sq[0] + sq[1]]) * m / 12.0)


def point_masses(masses: ArrayLike, positions: ArrayLike) -> MassProperties:
    """A rigid set of point masses: ``I = Σ m_i (r_i² δ − r_i r_iᵀ)`` about their centre of mass.

    Parameters
    ----------
    masses : array_like, shape (n,)
        kg, each > 0.
    positions : array_like, shape (n, 3)
        m.
    """
    m = finite_array(masses, "masses")
    if m.ndim != 1 or m.size == 0:
        raise ValueError(f"masses must be a non-empty 1-D array, got shape {m.shape}")
    if np.any(m <= 0):
        raise ValueError(f"every point mass must be positive, got {m.tolist()}")
    r = finite_array(positions, "positions", (m.size, 3))
    total = float(m.sum())
    com = (m @ r) / total
    d = r - com
    r2 = np.einsum("ij,ij->i", d, d)
    tensor = np.einsum("i,i->", m, r2) * np.eye(3) - np.einsum("i,ij,ik->jk", m, d, d)
    return MassProperties(total, com, tensor)


def _winding_number(mesh: trimesh.Trimesh, point: NDArray[np.float64]) -> float:
    """How many times a closed mesh winds around ``point`` (1 inside, 0 outside an outward-wound solid).

    The sum of the triangles' signed solid angles over 4π (Van Oosterom & Strackee, IEEE Trans. Biomed.
    Eng. 30, 125 (1983)); numpy only (trimesh's ``contains`` needs rtree).
    """
    a, b, c = (np.asarray(mesh.triangles[:, k], dtype=float) - point for k in range(3))
    la, lb, lc = (np.linalg.norm(x, axis=1) for x in (a, b, c))
    numerator = np.einsum("ij,ij->i", a, np.cross(b, c))
    denominator = la * lb * lc + np.einsum("ij,ij->i", a, b) * lc + np.einsum("ij,ij->i", b, c) * la
    denominator += np.einsum("ij,ij->i", c, a) * lb
    return float(np.sum(2.0 * np.arctan2(numerator, denominator)) / (4.0 * np.pi))


def _check_parts_wound_alike(mesh: trimesh.Trimesh) -> None:
    """Refuse a mesh with a separate part wound inside out (negative volume) that is not a cavity.

    A part with negative signed volume is a void only if it lies inside a part of positive volume (a
    hollow shell); anywhere else it would subtract its volume from the body's mass.
    """
    parts = mesh.split(only_watertight=False)
    if len(parts) < 2:
        return
    with np.errstate(divide="ignore", invalid="ignore"):  # trimesh also divides by each part's volume
        volumes = [float(p.volume) for p in parts]
    solids = [p for p, v in zip(parts, volumes, strict=True) if v > 0]
    for part, volume in zip(parts, volumes, strict=True):
        if volume < 0 and not any(_winding_number(s, part.vertices[0]) > 0.5 for s in solids):
            raise ValueError(
                f"a separate part of the mesh ({len(part.faces)} triangles) is wound inside out (its normals "
                "face inward) and is not a cavity inside another part, so the mass would be wrong; fix its "
                "winding and try again"
            )


def from_mesh(mesh: trimesh.Trimesh, *, mass: float | None = None, density: float | None = None) -> MassProperties:
    """Mass properties of a closed triangle mesh of uniform density.

    Parameters
    ----------
    mesh : trimesh.Trimesh
        A watertight mesh, vertices in m. An inverted winding (negative volume) is fixed on a copy,
        not refused.
    mass : float, optional
        Total mass, kg. Give ``mass`` or ``density``, not both.
    density : float, optional
        kg/m³. If neither is given, 1000 kg/m³ (water).

    Raises
    ------
    ValueError
        For an empty mesh, one that is not watertight, one whose triangles are wound inconsistently (or
        with a separate part inside out that is not a cavity), one of zero volume, or non-finite vertices;
        for a mesh so small or large that its mass or moments leave the float range ("too small"/"too
        large", with the range: the mass and mass × size² within 1e-308..1e308).

    Notes
    -----
    Computed on the mesh centred and scaled by a power of two to a size of about 1 m (exactly), then
    scaled back (mass ∝ density · size³, moments ∝ mass · size²): a 1e-100 m box of 1 kg is as exact as a
    1 m one.
    """
    import trimesh  # imported here so the rest of the module has no trimesh import cost

    if not isinstance(mesh, trimesh.Trimesh):
        raise ValueError(f"expected a trimesh.Trimesh, got {type(mesh).__name__}")
    if mass is not None and density is not None:
        raise ValueError("give the mass or the density of the mesh, not both")
    if len(mesh.faces) == 0 or len(mesh.vertices) == 0:
        raise ValueError("the mesh is empty: it has no triangles")
    if not np.all(np.isfinite(mesh.vertices)):
        raise ValueError("the mesh has vertices that are not finite numbers")
    # Mass properties scale exactly with the size: work on the mesh moved to its bounding box's centre and
    # scaled by a power of two (exact) to a size of about 1 m, where nothing over- or underflows and
    # trimesh's tolerances (merging, degeneracy) mean what they say; the results are scaled back below.
    vertices = np.asarray(mesh.vertices, dtype=float)
    low, high = np.min(vertices, axis=0), np.max(vertices, axis=0)
    centre = 0.5 * low + 0.5 * high
    with np.errstate(over="ignore"):
        extent = float(np.max(np.abs(vertices - centre)))
    if not np.isfinite(extent):
        raise ValueError("the mesh is too large: its vertices span more than the float range (1.8e308 m)")
    if extent == 0.0:
        raise ValueError("the mesh encloses zero volume: all its vertices are one point")
    size_exponent = math.frexp(extent)[1]  # extent in [2^(e-1), 2^e): the unit mesh's extent in [0.5, 1)
    unit = trimesh.Trimesh(vertices=np.ldexp(vertices - centre, -size_exponent), faces=mesh.faces, process=False)
    _from_unit_mesh_checks(unit)
    if mass is not None:
        total = _positive(mass, "mass")
    else:
        rho = _positive(density if density is not None else 1000.0, "density")
    with np.errstate(divide="ignore", invalid="ignore"):  # trimesh divides by the volume, which may be 0
        props = unit.mass_properties  # density 1 on the unit mesh: its mass is its volume
    unit_volume = float(props["mass"])
    if mass is None:
        total = _scaled(rho * unit_volume, 3 * size_exponent, "mass (density × volume)")
    # I = M · (Ĩ / Ṽ) · size², the centre of mass c̃ · size + centre.
    per_mass = np.asarray(props["inertia"], dtype=float) / unit_volume
    tensor = _scaled_tensor(per_mass * total, 2 * size_exponent)
    com = np.ldexp(np.asarray(props["center_mass"], dtype=float), size_exponent) + centre
    return MassProperties(total, com, tensor)


_SIZES = "the mass (kg) and mass × size² (kg m²) must lie between 1e-308 and 1e308"


def _scaled(value: float, exponent: int, what: str) -> float:
    """``value · 2^exponent``, refused when it leaves the range of normal floats (it would be inf or lose
    its digits)."""
    try:
        out = math.ldexp(value, exponent)
    except OverflowError:
        out = math.inf
    if not (np.isfinite(out) and out >= np.finfo(float).tiny):
        size = "large" if exponent > 0 else "small"
        raise ValueError(
            f"the mesh is too {size}: its {what} would be about 10^{math.log10(value) + exponent * math.log10(2):.0f}, "
            f"outside the float range; {_SIZES}. Scale the mesh (metres), or give it another mass"
        )
    return out


def _scaled_tensor(tensor: NDArray[np.float64], exponent: int) -> NDArray[np.float64]:
    """The unit mesh's tensor (kg m², at size 1) times ``2^exponent`` (the size squared), refused when its
    largest entry leaves the range of normal floats."""
    largest = float(np.max(np.abs(tensor)))
    _scaled(largest, exponent, "moments of inertia (kg m²)")
    return np.ldexp(tensor, exponent)


def _from_unit_mesh_checks(unit: trimesh.Trimesh) -> None:
    """Watertight, consistently wound, not inside out in a separate part, not flat: checked on the mesh
    scaled to about 1 m (the checks' tolerances are absolute)."""
    mesh = unit
    if not mesh.is_watertight:
        raise ValueError(
            "the mesh is not watertight (it has holes or open edges), so it encloses no volume and has no "
            "defined mass distribution; close it or use its convex hull"
        )
    if not mesh.is_winding_consistent:
        raise ValueError(
            "the mesh's triangles are wound inconsistently (some face inward, some outward), so its "
            "volume and mass would be wrong; re-orient its faces consistently in the modelling program (in "
            "Blender: Mesh > Normals > Recalculate Outside) and try again"
        )
    with np.errstate(divide="ignore", invalid="ignore"):  # trimesh divides by the volume, which may be 0
        volume = float(mesh.volume)
    if volume < 0:
        mesh.invert()  # inward-facing normals: the same solid, wound the other way (the unit mesh is a copy)
        volume = -volume
    _check_parts_wound_alike(mesh)
    scale = float(np.max(np.ptp(mesh.vertices, axis=0))) ** 3
    if not np.isfinite(volume) or volume <= 1e-12 * max(scale, np.finfo(float).tiny):
        raise ValueError("the mesh encloses zero volume (it is flat or degenerate)")
