"""Inertia explorer: pick or upload a body; see its principal axes, moments and inertia ellipsoid, and the
tensor about a movable pivot by the parallel-axis theorem.

More in docs/app-notes.md (``app.scenes.inertia_explorer``).
"""

from __future__ import annotations

from types import SimpleNamespace
from typing import Any

import numpy as np
import trimesh
import viser

from app import controls, draw
from app.language.words import keep, mark, say
from app.recording.columns import vector_columns
from app.scenes.base import Scene, register
from app.scenes.wording import amount, listing
from app.uploads.reading import NotWatertightError, UploadedBody, body_from_mesh
from app.uploads.worker import body_in_worker
from assets import ASSETS, load_mesh, mass_properties
from physics.inertia import MassProperties, box, point_masses, rod, solid_cylinder, solid_sphere

PRIMITIVES = (
    mark("Rod"),
    mark("Solid sphere"),
    mark("Solid cylinder"),
    mark("Box (L × 2a × a)"),
    mark("Point masses (4, unequal)"),
    mark("Point masses: dumbbell (2 × 0.5 kg)"),
    mark("Point masses: square (4 × 0.25 kg)"),
)
ASSET_CHOICES = {ASSETS[k].label: k for k in ASSETS}
ASSET_WORDS = (
    mark("Tennis racket"),
    mark("T-handle (Dzhanibekov nut)"),
    mark("Spinning top"),
    mark("Baseball bat"),
    mark("Book"),
)
"""The assets' labels (:data:`assets.ASSETS`), marked here for the catalogs: assets/ is below app/ and
knows nothing of its languages; a label changed there without this list is found by the language tests."""
POINT_MASSES = np.array([1.0, 2.0, 1.0, 0.5])  # kg
POINT_POSITIONS = np.array([[0.5, 0.0, 0.0], [-0.5, 0.2, 0.0], [0.0, -0.4, 0.3], [0.1, 0.3, -0.4]])  # × L
POINT_SETS = {  # name prefix -> (masses kg, positions × L)
    "Point masses (4": (POINT_MASSES, POINT_POSITIONS),
    "Point masses: dumbbell": (np.array([1.0, 1.0]), np.array([[0.0, 0.0, 0.5], [0.0, 0.0, -0.5]])),
    "Point masses: square": (
        np.ones(4),
        np.array([[0.5, 0.5, 0.0], [-0.5, 0.5, 0.0], [-0.5, -0.5, 0.0], [0.5, -0.5, 0.0]]),
    ),
}
_MOMENTS = "{I1:.4g}, {I2:.4g}, {I3:.4g}"  # numbers alone: written per locale, nothing to translate
_TWO = "{pivot}\n\n{centre}"  # two tensors' Markdown, one after the other (markup alone)
DISPLAY_SIZE = 1.2  # m: the body is drawn scaled so its largest extent is this
AXES_LENGTH = 0.9  # m: the drawn principal axes (e₁, e₂ at 0.8 of it), longer than half the body's largest extent
ELLIPSOID_CAP = 4.0  # a zero moment (rod) would give an infinite ellipsoid axis: cap at 4× the smallest


def primitive_body(kind: str, a: float, length: float) -> tuple[trimesh.Trimesh, MassProperties]:
    """Display mesh (m) and mass properties (1 kg in total) of a primitive of size ``a`` and ``length``."""
    if kind == "Rod":
        return trimesh.creation.cylinder(radius=length / 150, height=length, sections=16), rod(1.0, length)
    if kind == "Solid sphere":
        return trimesh.creation.icosphere(subdivisions=3, radius=a), solid_sphere(1.0, a)
    if kind == "Solid cylinder":
        return trimesh.creation.cylinder(radius=a, height=length, sections=48), solid_cylinder(1.0, a, length)
    if kind.startswith("Box"):
        extents = [length, 2 * a, a]
        return trimesh.creation.box(extents=extents), box(1.0, extents)
    for prefix, (masses, unit_positions) in POINT_SETS.items():
        if kind.startswith(prefix):
            return _point_set(masses, unit_positions * length, length)
    raise ValueError(f"unknown body {kind!r}")


def _point_set(masses: np.ndarray, pos: np.ndarray, length: float) -> tuple[trimesh.Trimesh, MassProperties]:
    """Balls (volume ∝ mass) on struts to the centre of mass; 1 kg in total."""
    props = point_masses(masses / masses.sum(), pos)
    parts = []
    for m, p in zip(masses / masses.max(), pos):
        ball = trimesh.creation.icosphere(subdivisions=2, radius=0.06 * length * m ** (1 / 3))
        ball.apply_translation(p)
        parts.append(ball)
        if np.linalg.norm(p - props.center_of_mass) > 0:
            parts.append(
                trimesh.creation.cylinder(radius=0.008 * length, segment=[props.center_of_mass, p], sections=8)
            )
    mesh = trimesh.util.concatenate(parts)
    assert isinstance(mesh, trimesh.Trimesh)  # concatenating meshes gives a mesh
    return mesh, props


def tensor_markdown(tensor: np.ndarray, title: str) -> str:
    # Round-off-sized entries (1e-21 next to 1e-2) print as 0 so the structure reads at a glance.
    shown = np.where(np.abs(tensor) < 1e-12 * max(float(np.abs(tensor).max()), 1e-300), 0.0, tensor)
    rows = "\n".join("| " + " | ".join(f"{v: .4g}" for v in row) + " |" for row in shown)
    return say("**{title}** (kg m²)\n\n| x | y | z |\n|---|---|---|\n{rows}", title=title, rows=rows)


@register
class InertiaExplorer(Scene):
    name = "inertia_explorer"
    title = mark("Inertia explorer")
    order = 50  # after the frame's scenes: the heavy top stays the first thing a user sees
    quantities = ("body", "axes", "ellipsoid", "pivot")
    params: controls.ParameterPanel  # made in build()
    caption = keep(  # made once: it must not be forgotten among the frames' readouts
        say(
            "**The inertia tensor.** Pick a body (the shapes weigh 1 kg, the meshes their real mass, "
            "{lightest:.2g} to {heaviest:.2g} kg) "
            "or upload your own mesh. The axes at the centre of mass are the principal axes (labelled 1, 2, 3 "
            "with I₁ ≥ I₂ ≥ I₃); the translucent ellipsoid is the inertia ellipsoid xᵀ I x = const (long where I "
            "is small). Move the pivot by d from the centre of mass: the tensor about it is "
            "I(d) = I_CM + M (d² δ − d dᵀ) (parallel-axis theorem).",
            lightest=min(a.mass for a in ASSETS.values()),
            heaviest=max(a.mass for a in ASSETS.values()),
        )
    )
    camera = ((2.4, -2.4, 2.0), (0.0, 0.0, 1.0))
    view = (1.9, 1.9)  # the body, its principal axes and a pivot up to 0.5 m off
    static = True  # nothing moves: no clock
    centre = np.array([0.0, 0.0, 1.0])  # where the centre of mass is drawn (m)

    def build(self) -> None:
        server, root, gui = self.ctx.server, self.ctx.root, self.ctx.server.gui
        self.uploaded: UploadedBody | None = None
        self.pending_hull: tuple[str, trimesh.Trimesh] | None = None
        self.upload_refusals = 0
        self.closed = False  # set by teardown: an upload parsed after a scene switch is dropped
        self.last_upload_message = ""
        # Opaque (3:1 against what is behind it, docs/look.md); the principal axes reach past the drawn body
        # (at most 0.6 m from its centre of mass, DISPLAY_SIZE / 2) so they show outside it.
        self.body = draw.BodyMesh(server, root + "/body", trimesh.creation.box())
        self.frame = draw.PrincipalFrame(server, root + "/principal", length=AXES_LENGTH, dark=self.ctx.dark)
        self.axis_labels = [draw.add_label(server, f"{root}/axis_label_{i + 1}", f"{i + 1}") for i in range(3)]
        self.ellipsoid = draw.InertiaEllipsoid(server, root + "/ellipsoid", cap=ELLIPSOID_CAP)
        self.pivot_marker = server.scene.add_icosphere(root + "/pivot", radius=0.035, color=draw.COLOURS["pivot"])
        self.pivot_frame = draw.PrincipalFrame(server, root + "/pivot_axes", length=0.4, quantity="pivot")
        self.lever = server.scene.add_line_segments(
            root + "/lever",
            points=np.zeros((1, 2, 3), dtype=np.float32),
            colors=draw.COLOURS["pivot"],
            thickness=2.0,
            thickness_units="screen",
        )

        self.choice = controls.refusable_dropdown(
            self.ctx,
            mark("Body"),
            (*PRIMITIVES, *ASSET_CHOICES),
            mark("Box (L × 2a × a)"),
            apply=lambda: self.params.offer({}),
        )
        self.params = controls.ParameterPanel(
            self.ctx,
            [
                controls.SliderSpec("a", mark("radius / size a (m)"), 0.02, 0.5, 0.01, 0.15),
                controls.SliderSpec("length", mark("length L (m)"), 0.05, 2.0, 0.05, 0.8),
                controls.SliderSpec("px", mark("pivot x from the CM (m)"), -1.0, 1.0, 0.05, 0.4),
                controls.SliderSpec("py", mark("pivot y from the CM (m)"), -1.0, 1.0, 0.05, 0.0),
                controls.SliderSpec("pz", mark("pivot z from the CM (m)"), -1.0, 1.0, 0.05, 0.0),
            ],
            apply=self.apply,
        )
        self.upload = gui.add_upload_button(
            mark("Upload a mesh (STL, OBJ, PLY, GLB)"),
            icon=None,
            hint=mark("watertight, at most 20 MB and 500,000 triangles; metres (or mm)"),
            mime_type=".stl,.obj,.ply,.glb",
        )
        # Not guarded: the file is parsed outside the simulation lock (load_upload takes it to swap the body in).
        controls.take_uploads(self.ctx, self.upload, self.load_upload, self._refuse)
        self.hull_button = gui.add_button(mark("Use its convex hull instead"), visible=False)
        self.hull_button.on_click(self.ctx.guarded(self._use_hull))
        self.spin_button = gui.add_button(mark("Spin it (torque-free)"))
        self.spin_button.on_click(self.ctx.guarded(self._spin_it))
        self.moments_readout = controls.Readout(self.ctx, mark("I₁ ≥ I₂ ≥ I₃ at the CM (kg m²)"), fmt="{}")
        self.pivot_readout = controls.Readout(self.ctx, mark("principal moments about the pivot (kg m²)"), fmt="{}")
        self.note = gui.add_markdown("")
        self.tensor_md = gui.add_markdown("")
        self._last_choice = self.choice.value
        self.apply(self.params.values)

    # -- bodies ------------------------------------------------------------------------------------
    def current_body(self, values: dict[str, float]) -> tuple[str, trimesh.Trimesh, MassProperties]:
        choice = self.choice.value
        if self.uploaded is not None and choice == self._upload_label():
            return self.uploaded.name, self.uploaded.mesh, self.uploaded.mass_properties
        if choice in ASSET_CHOICES:
            key = ASSET_CHOICES[choice]
            return choice, load_mesh(key), mass_properties(key)
        mesh, props = primitive_body(choice, values["a"], values["length"])
        return choice, mesh, props

    def _upload_label(self) -> str:
        return say("Uploaded: {name}", name=self.uploaded.name) if self.uploaded is not None else ""

    def apply(self, values: dict[str, float]) -> None:
        label, mesh, props = self.current_body(values)
        moments, axes = props.principal()
        pivot_offset = np.array([values["px"], values["py"], values["pz"]])
        pivot = props.center_of_mass + pivot_offset
        tensor_pivot = props.tensor_about(pivot)
        pivot_moments, pivot_axes = np.linalg.eigh(tensor_pivot)
        order = np.argsort(-pivot_moments)
        pivot_moments, pivot_axes = pivot_moments[order], pivot_axes[:, order]
        if np.linalg.det(pivot_axes) < 0:
            pivot_axes[:, 2] *= -1
        # Display: the body scaled so its largest extent is DISPLAY_SIZE, its CM at `centre`.
        extent = float(np.max(np.ptp(mesh.vertices, axis=0)))
        scale = DISPLAY_SIZE / max(extent, 1e-9)
        drawn = mesh.copy()
        drawn.apply_translation(-props.center_of_mass)
        drawn.apply_scale(scale)  # type: ignore[no-untyped-call]  # trimesh does not annotate it
        self.body.set_mesh(drawn)
        self.body.set_pose(np.eye(3), self.centre)
        self.frame.set_pose(axes, self.centre)
        for i, lab in enumerate(self.axis_labels):
            lab.position = self.centre + 1.1 * AXES_LENGTH * axes[:, i]
        self.ellipsoid.set(moments, axes, 0.55 * DISPLAY_SIZE, self.centre)
        p_draw = self.centre + scale * pivot_offset
        self.pivot_marker.position = p_draw
        self.pivot_frame.set_pose(pivot_axes, p_draw)
        self.lever.points = np.array([[self.centre, p_draw]], dtype=np.float32)
        self.label, self.mesh, self.props = label, mesh, props
        self.moments, self.axes, self.pivot, self.tensor_pivot = moments, axes, pivot, tensor_pivot
        self.pivot_moments = pivot_moments
        self.display_scale = scale
        self.moments_readout.set(say(_MOMENTS, I1=moments[0], I2=moments[1], I3=moments[2]))
        self.pivot_readout.set(say(_MOMENTS, I1=pivot_moments[0], I2=pivot_moments[1], I3=pivot_moments[2]))
        self.tensor_md.content = say(
            _TWO,
            pivot=tensor_markdown(tensor_pivot, mark("Tensor about the pivot")),
            centre=tensor_markdown(props.tensor, mark("Tensor about the centre of mass")),
        )
        self.note.content = say(
            "**{label}**, {mass:.4g} kg; drawn at {scale:.4g}× its size. Pivot d = {d:.4g} m from the CM: M d² = "
            "{Md2:.4g} kg m².",
            label=controls.markdown_text(label),
            mass=props.mass,
            scale=scale,
            d=float(np.linalg.norm(pivot_offset)),
            Md2=props.mass * float(pivot_offset @ pivot_offset),
        )
        self._last_choice = self.choice.value
        self.ctx.request_redraw()

    # -- uploads -----------------------------------------------------------------------------------
    def load_upload(self, filename: str, content: bytes, client: viser.ClientHandle | None = None) -> bool:
        """Check an uploaded file; on success show it, on refusal keep the previous body and say why.

        Parsing and checking (up to ~1 s for a large file) run outside the simulation lock, so the other
        browsers keep moving; the lock is taken only to swap the new body in (or to refuse it).
        """
        try:
            result: UploadedBody | Exception = body_in_worker(filename, content)
        except Exception as exc:  # noqa: BLE001 - shown to the user by the guarded swap below
            result = exc
        # Guarded: under the lock, any surprise shown to the user who uploaded, then a redraw.
        swap = self.ctx.guarded(lambda _event: self._swap_in(filename, result, client))
        return bool(swap(SimpleNamespace(client=client)))

    def _swap_in(self, filename: str, result: UploadedBody | Exception, client: viser.ClientHandle | None) -> bool:
        if self.closed:  # the user left the scene while the file was being parsed
            return False
        if isinstance(result, NotWatertightError):
            self.pending_hull = (filename, result.hull) if result.hull is not None else None
            self.hull_button.visible = self.pending_hull is not None
        if isinstance(result, ValueError):
            return self._refuse(str(result), client)
        if isinstance(result, Exception):
            raise result
        return self._adopt(result, client)

    def _refuse(self, message: str, client: viser.ClientHandle | None) -> bool:
        self.upload_refusals += 1
        self.last_upload_message = message
        self.ctx.notify(mark("Upload refused — the previous body stays"), message, client=client, error=True)
        return False

    def _use_hull(self, event: Any) -> None:
        if self.pending_hull is None:
            return
        filename, hull = self.pending_hull
        body = body_from_mesh(hull, say("{filename} (convex hull)", filename=filename))
        self._adopt(body, getattr(event, "client", None))

    def _adopt(self, body: UploadedBody, client: viser.ClientHandle | None) -> bool:
        previous = (self.uploaded, self.choice.options, self.choice.value)
        self.uploaded = body
        self.pending_hull = None
        self.hull_button.visible = False
        self.choice.options = (*PRIMITIVES, *ASSET_CHOICES, self._upload_label())
        self.choice.value = self._upload_label()
        try:
            self.apply(self.params.values)
        except ValueError as exc:
            self.uploaded, self.choice.options, self.choice.value = previous
            return self._refuse(str(exc), client)
        self.last_upload_message = body.note
        self.ctx.notify(mark("Mesh loaded"), body.note, client=client)
        return True

    # -- copies (presenter mode's "Explore on my own") ------------------------------------------------
    def snapshot(self) -> dict[str, Any]:
        # An uploaded body is not in the controls: its copy needs the body itself (a state text refuses it).
        return {"uploaded": self.uploaded} if self.uploaded is not None else {}

    def prepare(self, motion: dict[str, Any]) -> None:
        body = motion.get("uploaded")
        if isinstance(body, UploadedBody):  # the Body dropdown's "Uploaded: …" is then a choice here too
            self.uploaded = body
            self.choice.options = (*PRIMITIVES, *ASSET_CHOICES, self._upload_label())

    # -- hand over ---------------------------------------------------------------------------------
    def _spin_it(self, event: Any) -> None:
        # Any body: the torque-free scene also spins symmetric ones (they precess instead of flipping).
        self.ctx.switch_to(
            "tennis_racket", payload={"label": self.label, "mesh": self.mesh, "mass_properties": self.props}
        )

    def teardown(self) -> None:
        with self.ctx.lock:
            self.closed = True

    def describe(self, state: dict[str, Any]) -> str:
        d = float(np.linalg.norm(self.pivot - self.props.center_of_mass))
        return say(
            "Inertia explorer, {body}, {mass}: principal moments {moments} about the centre of mass; about the "
            "pivot {distance} away, {pivot_moments}.",
            body=self.label,
            mass=amount(self.props.mass, "kg"),
            moments=listing(tuple(self.moments), "kg m²"),
            distance=amount(d, "m"),
            pivot_moments=listing(tuple(self.pivot_moments), "kg m²"),
        )

    def compute(self, t: float, dt: float) -> dict[str, Any]:
        return {"t": t}

    def columns(self, state: dict[str, Any]) -> dict[str, float]:
        # A still body: its principal moments at the centre of mass and about the pivot, constant in t.
        return {
            **vector_columns("I", self.moments, "kg m^2", "123"),
            **vector_columns("I_pivot", self.pivot_moments, "kg m^2", "123"),
        }

    def draw(self, state: dict[str, Any]) -> None:
        # A static scene: everything is placed when a parameter changes (apply).
        return None
