"""Headless tests of the app: every scene builds and steps, handles move, sliders change the model,
bad input is refused and the server stays alive, NaN pauses the scene, the clock works.

One App (a real viser server on a free port, no loop thread) serves the module; each test builds its
scene afresh with ``switch_scene``. Frames are driven by calling ``App.frame(dt)`` directly.
"""

from __future__ import annotations

import math
import subprocess
import sys

import numpy as np
import pytest
from scipy.spatial.transform import Rotation

from app import draw
from app.scenes import REGISTRY, scene_names
from app.server import App, NumericalFailure, check_finite
from browser import FRAME, free_port, matrix, open_scene, running_app
from physics import G
from physics.free_body import FreeBody
from physics.heavy_top import HeavyTop

SCENES = ["heavy_top", "wobble", "free_fall"]




# --------------------------------------------------------------------------------------------------
# Shared pieces
# --------------------------------------------------------------------------------------------------


def test_registry_lists_the_three_scenes_in_picker_order():
    names = scene_names()
    assert names[:3] == SCENES or set(SCENES) <= set(names)
    for name in SCENES:
        cls = REGISTRY[name]
        assert cls.title and cls.quantities and cls.caption
        assert all(q in draw.COLOURS for q in cls.quantities)


def test_wxyz_from_matrix_and_scipy_quaternion_agree():
    rot = Rotation.from_rotvec([0.3, -1.2, 0.7])
    from_matrix = draw.wxyz(rot.as_matrix())
    from_quat = draw.wxyz(rot.as_quat())
    # Same rotation up to the quaternion sign; both unit norm (round-off only).
    assert min(np.abs(from_matrix - from_quat).max(), np.abs(from_matrix + from_quat).max()) < 1e-12
    np.testing.assert_allclose(draw.wxyz(np.eye(3)), [1.0, 0.0, 0.0, 0.0], atol=1e-15)
    x, y, z, w = rot.as_quat()
    np.testing.assert_allclose(draw.wxyz(rot.as_quat()), [w, x, y, z], atol=1e-15)
    # The fast single-matrix path (Shepperd) against scipy on many rotations, including half turns
    # (trace -1: the branch that divides by the largest diagonal term).
    mats = np.concatenate([Rotation.random(500, random_state=3).as_matrix(),
                           Rotation.from_rotvec(np.pi * np.eye(3)).as_matrix()])
    for m in mats:
        a, b = draw.wxyz(m), draw.wxyz(m[None])[0]
        assert min(np.abs(a - b).max(), np.abs(a + b).max()) < 1e-14
    batch = draw.wxyz(np.stack([np.eye(3), rot.as_matrix()]))
    assert batch.shape == (2, 4)
    with pytest.raises(ValueError, match="rotation matrix"):
        draw.wxyz(np.zeros(5))


def test_trace_is_a_bounded_ring_buffer_in_time_order(app):
    trace = draw.Trace(app.server, "/test_trace", capacity=10)
    for i in range(25):
        trace.append([float(i), 0.0, 0.0])
    pts = trace.points()
    assert pts.shape == (10, 3)
    np.testing.assert_array_equal(pts[:, 0], np.arange(15, 25))
    # The drawn segments join consecutive points, oldest first.
    segs = np.asarray(trace.handle.points)
    np.testing.assert_array_equal(segs[:, 0, 0], np.arange(15, 24))
    np.testing.assert_array_equal(segs[:, 1, 0], np.arange(16, 25))
    trace.resize(4)
    assert trace.points().shape == (0, 3)
    with pytest.raises(ValueError, match="at least 2"):
        trace.resize(1)
    trace.handle.remove()


def test_cone_points_along_its_axis_with_its_half_angle(app):
    cone = draw.Cone(app.server, "/test_cone", "body_cone")
    axis = np.array([0.3, -0.5, -0.8])
    cone.set(axis, math.radians(25.0), 2.0, apex=(1.0, 2.0, 3.0))
    R = matrix(cone.handle)
    # viser stores float32: agreement to ~1e-7.
    np.testing.assert_allclose(R @ [0, 0, 1], axis / np.linalg.norm(axis), atol=1e-6)
    r, _, h = cone.handle.scale
    assert math.degrees(math.atan2(r, h)) == pytest.approx(25.0, abs=1e-9)
    assert math.hypot(r, h) == pytest.approx(2.0, rel=1e-12)
    np.testing.assert_allclose(cone.handle.position, [1.0, 2.0, 3.0])
    cone.set(axis, 0.0, 2.0)  # degenerate: hidden
    assert not cone.handle.visible
    cone.handle.remove()
    cone.rim.remove()


def test_check_finite_names_the_bad_value():
    check_finite({"a": 1.0, "b": np.ones(3), "c": {"d": np.eye(3)}, "name": "text"})
    with pytest.raises(NumericalFailure, match="c.d"):
        check_finite({"c": {"d": np.array([0.0, np.nan])}})
    with pytest.raises(NumericalFailure, match="theta"):
        check_finite({"theta": math.inf})


# --------------------------------------------------------------------------------------------------
# Every scene builds, steps and its handles move
# --------------------------------------------------------------------------------------------------


@pytest.mark.parametrize("name", SCENES)
def test_each_scene_builds_steps_and_moves_its_handles(app, name):
    scene = open_scene(app, name)
    assert app.scene_picker.value == REGISTRY[name].title
    before = np.array(scene.body.handle.wxyz)
    for _ in range(30):
        assert app.frame(FRAME)
    after = np.array(scene.body.handle.wxyz)
    assert app.time == pytest.approx(31 * FRAME, rel=1e-12)
    # The body turned (several degrees in half a second at these spins).
    angle = 2 * math.acos(min(1.0, abs(float(before @ after))))
    assert angle > math.radians(2)
    assert len(scene.trace.points()) > 10
    assert scene.omega_arrow.handle.visible and scene.L_arrow.handle.visible


def test_paused_clock_holds_time_and_step_advances_one_frame(app):
    open_scene(app, "wobble")
    app.set_playing(False)
    t0 = app.time
    app.frame(FRAME)
    assert app.time == t0
    assert not app.frame(FRAME)  # nothing to redraw
    app.set_speed(2.5)
    app.step()
    assert app.frame(FRAME)
    assert app.time == pytest.approx(t0 + 2.5 / 60.0, rel=1e-12)
    with pytest.raises(ValueError, match="speed"):
        app.set_speed(50.0)
    app.restart()
    assert app.time == 0.0


def test_speed_scales_simulation_time(app):
    open_scene(app, "wobble")
    app.restart()
    app.set_speed(10.0)
    app.frame(0.05)
    assert app.time == pytest.approx(0.5, rel=1e-12)
    app.set_speed(0.1)
    app.frame(0.05)
    assert app.time == pytest.approx(0.505, rel=1e-12)


def test_buttons_and_speed_slider_drive_the_clock(app):
    open_scene(app, "wobble")
    app.play_button._impl.value = True
    for cb in app.play_button._impl.update_cb:  # a click from the page arrives like this
        cb(None)
    assert not app.playing and app.play_button.label == "Play"
    app.speed_slider.value = 3.0
    assert app.speed == 3.0


# --------------------------------------------------------------------------------------------------
# The models behind the pictures
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
    assert scene.plot_theta > 0.0  # the plot has been drawn at least once
    x, U, energy, now = (np.asarray(a) for a in scene.plot.data)
    # uPlot draws nothing at all when a series holds NaN: every series must be finite.
    assert all(np.all(np.isfinite(a)) for a in (x, U, energy, now))
    exact = scene.exact
    # Released at rest in θ: the energy line is U(θ0) (θ̇0 = 0), to round-off of the partial fractions.
    U0 = scene.top.effective_potential(np.array([scene.start[0]]), exact.Lz, exact.L3)[0]
    np.testing.assert_allclose(energy, U0, rtol=1e-9)
    # One visible "now" point, inside the y range, on the curve U at the current θ.
    lo, hi = scene._y_range
    visible = np.flatnonzero((now >= lo) & (now <= hi))
    assert visible.size == 1
    theta = scene.plot_theta
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


def test_heavy_top_presets_reach_cusps_loops_and_waves(app):
    scene = open_scene(app, "heavy_top")
    expected = {"cusps": 0.0, "loops": -1.0, "waves": 2.0}
    for name in scene.presets.presets:
        assert scene.presets.choose(name), name
        app.frame(FRAME)
        key = name.split()[0]
        if key in expected:
            v = scene.params.values
            steady = HeavyTop(v["I1"], v["I3"], v["mgl"]).steady_precession_rates(math.radians(v["theta0"]),
                                                                                    v["I3"] * v["spin"])[0]
            assert v["phidot0"] == pytest.approx(expected[key] * steady, abs=1e-3)
    # Loops: φ̇ changes sign along the motion; waves: it does not; cusps: it touches 0.
    scene.presets.choose("loops (φ̇0 = −1 × steady)")
    v = scene.params.values
    theta0 = math.radians(v["theta0"])
    sol = scene.top.solve(theta0, 0.0, v["phidot0"], v["spin"] - v["phidot0"] * math.cos(theta0),
                          np.linspace(0, 3 * scene.exact.nutation_period, 600))
    assert sol.phidot.min() < 0.0 < sol.phidot.max()


def test_heavy_top_with_friction_spins_down_and_falls(app):
    scene = open_scene(app, "heavy_top")
    assert scene.presets.choose("sleeping top with friction: falls")
    L3_start = scene.L_body[2]
    app.set_speed(10.0)
    thetas = []
    for _ in range(25):  # 0.1 s of wall time at 10x: 1 s of simulation per frame, 25 s in all
        app.frame(0.1)
        thetas.append(math.degrees(math.acos(np.clip(scene.R[2, 2], -1, 1))))
    assert app.time == pytest.approx(25.0, rel=1e-12)
    # Spin friction alone: L3 decays as exp(-c t / I3) (dL3/dt = -c L3/I3; gravity's torque has no axis part).
    c, I3 = scene.params.values["friction"], scene.params.values["I3"]
    assert scene.L_body[2] == pytest.approx(L3_start * math.exp(-c * 25.0 / I3), rel=1e-6)
    assert thetas[0] < 5.0  # still sleeping at first
    assert max(thetas) > 45.0  # below the threshold it wobbles and falls
    assert "too slow to sleep" in scene.gauge.text.content


def test_wobble_keeps_L_fixed_and_omega_on_the_cones(app):
    scene = open_scene(app, "wobble")
    L_tips, angles = [], []
    for _ in range(60):
        app.frame(FRAME)
        L_tips.append(np.array(scene.L_arrow.handle.points[0, 1]) + scene.L_arrow.handle.position)
        R = matrix(scene.body.handle)
        w = scene.omega_arrow.handle.points[0, 1] - scene.omega_arrow.handle.points[0, 0]
        angles.append(math.degrees(math.acos(R[:, 2] @ w / np.linalg.norm(w))))
    # L fixed in space (float32 transport: ~1e-7 m).
    assert np.ptp(np.array(L_tips), axis=0).max() < 1e-6
    # The angle between ω and the symmetry axis is constant: the body-cone half-angle.
    assert np.ptp(angles) < 1e-3
    v = scene.params.values
    fb = FreeBody(scene.moments)
    rates = fb.precession_rates(scene.omega0)
    assert scene.Omega_readout.text == f"{rates.body:.4g}"
    assert rates.body == pytest.approx(v["spin"] * math.cos(math.radians(v["tilt"])) * (1 - v["ratio"]), rel=1e-12)


def test_wobble_body_view_holds_the_body_still(app):
    scene = open_scene(app, "wobble")
    scene.body_view.value = True
    q = []
    for _ in range(20):
        app.frame(FRAME)
        q.append(np.array(scene.body.handle.wxyz))
    np.testing.assert_allclose(np.abs(np.array(q) @ np.array([1.0, 0, 0, 0])), 1.0, atol=1e-6)
    scene.body_view.value = False


def test_free_fall_centre_follows_the_parabola_and_spins_like_the_wobble(app):
    from app.scenes.free_fall import START, VELOCITY

    scene = open_scene(app, "free_fall")
    for _ in range(20):
        app.frame(FRAME)
    tau = app.time % scene.flight_time
    expected = START + VELOCITY * tau - 0.5 * G * tau**2 * np.array([0, 0, 1.0])
    np.testing.assert_allclose(scene.body.handle.position, expected, atol=1e-6)
    # The arrows start at the centre of mass.
    np.testing.assert_allclose(scene.L_arrow.handle.position, expected, atol=1e-6)
    np.testing.assert_allclose(scene.L_arrow.handle.points[0, 0], 0.0)
    R_expected = FreeBody(scene.moments).attitude(scene.omega0, [app.time], scene.attitude0)[0]
    np.testing.assert_allclose(matrix(scene.body.handle), R_expected, atol=2e-6)


# --------------------------------------------------------------------------------------------------
# Bad input and robustness
# --------------------------------------------------------------------------------------------------


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


def test_impossible_wobble_shape_is_refused(app):
    scene = open_scene(app, "wobble")
    scene.params.sliders["ratio"].value = 2.3
    assert scene.params.values["ratio"] == 1.6
    assert scene.params.sliders["ratio"].value == 1.6
    assert "no rigid body has these moments" in app.messages[-1][1]
    assert app.frame(FRAME)


def test_nan_in_a_frame_pauses_with_a_message_and_keeps_the_last_state(app, monkeypatch):
    scene = open_scene(app, "wobble")
    for _ in range(5):
        app.frame(FRAME)
    t, pose = app.time, np.array(scene.body.handle.wxyz)
    good = scene.compute

    def broken(t, dt):
        state = good(t, dt)
        state["omega_space"] = np.array([np.nan, 0.0, 0.0])
        return state

    monkeypatch.setattr(scene, "compute", broken)
    assert not app.frame(FRAME)
    assert not app.playing
    assert app.time == t
    assert "numerical failure" in app.messages[-1][1] and "omega_space" in app.messages[-1][1]
    assert "⚠" in app.status.content
    np.testing.assert_array_equal(scene.body.handle.wxyz, pose)
    monkeypatch.setattr(scene, "compute", good)
    app.set_playing(True)
    assert app.frame(FRAME)


def test_exception_in_a_frame_or_a_callback_is_shown_not_swallowed(app, monkeypatch):
    scene = open_scene(app, "heavy_top")

    def boom(t, dt):
        raise RuntimeError("the model broke")

    monkeypatch.setattr(scene, "compute", boom)
    assert not app.frame(FRAME)
    assert "RuntimeError: the model broke" in app.messages[-1][1]
    assert not app.playing
    monkeypatch.undo()

    @app.guarded
    def callback(event):
        raise KeyError("missing")

    assert callback(None) is None  # nothing escapes into viser's thread pool
    assert app.messages[-1][0] == "Something went wrong" and "KeyError" in app.messages[-1][1]


def test_a_scene_that_fails_to_build_leaves_the_previous_one(app, monkeypatch):
    open_scene(app, "wobble")

    def broken_build(self):
        raise RuntimeError("cannot build")

    monkeypatch.setattr(REGISTRY["free_fall"], "build", broken_build)
    app.scene_picker.value = REGISTRY["free_fall"].title  # the picker, as from the page
    assert app.scene.name == "wobble"
    assert app.scene_picker.value == REGISTRY["wobble"].title
    assert "cannot build" in app.messages[-1][1]
    assert app.frame(FRAME)


def test_switching_scenes_from_the_picker_replaces_the_scene(app):
    open_scene(app, "heavy_top")
    app.scene_picker.value = REGISTRY["wobble"].title
    assert app.scene.name == "wobble" and app.time == 0.0
    assert "body cone" in app.legend.content
    assert app.frame(FRAME)


def test_the_loop_thread_runs_the_clock():
    with running_app("wobble") as a:
        from browser import wait_for

        wait_for(lambda: a.frames > 5 and a.time > 0.0, timeout=20, what="the loop to draw frames")


def test_unknown_scene_is_refused():
    with pytest.raises(ValueError, match="unknown scene"):
        App(port=free_port(), scene="nope", start_loop=False)


def test_command_prints_the_address():
    port = free_port()
    proc = subprocess.Popen([sys.executable, "-m", "app", "--port", str(port), "--scene", "wobble"],
                            stdout=subprocess.PIPE, stderr=subprocess.DEVNULL, text=True)
    line = ""
    try:
        # viser prints its own banner first; our line follows it.
        for _ in range(40):
            line = proc.stdout.readline()
            if line.startswith("Rigid Body Lab") or not line:
                break
    finally:
        proc.terminate()
        proc.wait(timeout=10)
    assert line.strip() == f"Rigid Body Lab serving on http://127.0.0.1:{port}"
