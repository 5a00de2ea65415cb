"""The server headless: registry, clock (pause, step, speed, buttons), NaN and exceptions pause with a
message and keep the last state, a scene that fails to build leaves the previous one, the command.

One App (a real viser server on a free port, no loop thread) serves the module; frames are driven by
``App.frame(dt)``.
"""

from __future__ import annotations

import math
import subprocess
import sys

import numpy as np
import pytest

from app import draw
from app.scenes import REGISTRY, load_all, scene_names
from app.serving.app import App
from app.serving.finite import NumericalFailure, check_finite
from tests.harness import FRAME, free_port, open_scene, running_app

SCENES = ["heavy_top", "wobble", "free_fall"]


def test_registry_lists_the_three_scenes_in_picker_order():
    names = scene_names()
    assert names[:3] == SCENES or set(SCENES) <= set(names)
    for name in SCENES:
        cls = REGISTRY[name]
        assert cls.title and cls.quantities and cls.caption
        assert all(q in draw.COLOURS for q in cls.quantities)


def test_check_finite_names_the_bad_value():
    check_finite({"a": 1.0, "b": np.ones(3), "c": {"d": np.eye(3)}, "name": "text"})
    with pytest.raises(NumericalFailure, match="c.d"):
        check_finite({"c": {"d": np.array([0.0, np.nan])}})
    with pytest.raises(NumericalFailure, match="theta"):
        check_finite({"theta": math.inf})


REAL = (np.float16, np.float32, np.float64, np.longdouble)
COMPLEX = (np.complex64, np.complex128)
BAD_REAL = (math.nan, math.inf, -math.inf)
BAD_COMPLEX = (*BAD_REAL, complex(0.0, math.inf), complex(math.nan, 0.0))


@pytest.mark.parametrize("size", [1, 9, 64, 65, 1000])  # checked in Python up to 64 elements, by numpy above
@pytest.mark.parametrize(
    "dtype, bad", [(d, b) for d in REAL for b in BAD_REAL] + [(d, b) for d in COMPLEX for b in BAD_COMPLEX]
)
def test_check_finite_finds_one_bad_element_in_an_array_of_any_size_and_float_type(size, dtype, bad):
    values = np.full(size, np.finfo(dtype).max, dtype=dtype)  # the largest finite number is finite
    check_finite({"v": values})
    values[size // 2] = bad
    with pytest.raises(NumericalFailure, match="v contains NaN or inf"):
        check_finite({"v": values})


@pytest.mark.parametrize("name", SCENES)
def test_each_scene_builds_steps_and_moves_its_handles(app, name):
    scene = open_scene(app, name)
    assert app.simulation.scene_picker.value == REGISTRY[name].title
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
    app.simulation.step()
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
    app.simulation.play_button._impl.value = True
    for cb in app.simulation.play_button._impl.update_cb:  # a click from the page arrives like this
        cb(None)
    assert not app.simulation.playing and app.simulation.play_button.label == "Play"
    app.simulation.speed_slider.value = 0.5  # the slider is logarithmic (app.panel.speed): half-way right is 10^0.5×
    assert (
        app.simulation.speed == pytest.approx(10**0.5, rel=1e-15) and app.simulation.speed_slider.label == "Speed 3.2×"
    )
    app.simulation.speed_slider.value = -1.0
    assert app.simulation.speed == pytest.approx(0.01, rel=1e-15) and app.simulation.speed_slider.label == "Speed 0.01×"
    app.set_speed(1.0)
    assert app.simulation.speed_slider.value == 0.0 and app.simulation.speed_slider.label == "Speed 1×"


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
    assert not app.simulation.playing
    assert app.time == t
    assert "numerical failure" in app.messages[-1][1] and "omega_space" in app.messages[-1][1]
    assert "⚠" in app.simulation.status.content
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
    assert not app.simulation.playing
    monkeypatch.undo()

    @app.simulation.guarded
    def callback(event):
        raise KeyError("missing")

    assert callback(None) is None  # nothing escapes into viser's thread pool
    assert app.messages[-1][0] == "Something went wrong" and "KeyError" in app.messages[-1][1]


def test_a_scene_that_fails_to_build_leaves_the_previous_one(app, monkeypatch):
    open_scene(app, "wobble")

    def broken_build(self):
        raise RuntimeError("cannot build")

    monkeypatch.setattr(REGISTRY["free_fall"], "build", broken_build)
    app.simulation.scene_picker.value = REGISTRY["free_fall"].title  # the picker, as from the page
    assert app.scene.name == "wobble"
    assert app.simulation.scene_picker.value == REGISTRY["wobble"].title
    assert "cannot build" in app.messages[-1][1]
    assert app.frame(FRAME)


def test_switching_scenes_from_the_picker_replaces_the_scene(app):
    open_scene(app, "heavy_top")
    app.simulation.scene_picker.value = REGISTRY["wobble"].title
    assert app.scene.name == "wobble" and app.time == 0.0
    assert "body cone" in app.simulation.legend.content
    assert app.frame(FRAME)


def test_the_loop_thread_runs_the_clock():
    with running_app("wobble") as a:
        from tests.harness import wait_for

        wait_for(lambda: a.frames > 5 and a.time > 0.0, timeout=20, what="the loop to draw frames")


def test_unknown_scene_is_refused():
    with pytest.raises(ValueError, match="unknown scene"):
        App(port=free_port(), scene="nope", start_loop=False)


def test_command_prints_the_address():
    port = free_port()
    proc = subprocess.Popen(
        [sys.executable, "-m", "app", "--port", str(port), "--scene", "wobble"],
        stdout=subprocess.PIPE,
        stderr=subprocess.DEVNULL,
        text=True,
    )
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


def test_scenes_are_registered_with_legends():
    load_all()
    for name in ("inertia_explorer", "pendulum", "tennis_racket"):
        cls = REGISTRY[name]
        assert cls.title and cls.caption and cls.quantities
