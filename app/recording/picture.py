"""A picture of the scene without a browser: the kept scene nodes drawn in software, for the export's PNG.

More in docs/app-notes.md (``app.recording.picture``).
"""

from __future__ import annotations

import io
import math
from collections.abc import Iterator
from typing import Any

import numpy as np
import trimesh
from numpy.typing import NDArray
from PIL import Image, ImageDraw

from app.guards.handles import is_removed, node_pose, prop, properties

__all__ = ["render_png"]

Floats = NDArray[np.float64]
SUPERSAMPLE = 2
BACKGROUND = (255, 255, 255)
_SPHERE = trimesh.creation.icosphere(subdivisions=2, radius=1.0)


def _rotation(wxyz: Any) -> Floats:
    w, x, y, z = (float(c) for c in wxyz)
    n = math.sqrt(w * w + x * x + y * y + z * z) or 1.0
    w, x, y, z = w / n, x / n, y / n, z / n
    return np.array(
        [
            [1 - 2 * (y * y + z * z), 2 * (x * y - w * z), 2 * (x * z + w * y)],
            [2 * (x * y + w * z), 1 - 2 * (x * x + z * z), 2 * (y * z - w * x)],
            [2 * (x * z - w * y), 2 * (y * z + w * x), 1 - 2 * (x * x + y * y)],
        ]
    )


def _world_poses(handles: dict[str, Any]) -> Iterator[tuple[Any, Floats, Floats, float]]:
    """Every visible node with its world rotation (3, 3), translation (3,) and scale (viser's parents are
    the nodes whose names are prefixes of the name, as in the browser's scene tree)."""
    for name, handle in handles.items():
        if is_removed(handle):
            continue
        parts = name.strip("/").split("/")
        chain = ["/" + "/".join(parts[: k + 1]) for k in range(len(parts))]
        R, p, visible = np.eye(3), np.zeros(3), True
        for link in chain:
            node = handles.get(link)
            if node is None:
                continue
            shown, wxyz, position = node_pose(node)
            if not shown:
                visible = False
                break
            Rl = _rotation(wxyz)
            p = p + R @ np.asarray(position, dtype=float)
            R = R @ Rl
        if visible:
            scale = prop(handle, "scale", 1.0)
            yield handle, R, p, float(np.mean(scale)) if np.ndim(scale) else float(scale)


def _primitives(handles: dict[str, Any]) -> Iterator[tuple[str, Floats, tuple[int, ...], float]]:
    """(kind, world points, colour, opacity): kind "tri" with (3, 3) points or "seg" with (2, 3) points."""
    for handle, R, p, scale in _world_poses(handles):
        props = properties(handle)
        kind = type(props).__name__
        if kind in ("MeshProps", "IcosphereProps"):
            if kind == "MeshProps":
                vertices, faces = np.asarray(props.vertices, dtype=float), np.asarray(props.faces)
            else:
                vertices, faces = _SPHERE.vertices * float(props.radius), _SPHERE.faces
            world = (vertices * scale) @ R.T + p
            colour = tuple(int(c) for c in props.color)
            opacity = 1.0 if props.opacity is None else float(props.opacity)
            for tri in world[faces]:
                yield "tri", tri, colour, opacity
        elif kind in ("LineSegmentsProps", "ArrowProps"):
            points = np.asarray(props.points, dtype=float).reshape(-1, 2, 3) * scale @ R.T + p
            colours = np.asarray(props.colors).reshape(-1, 2, 3) if np.size(props.colors) > 3 else None
            base = tuple(int(c) for c in np.asarray(props.colors).reshape(-1)[:3])
            for i, seg in enumerate(points):
                colour = tuple(int(c) for c in colours[i, 0]) if colours is not None else base
                if np.allclose(seg[0], seg[1]):
                    continue
                yield ("arrow" if kind == "ArrowProps" else "seg"), seg, colour, 1.0
        elif kind == "GridProps" and props.plane == "xy":
            half_w, half_h, step = props.width / 2, props.height / 2, props.section_size
            colour = tuple(int(c) for c in props.section_color)
            for x in np.arange(-half_w, half_w + 1e-9, step):
                yield "grid", np.array([[x, -half_h, 0.0], [x, half_h, 0.0]]) @ R.T + p, colour, 0.5
            for y in np.arange(-half_h, half_h + 1e-9, step):
                yield "grid", np.array([[-half_w, y, 0.0], [half_w, y, 0.0]]) @ R.T + p, colour, 0.5


def render_png(
    handles: dict[str, Any],
    position: Any,
    look_at: Any,
    *,
    size: tuple[int, int] = (960, 720),
    fov: float = math.radians(50.0),
) -> bytes:
    """A PNG of the scene nodes seen from ``position`` towards ``look_at`` (m, z up).

    Parameters
    ----------
    handles : dict of str to viser scene-node handle
        The scene's nodes by name (``app.guards.handles.scene_nodes``).
    position, look_at : array_like, shape (3,)
        The camera's position and the point it looks at (m).
    size : (int, int)
        Width and height in pixels.
    fov : float
        Vertical field of view (rad).
    """
    eye, target = np.asarray(position, dtype=float), np.asarray(look_at, dtype=float)
    forward = target - eye
    if not np.all(np.isfinite(forward)) or np.linalg.norm(forward) == 0.0:
        raise ValueError(f"the camera needs distinct finite position and look_at, got {eye} and {target}")
    forward /= np.linalg.norm(forward)
    right = np.cross(forward, [0.0, 0.0, 1.0])
    if np.linalg.norm(right) < 1e-9:  # looking straight down or up
        right = np.array([1.0, 0.0, 0.0])
    right /= np.linalg.norm(right)
    up = np.cross(right, forward)
    width, height = size[0] * SUPERSAMPLE, size[1] * SUPERSAMPLE
    focal = 0.5 * height / math.tan(0.5 * fov)

    def project(points: Floats) -> tuple[Floats, Floats]:
        rel = points - eye
        depth = rel @ forward
        xy = np.stack([rel @ right, rel @ up], axis=-1) * (focal / np.maximum(depth, 1e-6))[..., None]
        return np.stack([width / 2 + xy[..., 0], height / 2 - xy[..., 1]], axis=-1), depth

    items: list[tuple[float, str, Any, tuple[int, ...], float, float]] = []
    for kind, pts, colour, opacity in _primitives(handles):
        screen, depth = project(pts)
        if np.any(depth <= 0.05):
            continue  # behind or at the camera
        shade = 1.0
        if kind == "tri":
            normal = np.cross(pts[1] - pts[0], pts[2] - pts[0])
            norm = np.linalg.norm(normal)
            if norm == 0.0:
                continue
            # Two-sided Lambert from a light at the camera, with an ambient floor.
            shade = 0.45 + 0.55 * abs(float(normal @ forward)) / float(norm)
        items.append((float(depth.mean()), kind, screen, colour, opacity, shade))
    items.sort(key=lambda item: -item[0])

    image = Image.new("RGB", (width, height), BACKGROUND)
    canvas = ImageDraw.Draw(image, "RGBA")
    for _, kind, screen, colour, opacity, shade in items:
        rgba = tuple(min(255, int(c * shade)) for c in colour[:3]) + (int(255 * opacity),)
        corners = [tuple(map(float, p)) for p in screen]
        if kind == "tri":
            canvas.polygon(corners, fill=rgba)
        elif kind == "arrow":
            canvas.line(corners, fill=rgba, width=4 * SUPERSAMPLE)
            tip, tail = screen[1], screen[0]
            direction = tip - tail
            length = float(np.linalg.norm(direction))
            if length > 1.0:
                d = direction / length
                n = np.array([-d[1], d[0]])
                head = min(12.0 * SUPERSAMPLE, 0.4 * length)
                canvas.polygon(
                    [tuple(tip), tuple(tip - head * d + 0.5 * head * n), tuple(tip - head * d - 0.5 * head * n)],
                    fill=rgba,
                )
        else:
            canvas.line(corners, fill=rgba, width=(1 if kind == "grid" else 2) * SUPERSAMPLE)
    image = image.resize(size, Image.Resampling.LANCZOS)
    out = io.BytesIO()
    image.save(out, format="PNG")
    return out.getvalue()
