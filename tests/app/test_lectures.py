"""Lectures (issue 13, item 1): a TOML file of steps, walked with Previous and Next; a bad file is
refused with a message that names the step and the key, before anything starts."""

from __future__ import annotations

import tomllib

import pytest

from app.__main__ import main
from app.lectures import LECTURES, read_lecture
from tests.harness import running_app

SHIPPED = LECTURES / "rigid-body-motion.toml"


def _write(tmp_path, text: str):
    path = tmp_path / "lecture.toml"
    path.write_text(text, encoding="utf-8")
    return str(path)


def test_the_shipped_lecture_follows_the_lectures_order_and_every_step_shows():
    lecture = read_lecture("rigid-body-motion")  # found by name
    scenes = [step.scene for step in lecture.steps]
    order = ["inertia_explorer", "pendulum", "wobble", "tennis_racket", "heavy_top"]
    assert [s for i, s in enumerate(scenes) if i == 0 or s != scenes[i - 1]] == order
    assert lecture.steps[-1].preset == "sleeping top with friction: falls"  # friction last
    with running_app(start_loop=False) as app:
        app.load_lecture(lecture)  # every step applied once: presets and values all accepted
        for k, step in enumerate(lecture.steps):
            app.go_to_step(k)
            assert app.scene.name == step.scene
            assert f"step {k + 1} of {len(lecture.steps)}" in app._lecture_text.content
            if step.preset:
                assert app.scene.presets.last == step.preset
            for key, value in step.values.items():
                assert app.scene.params.values[key] == value
        app.go_to_step(len(lecture.steps) + 5)  # Next at the last step stays there
        assert app.step_index == len(lecture.steps) - 1
        app.go_to_step(-3)
        assert app.step_index == 0


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
        ('scene = "heavy_top"\nvalues = { I1 = 0.05, I3 = 0.5 }', "step 2: values were refused: no rigid body"),
    ],
)
def test_what_only_a_scene_can_check_is_checked_before_the_lecture_starts(tmp_path, step, message):
    path = _write(tmp_path, f'[[step]]\nscene = "pendulum"\n\n[[step]]\n{step}\n')
    with pytest.raises(ValueError, match=message), running_app(start_loop=False) as app:
        app.load_lecture(read_lecture(path))
    with pytest.raises(SystemExit) as info:
        main(["--lecture", path, "--port", "0"])
    assert info.value.code == 2


def test_a_step_with_seconds_moves_on_by_itself_and_the_last_stays(tmp_path):
    path = _write(
        tmp_path, '[[step]]\nscene = "wobble"\nseconds = 0.5\n\n[[step]]\nscene = "pendulum"\nseconds = 0.5\n'
    )
    with running_app(start_loop=False) as app:
        app.load_lecture(read_lecture(path))
        assert app.scene.name == "wobble"
        app.frame(1.0 / 60.0)
        assert app.step_index == 0  # not yet
        app._step_started -= 1.0  # as if a second had passed
        app.frame(1.0 / 60.0)
        assert (app.step_index, app.scene.name) == (1, "pendulum")
        app._step_started -= 1.0
        app.frame(1.0 / 60.0)
        assert app.step_index == 1


def test_a_step_can_be_a_state_text_and_sets_the_camera(tmp_path):
    with running_app("heavy_top", start_loop=False) as source:
        source.set_speed(2.0)
        text = source.state_text()
    path = _write(
        tmp_path,
        f'[[step]]\nstate = "{text}"\ncamera = {{ position = [3.0, -3.0, 2.0], look_at = [0.0, 0.0, 0.5] }}\n',
    )
    with running_app("wobble", start_loop=False) as app:
        app.load_lecture(read_lecture(path))
        assert app.scene.name == "heavy_top" and app.speed == 2.0
        assert list(app.server.initial_camera.position) == [3.0, -3.0, 2.0]


def test_the_shipped_file_is_plain_toml():
    document = tomllib.loads(SHIPPED.read_text(encoding="utf-8"))
    assert document["title"] and len(document["step"]) >= 10
