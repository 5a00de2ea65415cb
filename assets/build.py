"""Make the meshes the scenes use: ``python -m assets.build``.

Every body is a *single* watertight solid built from a profile, never a union of overlapping parts
(overlaps would count their shared volume twice in the inertia tensor):

- round bodies (spinning top, baseball bat) revolve a profile about their axis
  (:func:`trimesh.creation.revolve`);
- flat bodies (tennis racket, T-handle, book) extrude a planar region whose triangulation is built
  here (:func:`trimesh.creation.extrude_triangulation`), so no polygon library is needed.

Lengths are metres. Output is binary PLY (shared vertices: a few tens of kB each) and is
deterministic: running the script twice gives byte-identical files.
"""

from __future__ import annotations

import argparse
from pathlib import Path

import numpy as np
import trimesh
from numpy.typing import NDArray

ASSET_DIR = Path(__file__).resolve().parent

# Rotations that carry an extrusion made along +z into the plane the body lives in.
_Z_TO_Y = trimesh.transformations.rotation_matrix(np.pi / 2, [1.0, 0.0, 0.0])  # 2-D y -> +z, extrusion axis -> -y

# --------------------------------------------------------------------------------------------------
# planar regions
# --------------------------------------------------------------------------------------------------


def _ray_exit(polygon: NDArray[np.float64], centre: NDArray[np.float64], angle: float) -> float:
    """Distance from ``centre`` along direction ``angle`` to the last crossing of a convex polygon's edges.

    Returns 0 when the ray misses the polygon.
    """
    d = np.array([np.cos(angle), np.sin(angle)])
    best = 0.0
    n = len(polygon)
    for i in range(n):
        p, q = polygon[i], polygon[(i + 1) % n]
        e = q - p
        # Solve centre + t d = p + s e for (t, s).
        m = np.array([[d[0], -e[0]], [d[1], -e[1]]])
        det = np.linalg.det(m)
        if abs(det) < 1e-15:
            continue
        t, s = np.linalg.solve(m, p - centre)
        if t > 0.0 and -1e-12 <= s <= 1.0 + 1e-12:
            best = max(best, float(t))
    return best


def _ellipse_radius(a: float, b: float, angle: NDArray[np.float64]) -> NDArray[np.float64]:
    """Polar radius of the ellipse x²/a² + y²/b² = 1 about its centre."""
    return 1.0 / np.sqrt((np.cos(angle) / a) ** 2 + (np.sin(angle) / b) ** 2)


def _annulus_triangulation(
    inner: NDArray[np.float64], outer: NDArray[np.float64]
) -> tuple[NDArray[np.float64], NDArray[np.int64]]:
    """Triangulate the region between two closed loops sampled on the same rays (counter-clockwise)."""
    n = len(inner)
    vertices = np.vstack([inner, outer])
    i = np.arange(n)
    j = (i + 1) % n
    # Quad (inner_i, outer_i, outer_j, inner_j), split along inner_i - outer_j; wound counter-clockwise.
    faces = np.vstack([np.column_stack([i, n + i, n + j]), np.column_stack([i, n + j, j])])
    return vertices, faces


def _check_counter_clockwise(vertices: NDArray[np.float64], faces: NDArray[np.int64]) -> None:
    a, b, c = (vertices[faces[:, k]] for k in range(3))
    cross = (b - a)[:, 0] * (c - a)[:, 1] - (b - a)[:, 1] * (c - a)[:, 0]
    if np.any(cross <= 0.0):
        raise RuntimeError("planar triangulation has a flipped or degenerate triangle")


# --------------------------------------------------------------------------------------------------
# the bodies
# --------------------------------------------------------------------------------------------------


def tennis_racket() -> trimesh.Trimesh:
    """A tennis racket: oval frame with an open head, solid throat and handle; 0.685 m long.

    Modelling frame: long axis +z with the butt of the handle at the origin, face in the x-z plane
    (face normal y). The strings are left out (a few grams); the frame alone already has three
    distinct moments, I(normal) > I(across the face) > I(along the handle).
    """
    head_centre = np.array([0.0, 0.52])  # (x, z) in the racket plane
    a_out, b_out, rim = 0.135, 0.165, 0.012
    # Throat + handle: a convex hexagon whose top edge lies inside the head oval, so the union with
    # the oval is star-shaped about the head centre and each ray has one outer radius.
    handle = np.array([[0.016, 0.0], [0.016, 0.27], [0.075, 0.40], [-0.075, 0.40], [-0.016, 0.27], [-0.016, 0.0]])
    uniform = np.linspace(-np.pi / 2, 3 * np.pi / 2, 192, endpoint=False)
    corners = np.arctan2(handle[:, 1] - head_centre[1], handle[:, 0] - head_centre[0])
    near_handle = -np.pi / 2 + np.linspace(-0.25, 0.25, 61)
    angles = np.concatenate([uniform, corners, near_handle])
    # One turn starting at the handle's direction, sorted so the loops run counter-clockwise.
    angles = np.unique(np.round((angles + np.pi / 2) % (2 * np.pi) - np.pi / 2, 12))
    r_oval = _ellipse_radius(a_out, b_out, angles)
    r_handle = np.array([_ray_exit(handle, head_centre, t) for t in angles])
    r_out = np.maximum(r_oval, r_handle)
    r_in = _ellipse_radius(a_out - rim, b_out - rim, angles)
    unit = np.column_stack([np.cos(angles), np.sin(angles)])
    outer = head_centre + unit * r_out[:, None]
    inner = head_centre + unit * r_in[:, None]
    vertices, faces = _annulus_triangulation(inner, outer)
    _check_counter_clockwise(vertices, faces)
    thickness = 0.022
    mesh = trimesh.creation.extrude_triangulation(vertices, faces, thickness)
    mesh.apply_translation([0.0, 0.0, -thickness / 2])
    mesh.apply_transform(_Z_TO_Y)  # racket plane (x, y) -> (x, z); thickness along y
    return mesh


def t_handle() -> trimesh.Trimesh:
    """The Dzhanibekov T-handle (wing nut): a 70 mm crossbar with a 60 mm stem, square bars 12 mm thick.

    Modelling frame: crossbar along x, stem along -z from the crossbar, thickness along y; the
    origin is the middle of the crossbar's lower edge. Proportions chosen so the three moments are
    well apart (about 2.9 : 2.0 : 1): the smallest about the stem, the intermediate about the
    crossbar, the largest about the normal to the T's plane.
    """
    half_bar, bar, half_stem, stem = 0.035, 0.012, 0.006, 0.060
    # Crossbar polygon includes the stem's two attachment points so the two pieces share the edge.
    vertices = np.array(
        [
            [-half_bar, 0.0],  # 0
            [-half_stem, 0.0],  # 1
            [half_stem, 0.0],  # 2
            [half_bar, 0.0],  # 3
            [half_bar, bar],  # 4
            [-half_bar, bar],  # 5
            [half_stem, -stem],  # 6
            [-half_stem, -stem],  # 7
        ]
    )
    faces = np.array(
        [
            [5, 0, 1], [5, 1, 2], [5, 2, 3], [5, 3, 4],  # crossbar, fanned from a top corner
            [7, 6, 2], [7, 2, 1],  # stem
        ]
    )  # fmt: skip
    _check_counter_clockwise(vertices, faces)
    mesh = trimesh.creation.extrude_triangulation(vertices, faces, bar)
    mesh.apply_translation([0.0, 0.0, -bar / 2])
    mesh.apply_transform(_Z_TO_Y)
    return mesh


def spinning_top() -> trimesh.Trimesh:
    """A spinning top: tip at the origin, symmetry axis +z, a heavy rim and a short stem; 92 mm tall."""
    profile = np.array(
        [
            [0.0, 0.0],
            [0.003, 0.002],
            [0.010, 0.010],
            [0.034, 0.030],
            [0.040, 0.036],
            [0.041, 0.040],
            [0.040, 0.044],
            [0.030, 0.050],
            [0.008, 0.054],
            [0.006, 0.058],
            [0.006, 0.088],
            [0.004, 0.092],
            [0.0, 0.092],
        ]
    )
    return trimesh.creation.revolve(profile, sections=64)


def baseball_bat() -> trimesh.Trimesh:
    """A baseball bat 0.84 m long: knob at the origin, axis +z, handle 25 mm, barrel 66 mm across."""
    z_knob = [0.0, 0.004, 0.010, 0.016]
    r_knob = [0.024, 0.028, 0.026, 0.013]
    z_taper = np.linspace(0.30, 0.62, 9)
    r_taper = 0.0125 + (0.033 - 0.0125) * 0.5 * (1 - np.cos(np.pi * (z_taper - 0.30) / 0.32))
    cap = np.linspace(0.0, np.pi / 2, 7)[1:]
    z_cap = 0.815 + 0.025 * np.sin(cap)
    r_cap = 0.033 * np.cos(cap) + 0.0 * cap
    profile = np.concatenate(
        [
            [[0.0, 0.0]],
            np.column_stack([r_knob, z_knob]),
            [[0.0125, 0.030]],
            np.column_stack([r_taper, z_taper]),
            [[0.033, 0.815]],
            np.column_stack([r_cap, z_cap])[:-1],
            [[0.0, 0.840]],
        ]
    )
    return trimesh.creation.revolve(profile, sections=48)


def book() -> trimesh.Trimesh:
    """A closed hardback book, 240 x 170 x 35 mm, with a rounded spine.

    Modelling frame: centred; width x (spine at -x), height y, thickness z. Its three moments are
    distinct: a book tossed about its middle axis tumbles.
    """
    width, height, thick = 0.170, 0.240, 0.035
    spine = np.linspace(np.pi / 2, 3 * np.pi / 2, 13)  # semicircle bulging out on -x
    cross_section = np.concatenate(
        [
            [[width / 2, -thick / 2], [width / 2, thick / 2]],
            np.column_stack([-width / 2 + 0.006 * np.cos(spine) - 0.0, thick / 2 * np.sin(spine)]),
        ]
    )
    # Star-shaped about the centre (0, 0): fan triangulation from an added centre vertex.
    n = len(cross_section)
    vertices = np.vstack([[[0.0, 0.0]], cross_section])
    idx = np.arange(n)
    faces = np.column_stack([np.zeros(n, dtype=np.int64), 1 + idx, 1 + (idx + 1) % n])
    _check_counter_clockwise(vertices, faces)
    mesh = trimesh.creation.extrude_triangulation(vertices, faces, height)
    mesh.apply_translation([0.0, 0.0, -height / 2])
    # Cross-section (x, z_book) was drawn in the 2-D (x, y) plane; height was extruded along z.
    swap = np.array([[1, 0, 0, 0], [0, 0, 1, 0], [0, -1, 0, 0], [0, 0, 0, 1]], dtype=float)
    mesh.apply_transform(swap)
    return mesh


BUILDERS = {
    "tennis_racket": tennis_racket,
    "t_handle": t_handle,
    "spinning_top": spinning_top,
    "baseball_bat": baseball_bat,
    "book": book,
}
"""Asset name -> function making its mesh. The file is ``<name>.ply`` beside this script."""


def build(name: str) -> trimesh.Trimesh:
    """Make one asset's mesh and check it is a closed, outward-wound solid."""
    mesh = BUILDERS[name]()
    mesh.merge_vertices()
    if not mesh.is_watertight:
        raise RuntimeError(f"{name}: the generated mesh is not watertight")
    if not mesh.is_winding_consistent or mesh.volume <= 0.0:
        raise RuntimeError(f"{name}: the generated mesh is not wound outwards")
    return mesh


def write(name: str, directory: Path = ASSET_DIR) -> Path:
    """Build ``name`` and write it as binary PLY; returns the path."""
    path = directory / f"{name}.ply"
    data = build(name).export(file_type="ply", encoding="binary")
    path.write_bytes(data)
    return path


def main(argv: list[str] | None = None) -> None:
    parser = argparse.ArgumentParser(prog="python -m assets.build", description=__doc__.splitlines()[0])
    parser.add_argument("--out", type=Path, default=ASSET_DIR, help="output directory (default: assets/)")
    args = parser.parse_args(argv)
    args.out.mkdir(parents=True, exist_ok=True)
    for name in BUILDERS:
        path = write(name, args.out)
        mesh = trimesh.load_mesh(path)
        print(
            f"{path.name:20s} {path.stat().st_size / 1024:7.1f} kB {len(mesh.faces):6d} faces "
            f"watertight={mesh.is_watertight} volume={mesh.volume * 1e6:.1f} cm³"
        )


if __name__ == "__main__":
    main()
