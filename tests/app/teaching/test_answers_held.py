"""What a scene holds back while a class question asks for it (``Scene.answers``, ``Scene.hold``), the
lecture's ``about`` key, and the steady top's words: headless, the scene's own objects."""

from __future__ import annotations

import math

import pytest

from app.panel.parameters import HELD, Readout
from app.scenes import REGISTRY, load_all
from app.scenes.base import Answer, Scene
from app.teaching.lectures import read_lecture
from app.teaching.questions import Ask, check_ask, held_back
from physics.heavy_top import HeavyTop
from tests.harness import FRAME, open_scene, running_app

load_all()
DECLARING = sorted(name for name, cls in REGISTRY.items() if cls.answers)


def test_the_scenes_that_questions_ask_about_declare_their_answers():
    assert DECLARING == ["heavy_top", "pendulum", "phone_toss", "tennis_racket"]
    quantities = {a.quantity for name in DECLARING for a in REGISTRY[name].answers}
    assert quantities == {"centre_of_percussion", "precession_rate", "flip"}


@pytest.mark.parametrize("name", DECLARING)
def test_every_declared_element_exists_and_comes_back_as_it_was(name):
    """A misspelt path in a declaration would hold nothing back: each one names a real readout or node,
    held while asked about and back at the reveal, with its visibility as it was."""
    with running_app(start_loop=False) as app:
        scene = open_scene(app, name)
        for answer in scene.answers:
            readouts = [_at(scene, p) for p in answer.readouts]
            nodes = [_at(scene, p) for p in answer.hidden]
            assert all(isinstance(r, Readout) for r in readouts), answer.readouts
            before = [(r.text, r.value_text) for r in readouts]
            shown = [n.visible for n in nodes]
            app.simulation.hold_back((answer.quantity,))
            app.frame(FRAME)  # a frame while held: the readouts set their values again, still held
            assert all(r.text == HELD for r in readouts) and not any(n.visible for n in nodes)
            assert scene.held == {answer.quantity}
            app.simulation.hold_back(())
            assert [n.visible for n in nodes] == shown
            assert [r.text for r in readouts] == [r.value_text for r in readouts]
            assert before[0][0] == before[0][1] != HELD


def _at(scene: Scene, path: str):
    obj = scene
    for part in path.split("."):
        obj = obj[part] if isinstance(obj, dict) else getattr(obj, part)
    return obj


def test_the_words_leave_the_answer_out_while_it_is_held():
    with running_app(start_loop=False) as app:
        scene = open_scene(app, "pendulum")
        ell = f"{scene.model.effective_length:.3g}"
        period = f"{scene.model.small_oscillation_period:.3g}"
        state = scene.compute(0.0, 0.0)
        assert ell in scene.describe(state) and period in scene.describe(state)
        app.simulation.hold_back(("centre_of_percussion",))
        said = scene.describe(state)
        assert ell not in said and period not in said and "released at 30°" in said
        scene = open_scene(app, "tennis_racket")
        app.simulation.hold_back(("flip",))
        said = scene.describe(scene.compute(0.0, 0.0))
        assert "flip" not in said.replace("the class question", "") and "class question" in said
        assert not scene.caption_markdown.visible  # the caption states the theorem
        scene = open_scene(app, "heavy_top")
        app.simulation.hold_back(("precession_rate",))
        said = scene.describe(scene.compute(0.0, 0.0))
        assert "rad/s," not in said.split(";")[0] and "its rate is the class question" in said


def test_a_scene_refuses_to_hold_what_it_does_not_declare():
    with running_app(start_loop=False) as app:
        scene = open_scene(app, "pendulum")
        with pytest.raises(ValueError, match="declares no answer 'flip'; it declares \\['centre_of_percussion'\\]"):
            scene.hold(("flip",))
        assert held_back(Ask("Q", range=(0, 1), truth="precession_rate"), scene) == ()  # another scene's
        assert held_back(Ask("Q", range=(0, 1), truth="centre_of_percussion"), scene) == ("centre_of_percussion",)
        assert held_back(None, scene) == ()


def test_about_names_what_a_question_asks_about():
    ask = check_ask({"question": "Q", "choices": ["a", "b"], "about": "flip"})
    assert ask.about == ("flip",) and ask.holds == ("flip",)
    ask = check_ask({"question": "Q", "range": [0, 1], "truth": "precession_rate"}, "heavy_top")
    assert ask.holds == ("precession_rate",)
    for bad in (3, ["x" * 41], [""], ["a"] * 9):
        with pytest.raises(ValueError, match="about: a quantity of the scene"):
            check_ask({"question": "Q", "choices": ["a", "b"], "about": bad})


def test_a_lecture_asking_about_what_its_scene_does_not_declare_is_refused(tmp_path):
    path = tmp_path / "bad.toml"
    path.write_text(
        'title = "t"\n[[step]]\nscene = "wobble"\nquestion = "Q?"\nchoices = ["a", "b"]\nabout = "flip"\n',
        encoding="utf-8",
    )
    with running_app(start_loop=False) as app, pytest.raises(ValueError, match="step 1: about: wobble declares no"):
        app.simulation.load_lecture(read_lecture(str(path)))


def test_the_shipped_questions_say_what_they_ask_about_and_give_what_is_needed():
    lecture = read_lecture("rigid-body-motion")
    asked = [(k, s.ask) for k, s in enumerate(lecture.steps) if s.ask is not None]
    assert [(k, ask.holds) for k, ask in asked] == [
        (2, ("centre_of_percussion",)),
        (6, ("flip",)),
        (7, ("precession_rate",)),
        (9, ("precession_rate",)),
        (12, ("flip",)),
    ]
    with running_app(start_loop=False) as app:
        app.simulation.load_lecture(lecture)
        app.go_to_step(2)
        model = app.scene.model
        text = lecture.steps[2].ask.text
        assert f"k = {model.radius_of_gyration:.4g} m" in text and f"a⊥ = {model.a_perp:.4g} m" in text
        app.go_to_step(9)
        top, values = app.scene.top, app.scene.params.values
        text = lecture.steps[9].ask.text
        for said in (f"I₁ = {top.I1:g} kg m²", f"I₃ = {top.I3:g} kg m²", f"M g ℓ = {top.mgl:g} N m"):
            assert said in text
        assert f"ω₃ = {values['spin']:g} rad/s" in text and f"θ = {values['theta0']:g}°" in text
    # No caption before a question states its answer (the steady rate, to three digits).
    rate = f"{abs(app_rate()):.3g}"
    assert not any(rate in step.caption for step in lecture.steps[:9])


def app_rate() -> float:
    """The steady precession's slow rate at the shipped step (I₁ = 0.4, I₃ = 0.2 kg m², M g ℓ = 1 N m)."""
    return float(HeavyTop(0.4, 0.2, 1.0).steady_precession_rates(math.radians(60.0), 2.0)[0])


def test_the_steady_top_is_not_said_to_nutate_between_one_angle_and_itself():
    with running_app(start_loop=False) as app:
        scene = open_scene(app, "heavy_top")
        scene.presets.choose("steady precession (slow rate)")
        app.frame(FRAME)
        said = scene.describe(scene.compute(0.0, 0.0))
        assert "between 60° and 60°" not in said and "nearly steady precession" in said and "at a tilt of 60°" in said


def test_a_readout_held_keeps_its_value_for_the_reveal():
    class Gui:
        def add_text(self, label, initial_value, disabled, hint):
            return type("H", (), {"value": initial_value})()

    ctx = type("Ctx", (), {"server": type("S", (), {"gui": Gui()})()})()
    readout = Readout(ctx, "x (m)")
    readout.hold(True)
    readout.set(0.57692)
    assert readout.text == HELD and readout.value_text == "0.5769"
    readout.hold(False)
    assert readout.text == "0.5769"
    assert Answer("q").readouts == () and Answer("q").hidden == ()
