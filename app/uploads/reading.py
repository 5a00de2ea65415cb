"""Reading an uploaded mesh file into a body of uniform density, or a ValueError saying what to fix.

Pure functions (nothing touches viser). Refused in this order: a file over the size limit (:mod:`app.uploads.limits`), a
type other than STL, OBJ, PLY, GLB, a file read as nothing, too many triangles or non-finite vertices, a
mesh that is not watertight (:class:`NotWatertightError` offers its convex hull), a flat mesh. Meshes are
in metres; one larger than :data:`MILLIMETRE_GUESS` is read as millimetres, and the note says so.
"""

from __future__ import annotations

import io
import math
from dataclasses import dataclass
from pathlib import PurePath

import numpy as np
import trimesh

from app.language.words import joined, mark, say
from app.uploads import limits
from physics.inertia import MassProperties, from_mesh

__all__ = [
    "FORMATS",
    "MILLIMETRE_GUESS",
    "UploadedBody",
    "NotWatertightError",
    "read_mesh",
    "parse_mesh",
    "body_from_mesh",
    "body_from_upload",
    "body_from_parsed_upload",
]

FORMATS = ("stl", "obj", "ply", "glb")
"""File extensions accepted (lower case)."""
MILLIMETRE_GUESS = 5.0
"""A mesh whose largest extent exceeds this many metres is taken to be in millimetres."""
DEFAULT_MASS = 1.0
"""kg given to an uploaded body (uniform density); moments scale with it."""


class NotWatertightError(ValueError):
    """The mesh has holes. ``hull`` is its convex hull (watertight), which the user may use instead."""

    def __init__(self, message: str, hull: trimesh.Trimesh | None) -> None:
        super().__init__(message)
        self.hull = hull


@dataclass(frozen=True)
class UploadedBody:
    """An accepted upload: the mesh (m, recentred nowhere: as given), its mass properties and a note."""

    name: str
    mesh: trimesh.Trimesh
    mass_properties: MassProperties
    note: str


def read_mesh(filename: str, content: bytes) -> trimesh.Trimesh:
    """Parse an uploaded file into one triangle mesh, refusing what is not a usable mesh.

    Parameters
    ----------
    filename : str
        The uploaded file's name; its extension selects the format (STL, OBJ, PLY, GLB).
    content : bytes
        The file's bytes.

    Returns
    -------
    trimesh.Trimesh
        With duplicate vertices merged (an STL stores each triangle's corners separately). Not yet
        checked for watertightness: see :func:`body_from_mesh`.

    Raises
    ------
    ValueError
        Too large, unknown type, unreadable, empty, too many faces, or non-finite vertices; the
        message names the file and the problem.
    """
    limits.check_size(filename, content)
    return parse_mesh(filename, content)


def parse_mesh(filename: str, content: bytes) -> trimesh.Trimesh:
    """:func:`read_mesh` for a file whose size was checked already (:func:`app.uploads.limits.check_size`)."""
    name = PurePath(filename or "upload").name
    ext = PurePath(name).suffix.lower().lstrip(".")
    if ext not in FORMATS:
        got = "." + ext if ext else mark("no extension")
        raise ValueError(
            say(
                "{name} is not a mesh file this app reads: upload an STL, OBJ, PLY or GLB file (got {got}).",
                name=name,
                got=got,
            )
        )
    if len(content) == 0:
        raise ValueError(say("{name} is empty (0 bytes): there is no mesh in it.", name=name))
    try:
        # Unprocessed: trimesh's own merging (absolute tolerance 1e-8) would weld every corner of a
        # part smaller than 1e-8 m into one point; the vertices are merged below, at unit scale.
        loaded = trimesh.load(io.BytesIO(content), file_type=ext, process=False)
    except MemoryError:
        raise  # not the file's form but its size: the worker's memory limit says so (app.uploads.worker)
    except Exception as exc:  # noqa: BLE001 - any parser failure means "not a readable mesh"
        raise ValueError(
            say(
                "{name} could not be read as a {format} mesh ({kind}: {reason}).",
                name=name,
                format=ext.upper(),
                kind=type(exc).__name__,
                reason=str(exc),
            )
        ) from exc
    if isinstance(loaded, trimesh.Scene):
        # GLB (and a failed STL/OBJ parse) come back as a scene: flatten its geometry into one mesh.
        meshes = [g for g in loaded.dump() if isinstance(g, trimesh.Trimesh)] if loaded.geometry else []
        loaded = trimesh.util.concatenate(meshes) if meshes else None  # type: ignore[assignment]
    if not isinstance(loaded, trimesh.Trimesh) or len(loaded.faces) == 0 or len(loaded.vertices) == 0:
        raise ValueError(
            say(
                "{name} contains no triangles: the file is empty or is not really a {format} mesh "
                "(a point cloud, lines only, or garbage).",
                name=name,
                format=ext.upper(),
            )
        )
    if len(loaded.faces) > limits.MAX_FACES:
        raise ValueError(
            say(
                "{name} has {count:,} triangles; the limit is {limit:,}. Decimate the mesh and upload it again.",
                name=name,
                count=len(loaded.faces),
                limit=limits.MAX_FACES,
            )
        )
    stl = mark(" (an STL file stores 32-bit numbers: sizes beyond 3.4e38 become infinite)") if ext == "stl" else ""
    if not np.all(np.isfinite(loaded.vertices)):
        raise ValueError(
            say("{name} has vertices that are not finite numbers (NaN or infinity){why}.", name=name, why=stl)
        )
    vertices = np.asarray(loaded.vertices, dtype=float)
    extent = float(np.max(np.ptp(vertices, axis=0)))
    if extent == 0.0:
        tiny = (
            mark(" (an STL file stores 32-bit numbers: sizes below about 1e-38 m round to 0)") if ext == "stl" else ""
        )
        raise ValueError(
            say(
                "{name} is too small: all its vertices are one point{why}. Scale it up and upload it again.",
                name=name,
                why=tiny,
            )
        )
    # Merge duplicate corners (an STL stores each triangle's separately) on the mesh scaled by a power of
    # two to a size of about 1, where trimesh's merge tolerance (1e-8, absolute) is relative to the size;
    # the scaling is exact, so the vertices come back as given.
    size_exponent = math.frexp(extent)[1]
    mesh = trimesh.Trimesh(vertices=np.ldexp(vertices, -size_exponent), faces=loaded.faces, process=True)
    mesh.merge_vertices()
    mesh.remove_unreferenced_vertices()
    return trimesh.Trimesh(vertices=np.ldexp(mesh.vertices, size_exponent), faces=mesh.faces, process=False)


def body_from_mesh(
    mesh: trimesh.Trimesh, name: str = "upload", *, use_convex_hull: bool = False, mass: float = DEFAULT_MASS
) -> UploadedBody:
    """Turn a parsed mesh into a body of uniform density, or refuse it saying why.

    Parameters
    ----------
    mesh : trimesh.Trimesh
        Vertices in m (or mm: see :data:`MILLIMETRE_GUESS`).
    name : str
        Shown in messages.
    use_convex_hull : bool
        If the mesh is not watertight, use its convex hull instead of refusing it.
    mass : float
        Total mass, kg.

    Raises
    ------
    NotWatertightError
        The mesh is not watertight and ``use_convex_hull`` is False; ``.hull`` is offered.
    ValueError
        The mesh has zero volume, or a convex hull cannot be formed (all points on a plane).
    """
    notes = []
    extent = float(np.max(np.ptp(mesh.vertices, axis=0)))
    if extent > MILLIMETRE_GUESS:
        mesh = mesh.copy()
        mesh.apply_scale(1e-3)  # type: ignore[no-untyped-call]  # trimesh does not annotate it
        notes.append(
            say(
                "its largest size was {extent:.4g}, so it was read as millimetres ({metres:.3g} m)",
                extent=extent,
                metres=extent / 1000,
            )
        )
    if not mesh.is_watertight:
        open_edges = _open_edge_count(mesh)
        hull = _convex_hull_or_none(mesh)
        why = (
            say(
                "{name} is not watertight: {count} edge belongs to only one triangle (a hole or a surface that "
                "is not closed), so it encloses no definite volume and has no mass distribution.",
                name=name,
                count=open_edges,
            )
            if open_edges == 1
            else say(
                "{name} is not watertight: {count} edges belong to only one triangle (holes or a surface that is "
                "not closed), so it encloses no definite volume and has no mass distribution.",
                name=name,
                count=open_edges,
            )
        )
        if not use_convex_hull:
            offer = mark("You can use its convex hull instead (the shape shrink-wrapped).") if hull is not None else ""
            raise NotWatertightError(say("{why} {offer}", why=why, offer=offer) if offer else why, hull)
        if hull is None:
            flat = mark("Its points all lie on a plane, so it has no convex hull with volume either.")
            raise ValueError(say("{why} {flat}", why=why, flat=flat))
        mesh = hull
        notes.append(mark("replaced by its convex hull because it was not watertight"))
    try:
        props = from_mesh(mesh, mass=mass)
    except ValueError as exc:
        raise ValueError(say("{name}: {reason}", name=name, reason=str(exc))) from exc
    note = say(
        "{name}: {count:,} triangles, {mass:g} kg of uniform density", name=name, count=len(mesh.faces), mass=mass
    )
    return UploadedBody(name, mesh, props, say("{note}.", note=joined([note, *notes], "; ")))


def body_from_upload(
    filename: str, content: bytes, *, use_convex_hull: bool = False, mass: float = DEFAULT_MASS
) -> UploadedBody:
    """:func:`read_mesh` then :func:`body_from_mesh`: the whole check of one uploaded file."""
    name = PurePath(filename or "upload").name
    return body_from_mesh(read_mesh(filename, content), name, use_convex_hull=use_convex_hull, mass=mass)


def body_from_parsed_upload(
    filename: str, content: bytes, *, use_convex_hull: bool = False, mass: float = DEFAULT_MASS
) -> UploadedBody:
    """:func:`body_from_upload` for a file that has passed :func:`app.uploads.limits.check_upload` already
    (the worker's: its caller checked the file before handing it over)."""
    name = PurePath(filename or "upload").name
    return body_from_mesh(parse_mesh(filename, content), name, use_convex_hull=use_convex_hull, mass=mass)


def _open_edge_count(mesh: trimesh.Trimesh) -> int:
    # Edges used by exactly one face (a closed surface uses each edge twice).
    edges = np.sort(mesh.edges, axis=1)
    _, counts = np.unique(edges, axis=0, return_counts=True)
    return int(np.sum(counts == 1))


def _convex_hull_or_none(mesh: trimesh.Trimesh) -> trimesh.Trimesh | None:
    # A flat mesh's hull has zero volume: trimesh divides by it (centre of mass) on the way to refusing it.
    with np.errstate(divide="ignore", invalid="ignore"):
        try:
            hull = mesh.convex_hull
        except Exception:  # noqa: BLE001 - qhull fails on coplanar points
            return None
        if not isinstance(hull, trimesh.Trimesh) or len(hull.faces) < 4 or not hull.is_watertight or hull.volume <= 0:
            return None
    return hull
