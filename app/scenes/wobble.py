"""Torque-free symmetric body (the wobble): L fixed, ω precessing about the symmetry axis, the two cones.

Model: :class:`physics.free_body.FreeBody`, evaluated in closed form at the clock's time (lecture,
"the symmetric body": Ω = ω3 (I1 − I3)/I1 in the body, φ̇ = L/I1 in space).
"""

from __future__ import annotations

import math
from typing import Any, ClassVar

import numpy as np

from app import controls, draw
from app.drawing.ghost import IntegratorGhost
from app.language.words import mark, say
from app.recording.columns import euler_columns, vector_columns
from app.scenes.base import Scene, register
from app.scenes.wording import amount, angle
from physics.free_body import FreeBody
from physics.inertia import validate_moments
from physics.rotations import frame_from_axis

_MOMENTS = "{I1:.4g}, {I3:.4g}"  # numbers alone: written per locale, nothing to translate


def cylinder_for_ratio(ratio: float, size: float) -> tuple[float, float]:
    """Radius and length (m) of a solid cylinder with I3/I1 = ``ratio`` whose larger dimension is ``size``.

    For a cylinder ``I1 = M (a²/4 + h²/12)`` and ``I3 = M a²/2`` (docs/conventions.md erratum 1), so ``h² = a² (6/ratio − 3)``:
    ratio 2 is a flat disc (a lamina), ratio 1 has h = a√3, small ratios are long rods.
    """
    h_over_a = math.sqrt(max(6.0 / ratio - 3.0, 0.0))
    a = size / max(2.0, h_over_a)
    return a, a * h_over_a


def _angle(u: np.ndarray, v: np.ndarray) -> float:
    """The angle between two 3-vectors, atan2(|u × v|, u·v) (accurate at 0 and π), on floats: a frame
    asks twice and numpy's cross and norm cost more than the arithmetic."""
    u0, u1, u2 = float(u[0]), float(u[1]), float(u[2])
    v0, v1, v2 = float(v[0]), float(v[1]), float(v[2])
    cross = math.sqrt((u1 * v2 - u2 * v1) ** 2 + (u2 * v0 - u0 * v2) ** 2 + (u0 * v1 - u1 * v0) ** 2)
    return math.atan2(cross, u0 * v0 + u1 * v1 + u2 * v2)


@register
class Wobble(Scene):
    name = "wobble"
    title = mark("Torque-free wobble")
    order = 20
    quantities: ClassVar[tuple[str, ...]] = ("L", "omega", "body_cone", "space_cone", "trace", "axes", "ghost")
    # "&lt;", as the panel shows it: the caption is sanitised as Markdown (app.guards.text.lecturer_markdown),
    # which writes a "<" so, and the text shown must be the catalogs' message to be translated.
    caption = mark(
        "**Torque-free symmetric body.** L is fixed in space. In the body, ω turns about the symmetry axis "
        "at Ω = ω₃ (I₁ − I₃)/I₁; in space the axis turns about L at φ̇ = L/I₁. The body cone (about the "
        "axis) rolls on the space cone (about L) along ω. I₃/I₁ &lt; 1: prolate (rod-like), > 1: oblate (disc). "
        "The arrows L and ω keep their lengths (|L| and |ω| are constant here): both are drawn 1.1 m long."
    )
    camera = ((2.2, -2.2, 1.9), (0.0, 0.0, 1.15))
    view: ClassVar[tuple[float, float] | None] = (2.4, 2.4)  # the body, its cones and L and ω
    centre = np.array([0.0, 0.0, 1.0])  # where the centre of mass sits (m)
    size = 1.0  # largest dimension of the body (m); arrows and cones scale with it
    reach = 1.1  # L's and ω's drawn lengths, in sizes: they leave the body

    def build(self) -> None:
        self.screen = draw.screen_axes(type(self).camera)  # the view L's and ω's labels are kept apart in
        server, root = self.ctx.server, self.ctx.root
        self.body = draw.BodyMesh(server, root + "/body", draw.cylinder_mesh(0.5, 0.5))
        # A child of the body: it turns with it without a message of its own each frame.
        self.frame = draw.PrincipalFrame(server, root + "/body/frame", length=0.75 * self.size, dark=self.ctx.dark)
        self.L_arrow = draw.Arrow(server, root + "/L", "L", label="L")
        self.omega_arrow = draw.Arrow(server, root + "/omega", "omega", label="ω")
        self.body_cone = draw.Cone(server, root + "/body_cone", "body_cone")
        self.space_cone = draw.Cone(server, root + "/space_cone", "space_cone")
        self.trace = draw.Trace(server, root + "/trace", capacity=600)
        self.traces: list[Any] = [self.trace]
        self.params = controls.ParameterPanel(
            self.ctx,
            [
                controls.SliderSpec(
                    "ratio",
                    mark("I₃/I₁ (shape)"),
                    0.1,
                    2.5,
                    0.05,
                    1.6,
                    hint=mark("< 1 prolate (rod-like), > 1 oblate (disc); 2 is a flat disc, above is impossible"),
                ),
                controls.SliderSpec("spin", mark("|ω| (rad/s)"), 0.2, 10.0, 0.1, 3.0),
                controls.SliderSpec("tilt", mark("angle of ω from the axis (°)"), 0.0, 89.0, 1.0, 20.0),
            ],
            apply=self.apply,
        )
        self.presets = controls.Presets(
            self.ctx,
            self.params,
            {
                mark("disc (oblate)"): {"ratio": 1.9},
                mark("sphere-like (I₃ = I₁)"): {"ratio": 1.0},
                mark("rod-like (prolate)"): {"ratio": 0.3},
            },
        )
        self.body_view = self.ctx.server.gui.add_checkbox(mark("Body view (ride with the body)"), initial_value=False)
        self.body_view.on_update(self.ctx.guarded(lambda _: self.ctx.restart()))
        self.Omega_readout = controls.Readout(self.ctx, mark("Ω body precession (rad/s)"))
        self.phidot_readout = controls.Readout(self.ctx, mark("L/I₁ space precession (rad/s)"))
        self.moments_readout = controls.Readout(self.ctx, mark("I₁, I₃ (kg m², M = 1 kg)"), fmt="{}")
        self.drift = controls.InvariantDrift(self.ctx, ("E", "|L|"), (draw.hex_colour("black"), draw.hex_colour("L")))
        self.ghost = IntegratorGhost(self.ctx, root + "/ghost", draw.cylinder_mesh(0.5, 0.5))
        self.traces += [self.drift, self.ghost]
        self.apply(self.params.values)

    # -- parameters
    def apply(self, values: dict[str, float]) -> None:
        ratio = values["ratio"]
        validate_moments([1.0, 1.0, ratio])  # the triangle inequality: I3 ≤ 2 I1 (raises with the reason)
        a, h = cylinder_for_ratio(ratio, self.size)
        moments = np.array([a * a / (2.0 * ratio), a * a / (2.0 * ratio), a * a / 2.0])  # M = 1 kg
        model = FreeBody(moments)
        alpha = math.radians(values["tilt"])
        omega0 = values["spin"] * np.array([math.sin(alpha), 0.0, math.cos(alpha)])
        L_body = moments * omega0
        # Start with L along +z: R0 maps the unit L (body) to ẑ.
        self.attitude0 = frame_from_axis(L_body).T
        self.model, self.omega0, self.moments = model, omega0, moments
        self.motion = model.trajectory(omega0, self.attitude0)  # solved once: a frame only evaluates it
        self.L_space = self.attitude0 @ L_body
        self.L_scale = self.reach * self.size / float(np.linalg.norm(L_body))
        self._energy_scale = 0.5 * float(omega0 @ L_body)
        self._L_size = float(np.linalg.norm(L_body))
        self.omega_scale = self.reach * self.size / float(np.linalg.norm(omega0))
        mesh = draw.cylinder_mesh(a, max(h, 0.01 * self.size))
        self.body.set_mesh(mesh)
        self.ghost.start_free(moments, self.motion, mesh)
        rates = model.precession_rates(omega0)
        self.Omega_readout.set(rates.body)
        self.phidot_readout.set(rates.space)
        self.moments_readout.set(say(_MOMENTS, I1=moments[0], I3=moments[2]))
        self.ctx.restart()

    # -- the state
    def centre_at(self, t: float) -> np.ndarray:
        """Position of the centre of mass at time t (m); fixed here, a parabola in free fall."""
        return self.centre

    def compute(self, t: float, dt: float) -> dict[str, Any]:
        now = self.motion.at(t)
        return {
            "R": now.attitude,
            "omega_space": now.attitude @ now.omega,
            "centre": np.asarray(self.centre_at(t), dtype=float),
            "t": t,
        }

    def draw(self, state: dict[str, Any]) -> None:
        R, w, c = state["R"], state["omega_space"], state["centre"]
        # Body view: everything expressed in body axes (the body stands still, L and ω move).
        V = R.T if self.body_view.value else np.eye(3)
        axis, L = V @ R[:, 2], V @ self.L_space
        self.body.set_pose(V @ R, c)
        self.L_arrow.set(L * self.L_scale, c)
        self.omega_arrow.set(V @ w * self.omega_scale, c, apart_from=self.L_arrow, screen=self.screen)
        slant = float(np.linalg.norm(w)) * self.omega_scale
        self.body_cone.set(axis, _angle(w, R[:, 2]), slant, c)
        self.space_cone.set(L, _angle(w, self.L_space), slant, c)
        # The trace follows the axis tip in space, the tip of ω in the body view.
        tip = V @ w * self.omega_scale if self.body_view.value else axis * 0.75 * self.size
        self.trace.append(c + tip, state["t"])
        # Rotational energy ½ ω·L and |L| (about the centre of mass): constant without torque.
        self.drift.add(state["t"], lambda: self._invariants(R.T @ w))
        self.ghost.follow(state["t"], lambda Rg: (V @ Rg, self.centre_at(self.ghost.t)))

    def describe(self, state: dict[str, Any]) -> str:
        return say("{title}: {wobble}.", title=self.title, wobble=self.wobble_words())

    def wobble_words(self) -> str:
        """The torque-free wobble: the cone angle of the symmetry axis about L and the two precession rates."""
        rates, L_body = self.model.precession_rates(self.omega0), self.moments * self.omega0
        cone = math.atan2(math.hypot(L_body[0], L_body[1]), L_body[2])
        return say(
            "the symmetry axis turns about the fixed L at {space}, {cone} from it; in the body, ω turns about the "
            "axis at {body}",
            space=amount(rates.space, "rad/s"),
            cone=angle(cone),
            body=amount(rates.body, "rad/s"),
        )

    def columns(self, state: dict[str, Any]) -> dict[str, float]:
        R, w = state["R"], state["omega_space"]
        return {
            **euler_columns(R),
            **vector_columns("omega", w, "rad/s"),
            **vector_columns("L", self.L_space, "kg m^2/s"),
            "E (J)": self._invariants(R.T @ w)["E"][0],
            **vector_columns("centre", state["centre"], "m"),
        }

    def _invariants(self, omega_body: np.ndarray) -> dict[str, tuple[float, float]]:
        L_body = self.moments * omega_body
        energy, size = 0.5 * float(omega_body @ L_body), float(np.linalg.norm(L_body))
        return {"E": (energy, self._energy_scale), "|L|": (size, self._L_size)}
