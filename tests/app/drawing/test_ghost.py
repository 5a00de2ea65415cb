"""Exact beside numerical (:mod:`app.drawing.ghost`): the ghost and its error plot against an independent computation.

The independent computation: the physics API's :func:`physics.integrators.integrate` (or ``advance`` for
classical RK4, whose R leaves SO(3)) from the scene's start with the same step, compared with
``HeavyTop.trajectory`` / ``FreeBody.trajectory`` at the ghost's time, and the angle taken with
``physics.rotations.rotation_angle`` where both are rotations. The plot shows log₁₀ of the angle.

Those reuse the app's own integrators and closed forms; :func:`test_the_plotted_error_against_code_written_here`
uses neither: a classical RK4 written in this file (numpy, the twelve components) for the ghost and scipy's
DOP853 at rtol = atol = 1e-13 for the exact side, on the equations of motion written here too.
"""

from __future__ import annotations

import math

import numpy as np
import pytest

from app.drawing.ghost import METHODS, chordal_angle
from physics import G
from physics.free_body import FreeBody
from physics.heavy_top import HeavyTop
from physics.integrators import (
    BlanesMoan6,
    ClassicalRK4,
    GravityTorque,
    LiePoissonStrang,
    SofroniouSpaletta10,
    Yoshida6,
    advance,
)
from physics.rotations import hat, rotation_about, rotation_angle
from tests.harness import open_scene, running_app

RK4, SPLIT, BEST, OPTIMISED6, TENTH = list(METHODS)[1:]


def _choose(app, scene, method: str, step: float | None = None) -> None:
    with app.simulation.lock:
        if step is not None:
            scene.ghost.step_slider.value = step
        scene.ghost.choice.value = method
        scene.ghost._changed()
        app.restart()


def _run(app, frames: int) -> None:
    app.set_playing(True)
    for _ in range(frames):
        app.frame(1.0 / 60.0)


def test_chordal_angle_is_the_rotation_angle():
    for angle in (1e-12, 1e-6, 0.3, 2.0, math.pi - 1e-3):
        a = rotation_about([0.2, -0.5, 0.8], 0.7)
        b = a @ rotation_about([1.0, 0.3, -0.2], angle)
        assert chordal_angle(a, b) == pytest.approx(angle, rel=1e-12)
        assert chordal_angle(a, b) == pytest.approx(float(rotation_angle(a, b)), rel=1e-9, abs=2e-8)


@pytest.mark.parametrize(
    "label, cls",
    [
        (RK4, ClassicalRK4),
        (SPLIT, LiePoissonStrang),
        (BEST, Yoshida6),
        (OPTIMISED6, BlanesMoan6),
        (TENTH, SofroniouSpaletta10),
    ],
)
def test_heavy_top_ghost_is_the_integrator_from_the_same_start(label, cls):
    with running_app("heavy_top", start_loop=False) as app:
        scene = open_scene(app, "heavy_top")
        _choose(app, scene, label, step=0.02)
        _run(app, 181)  # 3 s
        ghost = scene.ghost
        steps = round((ghost.t - ghost.t0) / 0.02)
        assert ghost.t0 == 0.0 and steps == 150 and ghost.body.handle.visible

        # Independently: the same top from the same start (spin 10, tilt 60°, at rest; I1 0.4, I3 0.2).
        top = HeavyTop(0.4, 0.2, 1.0)
        motion = top.trajectory(math.pi / 3, 0.0, 0.0, 10.0)
        start = motion.at(0.0)
        moments = np.array([0.4, 0.4, 0.2])
        torque = GravityTorque(1.0 / (G * 0.5), [0.0, 0.0, 0.5])
        state = advance(
            cls(moments, torque), np.concatenate([start.attitude.ravel(), moments * start.omega_body]), 0.02, steps
        )
        R = state[:9].reshape(3, 3)
        np.testing.assert_allclose(ghost.state, state, rtol=0, atol=1e-13)
        exact = motion.at(steps * 0.02).attitude
        angle = chordal_angle(R, exact)
        assert ghost.last_angle == pytest.approx(angle, rel=1e-12)
        if cls is not ClassicalRK4:
            assert angle == pytest.approx(float(rotation_angle(R, exact)), rel=1e-7)
        energy = 0.5 * float(state[9:] @ (state[9:] / moments)) + 1.0 * R[2, 2]
        e0 = 0.5 * float((moments * start.omega_body) @ start.omega_body) + math.cos(math.pi / 3)
        # The plot's newest point: sampled every 15th frame, the last at frame 181 (t = 3 s).
        latest = ghost.plot.latest()
        # The angle is 1.5e-8 rad for Yoshida 6: the plot's log10 is held to what 1e-13 in the state allows.
        assert latest["angle"] == pytest.approx(math.log10(angle), abs=1e-13 / angle)
        # The drift itself to 1e-14 (the ghost steps in frame-sized chunks, this reference in one run: the
        # two differ by round-off, which is all of the drift's last digits for Yoshida 6).
        assert 10.0 ** latest["E"] == pytest.approx(abs(energy - e0) / (abs(e0) + 1.0), abs=1e-14)


def test_the_geometric_composition_keeps_the_flip_and_careless_steps_lose_it():
    """The tennis racket at a coarse step: Yoshida 6 stays within a milliradian of the exact body over
    15 s of flips; the Lie–Poisson splitting (order 2) at the same step is a whole flip off."""
    with running_app("tennis_racket", start_loop=False) as app:
        scene = open_scene(app, "tennis_racket")
        angles = {}
        for label in (SPLIT, BEST):
            _choose(app, scene, label, step=0.05)
            _run(app, 900)
            angles[label] = scene.ghost.last_angle
        assert angles[BEST] < 1e-3 and angles[SPLIT] > 0.5, angles


def test_reset_rewind_and_choices():
    with running_app("wobble", start_loop=False) as app:
        scene = open_scene(app, "wobble")
        ghost = scene.ghost
        assert not ghost.body.handle.visible and not ghost.plot.handle.visible  # "none" by default
        _choose(app, scene, BEST)
        _run(app, 60)
        assert ghost.steps > 0 and ghost.body.handle.visible and ghost.plot.handle.visible
        app.restart()  # Reset: the ghost starts again from the exact start
        _run(app, 1)
        assert ghost.t0 == 0.0 and ghost.steps == 0 and app.time > 0.0
        with app.simulation.lock:
            app.simulation.set_time(500.0)  # a jump (an opened state): restart there, not 10,000 steps
            app.simulation.request_redraw()
        _run(app, 1)
        assert ghost.t0 > 499.0 and ghost.steps <= 1
        _choose(app, scene, "none")
        assert not ghost.body.handle.visible and ghost.method is None


def test_no_ghost_for_the_friction_top():
    with running_app("heavy_top", start_loop=False) as app:
        scene = open_scene(app, "heavy_top")
        _choose(app, scene, BEST)
        assert scene.params.offer({"friction": 0.02})
        _run(app, 30)
        assert scene.ghost.method is None and not scene.ghost.body.handle.visible


def test_free_body_ghost_matches_integrate():
    with running_app("wobble", start_loop=False) as app:
        scene = open_scene(app, "wobble")
        _choose(app, scene, SPLIT, step=0.01)
        _run(app, 121)
        ghost = scene.ghost
        body = FreeBody(scene.moments)
        start = np.concatenate([scene.attitude0.ravel(), scene.moments * scene.omega0])
        state = advance(LiePoissonStrang(scene.moments), start, 0.01, ghost.steps)
        np.testing.assert_allclose(ghost.state, state, rtol=0, atol=1e-13)
        exact = body.trajectory(scene.omega0, scene.attitude0).at(ghost.t).attitude
        assert ghost.last_angle == pytest.approx(float(rotation_angle(state[:9].reshape(3, 3), exact)), rel=1e-7)


def _rigid_body_rates(y: np.ndarray, moments: np.ndarray, mgl: float, ell: float) -> np.ndarray:
    """d/dt of (R row-major, L_body) for a body on its tip with its centre of mass at ``ell`` on body axis 3:
    Ṙ = R hat(ω), L̇_body = L_body × ω + τ_body, τ_body = (0, 0, ℓ) × Rᵀ (0, 0, −M g) (written here, not
    taken from physics/)."""
    R, L = y[:9].reshape(3, 3), y[9:]
    omega = L / moments
    weight = R.T @ np.array([0.0, 0.0, -mgl / ell])  # M g in the body frame
    torque = np.cross([0.0, 0.0, ell], weight)
    return np.concatenate([(R @ hat(omega)).ravel(), np.cross(L, omega) + torque])


def test_the_plotted_error_against_code_written_here():
    """The heavy top's ghost under classical RK4 at h = 0.02 s for 3 s: its state is the RK4 written here, and
    the plotted log₁₀ angle and energy drift are those of that state against scipy's DOP853 (rtol 1e-13)."""
    from scipy.integrate import solve_ivp

    h, steps, mgl, ell = 0.02, 150, 1.0, 0.5
    moments = np.array([0.4, 0.4, 0.2])
    with running_app("heavy_top", start_loop=False) as app:
        scene = open_scene(app, "heavy_top")
        _choose(app, scene, RK4, step=h)
        _run(app, 181)  # 3 s; the plot samples every 15th frame, the last at t = 3 s
        ghost = scene.ghost
        assert round((ghost.t - ghost.t0) / h) == steps and ghost.t == pytest.approx(3.0, abs=1e-12)
        latest = ghost.plot.latest()
        ghost_state = ghost.state.copy()

    # The start: tilted 60° about x, at rest in θ, spinning 10 rad/s about its axis (R = Rx(60°), ω = 10 e₃).
    c, s_ = math.cos(math.pi / 3), math.sin(math.pi / 3)
    R0 = np.array([[1.0, 0.0, 0.0], [0.0, c, -s_], [0.0, s_, c]])
    y0 = np.concatenate([R0.ravel(), moments * np.array([0.0, 0.0, 10.0])])
    # The ghost's start is the same state (to round-off: it comes from the closed form at t = 0).
    rates = lambda y: _rigid_body_rates(y, moments, mgl, ell)  # noqa: E731

    # Classical RK4, written out.
    y = y0.copy()
    for _ in range(steps):
        k1 = rates(y)
        k2 = rates(y + 0.5 * h * k1)
        k3 = rates(y + 0.5 * h * k2)
        k4 = rates(y + h * k3)
        y = y + h / 6.0 * (k1 + 2.0 * k2 + 2.0 * k3 + k4)
    # Round-off only: 150 steps of 12 components in a different order of operations (measured 8.5e-16).
    np.testing.assert_allclose(ghost_state, y, rtol=0, atol=1e-14)

    # The exact side: DOP853 at its tightest practical tolerance (its error here ~1e-12 rad).
    exact = solve_ivp(lambda t, v: rates(v), (0.0, steps * h), y0, method="DOP853", rtol=1e-13, atol=1e-13)
    R_exact = exact.y[:9, -1].reshape(3, 3)
    angle = chordal_angle(y[:9].reshape(3, 3), R_exact)
    assert 1e-7 < angle < 1e-2  # a visible error, far above both references' own
    # The plotted angle (4.1e-4 rad) to 1e-11 rad: the DOP853 reference's own error (measured 7.7e-13).
    assert abs(10.0 ** latest["angle"] - angle) < 1e-11, (10.0 ** latest["angle"], angle)

    def energy(v: np.ndarray) -> float:
        return 0.5 * float(v[9:] @ (v[9:] / moments)) + mgl * float(v[8])  # ½ L·ω + M g ℓ cos θ

    drift = abs(energy(y) - energy(y0)) / (abs(energy(y0)) + mgl)  # the plot's scale: |E₀| + M g ℓ
    assert drift > 1e-9  # RK4 is not geometric: its energy drifts
    # The plotted drift (5.0e-7) to the round-off of the states it is computed from.
    assert abs(10.0 ** latest["E"] - drift) < 1e-14, (10.0 ** latest["E"], drift)


def test_a_step_the_method_refuses_stops_the_ghost_not_the_scene():
    with running_app("tennis_racket", start_loop=False) as app:
        scene = open_scene(app, "tennis_racket")
        assert scene.params.offer({"spin": float(scene.params.sliders["spin"].max)})
        _choose(app, scene, RK4, step=0.2)  # |ω| h far past RK4's stability limit 2√2
        frames = app.frames
        _run(app, 30)
        assert app.simulation.playing and app.frames == frames + 30  # the scene was not paused
        assert not [m for m in app.messages if m[0] == "Paused"]
        assert app.messages[-1][0] == "Integrator ghost stopped" and "stability limit" in app.messages[-1][1]
        assert scene.ghost.choice.value == "none" and scene.ghost.method is None
        assert not scene.ghost.body.handle.visible
        _choose(app, scene, BEST, step=0.01)  # another choice runs again
        _run(app, 30)
        assert scene.ghost.method is not None and scene.ghost.steps > 0


def test_the_timeline_moved_back_then_on_shows_the_ghosts_states_bit_for_bit():
    """The ghost keeps its start and a checkpoint every quarter second of its time: scrubbed back (into the
    run, not to its start) and played on, it passes through the very states it showed before, and the
    checkpoints' steps are the same whatever frames they fell in."""
    with running_app("tennis_racket", start_loop=False) as app:
        scene = open_scene(app, "tennis_racket")
        _choose(app, scene, SPLIT, step=0.01)
        ghost = scene.ghost
        seen = {}
        app.set_playing(True)
        for _ in range(240):  # 4 s
            app.frame(1.0 / 60.0)
            seen[ghost.steps] = ghost.state.copy()
        assert ghost.t0 == 0.0 and sorted(ghost.checkpoints) == list(range(0, 401, 25))  # every 0.25 s
        app.simulation.timeline.seek(1.53)
        app.frame(1.0 / 60.0)
        assert ghost.t0 == 0.0 and ghost.steps == 153  # stepped on from the checkpoint at 1.5 s, not restarted
        compared = 0
        app.set_playing(True)
        for _ in range(120):
            app.frame(1.0 / 60.0)
            if ghost.steps in seen:
                assert np.array_equal(ghost.state, seen[ghost.steps]), ghost.steps
                compared += 1
        assert compared >= 60  # the frames after the scrub fall on many of the steps the first run showed
        app.simulation.timeline.seek(3.2)  # on again, within what it has been through
        app.frame(1.0 / 60.0)
        assert ghost.t0 == 0.0 and np.array_equal(ghost.state, seen[320])


def test_a_step_read_before_its_callback_has_cleared_the_ghost_starts_a_new_run():
    """viser stores a slider's new value before its callback runs (the callback waits for the simulation's
    lock): a frame may read the new step h while the checkpoints are the old h's. The ghost then starts a new
    run where it is, instead of looking for a checkpoint the new h would have made (a KeyError that paused
    the scene, found by the GUI fuzz test)."""
    with running_app("tennis_racket", start_loop=False) as app:
        scene = open_scene(app, "tennis_racket")
        _choose(app, scene, SPLIT, step=0.05)
        _run(app, 29)  # 0.48 s: checkpoints at 0 and 5 steps (every quarter second)
        ghost = scene.ghost
        assert sorted(ghost.checkpoints) == [0, 5] and ghost.t0 == 0.0
        ghost.step_slider._impl.value = 0.025  # stored, its callback not run yet: 10 steps a quarter second
        _run(app, 1)
        assert app.simulation.playing and ghost.method is not None  # the scene goes on, the ghost too
        assert ghost.checkpoint_step == 0.025 and ghost.t0 > 0.48 and ghost.steps == 0
