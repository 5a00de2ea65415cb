"""Exact beside numerical: a translucent "ghost" of the body moved by an integrator from the same start.

More in docs/app-notes.md (``app.drawing.ghost``).
"""

from __future__ import annotations

import math
from collections.abc import Callable
from typing import Any

import numpy as np
import trimesh
from numpy.typing import NDArray

from app.contracts import SceneContext
from app.drawing.palette import COLOURS, GHOST_OPACITY, hex_colour
from app.drawing.pieces import BodyMesh
from app.language.words import mark, say
from app.panel.drift import InvariantDrift
from physics.integrators import BlanesMoan6, ClassicalRK4, LiePoissonStrang, SofroniouSpaletta10, Yoshida6, advance

__all__ = ["IntegratorGhost", "METHODS", "chordal_angle"]

METHODS: dict[str, type | None] = {
    mark("none"): None,
    mark("classical RK4 (not geometric)"): ClassicalRK4,
    mark("Lie–Poisson splitting (order 2)"): LiePoissonStrang,
    mark("Yoshida 6 composition (order 6)"): Yoshida6,
    mark("Blanes–Moan 6 splitting (order 6, optimised)"): BlanesMoan6,
    mark("Sofroniou–Spaletta 10 composition (order 10)"): SofroniouSpaletta10,
}
STEP = (0.002, 0.2, 0.002, 0.05)
"""The step slider (s): least, most, resolution, default."""
CATCH_UP = 5.0
"""A clock jump ahead of everything the ghost has stepped through larger than this (s) restarts the ghost
there instead of stepping it there."""
CHECKPOINT_SECONDS = 0.25
"""The ghost keeps its state about every quarter second of its time (at a whole number of steps), so that the
timeline moved back (or on again) puts it where it was, bit for bit: each frame steps on from the checkpoint
before (at most 125 steps, at the smallest step h)."""
CHECKPOINTS = 3600
"""Checkpoints kept (the newest): fifteen minutes of the ghost's time, 96 bytes each."""

Exact = Callable[[float], tuple[NDArray[np.float64], NDArray[np.float64]]]


def chordal_angle(a: NDArray[np.float64], b: NDArray[np.float64]) -> float:
    """The angle between two attitudes, ``2 arcsin(‖A − B‖_F / √8)`` (rad).

    For two rotations it is the angle of ``AᵀB``, accurate down to roundoff at small angles (arccos of the
    trace floors near 1.5e-8); it stays defined when ``B`` has left SO(3) (classical RK4).
    """
    return 2.0 * math.asin(min(1.0, float(np.linalg.norm(a - b)) / math.sqrt(8.0)))


def _nearest_rotation(R: NDArray[np.float64]) -> NDArray[np.float64]:
    """The rotation nearest to ``R`` (polar factor), for drawing a ghost whose R left SO(3)."""
    u, _, vt = np.linalg.svd(R)
    q: NDArray[np.float64] = u @ vt
    if np.linalg.det(q) < 0.0:
        u[:, -1] *= -1.0
        q = u @ vt
    return q


class IntegratorGhost:
    """The ghost body, its controls and its error plot (made inside a scene's ``build``).

    Parameters
    ----------
    ctx : SceneContext
    name : str
        Scene-node name of the ghost mesh (under ``ctx.root``).
    mesh : trimesh.Trimesh
        The body's mesh, in body coordinates.
    """

    def __init__(self, ctx: SceneContext, name: str, mesh: trimesh.Trimesh) -> None:
        self.ctx = ctx
        gui = ctx.server.gui
        self.body = BodyMesh(ctx.server, name, mesh, colour=COLOURS["ghost"], opacity=GHOST_OPACITY)
        self.body.handle.visible = False
        self.choice = gui.add_dropdown(
            mark("Compare with integrator"), options=tuple(METHODS), initial_value=mark("none")
        )
        low, high, resolution, default = STEP
        self.step_slider = gui.add_slider(
            mark("integrator step h (s)"), min=low, max=high, step=resolution, initial_value=default
        )
        self.plot = InvariantDrift(
            ctx,
            (mark("angle"), "E"),
            (hex_colour("blue"), hex_colour("black")),
            title=mark("Ghost − exact: log₁₀ angle (rad), log₁₀ energy drift"),
        )
        self.plot.handle.visible = False
        self.choice.on_update(ctx.guarded(lambda _: self._changed()))
        self.step_slider.on_update(ctx.guarded(lambda _: self._changed()))
        self.method: Any = None
        self.exact: Exact | None = None
        self.energy: Callable[[NDArray[np.float64], NDArray[np.float64]], float] | None = None
        self.energy_scale = 1.0
        self.moments = np.ones(3)
        self.torque: Any = None
        self.state: NDArray[np.float64] | None = None  # R row-major, then L_body
        self.t = self.t0 = 0.0  # the ghost's time and its start (s)
        self.steps = 0  # steps taken since the start
        self.start_at = 0.0  # where the next start is (the clock when cleared)
        self.checkpoints: dict[int, NDArray[np.float64]] = {}  # steps since the start -> the state then
        self.checkpoint_step = math.nan  # the step h (s) the checkpoints were made with
        self.last_angle = 0.0

    # -- set up by the scene ------------------------------------------------------------------------
    def start(
        self,
        moments: NDArray[np.float64],
        exact: Exact | None,
        energy: Callable[[NDArray[np.float64], NDArray[np.float64]], float],
        energy_scale: float,
        torque: Any = None,
        mesh: trimesh.Trimesh | None = None,
    ) -> None:
        """A new motion: its principal moments, the exact ``t ↦ (R, L_body)`` (None: no exact solution, no
        ghost), its energy ``E(R, L_body)`` (J) with the scale a drift is measured against, the torque the
        integrator needs (e.g. gravity), and the body's mesh if it changed."""
        self.moments, self.exact, self.energy, self.torque = np.asarray(moments, float), exact, energy, torque
        self.energy_scale = max(float(energy_scale), 1e-300)
        if mesh is not None:
            self.body.set_mesh(mesh)
        self._changed()

    def start_free(self, moments: NDArray[np.float64], motion: Any, mesh: trimesh.Trimesh | None = None) -> None:
        """A torque-free motion (:meth:`physics.free_body.FreeBody.trajectory`): the ghost integrates
        Euler's equations without torque; its energy is ½ L·ω (a zero moment carries no L)."""
        moments = np.asarray(moments, dtype=float)
        inverse = np.divide(1.0, moments, out=np.zeros(3), where=moments > 0.0)

        def exact(t: float) -> tuple[NDArray[np.float64], NDArray[np.float64]]:
            now = motion.at(t)
            return now.attitude, moments * now.omega

        def energy(R: NDArray[np.float64], L_body: NDArray[np.float64]) -> float:
            return 0.5 * float(L_body @ (L_body * inverse))

        self.start(moments, exact, energy, energy(*exact(0.0)), mesh=mesh)

    def _changed(self) -> None:
        method = METHODS.get(str(self.choice.value))
        on = method is not None and self.exact is not None
        self.method = method(self.moments, self.torque) if on and method is not None else None
        self.body.handle.visible = on
        self.plot.handle.visible = on
        self.clear()
        self.ctx.request_redraw()

    def _stop(self, exc: ValueError) -> None:
        """The method refused the step (or diverged): the ghost goes off, the scene goes on, and the
        browsers are told why; the dropdown says "none" until someone chooses again."""
        name = str(self.choice.value)
        self.choice.value = "none"  # type: ignore[misc]  # (viser 1.1.1 types it read-only) its callback hides the ghost
        self._changed()  # also when the callback is not run (the same value set twice)
        self.ctx.notify(
            mark("Integrator ghost stopped"),
            say("{method}, h = {step:g} s: {reason}", method=name, step=float(self.step_slider.value), reason=str(exc)),
        )

    def clear(self) -> None:
        """Start again from the exact state at the next frame (a reset, a new parameter; it is in the scene's
        ``traces``)."""
        self.state = None
        self.start_at = float(self.ctx.time)  # the clock now (0 after a reset): the ghost starts here
        self.checkpoints = {}
        self.plot.clear()

    def rewind(self, t: float) -> None:
        """The timeline moved the clock to ``t`` (s): the ghost keeps its start and steps from its checkpoint
        before ``t`` at the next frame (:meth:`follow`), so it shows the states it showed there before; its
        plot keeps the samples up to ``t``."""
        self.plot.rewind(t)

    def _reaches(self, t: float, h: float, every: int) -> bool:
        """Whether the ghost's run reaches ``t`` (s) from a checkpoint it keeps, with at most :data:`CATCH_UP`
        seconds of steps beyond the furthest (else it starts again there)."""
        # A step slider moved (viser stores its value before its callback clears the ghost): a new run.
        if not self.checkpoints or h != self.checkpoint_step or t < self.t0 - 1e-12:
            return False
        target = math.floor((t - self.t0) / h + 1e-9)
        base = target - target % every
        if base < next(iter(self.checkpoints)):  # kept in order: the first is the earliest, the last the furthest
            return False
        return (base - next(reversed(self.checkpoints))) * h <= CATCH_UP

    # -- every frame ---------------------------------------------------------------------------------
    def follow(self, t: float, pose: Callable[[NDArray[np.float64]], tuple[NDArray[np.float64], Any]]) -> None:
        """Step the ghost to the clock's time ``t`` (s) and place it; ``pose(R)`` gives the attitude and
        position to draw a body of attitude ``R`` at (the scene's view: body view, centre of mass)."""
        if self.method is None or self.exact is None:
            return
        h = float(self.step_slider.value)
        every = max(1, round(CHECKPOINT_SECONDS / h))
        if self.state is None or not self._reaches(t, h, every):
            fresh = self.state is None and self.start_at <= t <= self.start_at + CATCH_UP
            t0 = self.start_at if fresh else t
            R, L = self.exact(t0)
            self.state, self.t0, self.steps, self.t = np.concatenate([np.asarray(R).ravel(), L]), t0, 0, t0
            self.checkpoints, self.checkpoint_step = {0: self.state.copy()}, h
        # Steps counted from the start, so the ghost's time t0 + k h carries no accumulated rounding. The
        # state after k steps is the checkpoint before it stepped on in one go, and each checkpoint the one
        # before stepped on in one go: the same numbers whichever frames asked (a splitting method merges
        # the half-steps of a run, so runs cut elsewhere differ in the last bits).
        target = int(math.floor((t - self.t0) / h + 1e-9))
        base = target - target % every
        try:
            latest = next(reversed(self.checkpoints))
            while latest < base:
                self.checkpoints[latest + every] = advance(self.method, self.checkpoints[latest], h, every)
                latest += every
                if len(self.checkpoints) > CHECKPOINTS:
                    del self.checkpoints[next(iter(self.checkpoints))]
            if target != self.steps:
                start = self.checkpoints[base]
                self.state = advance(self.method, start, h, target - base) if target > base else start.copy()
        except ValueError as exc:  # a step the method cannot take for this motion (RK4 past its limit)
            self._stop(exc)
            return
        self.steps = target
        self.t = self.t0 + self.steps * h
        R_ghost, L_ghost = self.state[:9].reshape(3, 3), self.state[9:]
        R_exact, _ = self.exact(self.t)
        attitude, position = pose(_nearest_rotation(R_ghost))
        self.body.set_pose(attitude, position)
        self.last_angle = chordal_angle(R_ghost, R_exact)
        energy = self.energy
        assert energy is not None
        self.plot.add(
            self.t, lambda: {"angle": (self.last_angle, 1.0), "E": (energy(R_ghost, L_ghost), self.energy_scale)}
        )
