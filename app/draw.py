"""Shared drawing pieces for every scene: body meshes, arrows, the principal frame, traces, cones, labels.

Every piece is created once (in a scene's ``build``) and then updated *in place* each frame by assigning
to the kept viser handle (``points``, ``wxyz``, ``position``, ``scale``, ``visible``); nothing is
re-added per frame. Each physical quantity has one colour in every scene (:data:`COLOURS`), and
:func:`legend_html` draws the legend for the quantities a scene shows.

Attitudes come from ``physics/`` as rotation matrices (body to space) or scipy quaternions
``(x, y, z, w)``; :func:`wxyz` is the one place where they become viser's ``(w, x, y, z)``.
"""

from __future__ import annotations

import math
from dataclasses import dataclass
from typing import Any, Literal

import numpy as np
import trimesh
import viser
from numpy.typing import ArrayLike, NDArray
from scipy.spatial.transform import Rotation

from app.wire import send_orientation, send_points, send_position

__all__ = [
    "OKABE_ITO",
    "COLOURS",
    "hex_colour",
    "instance_colour",
    "shown_colour",
    "LABELS",
    "wxyz",
    "legend_html",
    "light",
    "BodyMesh",
    "Arrow",
    "PrincipalFrame",
    "Trace",
    "Cone",
    "Caption",
    "faint_sphere",
    "InertiaEllipsoid",
    "top_mesh",
    "cylinder_mesh",
]

OKABE_ITO: dict[str, tuple[int, int, int]] = {
    "orange": (230, 159, 0),
    "sky_blue": (86, 180, 233),
    "bluish_green": (0, 158, 115),
    "yellow": (240, 228, 66),
    "blue": (0, 114, 178),
    "vermillion": (213, 94, 0),
    "reddish_purple": (204, 121, 167),
    "black": (0, 0, 0),
}
"""Okabe & Ito (2008), *Color Universal Design*: eight colours that stay distinct under every common
colour-vision deficiency. Every quantity below takes one of them; the body and the guides are greys."""

# One colour per quantity, the same in every scene (RGB 0-255); the legend shows exactly these, and
# tests/app/test_palette.py checks that every node a scene sends is drawn in one of them.
COLOURS: dict[str, tuple[int, int, int]] = {
    "L": OKABE_ITO["orange"],  # angular momentum
    "omega": OKABE_ITO["blue"],  # angular velocity
    "torque": OKABE_ITO["reddish_purple"],  # torque
    "trace": OKABE_ITO["vermillion"],  # trace of the symmetry-axis tip
    "polhode": OKABE_ITO["bluish_green"],  # the polhode: the path L draws in the body (no body cone there)
    "body_cone": OKABE_ITO["bluish_green"],  # body cone
    "space_cone": OKABE_ITO["sky_blue"],  # space cone
    "path": (96, 96, 96),  # path of the centre of mass: dark grey
    "axes": OKABE_ITO["black"],  # principal axes e1, e2, e3 (not RGB: the quantities have those colours)
    "body": (92, 105, 126),  # the body: slate, opaque, 3.7-7.8:1 light and 3.2-5.0:1 dark (docs/look.md)
    "impulse": OKABE_ITO["vermillion"],  # an impulse (strike); the pendulum shows no trace
    "reaction": OKABE_ITO["reddish_purple"],  # a constraint's reaction; the pendulum shows no torque
    "ghost": OKABE_ITO["black"],  # the body moved by an integrator: translucent (GHOST_OPACITY), a grey shadow
    "pivot": OKABE_ITO["black"],  # a fixed point or axle (the pendulum's), the explorer's point the tensor is about
    "ellipsoid": OKABE_ITO["yellow"],  # the inertia ellipsoid, translucent
    "guide": (150, 150, 150),  # construction lines: spheres, equators, the separatrix
}


GHOST_OPACITY = 0.35
"""Opacity of the integrator's ghost body (app.ghost), and of its swatch in the legend."""

SWATCH_OPACITY: dict[str, float] = {"ghost": GHOST_OPACITY}
"""Quantities drawn translucent whose legend swatch is shown as they look (the cones and the ellipsoid have
rims or are large enough to read at full colour)."""


def hex_colour(name: str) -> str:
    """``#rrggbb`` of a quantity's colour (a key of :data:`COLOURS`) or of an :data:`OKABE_ITO` name, for
    plots and HTML."""
    return _rgb_hex(COLOURS[name] if name in COLOURS else OKABE_ITO[name])


# Legend text per quantity (Unicode: viser's markdown has no LaTeX).
LABELS: dict[str, str] = {
    "L": "L — angular momentum (fixed in space without torque)",
    "omega": "ω — angular velocity",
    "torque": "τ — torque",
    "trace": "trace of the axis tip (a top's symmetry axis, the racket's spin axis; ω's tip in a body view)",
    "polhode": "polhode: the path of L seen from the body, on the L-sphere",
    "body_cone": "body cone (turns with the body)",
    "space_cone": "space cone (fixed about L)",
    "path": "path of the centre of mass",
    "axes": "principal axes e₁, e₂, e₃ (e₃ longest)",
    "body": "the body",
    "impulse": "J — impulse",
    "reaction": "pivot reaction",
    "ghost": "ghost (translucent) — the body moved by the integrator of “Compare with integrator”",
    "pivot": "pivot — the fixed axle, or the point the tensor is taken about (and its lever to the CM)",
    "ellipsoid": "inertia ellipsoid (long where the moment is small)",
    "guide": "guides (the sphere the axis tip moves on, the L-sphere, equators, the separatrix)",
}


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


def _rgb_hex(rgb: tuple[int, int, int]) -> str:
    return "#{:02x}{:02x}{:02x}".format(*rgb)


def instance_colour(quantity: str) -> tuple[int, int, int]:
    """What to send as an arrow's colour so that the page shows ``COLOURS[quantity]``.

    viser's client reads the per-instance colours of batched meshes (arrows; ``new THREE.Color(r, g, b)``
    in its ``BatchedMeshBase.tsx``) as *linear* RGB, but a mesh's or a line's colour as sRGB. Sent as it
    is, an arrow's colour comes out washed out (dark blue shows as sky blue, red as pink); so it goes
    out converted to linear light (IEC 61966-2-1's sRGB transfer function), and the page converts it
    back to within one level in 255.
    """
    c = np.asarray(COLOURS[quantity], dtype=float) / 255.0
    linear = np.where(c <= 0.04045, c / 12.92, ((c + 0.055) / 1.055) ** 2.4)
    r, g, b = (int(v) for v in np.rint(255.0 * linear))
    return (r, g, b)


def shown_colour(sent: ArrayLike) -> tuple[int, int, int]:
    """The sRGB colour a page shows for an arrow colour ``sent`` (the inverse of :func:`instance_colour`)."""
    c = np.asarray(sent, dtype=float) / 255.0
    srgb = np.where(c <= 0.0031308, 12.92 * c, 1.055 * c ** (1 / 2.4) - 0.055)
    r, g, b = (int(v) for v in np.rint(255.0 * srgb))
    return (r, g, b)


def legend_html(quantities: tuple[str, ...] | list[str]) -> str:
    """HTML legend: a coloured swatch and a name for each quantity key of :data:`COLOURS`."""
    rows = []
    for key in quantities:
        colour = _rgb_hex(COLOURS[key])
        # A translucent quantity: its colour at its opacity inside an outline of the full colour (the ghost's
        # swatch would otherwise be the guides' grey).
        opacity = (
            f";background:rgba({','.join(str(c) for c in COLOURS[key])},{SWATCH_OPACITY[key]})"
            f";box-shadow:inset 0 0 0 1px {colour}"
            if key in SWATCH_OPACITY
            else ""
        )
        rows.append(
            f'<div style="display:flex;align-items:center;gap:6px;margin:1px 0">'
            f'<span style="display:inline-block;width:22px;height:6px;border-radius:3px;background:{colour}{opacity}">'
            f"</span>{LABELS[key]}</div>"
        )
    return '<div class="rbl-legend">' + "".join(rows) + "</div>"


def light(scene: Any, dark: bool = False) -> None:
    """Light a scene so that a surface facing the viewer shows its colour as the legend does.

    viser's defaults (a warehouse environment map plus a directional light of intensity 3) wash the
    colours out: amber turns pale yellow, red turns pink. three.js's physically based lights give a
    Lambertian surface its own colour under an ambient intensity of π, so the scene gets 0.6 π of ambient
    light and 0.55 π from a light above and in front (faces towards it a little brighter than the legend,
    faces away at 0.6 of it, in linear light): solid bodies keep their shading, colours keep their hue.
    Against the dark look's near-black background the faces away from the light need more: 1.15 π of
    ambient and 0.4 π of key light keep the slate body above 3:1: measured 3.2 to 5.0:1 in the dark look and
    3.7 to 8.0:1 in the light one, every scene (docs/look.md, written by docs/look.py, checked by
    tests/browser/test_look.py).
    """
    ambient, key = (1.15, 0.4) if dark else (0.6, 0.55)
    scene.configure_environment_map(hdri=None)
    scene.configure_default_lights(enabled=False)
    scene.add_light_ambient("/lights/ambient", intensity=ambient * math.pi)
    scene.add_light_directional("/lights/key", intensity=key * math.pi, position=(2.0, -3.0, 5.0))


def _rotation_z_to(direction: NDArray[np.float64]) -> NDArray[np.float64]:
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
    cone.apply_transform(trimesh.transformations.rotation_matrix(math.pi, [1, 0, 0]))
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
    return trimesh.creation.cylinder(radius=radius, height=length, sections=sections)


class _Posed:
    """A node placed by an attitude and a position; only what changed is sent."""

    handle: Any

    def set_pose(self, attitude: ArrayLike, position: ArrayLike = (0.0, 0.0, 0.0)) -> None:
        """Place the body: ``attitude`` (3, 3) body-to-space or scipy quaternion (4,); position (3,), m."""
        send_orientation(self.handle, wxyz(attitude))
        send_position(self.handle, np.asarray(position, dtype=float))  # sent only when it changed


class BodyMesh(_Posed):
    """A body drawn from any ``trimesh.Trimesh`` (rod, cylinder, sphere, box, asset, upload).

    The mesh is given in body coordinates (principal frame, origin at the body's reference point);
    :meth:`set_pose` places it with a body-to-space attitude and a position.
    """

    def __init__(
        self,
        server: viser.ViserServer,
        name: str,
        mesh: trimesh.Trimesh,
        *,
        colour: tuple[int, int, int] = COLOURS["body"],
        opacity: float | None = None,
        flat_shading: bool = True,
    ) -> None:
        self.handle = server.scene.add_mesh_simple(
            name,
            vertices=np.asarray(mesh.vertices, dtype=np.float32),
            faces=np.asarray(mesh.faces, dtype=np.uint32),
            color=colour,
            opacity=opacity,
            flat_shading=flat_shading,
        )

    def set_mesh(self, mesh: trimesh.Trimesh) -> None:
        """Replace the geometry in place (a parameter change, not every frame)."""
        self.handle.vertices = np.asarray(mesh.vertices, dtype=np.float32)
        self.handle.faces = np.asarray(mesh.faces, dtype=np.uint32)


LABEL_GAP = 0.25
"""Share of the longer arrow's length within which two arrows' tips count as one place for their labels."""

Anchor = Literal["bottom-left", "top-right"]
"""The two places a label hangs from an arrow's tip."""

LABEL_ANCHOR: Anchor = "bottom-left"
"""Where an arrow's label hangs from its tip: its text above and right of the tip."""

LABEL_ANCHOR_APART: Anchor = "top-right"
"""The same for the second of two arrows whose tips meet: its text below and left, clear of the first's."""


LABEL_SCALE = 1.6
"""Every label in the 3D scene at this multiple of viser's size: readable on a projector from the back."""


def add_label(server: Any, name: str, text: str, **kwargs: Any) -> Any:
    """A label in the 3D scene at :data:`LABEL_SCALE` (the arrows', the markers' and the guides' alike)."""
    return server.scene.add_label(name, text, font_screen_scale=LABEL_SCALE, **kwargs)


class Arrow:
    """One arrow (L, ω, torque, ...) kept as a viser handle and moved in place.

    ``scale`` converts the quantity's units to metres on screen (e.g. 0.2 m per kg m²/s); the caption of a
    scene says which. A zero or non-finite vector hides the arrow.
    """

    def __init__(
        self,
        server: viser.ViserServer,
        name: str,
        quantity: str,
        *,
        scale: float = 1.0,
        shaft_radius: float = 0.03,
        label: str | None = None,
    ) -> None:
        self.quantity = quantity
        self.scale = float(scale)
        self.shaft_radius = shaft_radius
        self.handle = server.scene.add_arrows(
            name,
            points=np.array([[[0.0, 0.0, 0.0], [0.0, 0.0, 1e-3]]]),
            colors=instance_colour(quantity),
            shaft_radius=shaft_radius,
            head_radius=2.4 * shaft_radius,
            head_length=6.0 * shaft_radius,
        )
        self.label = add_label(server, name + "_label", label or quantity, anchor=LABEL_ANCHOR) if label else None
        self.tip = np.zeros(3)
        self.length = 0.0  # of the arrow last drawn, m
        self._anchor: Anchor = LABEL_ANCHOR
        self._vector = np.full(3, np.nan)  # what the browsers were last sent
        self._head = -1.0
        self._visible = True
        self._label_visible = True

    def set(self, vector: ArrayLike, origin: ArrayLike = (0.0, 0.0, 0.0), *, apart_from: Arrow | None = None) -> None:
        """Draw ``vector`` (the quantity, its own units) from ``origin`` (m).

        With ``apart_from`` (an arrow drawn before this one), this arrow's label hangs below and left of its
        tip (above and right is every label's place) while the two tips are within :data:`LABEL_GAP` of the
        longer arrow's length of each other (L and ω lined up): the two labels then sit in opposite corners of
        one point, at any zoom, and neither moves onto the body.
        """
        v = np.asarray(vector, dtype=float) * self.scale
        o = np.asarray(origin, dtype=float)
        length = float(np.linalg.norm(v))
        visible = math.isfinite(length) and length > 1e-6
        anchor: Anchor = LABEL_ANCHOR
        if visible:
            self.tip = o + v
            self.length = length
            if apart_from is not None and apart_from._visible:
                near = LABEL_GAP * max(length, apart_from.length)
                if float(np.linalg.norm(self.tip - apart_from.tip)) < near:
                    anchor = LABEL_ANCHOR_APART
            # The arrow's geometry starts at its node's origin; the node is moved to ``origin``
            # (the web client does not follow a change of the start point alone). A constant vector
            # (L of a free body) is not resent.
            if not np.array_equal(v, self._vector):
                self._vector = v
                send_points(self.handle, np.array([[np.zeros(3), v]]))
            send_position(self.handle, o)  # sent only when it changed
            # Keep the head in proportion for short arrows.
            head = min(6.0 * self.shaft_radius, 0.45 * length)
            if head != self._head:
                self._head = self.handle.head_length = head
        if visible != self._visible:
            self._visible = self.handle.visible = visible
        if self.label is not None:
            if self._label_visible != visible:
                self._label_visible = self.label.visible = visible
            if visible:
                send_position(self.label, self.tip)
                if anchor != self._anchor:  # sent only when it changes
                    self._anchor = self.label.anchor = anchor


class PrincipalFrame(_Posed):
    """The principal axes e1, e2, e3 of the body as black lines (e3, the symmetry axis, drawn longest).

    Not viser's RGB frame: red and green already mean ω and the body cone in every scene.
    """

    def __init__(self, server: viser.ViserServer, name: str, *, length: float = 0.6, thickness: float = 3.0) -> None:
        ends = np.diag([0.8 * length, 0.8 * length, length])
        points = np.stack([-ends, ends], axis=1)  # each axis through the origin, both ways
        self.handle = server.scene.add_line_segments(
            name,
            points=points.astype(np.float32),
            colors=COLOURS["axes"],
            thickness=thickness,
            thickness_units="screen",
        )


TRACE_CHUNK = 32
"""Segments per line-segments node of a :class:`Trace`: a frame rewrites one such node, not the trace."""


class Trace:
    """A bounded trace of a point, drawn as line segments in chunks so that a frame sends one chunk.

    The whole trace used to be resent every frame (1,500 segments: 36 kB a frame, 2 MB/s a browser).
    Here the segments live in chunks of :data:`TRACE_CHUNK`, each its own viser node; a new point adds
    one segment to the newest chunk and only that chunk is sent (768 bytes). When it is full, the oldest
    chunk is emptied and becomes the newest, so the oldest segments drop out a chunk at a time.

    Parameters
    ----------
    capacity : int
        Number of points kept (the oldest drop out); :meth:`resize` changes it. The drawing shows at
        least the last ``capacity`` points and at most :data:`TRACE_CHUNK` − 1 more.
    min_step : float
        A new point closer than this (m) to the last one replaces nothing and is skipped, so a paused or
        slow motion does not fill the buffer with duplicates.
    """

    def __init__(
        self,
        server: viser.ViserServer,
        name: str,
        *,
        quantity: str = "trace",
        capacity: int = 1500,
        thickness: float = 2.5,
        min_step: float = 1e-4,
    ) -> None:
        self._server = server
        self._name = name
        self.quantity = quantity
        self._thickness = thickness
        self.min_step = min_step
        self._chunks: list[viser.LineSegmentsHandle] = []
        self.resize(capacity)

    def resize(self, capacity: int) -> None:
        """Change the number of points kept (re-creates the chunks; the trace restarts)."""
        if capacity < 2:
            raise ValueError(f"a trace needs at least 2 points, got {capacity}")
        self.capacity = int(capacity)
        self._buf = np.zeros((self.capacity, 3))
        self._count = 0
        self._head = 0  # index of the next write
        self.remove()
        length = min(TRACE_CHUNK, self.capacity - 1)
        # One chunk more than the capacity needs: the newest may be nearly empty while the oldest is full.
        n_chunks = -(-(self.capacity - 1) // length) + 1
        self._segments = np.zeros((n_chunks, length, 2, 3), dtype=np.float32)
        self._fill = np.zeros(n_chunks, dtype=int)
        self._newest = 0
        self._chunks = [
            self._server.scene.add_line_segments(
                f"{self._name}/{k}",
                points=self._segments[k],
                colors=COLOURS[self.quantity],
                thickness=self._thickness,
                thickness_units="screen",
                visible=False,
            )
            for k in range(n_chunks)
        ]

    def remove(self) -> None:
        """Remove the trace's nodes from the scene."""
        for chunk in self._chunks:
            chunk.remove()
        self._chunks = []

    def clear(self) -> None:
        self._count = 0
        self._head = 0
        self._fill[:] = 0
        for chunk in self._chunks:
            if chunk.visible:
                chunk.visible = False

    def points(self) -> NDArray[np.float64]:
        """The kept points, oldest first, shape (k, 3)."""
        if self._count < self.capacity:
            return self._buf[: self._count].copy()
        return np.roll(self._buf, -self._head, axis=0)

    def drawn_segments(self) -> NDArray[np.float32]:
        """The segments on screen, oldest first, shape (k, 2, 3) (what the browsers were sent)."""
        n = len(self._chunks)
        order = [(self._newest + 1 + i) % n for i in range(n)]
        return np.concatenate([self._segments[k, : self._fill[k]] for k in order])

    def append(self, point: ArrayLike) -> None:
        """Add a point (m): one segment from the previous point, sent with its chunk only."""
        p = np.asarray(point, dtype=float)
        previous = self._buf[(self._head - 1) % self.capacity]
        if self._count and np.linalg.norm(p - previous) < self.min_step:
            return
        self._buf[self._head] = p
        self._head = (self._head + 1) % self.capacity
        self._count = min(self._count + 1, self.capacity)
        if self._count < 2:
            return
        k = self._newest
        if self._fill[k] == self._segments.shape[1]:
            k = self._newest = (k + 1) % len(self._chunks)  # the oldest chunk becomes the newest
            self._fill[k] = 0
        f = self._fill[k]
        self._segments[k, f, 0] = previous
        self._segments[k, f, 1] = p
        self._segments[k, f + 1 :] = p  # unused segments collapse onto the newest point (invisible)
        self._fill[k] = f + 1
        chunk = self._chunks[k]
        send_points(chunk, self._segments[k])
        if not chunk.visible:
            chunk.visible = True


class Cone:
    """A translucent cone with its apex at a point, drawn from one unit mesh scaled in place.

    :meth:`set` takes the cone's axis direction, half-angle and slant length; a degenerate cone (angle
    0 or non-finite) is hidden.
    """

    def __init__(
        self, server: viser.ViserServer, name: str, quantity: str, *, opacity: float = 0.25, sections: int = 64
    ):
        self.quantity = quantity
        ang = np.linspace(0.0, 2 * np.pi, sections, endpoint=False)
        # Unit cone: apex at the origin, base circle of radius 1 at z = 1 (open: no base disc).
        vertices = np.vstack([[0.0, 0.0, 0.0], np.column_stack([np.cos(ang), np.sin(ang), np.ones_like(ang)])])
        faces = np.array([[0, 1 + i, 1 + (i + 1) % sections] for i in range(sections)], dtype=np.uint32)
        self.handle = server.scene.add_mesh_simple(
            name,
            vertices=vertices.astype(np.float32),
            faces=faces,
            color=COLOURS[quantity],
            opacity=opacity,
            side="double",
            cast_shadow=False,
            receive_shadow=False,
        )
        # A child of the cone: it follows the cone's pose, so a frame moves one node, not two. Not its scale:
        # viser's client scales a mesh's own geometry, not the group its children hang from (BasicMesh.tsx), so
        # the rim is given the same scale (it was drawn as the unit circle, a metre from the axis).
        self.rim = server.scene.add_line_segments(
            name + "/rim",
            points=np.stack([vertices[1:], np.roll(vertices[1:], -1, axis=0)], axis=1).astype(np.float32),
            colors=COLOURS[quantity],
            thickness=2.0,
            thickness_units="screen",
        )
        self._apex: NDArray[np.float64] | None = None
        self._scale: tuple[float, float, float] | None = None
        self._shown = True

    def set(self, axis: ArrayLike, half_angle: float, slant: float, apex: ArrayLike = (0.0, 0.0, 0.0)) -> None:
        """Axis (3,) (any length), half-angle (rad), slant length (m), apex (3,) (m)."""
        a = np.asarray(axis, dtype=float)
        n = float(np.linalg.norm(a))
        ok = math.isfinite(n) and n > 0 and math.isfinite(half_angle) and 1e-4 < half_angle < math.pi - 1e-4
        if ok != self._shown:  # the rim, a child, is shown and hidden with the cone
            self._shown = self.handle.visible = ok
        if not ok:
            return
        q = wxyz(_rotation_z_to(a / n))
        r, h = slant * math.sin(half_angle), slant * math.cos(half_angle)
        apex = np.asarray(apex, dtype=float)
        moved = self._apex is None or not np.array_equal(apex, self._apex)
        # A cone of a constant angle and slant is resent only when it really changed (not by roundoff).
        resized = (
            self._scale is None
            or not math.isclose(r, self._scale[0], rel_tol=1e-9)
            or not math.isclose(h, self._scale[2], rel_tol=1e-9)
        )
        self._apex = apex
        send_orientation(self.handle, q)
        # Assign only what changed: each assignment is a message to every browser.
        if resized:  # compared with what was last sent, so a slow drift is sent once it adds up
            self._scale = (r, r, h)
            self.handle.scale = self._scale
            self.rim.scale = self._scale
        if moved:
            send_position(self.handle, apex)


@dataclass
class Caption:
    """A caption in the scene's panel (markdown, Unicode equations) that can be rewritten in place."""

    handle: viser.GuiMarkdownHandle

    @classmethod
    def add(cls, server: viser.ViserServer, text: str) -> Caption:
        return cls(server.gui.add_markdown(text))

    def set(self, text: str) -> None:
        if self.handle.content != text:
            self.handle.content = text


def faint_sphere(
    server: viser.ViserServer, name: str, radius: float, *, opacity: float = 0.08
) -> viser.IcosphereHandle:
    """A faint reference sphere (the axis tip of a top moves on it), with a thin equator."""
    handle = server.scene.add_icosphere(
        name,
        radius=radius,
        color=COLOURS["guide"],
        subdivisions=4,
        opacity=opacity,
        cast_shadow=False,
        receive_shadow=False,
    )
    ang = np.linspace(0, 2 * np.pi, 97)
    ring = radius * np.column_stack([np.cos(ang), np.sin(ang), np.zeros_like(ang)])
    server.scene.add_line_segments(
        name + "_equator",
        points=np.stack([ring[:-1], ring[1:]], axis=1),
        colors=COLOURS["guide"],
        thickness=1.0,
        thickness_units="screen",
    )
    return handle


class InertiaEllipsoid:
    """The inertia ellipsoid ``xᵀ I x = const`` of a body: semi-axes along the principal axes, in
    proportion ``1/√I_i`` (long where the moment is small), drawn translucent from one unit sphere
    scaled in place.

    A zero moment (a rod) would make one semi-axis infinite: it is capped at ``cap`` times the
    shortest, so the drawing stays finite and still shows the direction.
    """

    def __init__(
        self,
        server: viser.ViserServer,
        name: str,
        *,
        colour: tuple[int, int, int] = COLOURS["ellipsoid"],
        opacity: float = 0.25,
        cap: float = 4.0,
    ) -> None:
        self.cap = float(cap)
        self.handle = server.scene.add_icosphere(
            name, radius=1.0, color=colour, subdivisions=4, opacity=opacity, cast_shadow=False, receive_shadow=False
        )

    def semi_axes(self, moments: ArrayLike, largest: float) -> NDArray[np.float64]:
        """Semi-axes (m), shape (3,), for principal ``moments`` (kg m²), the longest equal to ``largest``."""
        m = np.asarray(moments, dtype=float)
        if not np.any(m > 0):
            return np.full(3, float(largest))
        inv = np.where(m > 0, 1.0 / np.sqrt(np.where(m > 0, m, 1.0)), np.inf)
        inv = np.minimum(inv, self.cap * float(np.min(inv)))
        return float(largest) * inv / float(np.max(inv))

    def set(self, moments: ArrayLike, axes: ArrayLike, largest: float, centre: ArrayLike = (0.0, 0.0, 0.0)) -> None:
        """Moments (3,), principal axes as columns (3, 3) (right-handed), longest semi-axis (m), centre (3,)."""
        a, b, c = (float(s) for s in self.semi_axes(moments, largest))
        self.handle.scale = (a, b, c)
        self.handle.wxyz = wxyz(np.asarray(axes, dtype=float))
        self.handle.position = np.asarray(centre, dtype=float)
