"""The heavy-top scene headless: the exact solution drawn, U(θ) plot, sliders, presets, friction, refusals."""

from __future__ import annotations

import math

import numpy as np
import pytest

from physics.heavy_top import HeavyTop
from tests.harness import FRAME, matrix, open_scene

SCENES = ["heavy_top", "wobble", "free_fall"]


# --------------------------------------------------------------------------------------------------
# Shared pieces
# --------------------------------------------------------------------------------------------------


def test_heavy_top_draws_the_exact_solution(app):
    scene = open_scene(app, "heavy_top")
    for _ in range(45):
        app.frame(FRAME)
    v = scene.params.values
    top = HeavyTop(v["I1"], v["I3"], v["mgl"])
    theta0 = math.radians(v["theta0"])
    sol = top.solve(theta0, 0.0, v["phidot0"], v["spin"] - v["phidot0"] * math.cos(theta0), [app.time])
    # The handle carries float32-rounded quaternions from viser: agreement to ~1e-6.
    np.testing.assert_allclose(matrix(scene.body.handle), sol.attitude[0], atol=2e-6)
    np.testing.assert_allclose(scene.trace.points()[-1], sol.axis[0], atol=1e-12)


def test_heavy_top_potential_plot_shows_U_energy_and_now(app):
    scene = open_scene(app, "heavy_top")
    for _ in range(20):
        app.frame(FRAME)
    assert scene.potential.x > 0.0  # the plot has been drawn at least once
    x, U, energy, now = (np.asarray(a) for a in scene.potential.handle.data)
    # uPlot draws nothing at all when a series holds NaN: every series must be finite.
    assert all(np.all(np.isfinite(a)) for a in (x, U, energy, now))
    exact = scene.exact
    # Released at rest in θ: the energy line is U(θ0) (θ̇0 = 0), to round-off of the partial fractions.
    U0 = scene.top.effective_potential(np.array([scene.start[0]]), exact.Lz, exact.L3)[0]
    np.testing.assert_allclose(energy, U0, rtol=1e-9)
    # One visible "now" point, inside the y range, on the curve U at the current θ.
    assert scene.potential.y_range is not None
    lo, hi = scene.potential.y_range
    visible = np.flatnonzero((now >= lo) & (now <= hi))
    assert visible.size == 1
    theta = scene.potential.x
    assert abs(math.radians(x[visible[0]]) - theta) <= math.radians(0.5) + 1e-12  # grid spacing 0.5°
    U_now = scene.top.effective_potential(np.array([theta]), exact.Lz, exact.L3)[0]
    assert now[visible[0]] == pytest.approx(U_now, rel=1e-6)  # θ̇² recovered from |ω⊥|²: round-off


def test_heavy_top_sliders_change_the_model_and_restart(app):
    scene = open_scene(app, "heavy_top")
    for _ in range(10):
        app.frame(FRAME)
    scene.params.sliders["mgl"].value = 2.0  # as a browser would (callbacks run)
    assert scene.top.mgl == 2.0 and app.time == 0.0
    assert scene.params.values["mgl"] == 2.0
    scene.params.sliders["spin"].value = 25.0
    assert scene.exact.L3 == pytest.approx(scene.top.I3 * 25.0, rel=1e-14)
    # A faster top precesses more slowly (pseudo-regular rate M g l / L3 to leading order).
    assert 0.0 < scene.exact.precession_rate < 2.0 / (0.2 * 25.0) * 1.2


def test_one_change_resets_the_heavy_top_once(app, monkeypatch):
    scene = open_scene(app, "heavy_top")
    for _ in range(5):
        app.frame(FRAME)
    resets = []
    reset = scene.reset
    monkeypatch.setattr(scene, "reset", lambda: (resets.append(app.time), reset())[1])
    scene.params.sliders["spin"].value = 12.0  # one slider, as a browser moves it
    assert resets == [0.0] and scene.exact.L3 == pytest.approx(scene.top.I3 * 12.0, rel=1e-14)
    assert scene.presets.choose("sleeping top with friction: falls")  # a preset: several sliders, one change
    assert len(resets) == 2 and scene.values["friction"] == 0.02
    app.restart()  # the Reset button: one reset too
    assert len(resets) == 3
    # And the reset it does is the whole one: the stepping state is the new start's.
    np.testing.assert_array_equal(scene.L_body, scene.top.moments * scene.exact.omega_body[0])
    assert not scene.landed


def test_heavy_top_presets_reach_cusps_loops_and_waves(app):
    scene = open_scene(app, "heavy_top")
    expected = {"cusps": 0.0, "loops": -1.0, "waves": 0.5}
    for name in scene.presets.presets:
        assert scene.presets.choose(name), name
        app.frame(FRAME)
        key = name.split()[0]
        if key in expected:
            v = scene.params.values
            steady = HeavyTop(v["I1"], v["I3"], v["mgl"]).steady_precession_rates(
                math.radians(v["theta0"]), v["I3"] * v["spin"]
            )[0]
            assert v["phidot0"] == pytest.approx(expected[key] * steady, abs=1e-3)

    # Loops: φ̇ changes sign along the motion; waves: it does not; cusps: it touches 0.
    def phidot_range(preset: str) -> tuple[float, float]:
        assert scene.presets.choose(preset), preset
        v = scene.params.values
        theta0 = math.radians(v["theta0"])
        sol = scene.top.solve(
            theta0,
            0.0,
            v["phidot0"],
            v["spin"] - v["phidot0"] * math.cos(theta0),
            np.linspace(0, 3 * scene.exact.nutation_period, 600),
        )
        return float(sol.phidot.min()), float(sol.phidot.max())

    low, high = phidot_range("loops (φ̇0 = −1 × steady)")
    assert low < 0.0 < high
    low, high = phidot_range("waves (φ̇0 = ½ × steady)")
    assert 0.0 < low < high  # φ̇ keeps its sign: waves, never a loop
    low, high = phidot_range("cusps (released from rest)")
    assert low == pytest.approx(0.0, abs=1e-9) and high > 0.0
    # The preset's former name (2 × steady, which drew small loops) still chooses it.
    assert scene.presets.choose("waves (φ̇0 = 2 × steady)")
    assert scene.presets.handle.value == "waves (φ̇0 = ½ × steady)"


def test_heavy_top_with_friction_spins_down_falls_and_lies_on_the_table(app):
    from app.scenes.heavy_top import TOP_MESH, TOUCH

    scene = open_scene(app, "heavy_top")
    assert scene.presets.choose("sleeping top with friction: falls")
    L3_start = scene.L_body[2]
    c, I3 = scene.params.values["friction"], scene.params.values["I3"]
    app.set_speed(10.0)
    thetas, lowest = [], []
    for _ in range(40):  # 0.1 s of wall time at 10x: 1 s of simulation per frame, 40 s in all
        app.frame(0.1)
        thetas.append(math.degrees(math.acos(np.clip(scene.R[2, 2], -1, 1))))
        lowest.append(float(np.min(TOP_MESH.vertices @ scene.R.T[:, 2])))  # the body's lowest point (m)
        if not scene.landed:
            # Spin friction alone: L3 decays as exp(-c t / I3) (dL3/dt = -c L3/I3; gravity has no axis part).
            assert scene.L_body[2] == pytest.approx(L3_start * math.exp(-c * app.time / I3), rel=1e-6)
    assert app.time == pytest.approx(40.0, rel=1e-12)
    assert thetas[0] < 5.0  # still sleeping at first
    # Below the threshold it falls until its rim meets the table, and lies there: never below it.
    assert scene.landed and thetas[-1] == pytest.approx(math.degrees(TOUCH), abs=1e-9)
    assert max(thetas) <= math.degrees(TOUCH) + 1e-9
    assert min(lowest) >= -1e-12, min(lowest)
    assert min(lowest) == pytest.approx(0.0, abs=1e-12)  # it does touch the table
    assert np.all(scene.L_body == 0.0) and "lying on the table" in scene.theta_readout.text
    # At rest on the table the table's push cancels gravity's torque: no τ arrow (dL/dt = 0 = τ).
    assert scene.compute(app.time, 0.0)["torque"].tolist() == [0.0, 0.0, 0.0]
    assert not scene.torque_arrow._visible
    assert "too slow to sleep" in scene.gauge.text.content


@pytest.mark.parametrize("spin", [0.0, 2.0])
def test_a_top_set_upright_below_the_threshold_topples_from_a_stated_nudge(app, spin):
    from app.scenes.heavy_top import UPRIGHT_NUDGE

    scene = open_scene(app, "heavy_top")
    assert scene.params.offer({"theta0": 0.0, "spin": spin, "phidot0": 0.0, "friction": 0.0})
    assert scene.start[0] == UPRIGHT_NUDGE and "unstable equilibrium" in scene.note.content
    tilts = []
    for _ in range(8 * 60):
        app.frame(FRAME)
        tilts.append(math.degrees(math.acos(np.clip(scene.R[2, 2], -1, 1))))
    # The nudge grows as exp(λt), λ = √(M g ℓ/I₁ − (L₃/2I₁)²) (1.6 and 1.5 /s here): within 8 s the top
    # has fallen far from upright (and, being exact and frictionless, swings back).
    assert tilts[0] < 0.1 and max(tilts) > 90.0


def test_a_top_set_upright_with_friction_sleeps_then_topples_and_lies_on_the_table(app):
    """Exactly upright and above the threshold, with spin friction: friction takes L₃ below the threshold,
    and a top exactly upright would have nothing to fall from; it starts nudged (said at the top of the
    panel), sleeps, then falls onto its rim."""
    from app.scenes.heavy_top import TOP_MESH, TOUCH, UPRIGHT_NUDGE

    scene = open_scene(app, "heavy_top")
    assert scene.params.offer({"theta0": 0.0, "spin": 20.0, "phidot0": 0.0, "friction": 0.02})
    assert scene.start[0] == UPRIGHT_NUDGE
    assert "with friction" in scene.note.content and "0.057°" in scene.note.content
    # The note is the first thing in the scene's folder, under the caption: above the fold.
    assert scene.note._impl.props.order < scene.params.sliders["spin"]._impl.props.order
    threshold = scene.top.sleeping_threshold()
    app.set_speed(10.0)
    tilts, lowest, crossed = [], [], None
    for _ in range(60):  # 1 s of simulation a frame
        app.frame(0.1)
        tilts.append(math.degrees(math.acos(np.clip(scene.R[2, 2], -1, 1))))
        lowest.append(float(np.min(TOP_MESH.vertices @ scene.R.T[:, 2])))
        if crossed is None and abs(scene.L_body[2]) < threshold:
            crossed = len(tilts)
        if scene.landed:
            break
    assert crossed is not None and max(tilts[: crossed - 1]) < 1.0  # it sleeps above the threshold
    assert scene.landed and tilts[-1] == pytest.approx(math.degrees(TOUCH), abs=1e-9)
    assert min(lowest) >= -1e-12 and min(lowest) == pytest.approx(0.0, abs=1e-12)  # on the table, not below
    assert "lying on the table" in scene.theta_readout.text


def test_a_sleeping_top_set_upright_stays_upright(app):
    scene = open_scene(app, "heavy_top")
    assert scene.params.offer({"theta0": 0.0, "spin": 20.0, "phidot0": 0.0, "friction": 0.0})
    assert scene.start[0] == 0.0 and scene.note.content == ""
    for _ in range(120):
        app.frame(FRAME)
    assert scene.R[2, 2] == pytest.approx(1.0, abs=1e-12)


def test_impossible_heavy_top_is_refused_and_the_last_state_stays(app):
    scene = open_scene(app, "heavy_top")
    for _ in range(5):
        app.frame(FRAME)
    top_before, t_before, refusals = scene.top, app.time, scene.params.refusals
    pose_before = np.array(scene.body.handle.wxyz)
    scene.params.sliders["I3"].value = 0.9  # I3 > 2 I1 = 0.8: no rigid body
    assert scene.params.refusals == refusals + 1
    assert scene.top is top_before and app.time == t_before
    assert scene.params.sliders["I3"].value == 0.2  # the slider snapped back
    title, body = app.messages[-1]
    assert title.startswith("Refused") and "no rigid body" in body and "I3" in body
    np.testing.assert_array_equal(scene.body.handle.wxyz, pose_before)
    assert app.frame(FRAME)  # the server goes on


def test_sleeping_is_said_only_of_a_top_that_stands_upright(app):
    scene = open_scene(app, "heavy_top")
    assert scene.params.offer({"spin": 30.0, "theta0": 60.0, "phidot0": 0.0, "friction": 0.0})
    app.frame(FRAME)
    text = scene.gauge.text.content
    assert "above it" in text and "tilted" in text and "sleeps" not in text  # above the threshold, at 60°
    assert scene.params.offer({"theta0": 2.0})
    app.frame(FRAME)
    assert "the top sleeps" in scene.gauge.text.content


def test_the_friction_top_steps_as_simulate_heavy_body_does(app):
    """The scene builds its Blanes–Moan 6 stepper once and steps it each frame: the same motion as the physics
    API's simulate_heavy_body over the same steps (to round-off)."""
    from app.scenes.heavy_top import ELL
    from physics import G
    from physics.heavy_top import simulate_heavy_body
    from physics.integrators import BlanesMoan6, SpinFriction

    scene = open_scene(app, "heavy_top")
    assert scene.presets.choose("sleeping top with friction: falls")
    app.set_speed(10.0)
    app.frame(0.1)  # 1 s of the simulation at t = 0: 240 steps of 1/240 s
    R0, L0 = scene.R.copy(), scene.L_body.copy()
    app.frame(0.1)
    top = scene.top
    moments = np.array([top.I1, top.I1, top.I3])
    run = simulate_heavy_body(
        moments,
        top.mgl / (G * ELL),
        [0.0, 0.0, ELL],
        R0,
        L0 / moments,
        1.0,
        1.0 / 240.0,
        torques=[SpinFriction(scene.params.values["friction"], moments)],
        method=BlanesMoan6,
        save_every=240,
    )
    np.testing.assert_allclose(scene.R, run.attitude[-1], rtol=0, atol=1e-13)
    np.testing.assert_allclose(scene.L_body, run.L_body[-1], rtol=0, atol=1e-13 * np.linalg.norm(L0))
