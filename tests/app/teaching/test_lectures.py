"""Lectures: a TOML file of steps, walked with Previous and Next; a bad file is
refused with a message that names the step and the key, before anything starts."""

from __future__ import annotations

import math
import re
import tomllib

import numpy as np
import pytest

from app.__main__ import main
from app.teaching.lectures import LECTURES, read_lecture
from tests.harness import running_app

SHIPPED = LECTURES / "rigid-body-motion.toml"


def _write(tmp_path, text: str):
    path = tmp_path / "lecture.toml"
    path.write_text(text, encoding="utf-8")
    return str(path)


def test_the_shipped_lecture_follows_the_lectures_order_and_every_step_shows():
    lecture = read_lecture("rigid-body-motion")  # found by name
    scenes = [step.scene for step in lecture.steps]
    # The lecture's sections in its order, then the class measures the flip themselves.
    order = ["inertia_explorer", "pendulum", "wobble", "tennis_racket", "heavy_top", "phone_toss"]
    assert [s for i, s in enumerate(scenes) if i == 0 or s != scenes[i - 1]] == order
    assert lecture.steps[-2].preset == "sleeping top with friction: falls"  # friction last of the theory
    with running_app(start_loop=False) as app:
        app.simulation.load_lecture(lecture)  # every step applied once: presets and values all accepted
        for k, step in enumerate(lecture.steps):
            app.go_to_step(k)
            assert app.scene.name == step.scene
            assert f"step {k + 1} of {len(lecture.steps)}" in app.simulation.following.text.content
            if step.preset:
                assert app.scene.presets.last == step.preset
            for label, choice in step.choices.items():
                assert next(h for h in app.simulation.scene_inputs if str(h.label) == label).value == choice
            for key, value in step.values.items():
                assert app.scene.params.values[key] == value
        app.go_to_step(len(lecture.steps) + 5)  # Next at the last step stays there
        assert app.simulation.step_index == len(lecture.steps) - 1
        app.go_to_step(-3)
        assert app.simulation.step_index == 0


def _shows(caption: str, value: float, digits: int = 4) -> None:
    """The caption states ``value`` to ``digits`` significant digits (as the panel's readouts print it)."""
    text = f"{value:.{digits}g}".replace("-", "−")  # captions write the minus sign
    assert re.search(rf"(?<![\d.]){re.escape(text)}(?![\d])", caption), f"{text} not in {caption!r}"


def _angle(u: np.ndarray, v: np.ndarray) -> float:
    return math.atan2(float(np.linalg.norm(np.cross(u, v))), float(u @ v))


def test_the_shipped_captions_state_what_each_step_shows():
    """Every number in a shipped caption is the app's own for that step, and every claim that can be
    measured is: the moments, the parallel-axis change, the pendulum's lengths, the strike at the centre of
    percussion, the wobble's rates and which cone lies inside which, the racket's growth, the tops'
    turning angles, rates and the friction top's fall."""
    lecture = read_lecture("rigid-body-motion")
    captions = [step.caption for step in lecture.steps]
    with running_app(start_loop=False) as app:
        app.simulation.load_lecture(lecture)

        def at(k: int):
            app.go_to_step(k)
            app.set_speed(1.0)
            app.set_playing(True)
            app.frame(1.0 / 60.0)
            return app.scene

        # 1: a solid cylinder (the dropdown's choice), I₃ = M a²/2, I₁ = I₂ = M (a²/4 + L²/12).
        s = at(0)
        assert s.label == "Solid cylinder" and s.props.mass == 1.0
        a, length = 0.05, 1.0
        np.testing.assert_allclose(s.moments, [a * a / 4 + length**2 / 12] * 2 + [a * a / 2], rtol=1e-12)
        for value in s.moments[1:]:
            _shows(captions[0], value)
        assert "solid cylinder" in captions[0].lower()
        # 2: d ⊥ the axis: the two moments about axes perpendicular to d grow by M d², the one along d stays.
        s = at(1)
        d = np.array([0.4, 0.0, 0.0])
        change = np.diag(s.tensor_pivot) - np.diag(s.props.tensor)
        np.testing.assert_allclose(change, [0.0, 0.16, 0.16], atol=1e-15)
        _shows(captions[1], 0.16)
        assert s.props.mass * float(d @ d) == pytest.approx(0.16)
        for value in (*np.diag(s.props.tensor)[[0, 2]], *np.diag(s.tensor_pivot)):
            _shows(captions[1], value)
        # 3: ℓ = k²/a⊥ > k > a⊥, and the small-swing period.
        s = at(2)
        m = s.model
        assert m.effective_length > m.radius_of_gyration > m.a_perp
        for value in (m.effective_length, m.radius_of_gyration, m.a_perp, m.small_oscillation_period):
            _shows(captions[2], value)
        _shows(captions[2], 2 * math.pi * math.sqrt(m.effective_length / 9.81))
        # 4: the strike point starts on the centre of percussion (the button's value); no blow at the pivot.
        s = at(3)
        assert "Move the strike point to the centre of percussion" in captions[3]
        assert s.params.values["strike"] == round(s.model.effective_length, 3)
        _shows(captions[3], s.params.values["strike"], 3)
        pivot = float(np.linalg.norm(s.strike().reaction_impulse))
        assert pivot < 5e-4 * s.params.values["impulse"]
        _shows(captions[3], pivot, 1)
        # 5 and 6: the rates, and which cone lies inside which.
        for k, inside in ((4, True), (5, False)):
            s = at(k)
            now = s.motion.at(1.234)
            axis, omega, L = now.attitude[:, 2], now.attitude @ now.omega, s.L_space
            body_half, space_half, apart = _angle(axis, omega), _angle(L, omega), _angle(axis, L)
            if inside:  # oblate: L between axis and ω, the space cone within the body cone
                assert s.moments[2] > s.moments[0] and apart == pytest.approx(body_half - space_half, abs=1e-12)
            else:  # prolate: ω between axis and L, the cones touch from outside
                assert s.moments[2] < s.moments[0] and apart == pytest.approx(body_half + space_half, abs=1e-12)
            rates = s.model.precession_rates(s.omega0)
            _shows(captions[k], rates.body)
            assert (rates.body < 0) == inside  # Ω against the spin for a disc
            if inside:
                _shows(captions[k], rates.space)  # L/I₁
        assert "inside the body cone" in captions[5] and "outside of the space cone" in captions[5]
        # 7: λ, the estimate of the first flip and the measured period.
        s = at(6)
        assert s.stability.kind == "unstable"
        _shows(captions[6], s.stability.rate, 3)
        _shows(captions[6], math.log(1.0 / s.eps) / s.stability.rate, 2)
        _shows(captions[6], s.flip_period)
        # 8-11: the tops' turning angles, rates and the threshold.
        s = at(7)
        _shows(captions[7], math.degrees(s.exact.theta_max), 3)
        _shows(captions[7], s.exact.nutation_period, 3)
        s = at(8)
        assert s.params.values["phidot0"] < 0
        _shows(captions[8], s.params.values["phidot0"], 3)
        _shows(captions[8], math.degrees(s.exact.theta_max))
        s = at(9)
        slow = s.top.steady_precession_rates(math.radians(60.0), s.top.I3 * 10.0)[0]
        assert s.params.values["phidot0"] == pytest.approx(slow, abs=5e-4)
        _shows(captions[9], slow)
        assert s.exact.theta_max - s.exact.theta_min < 1e-3
        _shows(captions[9], s.top.mgl / (s.top.I3 * 10.0), 1)
        s = at(10)
        L3, threshold = s.top.I3 * s.params.values["spin"], s.top.sleeping_threshold()
        assert L3 > threshold
        _shows(captions[10], L3, 1)
        _shows(captions[10], threshold)
        _shows(captions[10], math.degrees(s.exact.theta_max))
        # 12: L₃ passes the threshold after (I₃/c) ln(L₃/threshold), then the top falls onto its rim.
        s = at(11)
        c = s.params.values["friction"]
        crossing = s.top.I3 / c * math.log(L3 / threshold)
        _shows(captions[11], crossing, 3)
        _shows(captions[11], c, 1)
        app.set_speed(10.0)
        passed = None
        for _ in range(120):  # 10 s of simulation a frame (0.1 s of wall time × 10)
            app.frame(0.1)
            if passed is None and abs(s.L_body[2]) < threshold:
                passed = app.time
            if s.landed:
                break
        assert passed == pytest.approx(crossing, abs=1.0)
        assert s.landed and app.time > crossing
        from app.scenes.heavy_top import TOUCH

        _shows(captions[11], math.degrees(TOUCH), 3)
        # 13: the bundled tosses' fit, as the panel states it: the ratios, the residual, the half turns of
        # each toss (fitted and measured alike) and the share of |L| the drag took in the first.
        s = at(12)
        fit = s.result.fit
        assert s.result.source.startswith("example toss") and fit.axes[1] == "x"
        for value in fit.moments[:2]:
            _shows(captions[12], value)
        _shows(captions[12], fit.residual, 3)
        assert all(h.predicted.size == h.measured.size == 2 for h in fit.half_turn_times)
        assert "2 half turns in each toss" in captions[12]
        assert f"|L| down {fit.momentum_loss(0):.1%} in the first" in captions[12]
        # ω_x reverses at each half turn, ω_z keeps its sign and is largest where ω_x crosses zero.
        assert "ω_x, the spin about the middle axis" in captions[12] and "ω_z" in captions[12]
        for k, seg in enumerate(fit.segments):
            w = fit.predict(seg.times, k)
            assert w[:, 0].min() < 0.0 < w[:, 0].max() and (w[:, 2].min() > 0.0 or w[:, 2].max() < 0.0)
            crossing = int(np.argmin(np.abs(w[:, 0])))
            assert abs(w[crossing, 2]) > 0.9 * np.max(np.abs(w[:, 2]))


BAD_FILES = {
    "not toml": ("[[step]\nscene = 1", "not a TOML file"),
    "no steps": ('title = "x"', "at least one"),
    "unknown top key": ('titel = "x"\n[[step]]\nscene = "wobble"', "unknown key 'titel'"),
    "unknown step key": (
        '[[step]]\nscene = "wobble"\n\n[[step]]\nscene = "wobble"\nspeed = 2',
        "step 2: unknown key 'speed'",
    ),
    "unknown scene": ('[[step]]\nscene = "orrery"', "step 1, scene: no scene 'orrery'"),
    "no scene": ('[[step]]\ncaption = "hello"', "step 1: a step needs a scene"),
    "choices not a table": ('[[step]]\nscene = "wobble"\nchoices = "Body"', "step 1, choices: a table"),
    "choice not text": ('[[step]]\nscene = "inertia_explorer"\nchoices = { Body = 3 }', "step 1, choices.Body"),
    "values not numbers": ('[[step]]\nscene = "wobble"\nvalues = { spin = "fast" }', "step 1, values.spin"),
    "bad camera": ('[[step]]\nscene = "wobble"\ncamera = { position = [1, 2] }', "step 1, camera"),
    "bad seconds": ('[[step]]\nscene = "wobble"\nseconds = -1', "step 1, seconds"),
    "bad state": ('[[step]]\nstate = "rbl1:xyz"', "step 1, state"),
}


@pytest.mark.parametrize("name", list(BAD_FILES))
def test_a_bad_file_is_refused_naming_the_step_and_the_key(tmp_path, name):
    text, message = BAD_FILES[name]
    with pytest.raises(ValueError, match=message):
        read_lecture(_write(tmp_path, text))


@pytest.mark.parametrize(
    "step, message",
    [
        ('scene = "wobble"\npreset = "cube"', "step 2: preset: wobble has no preset 'cube'"),
        ('scene = "wobble"\nvalues = { spin = 99.0 }', "step 2: values.spin: spin must be between"),
        ('scene = "wobble"\nvalues = { wobble = 1.0 }', "step 2: values.wobble: there is no parameter"),
        ('scene = "wobble"\nchoices = { Body = "Box" }', "step 2: choices.Body: wobble has no dropdown 'Body'"),
        ('scene = "inertia_explorer"\nchoices = { Body = "Cube" }', "step 2: choices.Body: no choice 'Cube'"),
        ('scene = "heavy_top"\nvalues = { I1 = 0.05, I3 = 0.5 }', "step 2: values were refused: no rigid body"),
    ],
)
def test_what_only_a_scene_can_check_is_checked_before_the_lecture_starts(tmp_path, step, message):
    path = _write(tmp_path, f'[[step]]\nscene = "pendulum"\n\n[[step]]\n{step}\n')
    with pytest.raises(ValueError, match=message), running_app(start_loop=False) as app:
        app.simulation.load_lecture(read_lecture(path))
    with pytest.raises(SystemExit) as info:
        main(["--lecture", path, "--port", "0"])
    assert info.value.code == 2


def test_a_choice_the_scene_refuses_is_named(tmp_path, monkeypatch):
    from app.scenes.inertia_explorer import InertiaExplorer

    apply = InertiaExplorer.apply

    def refusing(self, values):
        if self.choice.value == "Solid sphere":
            raise ValueError("no spheres today")
        apply(self, values)

    monkeypatch.setattr(InertiaExplorer, "apply", refusing)
    path = _write(tmp_path, '[[step]]\nscene = "inertia_explorer"\nchoices = { Body = "Solid sphere" }\n')
    with pytest.raises(ValueError, match="step 1: choices.Body: 'Solid sphere' was refused: no spheres today"):
        with running_app(start_loop=False) as app:
            app.simulation.load_lecture(read_lecture(path))


def test_a_step_with_seconds_moves_on_by_itself_and_the_last_stays(tmp_path):
    path = _write(
        tmp_path, '[[step]]\nscene = "wobble"\nseconds = 0.5\n\n[[step]]\nscene = "pendulum"\nseconds = 0.5\n'
    )
    with running_app(start_loop=False) as app:
        app.simulation.load_lecture(read_lecture(path))
        assert app.scene.name == "wobble"
        app.frame(1.0 / 60.0)
        assert app.simulation.step_index == 0  # not yet
        app.simulation.following.step_started -= 1.0  # as if a second had passed
        app.frame(1.0 / 60.0)
        assert (app.simulation.step_index, app.scene.name) == (1, "pendulum")
        app.simulation.following.step_started -= 1.0
        app.frame(1.0 / 60.0)
        assert app.simulation.step_index == 1


def test_a_step_can_be_a_state_text_and_sets_the_camera(tmp_path):
    with running_app("heavy_top", start_loop=False) as source:
        source.set_speed(2.0)
        text = source.state_text()
    path = _write(
        tmp_path,
        f'[[step]]\nstate = "{text}"\ncamera = {{ position = [3.0, -3.0, 2.0], look_at = [0.0, 0.0, 0.5] }}\n',
    )
    with running_app("wobble", start_loop=False) as app:
        app.simulation.load_lecture(read_lecture(path))
        assert app.scene.name == "heavy_top" and app.simulation.speed == 2.0
        assert list(app.server.initial_camera.position) == [3.0, -3.0, 2.0]


def test_the_shipped_file_is_plain_toml():
    document = tomllib.loads(SHIPPED.read_text(encoding="utf-8"))
    assert document["title"] and len(document["step"]) >= 10


def _main_with_a_stand_in_app(argv: list[str], monkeypatch) -> dict:
    """``rigid-body-lab ARGV`` parsed by app.__main__.main up to the server it would start (returns what the
    App would have been given)."""
    import app.serving.app

    given: dict = {}

    class Started(Exception):
        pass

    class StandIn:
        def __init__(self, **kwargs):
            given.update(kwargs)
            raise Started

    monkeypatch.setattr(app.serving.app, "App", StandIn)
    with pytest.raises(Started):
        main(argv)
    return given


def test_the_command_line_finds_the_shipped_lecture_by_name(monkeypatch):
    given = _main_with_a_stand_in_app(["--lecture", "rigid-body-motion", "--port", "0"], monkeypatch)
    assert given["lecture"] == "rigid-body-motion"
    assert read_lecture(given["lecture"]).source == str(LECTURES / "rigid-body-motion.toml")
    assert (LECTURES / "__init__.py").is_file()  # the package whose data the wheel installs


STAND_IN = """
import sys
import app.serving.app
from app.__main__ import main

class StandIn:
    def __init__(self, **kwargs):
        from app.teaching.lectures import LECTURES, read_lecture
        lecture = read_lecture(kwargs["lecture"])
        print("APP", app.serving.app.__file__)
        print("LECTURE", lecture.source, len(lecture.steps))
        sys.exit(0)

app.serving.app.App = StandIn
main(["--lecture", "rigid-body-motion", "--port", "0"])
"""


def test_a_wheel_installs_the_lectures_and_the_command_line_finds_them(tmp_path):
    """Not an editable install: the wheel built from this tree, unpacked alone on the path (its own app, its
    own lectures, nothing from the source tree), run from another folder."""
    import os
    import shutil
    import subprocess
    import sys
    import zipfile
    from pathlib import Path

    root = Path(__file__).resolve().parents[3]
    source = tmp_path / "source"
    source.mkdir()
    for name in ("pyproject.toml", "README.md", "LICENSE"):
        shutil.copy(root / name, source / name)
    for name in ("app", "physics", "assets", "benchmarks", "lectures"):
        shutil.copytree(root / name, source / name, ignore=shutil.ignore_patterns("__pycache__", "*.png"))
    built = subprocess.run(
        [sys.executable, "-m", "pip", "wheel", "--no-deps", "--quiet", "-w", str(tmp_path / "dist"), str(source)],
        capture_output=True,
        text=True,
        timeout=600,
    )
    assert built.returncode == 0, built.stderr
    (wheel,) = (tmp_path / "dist").glob("*.whl")
    names = zipfile.ZipFile(wheel).namelist()
    assert "lectures/rigid-body-motion.toml" in names and "lectures/__init__.py" in names
    site = tmp_path / "site"
    zipfile.ZipFile(wheel).extractall(site)
    elsewhere = tmp_path / "elsewhere"
    elsewhere.mkdir()
    run = subprocess.run(
        [sys.executable, "-c", STAND_IN],
        cwd=elsewhere,
        env={**os.environ, "PYTHONPATH": str(site)},
        capture_output=True,
        text=True,
        timeout=300,
    )
    assert run.returncode == 0, run.stderr
    lines = dict(line.split(" ", 1) for line in run.stdout.splitlines() if line[:3] in ("APP", "LEC"))
    assert lines["APP"].startswith(str(site))  # the installed app, not the source tree
    path, steps = lines["LECTURE"].rsplit(" ", 1)
    assert path == str(site / "lectures" / "rigid-body-motion.toml") and int(steps) == 13


def test_a_step_opens_at_a_time_and_replays_the_seconds_before(tmp_path):
    path = _write(
        tmp_path,
        '[[step]]\nscene = "tennis_racket"\ntime = 1.8\n\n'
        '[[step]]\nscene = "tennis_racket"\ntime = 2.5\nreplay = 1.5\n\n[[step]]\nscene = "wobble"\n',
    )
    with running_app(start_loop=False) as app:
        sim = app.simulation
        sim.load_lecture(read_lecture(path))
        app.frame(1.0 / 60.0)
        assert sim.time == 1.8 and not sim.playing  # opened paused at the instant
        sim.go_to_step(1)
        replay = sim.timeline.replay
        assert replay is not None and (replay.start, replay.end) == (1.0, 2.5) and sim.speed == 0.1 and sim.playing
        app.frame(1.0 / 60.0)
        assert 1.0 < sim.time < 1.01
        sim.go_to_step(2)  # a new scene: the replay is over, the speed of before
        assert sim.timeline.replay is None and sim.speed == 1.0 and sim.time == 0.0


@pytest.mark.parametrize(
    ("step", "message"),
    [
        ("time = -1", "time: a number of seconds from 0 to 300"),
        ("time = 301", "time: a number of seconds from 0 to 300"),
        ('time = "soon"', "time: a number of seconds"),
        ("time = 2\nreplay = 0", "replay: a number of seconds from 0.1 to 60"),
        ("time = 2\nreplay = nan", "replay: a number of seconds"),
        ("replay = 2", "replay: replays the seconds before the step's `time`"),
    ],
)
def test_a_bad_time_or_replay_is_refused_naming_the_step(tmp_path, step, message):
    with pytest.raises(ValueError, match=re.escape(message)) as refused:
        read_lecture(_write(tmp_path, f'[[step]]\nscene = "pendulum"\n\n[[step]]\nscene = "pendulum"\n{step}\n'))
    assert "step 2" in str(refused.value)
