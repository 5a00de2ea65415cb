"""The heavy symmetric top on its tip: precession with nutation (waves, loops, cusps), sleeping, friction.

Model: :class:`physics.heavy_top.HeavyTop`. Without friction the motion is the exact closed form,
evaluated at the clock's time; with friction it is stepped by :func:`physics.heavy_top.friction_stepper`
(spin friction ``−c ω₃`` about the axis at the tip), so the spin decays, L₃ falls below the sleeping
threshold and the top falls.
"""

from __future__ import annotations

import math
from collections.abc import Callable
from typing import Any

import numpy as np
from numpy.typing import NDArray

from app import controls, draw
from app.drawing.ghost import IntegratorGhost
from app.language.words import mark, say
from app.recording.columns import euler_columns, vector_columns
from app.scenes.base import Answer, Scene, register
from app.scenes.wording import amount, angle, threshold_words, tip_path
from physics import G
from physics.heavy_top import HeavyTop, friction_stepper, on_the_table, touch_angle
from physics.history import SteppedHistory
from physics.integrators import BlanesMoan6, GravityTorque, advance

LENGTH = 1.0  # drawn length of the top, tip to stem end (m); the axis tip moves on this sphere
ELL = 0.5  # pivot-to-centre-of-mass distance used to split M g ℓ into M and ℓ for the stepping model (m)
PLOT_POINTS = 180  # one a degree: a smooth curve at a quarter of the bytes of a finer grid
STEP = 1.0 / 240.0
"""The friction top's grid step (s): its state at time t is the one at the grid time ``k STEP`` at or
before t, the same bits whether reached playing, scrubbing back or stepping forward again."""
KEPT = 300.0
"""How far back (s) the friction top's timeline reaches: its history (:class:`physics.history.SteppedHistory`)
keeps a checkpoint every :data:`CHECKPOINT` steps of the last five minutes (125 kB)."""
CHECKPOINT = 60
"""Steps between checkpoints (0.25 s): a scrub recomputes at most 59 steps (about 1.5 ms; a scrub and its
frame 0.97 ms on average, ``python -m benchmarks.scrub``)."""


def _theta_grid() -> np.ndarray:
    return np.radians(np.linspace(0.5, 179.5, PLOT_POINTS))


UPRIGHT_NUDGE = 1e-3
"""rad (0.057°): a top set exactly upright below the sleeping threshold, or upright with friction, starts
this far off the vertical. θ = 0 is an equilibrium, unstable below the threshold; a real top never stands
exactly upright, and the nudge grows as exp(λt), λ = √(M g ℓ/I₁ − (L₃/2I₁)²), so it topples within
seconds, as the lecture says. With friction a top above the threshold sleeps until L₃ falls below it and
then topples the same way; exactly upright it would have nothing to grow from and stand for ever."""


TOP_MESH = draw.top_mesh(LENGTH)
TOUCH = touch_angle(TOP_MESH.vertices)
"""Tilt at which the drawn top's rim meets the table (61.4°): the friction top comes to rest there."""


def _start(top: HeavyTop, values: dict[str, float]) -> tuple[float, float, float, float]:
    """(θ0, θ̇0, φ̇0, ψ̇0) from the sliders: released at rest in θ with spin ω3 = ψ̇ + φ̇ cos θ; exactly
    upright below the sleeping threshold or with friction, θ0 is :data:`UPRIGHT_NUDGE` instead (see
    :func:`_nudged`)."""
    theta0 = UPRIGHT_NUDGE if _nudged(top, values) else math.radians(values["theta0"])
    return theta0, 0.0, values["phidot0"], values["spin"] - values["phidot0"] * math.cos(theta0)


def _below_threshold(top: HeavyTop, values: dict[str, float]) -> bool:
    """L₃ = I₃ ω₃ from the sliders at or below the top's sleeping threshold: upright is unstable."""
    return top.below_sleeping_threshold(values["I3"] * values["spin"])


def _nudged(top: HeavyTop, values: dict[str, float]) -> bool:
    """True when the sliders ask for the upright equilibrium where it is (or, with friction, will become)
    unstable: θ0 = 0 and L₃ at or below the sleeping threshold, or θ0 = 0 with spin friction."""
    return values["theta0"] == 0.0 and (_below_threshold(top, values) or values["friction"] > 0.0)


def _nudge_words(top: HeavyTop, values: dict[str, float]) -> str:
    """The note shown at the top of the panel when the start was nudged (empty otherwise)."""
    if not _nudged(top, values):
        return ""
    nudge = math.degrees(UPRIGHT_NUDGE)
    if _below_threshold(top, values):
        return say(
            "⚠ θ₀ = 0 below the sleeping threshold is an unstable equilibrium: the top starts {nudge:.2g}° off "
            "the vertical (a tiny perturbation, as any real top has) and topples.",
            nudge=nudge,
        )
    return say(
        "⚠ θ₀ = 0 with friction: the top starts {nudge:.2g}° off the vertical (a tiny perturbation, as any real "
        "top has). It sleeps until friction takes L₃ below the threshold, then topples.",
        nudge=nudge,
    )


def _steady(values: dict[str, float]) -> float:
    top = HeavyTop(values["I1"], values["I3"], values["mgl"])
    return top.steady_precession_rates(math.radians(values["theta0"]), values["I3"] * values["spin"])[0]


def _with_phidot(factor: float) -> Callable[[dict[str, float]], dict[str, float]]:
    def preset(values: dict[str, float]) -> dict[str, float]:
        v = {**values, "spin": 10.0, "theta0": 60.0, "friction": 0.0}
        return {**v, "phidot0": round(factor * _steady(v), 3)}

    return preset


PRESETS: dict[str, dict[str, float] | Callable[[dict[str, float]], dict[str, float]]] = {
    mark("cusps (released from rest)"): {"spin": 10.0, "theta0": 60.0, "phidot0": 0.0, "friction": 0.0},
    mark("waves (φ̇0 = ½ × steady)"): _with_phidot(0.5),
    mark("loops (φ̇0 = −1 × steady)"): _with_phidot(-1.0),
    mark("steady precession (slow rate)"): _with_phidot(1.0),
    mark("sleeping top (above threshold)"): {"spin": 20.0, "theta0": 2.0, "phidot0": 0.0, "friction": 0.0},
    mark("sleeping top with friction: falls"): {"spin": 20.0, "theta0": 2.0, "phidot0": 0.0, "friction": 0.02},
}

RENAMED_PRESETS = {
    # Started at its lower turning point, 2 × steady drew small loops (φ̇ fell below 0 near the top).
    "waves (φ̇0 = 2 × steady)": "waves (φ̇0 = ½ × steady)",
}


THETA_BETWEEN = mark("θ turns between (°)")  # the exact top: its two turning angles
THETA_NOW = mark("θ now (°)")  # the friction top: no turning points, its tilt now (and whether it lies on the table)

_DEGREES = "{tilt:.4g}"  # a number alone: written per locale, nothing to translate

SLEEPING_TILT = math.radians(5.0)
"""Within this tilt of the vertical a top above the threshold is said to sleep (it stands, barely moving)."""


def _cross_down(axis: NDArray[np.float64]) -> NDArray[np.float64]:
    """``axis × (0, 0, -1)`` = ``(-a_y, a_x, 0)``, written out: ``np.cross`` costs more than the rest of a
    frame's arithmetic (it is called once per frame of every session)."""
    return np.array([-axis[1], axis[0], 0.0])


def _sleeping_words(above: bool, theta: float) -> str:
    """What the gauge says: sleeping only for a top that stands (nearly) upright above the threshold."""
    if not above:
        return mark("too slow to sleep: upright would be unstable")
    if theta <= SLEEPING_TILT:
        return mark("above it: stable upright, the top sleeps")
    return say("above it: it would sleep upright, but it is tilted {tilt:.4g}°", tilt=math.degrees(theta))


@register
class HeavyTopScene(Scene):
    name = "heavy_top"
    title = mark("Heavy top")
    order = 10
    quantities = ("L", "omega", "torque", "trace", "guide", "ghost")
    caption = mark(
        "**Heavy symmetric top** on a fixed tip. Gravity's torque τ = ℓ ê₃ × (−M g ẑ) is horizontal, so "
        "L_z and L₃ are conserved and θ moves in the effective potential "
        "U(θ) = (L_z − L₃ cos θ)²/(2 I₁² sin²θ) + (M g ℓ/I₁) cos θ between two turning points: the axis tip "
        "draws waves, loops or cusps. Stable upright (sleeping) when L₃ > 2√(M g ℓ I₁). "
        "Exact solution without friction (the tip is a pivot: the top may swing below it). With friction the "
        "top stands on the table: the spin decays, it falls and comes to rest on its rim."
    )
    camera = ((1.35, -2.33, 1.45), (0.0, 0.0, 0.45))
    view = (2.35, 2.1)  # the axis tip's sphere across (its diameter), L and ω above the top
    reach = (1.07, 0.95, 0.45)  # L's, ω's and τ's drawn lengths at the start (top lengths): in view as they precess
    key_plot = "nutation.handle"  # θ(t): the nutation between its turning points (U(θ) in the panel shows why)
    # The precession's rate and sense: its readout, the φ̇₀ slider a steady preset sets to it, the words.
    answers = (Answer("precession_rate", readouts=("precession_readout",), hidden=("params.sliders.phidot0",)),)

    def build(self) -> None:
        self.screen = draw.screen_axes(type(self).camera)  # the view L's and ω's labels are kept apart in
        server, root, gui = self.ctx.server, self.ctx.root, self.ctx.server.gui
        draw.faint_sphere(server, root + "/sphere", LENGTH)
        # First in the folder, under the caption: what the scene did to the sliders' start, and why.
        self.note = gui.add_markdown("")
        self.body = draw.BodyMesh(server, root + "/top", TOP_MESH)
        self.L_arrow = draw.Arrow(server, root + "/L", "L", label="L", shaft_radius=0.035)
        self.omega_arrow = draw.Arrow(server, root + "/omega", "omega", label="ω", shaft_radius=0.035)
        self.torque_arrow = draw.Arrow(server, root + "/torque", "torque", label="τ")
        self.trace = draw.Trace(server, root + "/trace", capacity=1500)
        self.traces = [self.trace]
        self.params = controls.ParameterPanel(
            self.ctx,
            [
                controls.SliderSpec("spin", mark("spin ω₃ (rad/s)"), 0.0, 40.0, 0.1, 10.0),
                controls.SliderSpec("theta0", mark("tilt θ₀ (°)"), 0.0, 179.0, 0.5, 60.0),
                controls.SliderSpec("phidot0", mark("initial precession φ̇₀ (rad/s)"), -3.0, 3.0, 0.005, 0.0),
                controls.SliderSpec("I1", mark("I₁ about the tip (kg m²)"), 0.05, 1.0, 0.01, 0.4),
                controls.SliderSpec("I3", mark("I₃ about the axis (kg m²)"), 0.02, 1.0, 0.01, 0.2),
                controls.SliderSpec("mgl", "M g ℓ (J)", 0.05, 3.0, 0.05, 1.0),
                controls.SliderSpec(
                    "friction",
                    mark("spin friction c (N m s)"),
                    0.0,
                    0.05,
                    0.001,
                    0.0,
                    hint=mark("torque −c ω₃ about the axis at the tip; 0 = exact solution"),
                ),
            ],
            apply=self.apply,
        )
        self.presets = controls.Presets(self.ctx, self.params, PRESETS, renamed=RENAMED_PRESETS)
        self.trace_length = gui.add_slider(
            mark("trace length (points)"), min=100, max=5000, step=100, initial_value=1500
        )
        self.trace_length.on_update(self.ctx.guarded(lambda _: self.trace.resize(int(self.trace_length.value))))
        self.nutation = controls.TimePlot(self.ctx, mark("Nutation: θ (°)"), [("θ (°)", draw.hex_colour("blue"))])
        # U(θ) with the energy and θ now: where the axis nutates between its turning points.
        self.potential = controls.PotentialPlot(
            self.ctx,
            _theta_grid(),
            shown=np.degrees(_theta_grid()),
            x_range=(0.0, 180.0),
            x_label="θ (°)",
            curve_label="U(θ)",
            title=mark("Effective potential U(θ) (1/s²)"),
            colours=(draw.hex_colour("blue"), draw.hex_colour("guide"), draw.hex_colour("vermillion")),
        )
        self.precession_readout = controls.Readout(self.ctx, mark("precession ⟨φ̇⟩ (rad/s)"))
        self.nutation_readout = controls.Readout(self.ctx, mark("nutation period (s)"))
        self.theta_readout = controls.Readout(self.ctx, THETA_BETWEEN, fmt="{}")
        self.gauge = controls.Gauge(self.ctx, mark("**L₃ against the sleeping threshold 2√(M g ℓ I₁)**"))
        self.drift = controls.InvariantDrift(
            self.ctx,
            ("E", "L_z", "L₃"),
            (draw.hex_colour("black"), draw.hex_colour("L"), draw.hex_colour("bluish_green")),
        )
        self.ghost = IntegratorGhost(self.ctx, root + "/ghost", TOP_MESH)
        self.traces += [self.drift, self.ghost, self.nutation]
        self.apply(self.params.values)
        self.reset()  # the stepping state from the start: ctx.restart() skips reset() while the scene is built

    # -- parameters
    def apply(self, values: dict[str, float]) -> None:
        top = HeavyTop(values["I1"], values["I3"], values["mgl"])  # raises for an impossible body
        start = _start(top, values)
        if values["friction"] < 0:
            raise ValueError("friction must be zero or positive")
        motion = top.trajectory(*start)  # solved once: a frame only evaluates it
        sol = motion.at(np.zeros(1))
        self.top, self.values, self.start, self.exact, self.motion = top, dict(values), start, sol, motion
        L0 = sol.attitude[0] @ (top.moments * sol.omega_body[0])
        # L and ω reach well past the top's end (LENGTH), so they and their labels stand clear of the body.
        reach_L, reach_omega, reach_torque = type(self).reach
        self.L_scale = reach_L * LENGTH / max(float(np.linalg.norm(L0)), 1e-9)
        self.omega_scale = reach_omega * LENGTH / max(float(np.linalg.norm(sol.omega_body[0])), 1e-9)
        self.torque_scale = reach_torque * LENGTH / top.mgl
        self.note.content = _nudge_words(top, values)
        self._start_ghost()
        self.ctx.restart()  # t = 0 and reset(): once a change

    def _start_ghost(self) -> None:
        """The integrator ghost from the same start, under the same gravity (none with friction: no exact)."""
        top, motion = self.top, self.motion
        moments = top.moments

        def exact(t: float) -> tuple[np.ndarray, np.ndarray]:
            now = motion.at(t)
            return now.attitude, moments * now.omega_body

        E0 = top.energy(*exact(0.0))
        self.ghost.start(
            moments,
            exact if self.values["friction"] == 0.0 else None,
            top.energy,
            abs(E0) + top.mgl,
            torque=GravityTorque(top.mgl / (G * ELL), [0.0, 0.0, ELL]),
        )

    def truth(self, quantity: str) -> float:
        if quantity == "precession_rate":  # the mean φ̇ over a nutation from the start (physics.heavy_top)
            return float(self.top.precession_rate(*self.start))
        return super().truth(quantity)

    def reset(self) -> None:
        super().reset()
        sol = self.exact
        # Stepping state (friction): attitude and body angular momentum about the tip.
        self.R = sol.attitude[0].copy()
        self.L_body = self.top.moments * sol.omega_body[0]
        self.landed = False  # the friction top has come to rest on the table
        self._start_history(0.0)
        self.potential.reset()
        self.nutation.clear()

    def snapshot(self) -> dict[str, Any]:
        # The friction top's stepped state, and the grid time it holds at.
        t = self.history.time if self.history is not None else self._history_t0
        t = self.ctx.time if t is None else t
        return {"R": self.R.copy(), "L_body": self.L_body.copy(), "landed": [float(self.landed)], "t": [t]}

    def restore(self, motion: dict[str, Any]) -> None:
        if motion:
            self.R, self.L_body = np.array(motion["R"], dtype=float), np.array(motion["L_body"], dtype=float)
            self.landed = bool(motion.get("landed", [0.0])[0])
            # A state written before it kept its time starts its history at the first frame's time.
            self._start_history(float(motion["t"][0]) if "t" in motion else None)

    def events(self, t0: float, t1: float) -> list[Any]:
        # With friction the motion is stepped: no closed form to solve the turning points from.
        return [] if self.values["friction"] > 0.0 else super().events(t0, t1)

    def earliest(self) -> float:
        if self.values["friction"] > 0.0 and self.history is not None:
            return self.history.earliest
        return 0.0

    # -- the state
    def _friction_stepper(self) -> Any:
        """:func:`physics.heavy_top.friction_stepper` (Blanes–Moan 6, gravity and spin friction) for this top:
        built once per body and friction, so a frame only steps. At the scene's 1/240 s it ends the benchmark's
        friction top (10 s) 2e-13 from the reference, against 3e-7 for Lie RK4, for 1.4 µs a step instead of
        0.3 (``python -m benchmarks.frame_time`` keeps the frame's budget)."""
        top, c = self.top, self.values["friction"]
        key = (top.I1, top.I3, top.mgl, c)
        if getattr(self, "_stepper_key", None) != key:
            self._stepper, self._stepper_key = friction_stepper(top, c, method=BlanesMoan6), key
        return self._stepper

    def _start_history(self, t0: float | None) -> None:
        """The friction top's history from the stepping state at time ``t0`` (s; None: at the next frame's)."""
        self.history: SteppedHistory | None = None
        self._history_t0 = t0

    def _table_step(self, state: np.ndarray) -> np.ndarray:
        """One grid step of the friction top, the table's contact folded in: ``(R row-major, L_body,
        landed)``, shape (13,). Lying on the table it rests (a deterministic function of the state alone)."""
        if state[12]:
            return state
        moved = advance(self._friction_stepper(), state[:12], STEP, 1)
        R, L_body, landed = on_the_table(moved[:9].reshape(3, 3), moved[9:], False, TOUCH)
        return np.concatenate([R.ravel(), L_body, [float(landed)]])

    def _stepped(self, t: float) -> tuple[np.ndarray, np.ndarray, bool]:
        """The friction top at time ``t`` (s): its history's state at the grid time at or before ``t``."""
        if self.history is None:
            start = np.concatenate([self.R.ravel(), self.L_body, [float(self.landed)]])
            t0 = t if self._history_t0 is None else self._history_t0
            self.history = SteppedHistory(self._table_step, start, STEP, t0=t0, keep=KEPT, checkpoint_every=CHECKPOINT)
        state = self.history.seek(max(t, self.history.earliest))
        return state[:9].reshape(3, 3), state[9:12], bool(state[12])

    def compute(self, t: float, dt: float) -> dict[str, Any]:
        top = self.top
        moments = top.moments
        landed = self.landed
        if self.values["friction"] > 0.0:
            R, L_body, landed = self._stepped(t)
        else:
            now = self.motion.at(t)
            R, L_body = now.attitude, moments * now.omega_body
        axis = R[:, 2]
        return {
            "R": R,
            "L_body": L_body,
            "axis": axis,
            "L": R @ L_body,
            "omega": R @ (L_body / moments),
            # Gravity's torque about the tip; lying on the table, the table's push cancels it (at rest, dL/dt = 0).
            "torque": np.zeros(3) if landed else top.mgl * _cross_down(axis),
            "theta": math.atan2(math.hypot(axis[0], axis[1]), axis[2]),
            "landed": landed,
        }

    def draw(self, state: dict[str, Any]) -> None:
        self.R, self.L_body = state["R"], state["L_body"]  # adopt the stepped state (friction)
        self.landed = state["landed"]
        self.body.set_pose(state["R"])
        self.L_arrow.set(state["L"] * self.L_scale)
        self.omega_arrow.set(state["omega"] * self.omega_scale, apart_from=self.L_arrow, screen=self.screen)
        # τ from the stem's end: drawn inside the body (its middle) it was a blob with its label on the body.
        # Where it points at the camera, its tip meets L's on the screen: L's label then names it too.
        self.torque_arrow.set(
            state["torque"] * self.torque_scale, LENGTH * state["axis"], apart_from=self.L_arrow, screen=self.screen
        )
        self.trace.append(LENGTH * state["axis"], self.ctx.time)
        self.nutation.sample(self.ctx.time, math.degrees(state["theta"]))
        self._readouts(state)
        self.drift.add(self.ctx.time, lambda: self._invariants(state))
        self.ghost.follow(self.ctx.time, lambda R: (R, (0.0, 0.0, 0.0)))

    def columns(self, state: dict[str, Any]) -> dict[str, float]:
        energy = self._invariants(state)["E"][0]
        return {
            **euler_columns(state["R"]),
            **vector_columns("omega", state["omega"], "rad/s"),
            **vector_columns("L", state["L"], "kg m^2/s"),
            "L_3 (kg m^2/s)": float(state["L_body"][2]),
            "E (J)": energy,
        }

    def describe(self, state: dict[str, Any]) -> str:
        top, L3 = self.top, float(state["L_body"][2])
        spin = say(
            "spin {spin}, {threshold}",
            spin=amount(L3 / top.I3, "rad/s"),
            threshold=threshold_words(L3, top.sleeping_threshold()),
        )
        if self.values["friction"] > 0.0:
            where = mark("lying on the table") if state["landed"] else say("tilted {tilt}", tilt=angle(state["theta"]))
            return say(
                "Heavy top with spin friction {friction}: {where}; {spin}.",
                friction=amount(self.values["friction"], "N m s"),
                where=where,
                spin=spin,
            )
        sol, kind = self.exact, self.motion.kind
        if kind == "vertical":
            return say("Heavy top, upright: standing on its tip; {spin}.", spin=spin)
        if "precession_rate" in self.held:  # a class question asks for it: the rate and its sense wait
            precessing = mark("precessing (its rate is the class question)")
        else:
            precessing = say("precessing at {rate}", rate=amount(sol.precession_rate, "rad/s"))
        if kind == "steady":
            return say(
                "Heavy top, steady precession: {precessing} at a tilt of {tilt}; {spin}.",
                precessing=precessing,
                tilt=angle(sol.theta_min),
                spin=spin,
            )
        if angle(sol.theta_min) == angle(sol.theta_max):  # a nutation too small to say in three digits
            return say(
                "Heavy top, nearly steady precession: {precessing} at a tilt of {tilt}, nutating by {nutation:.2g}°; "
                "{spin}.",
                precessing=precessing,
                tilt=angle(sol.theta_min),
                nutation=math.degrees(sol.theta_max - sol.theta_min),
                spin=spin,
            )
        return say(
            "Heavy top, {shape}: {precessing}, nutating between {low} and {high} every {period}; {spin}.",
            shape=tip_path(sol.Lz, sol.L3, sol.theta_min, sol.theta_max),
            precessing=precessing,
            low=angle(sol.theta_min),
            high=angle(sol.theta_max),
            period=amount(sol.nutation_period, "s"),
            spin=spin,
        )

    def _invariants(self, state: dict[str, Any]) -> dict[str, tuple[float, float]]:
        """E = ½ ω·L + M g ℓ cos θ (:meth:`HeavyTop.energy`), L_z and L₃ (with their scales): constant for
        the exact top."""
        L_body, L = state["L_body"], state["L"]
        top = self.top
        energy = top.energy(state["R"], L_body)
        size = float(np.linalg.norm(L))
        return {"E": (energy, abs(energy) + top.mgl), "L_z": (float(L[2]), size), "L₃": (float(L_body[2]), size)}

    def _theta_label(self, label: str) -> None:
        if self.theta_readout.handle.label != label:
            self.theta_readout.handle.label = label

    def _readouts(self, state: dict[str, Any]) -> None:
        top = self.top
        L3 = float(state["L_body"][2])
        Lz = float(state["L"][2])
        theta = state["theta"]
        threshold = top.sleeping_threshold()
        self.gauge.set(
            abs(L3),
            threshold,
            say(
                "L₃ = {L3:.4g} kg m²/s, threshold {threshold:.4g} kg m²/s: {words}",
                L3=L3,
                threshold=threshold,
                words=_sleeping_words(not top.below_sleeping_threshold(L3), theta),
            ),
        )
        friction = self.values["friction"] > 0.0
        if friction:
            self.precession_readout.set(mark("— (friction: no fixed rate)"))
            self.nutation_readout.set("—")
            self._theta_label(THETA_NOW)
            tilt = math.degrees(theta)
            self.theta_readout.set(
                say("{tilt:.4g}, lying on the table", tilt=tilt) if state["landed"] else say(_DEGREES, tilt=tilt)
            )
        else:
            sol = self.exact
            self.precession_readout.set(sol.precession_rate)
            self.nutation_readout.set(sol.nutation_period)
            self._theta_label(THETA_BETWEEN)
            self.theta_readout.set(
                say("{low:.4g} and {high:.4g}", low=math.degrees(sol.theta_min), high=math.degrees(sol.theta_max))
            )
        if not self.potential.due():
            return
        # Energy per I1: ℰ = θ̇²/2 + U(θ), θ̇² from |ω⊥|² = θ̇² + sin²θ φ̇² (φ̇ from L_z).
        thetadot2 = top.nutation_rate_squared(theta, Lz, L3, state["L_body"] / top.moments)
        energy = 0.5 * thetadot2 + float(top.effective_potential(np.array([theta]), Lz, L3)[0])
        self.potential.show(
            (round(L3, 4), round(Lz, 4), id(top)),
            lambda grid: top.effective_potential(grid, Lz, L3),
            theta,
            energy,
            energy - 0.5 * thetadot2,
        )
