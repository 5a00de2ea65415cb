"""The tennis racket (the intermediate axis): any asymmetric body spun about a principal axis, torque-free.

More in docs/app-notes.md (``app.scenes.tennis_racket``).
"""

from __future__ import annotations

import math
from typing import Any

import numpy as np
import trimesh
import viser

from app import controls, draw
from app.drawing.ghost import IntegratorGhost
from app.language.words import keep, mark, say
from app.panel.look import plot_axes, plot_colour
from app.recording.columns import euler_columns, vector_columns
from app.scenes.base import Answer, Scene, register
from app.scenes.wording import amount, listing
from assets import ASSETS, load_mesh, mass_properties
from physics.free_body import FreeBody
from physics.inertia import MassProperties, validate_moments
from physics.rotations import frame_from_axis

SLIDERS = mark("moments from the sliders (a box)")
BODIES = {
    mark("Tennis racket (mesh)"): "tennis_racket",
    mark("T-handle, Dzhanibekov (mesh)"): "t_handle",
    mark("Book (mesh)"): "book",
    SLIDERS: None,
}
AXES = {mark("1 — largest moment"): 0, mark("2 — intermediate (flips)"): 1, mark("3 — smallest moment"): 2}
KINDS = (mark("stable"), mark("unstable"), mark("neutral"))
"""The lecture's words for an axis (:class:`physics.free_body.Stability`'s ``kind``), marked for the
catalogs: a readout says one as a value, translated with it."""
_MOMENTS = "{I1:.4g}, {I2:.4g}, {I3:.4g}"  # numbers alone: written per locale, nothing to translate
HISTORY = 600  # samples of ω kept for the plot
PLOT_EVERY = 12  # frames between plot refreshes: 5 Hz at 60 frames/s (each refresh sends 19 kB)
SYMMETRY_RTOL = 1e-6  # moments closer than this (relative) are equal: a float32 mesh (STL) resolves no more


def snap_symmetric(moments: np.ndarray) -> np.ndarray:
    """Moments ``I1 >= I2 >= I3`` (kg m²) with neighbours equal to :data:`SYMMETRY_RTOL` made exactly equal
    (their mean: the sum, hence the triangle inequality, is kept), so that a cylinder or sphere mesh is
    the symmetric body it stands for and :class:`FreeBody` uses the symmetric solution."""
    m = np.array(moments, dtype=float)
    tol = SYMMETRY_RTOL * m[0]
    if m[0] - m[2] <= tol:
        m[:] = m.mean()
    elif m[0] - m[1] <= tol:
        m[:2] = m[:2].mean()
    elif m[1] - m[2] <= tol:
        m[1:] = m[1:].mean()
    return m


def principal_body(mesh: trimesh.Trimesh, props: MassProperties) -> tuple[np.ndarray, trimesh.Trimesh]:
    """Moments ``I1 >= I2 >= I3`` and the mesh moved into its principal frame (origin at the centre of mass)."""
    moments, axes = props.principal()
    body = mesh.copy()
    body.vertices = (np.asarray(mesh.vertices) - props.center_of_mass) @ axes  # rows: axesᵀ (v − c)
    return moments, body


def box_for_moments(moments: np.ndarray, mass: float = 1.0) -> trimesh.Trimesh:
    """A box whose principal moments (about its centre, axes 1, 2, 3 = x, y, z) are ``moments``.

    ``I1 = M (b² + c²)/12`` etc. give ``a² = 6 (I2 + I3 − I1)/M``; the triangle inequality makes it >= 0.
    """
    i1, i2, i3 = moments
    sq = 6.0 / mass * np.array([i2 + i3 - i1, i1 + i3 - i2, i1 + i2 - i3])
    extents = np.sqrt(np.maximum(sq, 0.0))
    box: trimesh.Trimesh = trimesh.creation.box(extents=np.maximum(extents, 0.01 * extents.max()))
    return box


def separatrix_circles(moments: np.ndarray, n: int = 181) -> np.ndarray:
    """The separatrix on the unit L-sphere seen in the body: ``L² = 2 E I2`` on ``|L| = 1``.

    ``Σ l_i² (1/I_i − 1/I2) = 0`` is the pair of planes ``l3 = ± s l1`` with
    ``s = tan θ = sqrt((1/I2 − 1/I1) / (1/I3 − 1/I2))``, through the intermediate axis. Returns the two
    great circles as line segments, shape (2 (n − 1), 2, 3). With two equal moments (a rod: ``I3 = 0``)
    the pair merges into the one circle of steady rotations about the equal axes (θ written without
    dividing, so it stays defined).
    """
    i1, i2, i3 = moments
    theta = math.atan2(math.sqrt(max((i1 - i2) * i3, 0.0)), math.sqrt(max((i2 - i3) * i1, 0.0)))
    ang = np.linspace(0, 2 * np.pi, n)
    segs = []
    for sign in (1.0, -1.0):
        u = np.array([math.cos(theta), 0.0, sign * math.sin(theta)])
        pts = np.outer(np.cos(ang), u) + np.outer(np.sin(ang), [0.0, 1.0, 0.0])
        segs.append(np.stack([pts[:-1], pts[1:]], axis=1))
    return np.concatenate(segs)


@register
class TennisRacket(Scene):
    name = "tennis_racket"
    title = mark("Tennis racket: the intermediate axis")
    order = 60
    quantities = ("L", "omega", "trace", "axes", "polhode", "guide", "ghost")
    params: controls.ParameterPanel  # made in build()
    caption = mark(
        "**The tennis-racket theorem.** Spin a body with I₁ > I₂ > I₃ about one principal axis, with a small "
        "push off it. About axis 1 or 3 it wobbles; about axis 2 the push grows like exp(λt), "
        "λ = Ω √((I₁ − I₂)(I₂ − I₃)/(I₁ I₃)), and the body flips over and back, again and again. L stays fixed. "
        "Left: L seen from the body, on the L-sphere, with the polhode and the separatrix (see the legend). "
        "A body with two equal moments (a cylinder from the explorer) has no intermediate axis: it precesses "
        "steadily at Ω = ω_s (I⊥ − I_s)/I⊥ and never flips."
    )
    # From above, so the racket spinning flat is seen across its face; the L-sphere beside it on screen.
    camera = ((2.4, -2.6, 2.4), (-0.45, -0.25, 1.0))
    view = (2.4, 1.8)  # the racket, its arrows and the L-sphere
    key_plot = "plot"  # ω₁ω₂ω₃: the flips, one component changing sign, the others dipping
    # Whether (and how often) it flips: the readouts of the linear stability and the measured period, the
    # polhode on the L-sphere, the caption that states the theorem.
    answers = (
        Answer(
            "flip",
            readouts=("stability_readout", "rate_readout", "first_flip_readout", "period_readout"),
            hidden=("polhode", "separatrix", "caption_markdown"),
        ),
    )
    centre = np.array([0.0, 0.0, 1.0])
    sphere_centre = np.array([-1.05, -0.95, 1.0])  # left of the body on screen, clear of it (the GUI is right)
    sphere_radius = 0.33
    size = 1.4  # largest dimension the body is drawn at (m)

    def build(self) -> None:
        self.screen = draw.screen_axes(type(self).camera)  # the view L's and ω's labels are kept apart in
        server, root, gui = self.ctx.server, self.ctx.root, self.ctx.server.gui
        self.handed: dict[str, Any] | None = None  # a body from the inertia explorer
        self._last_source = ""
        self.body = draw.BodyMesh(server, root + "/body", trimesh.creation.box())
        # A child of the body: it turns with it without a message of its own each frame.
        self.frame = draw.PrincipalFrame(server, root + "/body/frame", length=0.6 * self.size, dark=self.ctx.dark)
        self.L_arrow = draw.Arrow(server, root + "/L", "L", label="L")
        self.omega_arrow = draw.Arrow(server, root + "/omega", "omega", label="ω")
        # The L-sphere in body axes: faint sphere, body axes, separatrix, polhode, current L.
        lsphere_axes = draw.PrincipalFrame(
            server, root + "/lsphere_axes", length=1.25 * self.sphere_radius, dark=self.ctx.dark
        )
        lsphere_axes.set_pose(np.eye(3), self.sphere_centre)
        self.sphere_sphere = server.scene.add_icosphere(
            root + "/lsphere_shell",
            radius=self.sphere_radius,
            color=draw.COLOURS["guide"],
            opacity=0.08,
            position=self.sphere_centre,
            cast_shadow=False,
        )
        self.separatrix = server.scene.add_line_segments(
            root + "/separatrix",
            points=np.zeros((2, 2, 3), dtype=np.float32),
            colors=draw.COLOURS["guide"],
            thickness=1.5,
            thickness_units="screen",
        )
        self.polhode = server.scene.add_line_segments(
            root + "/polhode",
            points=np.zeros((2, 2, 3), dtype=np.float32),
            colors=draw.COLOURS["polhode"],
            thickness=3.0,
            thickness_units="screen",
        )
        self.L_dot = server.scene.add_icosphere(root + "/L_dot", radius=0.03, color=draw.COLOURS["L"])
        self.lsphere_label = draw.add_label(
            server,
            root + "/lsphere_label",
            mark("L seen from the body"),
            position=self.sphere_centre + [0, 0, 1.3 * self.sphere_radius],
        )

        self.source = controls.refusable_dropdown(
            self.ctx,
            mark("Body"),
            tuple(BODIES),
            mark("Tennis racket (mesh)"),
            apply=lambda: self.params.offer({}),
        )
        self.axis = controls.refusable_dropdown(
            self.ctx,
            mark("Spin about principal axis"),
            tuple(AXES),
            mark("2 — intermediate (flips)"),
            apply=lambda: self.params.offer({}),
        )
        self.params = controls.ParameterPanel(
            self.ctx,
            [
                controls.SliderSpec("spin", mark("spin Ω (rad/s)"), 0.5, 20.0, 0.5, 6.0),
                controls.SliderSpec(
                    "log_eps",
                    mark("push off the axis, log₁₀ ε"),
                    -8.0,
                    -0.5,
                    0.5,
                    -3.0,
                    hint=mark("each off-axis component of ω is ε Ω at t = 0 (Ω: the spin about the chosen axis)"),
                ),
                controls.SliderSpec("I1", mark("I₁ (kg m², slider body)"), 0.1, 5.0, 0.1, 3.0),
                controls.SliderSpec("I2", mark("I₂ (kg m², slider body)"), 0.1, 5.0, 0.1, 2.0),
                controls.SliderSpec("I3", mark("I₃ (kg m², slider body)"), 0.1, 5.0, 0.1, 1.0),
            ],
            apply=self.apply,
        )
        self.moments_readout = controls.Readout(self.ctx, mark("I₁, I₂, I₃ (kg m²)"), fmt="{}")
        self.stability_readout = controls.Readout(self.ctx, mark("lecture: this axis is"), fmt="{}")
        self.rate_readout = controls.Readout(self.ctx, mark("growth rate λ (1/s)"))
        self.first_flip_readout = controls.Readout(
            self.ctx, mark("first flip, estimated from the linear growth: ln(1/ε)/λ (s)")
        )
        self.period_readout = controls.Readout(self.ctx, mark("measured flip period (s)"))
        self.plot = gui.add_uplot(
            data=(np.zeros(2), np.zeros(2), np.zeros(2), np.zeros(2)),
            series=(
                viser.uplot.Series(label=mark("t (s)")),
                viser.uplot.Series(
                    label="ω₁", stroke=plot_colour(draw.hex_colour("vermillion"), self.ctx.dark), width=2
                ),
                viser.uplot.Series(
                    label="ω₂", stroke=plot_colour(draw.hex_colour("bluish_green"), self.ctx.dark), width=2
                ),
                viser.uplot.Series(label="ω₃", stroke=plot_colour(draw.hex_colour("blue"), self.ctx.dark), width=2),
            ),
            title=mark("ω in body axes (rad/s)"),
            axes=plot_axes(),
            scales={"x": viser.uplot.Scale(time=False, auto=True), "y": viser.uplot.Scale(auto=True)},
            aspect=1.6,
        )
        self._hist_t = np.zeros(HISTORY)
        self._hist_w = np.zeros((HISTORY, 3))
        self._hist_n = 0
        self._frames = 0
        self.trace = draw.Trace(server, root + "/trace", capacity=800)
        self.drift = controls.InvariantDrift(self.ctx, ("E", "|L|"), (draw.hex_colour("black"), draw.hex_colour("L")))
        self.ghost = IntegratorGhost(self.ctx, root + "/ghost", trimesh.creation.box())
        self.traces: list[Any] = [self.trace, self.drift, self.ghost]
        self.apply(self.params.values)

    def columns(self, state: dict[str, Any]) -> dict[str, float]:
        R, w = state["R"], state["omega_body"]
        return {
            **euler_columns(R),
            **vector_columns("omega", w, "rad/s", "123"),
            **vector_columns("L", R @ (self.moments * w), "kg m^2/s"),
            "E (J)": self._invariants(w)["E"][0],
        }

    def _invariants(self, omega_body: np.ndarray) -> dict[str, tuple[float, float]]:
        L_body = self.moments * omega_body
        energy, size = 0.5 * float(omega_body @ L_body), float(np.linalg.norm(L_body))
        return {"E": (energy, self._energy_scale), "|L|": (size, self.L_norm)}

    # -- parameters --------------------------------------------------------------------------------
    def _body(self, values: dict[str, float]) -> tuple[np.ndarray, trimesh.Trimesh, str]:
        """Moments (I1 >= I2 >= I3), the mesh in the principal frame, and a description."""
        choice = self.source.value
        if self.handed is not None and choice == self.handed["label"]:
            moments, mesh = principal_body(self.handed["mesh"], self.handed["mass_properties"])
            return moments, mesh, self.handed["label"]
        asset = BODIES.get(choice)
        if asset is not None:
            moments, mesh = principal_body(load_mesh(asset), mass_properties(asset))
            return moments, mesh, ASSETS[asset].label
        moments = validate_moments([values["I1"], values["I2"], values["I3"]])
        if not (moments[0] >= moments[1] >= moments[2]):
            raise ValueError(
                say(
                    "order the moments I₁ ≥ I₂ ≥ I₃ (got {moments}): the axes are numbered by their moment",
                    moments=str(moments.tolist()),
                )
            )
        return moments, box_for_moments(moments), mark("box")

    def apply(self, values: dict[str, float]) -> None:
        moments, mesh, label = self._body(values)
        moments = snap_symmetric(moments)
        model = FreeBody(moments)  # symmetric bodies (and a rod, I3 = 0) are solved exactly too
        axis = AXES[self.axis.value]
        spin, eps = values["spin"], 10.0 ** values["log_eps"]
        omega0 = np.full(3, eps * spin)
        omega0[axis] = spin
        L_body = moments * omega0
        self.attitude0 = frame_from_axis(L_body).T  # L along +z in space
        self.model, self.omega0, self.moments, self.axis_index, self.eps = model, omega0, moments, axis, eps
        self.motion = model.trajectory(omega0, self.attitude0)  # solved once: a frame only evaluates it
        self.L_space = self.attitude0 @ L_body
        self.L_norm = float(np.linalg.norm(L_body))
        self._energy_scale = 0.5 * float(omega0 @ L_body)
        scale = self.size / float(np.max(np.ptp(mesh.vertices, axis=0)))
        drawn = mesh.copy()
        drawn.apply_scale(scale)  # type: ignore[no-untyped-call]  # trimesh does not annotate it
        self.body.set_mesh(drawn)
        self.ghost.start_free(moments, self.motion, drawn)
        self.mesh_scale = scale
        # Past the racket's half-length (0.5 size) and its label still in the view (Scene.view, 0.9 m above).
        self.L_scale = 0.55 * self.size / self.L_norm
        self.omega_scale = 0.55 * self.size / float(np.linalg.norm(omega0))
        # Readouts: lecture's linear stability, and the flip period measured from the exact ω(t).
        stab = model.stability(axis, spin)
        self.stability = stab
        symmetric = bool(moments[0] == moments[1] or moments[1] == moments[2])
        self.precession = model.precession_rates(omega0) if symmetric else None
        self.moments_readout.set(say(_MOMENTS, I1=moments[0], I2=moments[1], I3=moments[2]))
        if self.precession is not None:
            # No intermediate axis: ω turns steadily about the symmetry axis (lecture's Ω), no flip.
            self.stability_readout.set(say("{kind} (two equal moments: it precesses, never flips)", kind=stab.kind))
            self.rate_readout.handle.label = mark("body precession Ω = ω_s (I⊥ − I_s)/I⊥ (rad/s)")
            self.rate_readout.set(self.precession.body)
            self.period_readout.handle.label = mark("measured precession period (s)")
        else:
            self.stability_readout.set(
                say("{kind} (flips)", kind=stab.kind)
                if stab.kind == "unstable"
                else say("{kind} (wobbles)", kind=stab.kind)
            )
            self.rate_readout.handle.label = (
                mark("growth rate λ (1/s)") if stab.kind == "unstable" else mark("wobble frequency (rad/s)")
            )
            self.rate_readout.set(stab.rate)
            self.period_readout.handle.label = (
                mark("measured flip period (s)") if stab.kind == "unstable" else mark("measured wobble period (s)")
            )
        self.first_flip_readout.set(
            math.log(1.0 / eps) / stab.rate if stab.kind == "unstable" else mark("— (a stable axis does not flip)")
        )
        self.flip_period = self.measured_flip_period()
        self.period_readout.set(self.flip_period)
        # Polhode: L/|L| in body axes over one period of ω.
        period = model.period(omega0)
        span = period if math.isfinite(period) else 20.0 / max(stab.rate, 1e-3)
        w = model.omega(omega0, np.linspace(0.0, span, 721))
        l_hat = w * moments
        l_hat /= np.linalg.norm(l_hat, axis=1, keepdims=True)
        pts = self.sphere_centre + 1.01 * self.sphere_radius * l_hat
        self.polhode.points = np.stack([pts[:-1], pts[1:]], axis=1).astype(np.float32)
        sep = self.sphere_centre + 1.005 * self.sphere_radius * separatrix_circles(moments)
        self.separatrix.points = sep.astype(np.float32)
        self.separatrix.visible = bool(moments[0] != moments[2])  # a sphere: every axis is steady, no separatrix
        self.description = label
        self._last_source = self.source.value
        self.ctx.restart()

    def measured_flip_period(self) -> float:
        """Period of ω, measured from the exact ω(t) (time between every other sign change of ω along
        the axis it flips about; for a stable axis, of an off-axis component; for a symmetric body, of a
        component across the symmetry axis). inf if none."""
        period = self.model.period(self.omega0)
        if not math.isfinite(period):
            return float("inf")
        t = np.linspace(0.0, 2.2 * period, 4001)
        w = self.model.omega(self.omega0, t)
        if self.precession is not None:
            k = (self.precession.symmetry_axis + 1) % 3
        else:
            k = self.axis_index if self.stability.kind == "unstable" else (self.axis_index + 1) % 3
        s = w[:, k]
        idx = np.nonzero(np.signbit(s[:-1]) != np.signbit(s[1:]))[0]
        if len(idx) < 3:
            return float("inf")
        # Linear interpolation of each crossing; a full period spans two crossings.
        tc = t[idx] - s[idx] * (t[idx + 1] - t[idx]) / (s[idx + 1] - s[idx])
        return float(np.mean(tc[2:] - tc[:-2]))

    def describe(self, state: dict[str, Any]) -> str:
        spun = say(
            "Intermediate axis, {body} (moments {moments}), spun at {spin} about axis {axis}",
            body=self.description,
            moments=listing(tuple(self.moments), "kg m²"),
            spin=amount(float(self.omega0[self.axis_index]), "rad/s"),
            axis=self.axis_index + 1,
        )
        period = amount(self.flip_period, "s")
        if "flip" in self.held:  # a class question asks what it does next
            return say("{spun}: what it does next is the class question.", spun=spun)
        if self.precession is not None:
            return say(
                "{spun}: two equal moments, so ω precesses at {rate} in the body, every {period}, and never flips.",
                spun=spun,
                rate=amount(self.precession.body, "rad/s"),
                period=period,
            )
        if self.stability.kind == "unstable":
            return say(
                "{spun}, the intermediate one: it flips over and back every {period}, growing at {rate}.",
                spun=spun,
                period=period,
                rate=amount(self.stability.rate, "1/s"),
            )
        return say("{spun}, a stable one: it wobbles every {period} and never flips.", spun=spun, period=period)

    def accept(self, payload: Any) -> None:
        """Take a body from another scene: ``{"label", "mesh", "mass_properties"}``."""
        # An option of the Body dropdown for as long as the scene lives: kept translatable.
        label = keep(say("{label} (from the explorer)", label=payload["label"]))
        self.handed = {"label": label, "mesh": payload["mesh"], "mass_properties": payload["mass_properties"]}
        self.source.options = (*BODIES, label)
        previous = self.source.value
        self.source.value = label
        try:
            self.apply(self.params.values)
        except ValueError:
            self.source.value = previous
            raise

    def reset(self) -> None:
        super().reset()
        self._hist_n = 0

    def vectors(self, state: dict[str, Any]) -> dict[str, Any]:
        R, w = state["R"], state["omega_body"]
        # The racket has no symmetry axis: the axis it was spun about stands for it (it is what flips).
        return {"L": self.L_space, "ω": R @ w, "symmetry axis": R[:, self.axis_index]}

    def rewind(self, t: float) -> None:
        super().rewind(t)
        # The ω plot keeps its samples up to t (they are in time order, oldest first).
        n = min(self._hist_n, HISTORY)
        order = np.arange(self._hist_n - n, self._hist_n) % HISTORY
        self._hist_n -= n - int(np.count_nonzero(self._hist_t[order] <= t))

    # -- the state --------------------------------------------------------------------------------
    def compute(self, t: float, dt: float) -> dict[str, Any]:
        now = self.motion.at(t)
        return {"R": now.attitude, "omega_body": now.omega, "t": t}

    def draw(self, state: dict[str, Any]) -> None:
        R, w, c = state["R"], state["omega_body"], self.centre
        self.body.set_pose(R, c)
        self.L_arrow.set(self.L_space * self.L_scale, c)
        self.omega_arrow.set(R @ w * self.omega_scale, c, apart_from=self.L_arrow, screen=self.screen)
        l_hat = self.moments * w / self.L_norm
        draw.move(self.L_dot, self.sphere_centre + 1.02 * self.sphere_radius * l_hat)
        # The tip of the spin axis traces its flips in space.
        self.trace.append(c + 0.5 * self.size * R[:, self.axis_index], state["t"])
        # ½ ω·L and |L| in the body: constant through every flip.
        self.drift.add(state["t"], lambda: self._invariants(w))
        self.ghost.follow(state["t"], lambda Rg: (Rg, c))
        t = state["t"]
        if self._hist_n == 0 or t != self._hist_t[(self._hist_n - 1) % HISTORY]:
            i = self._hist_n % HISTORY
            self._hist_t[i], self._hist_w[i] = t, w
            self._hist_n += 1
        self._frames += 1
        if self._frames % PLOT_EVERY == 0 or self._hist_n < 3:
            n = min(self._hist_n, HISTORY)
            order = np.arange(self._hist_n - n, self._hist_n) % HISTORY
            if n >= 2:
                self.plot.data = (self._hist_t[order], *self._hist_w[order].T)
