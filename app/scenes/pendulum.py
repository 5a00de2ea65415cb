"""Physical pendulum and the centre of percussion: a bat or rod swinging from a pivot, and a strike.

More in docs/app-notes.md (``app.scenes.pendulum``).
"""

from __future__ import annotations

import math
import time
from dataclasses import replace
from typing import Any

import numpy as np
import trimesh

from app import controls, draw
from app.language.words import mark, say
from app.scenes.base import Answer, Scene, register
from app.scenes.wording import amount, angle
from assets import load_mesh, mass_properties
from physics import G
from physics.events import events_between
from physics.inertia import MassProperties, rod
from physics.pendulum import PhysicalPendulum

BODIES = (mark("Baseball bat (mesh)"), mark("Uniform rod 0.84 m, 0.9 kg"))
ROD_LENGTH, ROD_MASS = 0.84, 0.9
HANG_HEIGHT = 1.9  # m: where the knob end is when the pivot slider is 0
AXIS = np.array([1.0, 0.0, 0.0])  # the fixed axis: horizontal, along x
ARROW_SHOW = 1.5  # s of simulation time the strike's arrows stay after the blow...
ARROW_SECONDS = 1.2  # ...and at least this long in wall time, however fast the clock runs
_STRIKE = "{delta:.4g}, {impulse:.4g}"  # numbers alone: written per locale, nothing to translate
wall_clock = time.monotonic  # (a test replaces it)
_FLIP = np.diag([1.0, -1.0, -1.0])  # half turn about x: the body's +z (knob to tip) now points down


def hanging_body(choice: str) -> tuple[trimesh.Trimesh, MassProperties, float]:
    """Mesh and mass properties of the body hanging straight down from its knob end at
    ``(0, 0, HANG_HEIGHT)``, and its length (m)."""
    if choice.startswith("Baseball"):
        mesh, props = load_mesh("baseball_bat"), mass_properties("baseball_bat")
    else:
        mesh = trimesh.creation.cylinder(radius=0.015, height=ROD_LENGTH, sections=24)
        mesh.apply_translation([0.0, 0.0, ROD_LENGTH / 2])
        props = rod(ROD_MASS, ROD_LENGTH).transformed(np.eye(3), [0.0, 0.0, ROD_LENGTH / 2])
    length = float(mesh.bounds[1, 2] - mesh.bounds[0, 2])
    shift = np.array([0.0, 0.0, HANG_HEIGHT])
    placed = mesh.copy()
    placed.apply_transform(np.block([[_FLIP, shift[:, None]], [np.zeros((1, 3)), np.ones((1, 1))]]))
    return placed, props.transformed(_FLIP, shift), length


def swing_amplitude(model: PhysicalPendulum, theta: float, thetadot: float) -> float | None:
    """The amplitude θ_max (rad) of the swing through (θ, θ̇), from the energy: ``cos θ_max = cos θ −
    θ̇² / (2 ω0²)`` (θ̈ = −ω0² sin θ); None past cos θ_max = −1 (over the top) or without a restoring torque."""
    if model.omega0 == 0.0:
        return None
    cos_max = math.cos(theta) - thetadot**2 / (2.0 * model.omega0**2)
    return None if cos_max < -1.0 else math.acos(min(1.0, cos_max))


def swing_period(model: PhysicalPendulum, amplitude: float) -> float:
    """The period (s) of a swing of ``amplitude`` (rad): the small-swing period at zero amplitude."""
    return float(model.period(amplitude)) if amplitude > 0 else model.small_oscillation_period


def _period_text(model: PhysicalPendulum, theta: float, thetadot: float) -> str:
    """The readout "small swings / this swing" (:func:`swing_amplitude`)."""
    small = model.small_oscillation_period
    if model.omega0 == 0.0:
        return mark("no restoring torque: it turns uniformly")
    amplitude = swing_amplitude(model, theta, thetadot)
    if amplitude is None:
        return say("{small:.4g} / over the top: no swing back", small=small)
    return say(_PERIODS, small=small, swing=swing_period(model, amplitude))


_PERIODS = "{small:.4g} / {swing:.4g}"  # numbers alone: written per locale, nothing to translate


CAMERA = ((2.3, -0.8, 1.6), (0.0, 0.0, 1.45))
_forward = np.subtract(CAMERA[1], CAMERA[0])
SCREEN_RIGHT = np.cross(_forward, [0.0, 0.0, 1.0]) / np.linalg.norm(np.cross(_forward, [0.0, 0.0, 1.0]))
"""The horizontal direction the scene's camera draws to the right (its labels sit to either side of the bat)."""
LABEL_OFFSET = 0.08
"""m from a marker's centre to its label: past the marker's radius (0.05 m at most)."""


@register
class Pendulum(Scene):
    name = "pendulum"
    title = mark("Physical pendulum & centre of percussion")
    order = 55
    quantities = ("impulse", "reaction", "path", "pivot")
    params: controls.ParameterPanel  # made in build()
    caption = mark(
        "**Physical pendulum.** I = I_CM + M a⊥² = M k² about the pivot: it swings like a simple pendulum of "
        "length ℓ = k²/a⊥. **Strike!** (arrow J): the pivot pushes back (arrow 'pivot') unless the blow lands "
        "at the centre of percussion, ℓ below the pivot: the bat's sweet spot (the button under *Strike!*)."
    )
    camera = CAMERA
    view = (1.8, 1.8)  # the bat and its swing
    key_plot = "swing_plot"  # θ(t): its period is 2π √(ℓ/g) for small swings
    # The effective length ℓ is the centre of percussion's depth; the period 2π √(ℓ/g) gives it too.
    answers = (
        Answer(
            "centre_of_percussion",
            readouts=("l_readout", "period_readout"),
            hidden=("cop_marker", "cop_label", "cop_button", "swing_plot"),
        ),
    )

    def build(self) -> None:
        server, root, gui = self.ctx.server, self.ctx.root, self.ctx.server.gui
        # Opaque (3:1 against what is behind it, docs/look.md); the markers are wider than the bat (0.033 m
        # at most) so they stand out of it.
        self.body = draw.BodyMesh(server, root + "/body", trimesh.creation.box())
        self.pivot_marker = server.scene.add_icosphere(root + "/pivot", radius=0.03, color=draw.COLOURS["pivot"])
        self.axle = server.scene.add_line_segments(
            root + "/axle",
            points=np.zeros((1, 2, 3), dtype=np.float32),
            colors=draw.COLOURS["pivot"],
            thickness=4.0,
            thickness_units="screen",
        )
        self.cm_marker = server.scene.add_icosphere(
            root + "/cm", radius=0.045, color=draw.colour("path", self.ctx.dark)
        )
        self.cop_marker = server.scene.add_icosphere(root + "/cop", radius=0.05, color=draw.COLOURS["impulse"])
        # The markers' labels in two columns beside the bat (CM and centre of percussion right, the strike
        # point left), each starting clear of its marker: never on the bat, never on each other.
        self.cop_label = draw.add_label(server, root + "/cop_label", mark("centre of percussion"), anchor="center-left")
        self.cm_label = draw.add_label(server, root + "/cm_label", "CM", anchor="center-left")
        self.hit_marker = server.scene.add_icosphere(root + "/hit", radius=0.04, color=draw.COLOURS["impulse"])
        # Both balls are the blow's colour: the labels tell the strike point from the centre of percussion.
        self.hit_label = draw.add_label(server, root + "/hit_label", mark("strike point"), anchor="center-right")
        self.impulse_arrow = draw.Arrow(server, root + "/impulse", "impulse", label="J", shaft_radius=0.02)
        self.reaction_arrow = draw.Arrow(server, root + "/reaction", "reaction", label=mark("pivot"), shaft_radius=0.02)
        self.trace = draw.Trace(server, root + "/trace", quantity="path", capacity=400, dark=self.ctx.dark)
        self.traces: list[Any] = [self.trace]

        self.choice = controls.refusable_dropdown(
            self.ctx, mark("Body"), tuple(BODIES), BODIES[0], apply=lambda: self.params.offer({})
        )
        self.params = controls.ParameterPanel(
            self.ctx,
            [
                controls.SliderSpec("pivot", mark("pivot below the knob end (m)"), 0.0, 0.6, 0.01, 0.08),
                controls.SliderSpec("amplitude", mark("release angle θ₀ (°)"), 0.0, 179.0, 1.0, 30.0),
                controls.SliderSpec("strike", mark("strike point below the pivot (m)"), 0.0, 0.84, 0.001, 0.4),
                controls.SliderSpec("impulse", mark("impulse J (N s)"), 0.1, 5.0, 0.1, 1.0),
            ],
            apply=self.apply,
        )
        self.strike_button = gui.add_button(mark("Strike!"))
        self.strike_button.on_click(self.ctx.guarded(lambda _: self.strike()))
        self.cop_button = gui.add_button(mark("Move the strike point to the centre of percussion"))
        self.cop_button.on_click(
            self.ctx.guarded(
                lambda e: self.params.offer(
                    {"strike": round(self.model.effective_length, 3)}, client=getattr(e, "client", None)
                )
            )
        )
        self.k_readout = controls.Readout(self.ctx, mark("radius of gyration k about the pivot (m)"))
        self.a_readout = controls.Readout(self.ctx, mark("a⊥: pivot to CM (m)"))
        self.l_readout = controls.Readout(self.ctx, mark("effective length ℓ = k²/a⊥ (m)"))
        self.period_readout = controls.Readout(self.ctx, mark("period: small swings / this swing (s)"), fmt="{}")
        self.strike_readout = controls.Readout(
            self.ctx, mark("last strike: Δω (rad/s), |pivot impulse| (N s)"), fmt="{}"
        )
        self.drift = controls.InvariantDrift(self.ctx, ("E",), (draw.hex_colour("black"),))
        self.traces.append(self.drift)
        # The swing in time: its period states ℓ (held back with the centre of percussion, as the period is).
        self.swing = controls.TimePlot(self.ctx, mark("The swing: θ (°)"), [("θ (°)", draw.hex_colour("blue"))])
        self.swing_plot = self.swing.handle
        self.last_strike: dict[str, Any] | None = None
        self.apply(self.params.values)

    # -- parameters --------------------------------------------------------------------------------
    def apply(self, values: dict[str, float]) -> None:
        mesh, props, length = hanging_body(self.choice.value)
        pivot_depth = values["pivot"]
        if pivot_depth >= length:
            raise ValueError(say("the pivot must be on the body: it is {length:.2f} m long", length=length))
        pivot = np.array([0.0, 0.0, HANG_HEIGHT - pivot_depth])
        model = PhysicalPendulum(props, pivot, AXIS)
        if not model.a_perp > 0.0:
            raise ValueError(mark("the pivot is at the centre of mass: the body is balanced and does not swing"))
        if not 0.0 <= values["strike"] <= length - pivot_depth + 1e-9:
            raise ValueError(
                say(
                    "the strike point must be on the body, between the pivot and the end {end:.2f} m below it "
                    "(got {strike:.2f} m)",
                    end=length - pivot_depth,
                    strike=values["strike"],
                )
            )
        swing = (self.choice.value, pivot_depth, values["amplitude"])
        if swing == getattr(self, "_swing", None):
            return  # only the strike point or impulse changed: the swing goes on
        self._swing = swing
        self.model, self.mesh, self.props, self.length, self.pivot = model, mesh, props, length, pivot
        self.body.set_mesh(mesh)
        self.pivot_marker.position = pivot
        self.axle.points = np.array([[pivot - 0.15 * AXIS, pivot + 0.15 * AXIS]], dtype=np.float32)
        self.k_readout.set(model.radius_of_gyration)
        self.a_readout.set(model.a_perp)
        self.l_readout.set(model.effective_length)
        theta0 = math.radians(values["amplitude"])
        self.period_readout.set(_period_text(model, theta0, 0.0))
        self.release = (theta0, 0.0)
        self.start = (theta0, 0.0, 0.0)  # also set here: restart() skips reset() while the scene is built
        self.last_strike = None
        self.ctx.restart()

    def truth(self, quantity: str) -> float:
        if quantity == "centre_of_percussion":  # its depth below the pivot: the effective length k²/a⊥
            return float(self.model.effective_length)
        return super().truth(quantity)

    def reset(self) -> None:
        super().reset()
        self.start = (*self.release, 0.0)  # θ, θ̇ and the time they hold at
        self.last_strike = None
        self.swing.clear()

    def earliest(self) -> float:
        # A strike starts a new swing: the timeline goes back to the blow, not into the swing before it.
        return float(self.start[2])

    def events(self, t0: float, t1: float) -> list[Any]:
        # The swing's own clock starts at the release or the last strike (self.start's time).
        start = self.start[2]
        self.state_at(start)  # the swing solved (once per swing)
        swing = events_between(self._motion, max(t0, start) - start, max(t1, start) - start)
        return [replace(e, time=e.time + start) for e in swing]

    # -- the strike --------------------------------------------------------------------------------
    def state_at(self, t: float) -> tuple[float, float]:
        theta0, thetadot0, t0 = self.start
        motion = getattr(self, "_motion", None)
        if motion is None or motion.model is not self.model or (motion.theta0, motion.thetadot0) != (theta0, thetadot0):
            # Solved once per swing (a new body, a release, a strike); a frame only evaluates it.
            motion = self._motion = self.model.trajectory(theta0, thetadot0)
        th, thd = motion.at(float(t - t0))
        return float(th), float(thd)

    def strike(self) -> Any:
        """Strike now at the slider's point, perpendicular to the body and the axis; the swing continues
        from the struck state. Returns :class:`physics.pendulum.Strike`."""
        t = self.ctx.time
        theta, thetadot = self.state_at(t)
        R = self.model.attitude(theta)
        down = R @ np.array([0.0, 0.0, -1.0])  # along the body, away from the pivot
        point = self.pivot + self.params.values["strike"] * down
        direction = np.cross(AXIS, down)  # perpendicular to the plane of the axis and the body
        impulse = self.params.values["impulse"] * direction
        result = self.model.strike(impulse, point, theta=theta)
        self.start = (theta, thetadot + result.delta_omega, t)
        self.drift.clear()  # the blow changes the energy: the drift is measured from the struck swing
        self.last_strike = {"t": t, "wall": wall_clock(), "point": point, "impulse": impulse, "result": result}
        self.strike_readout.set(
            say(_STRIKE, delta=result.delta_omega, impulse=float(np.linalg.norm(result.reaction_impulse)))
        )
        self.period_readout.set(_period_text(self.model, theta, thetadot + result.delta_omega))  # a new swing
        self.ctx.request_redraw()
        return result

    # -- the state ---------------------------------------------------------------------------------
    def compute(self, t: float, dt: float) -> dict[str, Any]:
        theta, thetadot = self.state_at(t)
        return {"theta": theta, "theta_dot": thetadot, "t": t}

    def describe(self, state: dict[str, Any]) -> str:
        model = self.model
        amplitude = swing_amplitude(model, state["theta"], state["theta_dot"])
        swing = (
            mark("going over the top, round and round")
            if amplitude is None
            else say(
                "swinging ±{amplitude} every {period}",
                amplitude=angle(amplitude),
                period=amount(swing_period(model, amplitude), "s"),
            )
        )
        hung = say(
            "Physical pendulum, {body} hung {pivot} below its end",
            body=self.choice.value,
            pivot=amount(self.params.values["pivot"], "m"),
        )
        strike = say("the strike point {strike}", strike=amount(self.params.values["strike"], "m"))
        if "centre_of_percussion" in self.held:  # a class question asks for ℓ: its periods would give it
            release = say("released at {angle}", angle=angle(math.radians(self.params.values["amplitude"])))
            return say("{hung}: {release}; {strike} below the pivot.", hung=hung, release=release, strike=strike)
        return say(
            "{hung}: {swing} (small swings {small}); the centre of percussion is {length} below the pivot, {strike}.",
            hung=hung,
            swing=swing,
            small=amount(model.small_oscillation_period, "s"),
            length=amount(model.effective_length, "m"),
            strike=strike,
        )

    def draw(self, state: dict[str, Any]) -> None:
        theta = state["theta"]
        R = self.model.attitude(theta)
        self.body.set_pose(R, self.pivot - R @ self.pivot)  # x ↦ pivot + R (x − pivot)
        cm = self.model.center_of_mass_at(theta)
        cop = self.model.center_of_percussion(theta)
        draw.move(self.cm_marker, cm)
        draw.move(self.cm_label, cm + LABEL_OFFSET * SCREEN_RIGHT)
        draw.move(self.cop_marker, cop)
        draw.move(self.cop_label, cop + LABEL_OFFSET * SCREEN_RIGHT)
        down = R @ np.array([0.0, 0.0, -1.0])
        hit = self.pivot + self.params.values["strike"] * down
        draw.move(self.hit_marker, hit)
        # Left of the bat: on the centre of percussion (the lecture's key step) it is not drawn over its label.
        draw.move(self.hit_label, hit - LABEL_OFFSET * SCREEN_RIGHT)
        self.trace.append(cm, state["t"])  # the legend says "path of the centre of mass": it is
        # The energy of the swing: constant between strikes (a strike starts a new reference).
        self.drift.add(state["t"], lambda: self._invariants(theta, state["theta_dot"]))
        self.swing.sample(state["t"], math.degrees(theta))
        s = self.last_strike
        if (
            s is not None
            and state["t"] >= s["t"]
            and (state["t"] - s["t"] <= ARROW_SHOW or wall_clock() - s["wall"] <= ARROW_SECONDS)
        ):
            j = s["impulse"]
            scale = 0.4 / max(float(np.linalg.norm(j)), 1e-12)  # the blow drawn 0.4 m long, the reaction alike
            self.impulse_arrow.set(j * scale, s["point"] - j * scale)
            self.reaction_arrow.set(s["result"].reaction_impulse * scale, self.pivot)
        else:
            self.impulse_arrow.set(np.zeros(3))
            self.reaction_arrow.set(np.zeros(3))

    def columns(self, state: dict[str, Any]) -> dict[str, float]:
        theta, theta_dot = state["theta"], state["theta_dot"]
        return {
            "theta (rad)": float(theta),
            "theta_dot (rad/s)": float(theta_dot),
            "E (J)": self._invariants(theta, theta_dot)["E"][0],
        }

    def _invariants(self, theta: float, theta_dot: float) -> dict[str, tuple[float, float]]:
        energy = float(self.model.energy(theta, theta_dot))
        return {"E": (energy, abs(energy) + self.model.mass * G * self.model.effective_length)}
