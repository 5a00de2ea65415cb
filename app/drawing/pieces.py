"""Kept-handle pieces every scene composes: body meshes, arrows with labels, the principal frame, traces,
cones, a faint sphere, the inertia ellipsoid.

Each is created once (in a scene's ``build``) and then updated *in place* each frame through its kept
viser handle (``points``, ``wxyz``, ``position``, ``scale``, ``visible``); nothing is re-added per frame.
"""

from __future__ import annotations

import math
from typing import Any, Literal

import numpy as np
import trimesh
import viser
from numpy.typing import ArrayLike, NDArray

from app.drawing.meshes import rotation_z_to, wxyz
from app.drawing.palette import COLOURS, colour, instance_colour
from app.guards.wire import send_orientation, send_points, send_position

__all__ = [
    "LABEL_SCALE",
    "add_label",
    "move",
    "BodyMesh",
    "Arrow",
    "PrincipalFrame",
    "Cone",
    "faint_sphere",
    "InertiaEllipsoid",
    "screen_axes",
]


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


def screen_axes(camera: tuple[ArrayLike, ArrayLike]) -> tuple[NDArray[np.float64], NDArray[np.float64]]:
    """The unit vectors (3,) that point right and up on the screen of a camera ``(position, look_at)`` (m)
    with +z up: what a scene's labels are composed for (framing moves the camera along its line of sight
    and pans it, never turns it)."""
    eye, target = np.asarray(camera[0], dtype=float), np.asarray(camera[1], dtype=float)
    forward = (target - eye) / np.linalg.norm(target - eye)
    right = np.cross(forward, (0.0, 0.0, 1.0))
    if np.linalg.norm(right) < 1e-9:  # looking straight down or up: any horizontal right will do
        right = np.array([1.0, 0.0, 0.0])
    right /= np.linalg.norm(right)
    return right, np.cross(right, forward)


LABEL_SCALE = 1.6
"""Every label in the 3D scene at this multiple of viser's size: readable on a projector from the back."""


def move(node: Any, position: NDArray[np.float64] | tuple[float, float, float]) -> None:
    """Put a scene node (a marker, a label) at ``position`` (3,), in m: sent to the browsers only when it
    changed, with the frame's other updates."""
    send_position(node, position)


def add_label(server: viser.ViserServer | viser.ClientHandle, name: str, text: str, **kwargs: Any) -> viser.LabelHandle:
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
        self._vector = (math.nan, math.nan, math.nan)  # what the browsers were last sent
        self._head = -1.0
        self._visible = True
        self._label_visible = True
        self.text = label or quantity  # the label's own text
        self._title = self.text  # what it says now: both arrows' names while another's label joins it
        self._joined: dict[str, bool] = {}  # the arrows drawn apart from this one: whether each names itself here

    def set(
        self,
        vector: ArrayLike,
        origin: ArrayLike = (0.0, 0.0, 0.0),
        *,
        apart_from: Arrow | None = None,
        screen: tuple[NDArray[np.float64], NDArray[np.float64]] | None = None,
    ) -> None:
        """Draw ``vector`` (the quantity, its own units) from ``origin`` (m).

        With ``apart_from`` (an arrow drawn before this one), this arrow's label hangs below and left of its
        tip (above and right is every label's place) while the two tips are within :data:`LABEL_GAP` of the
        longer arrow's length of each other (L and ω lined up): the two labels then sit in opposite corners of
        one point, at any zoom, and neither moves onto the body. With ``screen`` too (the right and up
        vectors of the view the scene is composed for, :func:`screen_axes`), "within" is measured on that
        screen, where two tips far apart in depth can meet, and the first arrow's label then names both
        ("L, ω") while this one's is hidden: two texts at one place on the screen cannot cross.
        """
        # Python floats, not numpy: three arrows a frame in every session, where numpy's per-call cost
        # on 3-vectors was most of the work.
        vx, vy, vz = (float(c) * self.scale for c in np.asarray(vector, dtype=float).reshape(3).tolist())
        ox, oy, oz = np.asarray(origin, dtype=float).reshape(3).tolist()
        length = math.sqrt(vx * vx + vy * vy + vz * vz)
        visible = math.isfinite(length) and length > 1e-6
        anchor: Anchor = LABEL_ANCHOR
        joined = False  # this arrow's name is on the other's label (their tips one place on the screen)
        if visible:
            tip = (ox + vx, oy + vy, oz + vz)
            self.tip = np.array(tip)
            self.length = length
            if apart_from is not None and apart_from.shown:
                near = LABEL_GAP * max(length, apart_from.length)
                ax, ay, az = apart_from.tip.tolist()
                offset = (tip[0] - ax, tip[1] - ay, tip[2] - az)
                if screen is None:
                    if math.sqrt(offset[0] ** 2 + offset[1] ** 2 + offset[2] ** 2) < near:
                        anchor = LABEL_ANCHOR_APART
                else:
                    dx = sum(o * r for o, r in zip(offset, screen[0].tolist(), strict=True))
                    dy = sum(o * u for o, u in zip(offset, screen[1].tolist(), strict=True))
                    joined = math.hypot(dx, dy) < near
            # The arrow's geometry starts at its node's origin; the node is moved to ``origin``
            # (the web client does not follow a change of the start point alone). A constant vector
            # (L of a free body) is not resent.
            if (vx, vy, vz) != self._vector:
                self._vector = (vx, vy, vz)
                send_points(self.handle, np.array([[[0.0, 0.0, 0.0], [vx, vy, vz]]]))
            send_position(self.handle, (ox, oy, oz))  # sent only when it changed
            # Keep the head in proportion for short arrows.
            head = min(6.0 * self.shaft_radius, 0.45 * length)
            if head != self._head:
                self._head = self.handle.head_length = head
        if visible != self._visible:
            self._visible = self.handle.visible = visible
        if apart_from is not None and screen is not None:
            apart_from.join(self.text, joined)
        if self.label is not None:
            shown = visible and not joined
            if self._label_visible != shown:
                self._label_visible = self.label.visible = shown
            if shown:
                send_position(self.label, tip)
                self._hang(anchor)

    def _hang(self, anchor: Anchor) -> None:
        """Hang the label by ``anchor`` (sent only when it changes)."""
        if self.label is not None and anchor != self._anchor:
            self._anchor = self.label.anchor = anchor

    @property
    def shown(self) -> bool:
        """Whether the arrow is drawn (a vector too short or not finite is hidden)."""
        return self._visible

    def join(self, name: str, joined: bool) -> None:
        """Let this arrow's label name the arrow ``name`` too (``joined``) or not: "L, ω", "L, ω, τ"."""
        self._joined[name] = joined
        self.name_label(", ".join([self.text, *(other for other, on in self._joined.items() if on)]))

    def name_label(self, title: str) -> None:
        """Let the label say ``title`` (sent only when it changes)."""
        if self.label is not None and title != self._title:
            self._title = self.label.text = title


class PrincipalFrame(_Posed):
    """The principal axes e1, e2, e3 of the body as lines (e3, the symmetry axis, drawn longest): black, light
    grey in the dark look (``dark``); in another quantity's colour for another point's axes (``quantity``,
    e.g. the explorer's pivot).

    Not viser's RGB frame: red and green already mean ω and the body cone in every scene.
    """

    def __init__(
        self,
        server: viser.ViserServer,
        name: str,
        *,
        length: float = 0.6,
        thickness: float = 3.0,
        quantity: str = "axes",
        dark: bool = False,
    ) -> None:
        ends = np.diag([0.8 * length, 0.8 * length, length])
        points = np.stack([-ends, ends], axis=1)  # each axis through the origin, both ways
        self.handle = server.scene.add_line_segments(
            name,
            points=points.astype(np.float32),
            colors=colour(quantity, dark),
            thickness=thickness,
            thickness_units="screen",
        )


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
        q = wxyz(rotation_z_to(a / n))
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
