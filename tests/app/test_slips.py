"""Small things a lecturer trips over (each once seen in class preparation): the dark look's principal axes,
the explorer's two sets of axes, free fall's two parabolas, the still explorer's clock, presets typed in
ASCII, ``--help``, a damaged state text."""

from __future__ import annotations

import base64

import numpy as np
import pytest

from app import draw
from app.__main__ import main, plain
from app.panel.look import contrast
from app.scenes.free_fall import FLIGHT_TIME, START, VELOCITY
from app.serving.app import export
from app.teaching.states import PREFIX, parse_state
from physics import G
from tests.harness import FRAME, open_scene, running_app

DARK_BACKGROUND = "#1a1b1e"  # the dark look's page, behind the 3D view (app.panel.look)


def _hex(rgb) -> str:
    return "#" + "".join(f"{int(c):02x}" for c in rgb)


def test_the_principal_axes_are_legible_in_both_looks():
    with running_app(start_loop=False, dark=True) as app:
        for name in ("wobble", "tennis_racket", "inertia_explorer"):
            scene = open_scene(app, name)
            rows = np.asarray(scene.frame.handle.colors).reshape(-1, 3)
            assert contrast(_hex(rows[0]), DARK_BACKGROUND) >= 7.0, name  # not black on near-black
            assert _hex(draw.DARK_COLOURS["axes"]) in app.simulation.legend.content  # the legend shows them as drawn
    with running_app(start_loop=False) as app:
        scene = open_scene(app, "wobble")
        assert tuple(np.asarray(scene.frame.handle.colors).reshape(-1, 3)[0]) == draw.COLOURS["axes"]


def test_the_explorer_draws_the_pivot_axes_unlike_the_principal_axes():
    with running_app(start_loop=False) as app:
        scene = open_scene(app, "inertia_explorer")
        principal = tuple(np.asarray(scene.frame.handle.colors).reshape(-1, 3)[0])
        pivot = tuple(np.asarray(scene.pivot_frame.handle.colors).reshape(-1, 3)[0])
        assert principal == draw.COLOURS["axes"] and pivot == draw.COLOURS["pivot"] != principal
        assert tuple(scene.pivot_marker.color) == draw.COLOURS["pivot"]


def test_free_fall_names_its_centre_of_mass_parabola_apart_from_the_axis_tip_trace():
    with running_app(start_loop=False) as app:
        scene = open_scene(app, "free_fall")
        for _ in range(30):
            app.frame(FRAME)
        path = app.server.scene._handle_from_node_name[app.simulation.root + "/path"]
        assert tuple(np.asarray(path.colors).reshape(-1, 3)[0]) != draw.COLOURS["trace"]
        assert scene.path_label.text == "centre of mass"
        # It hangs right of the launch point, under the rising leg, farther than the body reaches from its centre.
        position = np.asarray(scene.path_label.position)
        tau = np.linspace(0.0, FLIGHT_TIME, 400)
        path = START + VELOCITY * tau[:, None] - 0.5 * G * tau[:, None] ** 2 * np.array([0.0, 0.0, 1.0])
        assert np.min(np.linalg.norm(path - position, axis=1)) > scene.size / 2
        assert position[0] > START[0] and position[2] == START[2]
        assert scene.path_label.anchor == "center-left"  # its text reaches away from the path, under its rise


def test_the_still_explorer_has_no_running_clock():
    with running_app(start_loop=False) as app:
        open_scene(app, "inertia_explorer")  # open_scene presses Play
        assert (
            not app.simulation.playing
            and app.simulation.play_button.disabled
            and app.simulation.panel.step_button.disabled
        )
        app.simulation.step()
        for _ in range(5):
            app.frame(FRAME)
        assert app.time == 0.0
        open_scene(app, "wobble")  # a moving scene after it plays again
        assert app.simulation.playing and not app.simulation.play_button.disabled
        app.frame(FRAME)
        assert app.time > 0.0


@pytest.mark.parametrize(
    ("typed", "meant"),
    [
        ("loops", "loops (φ̇0 = −1 × steady)"),
        ("LOOPS (phidot0 = -1 x steady)", "loops (φ̇0 = −1 × steady)"),
        ("Waves (phidot0 = 1/2 x steady)", "waves (φ̇0 = ½ × steady)"),
        ("steady precession", "steady precession (slow rate)"),
        ("cusps (released from rest)", "cusps (released from rest)"),
    ],
)
def test_a_preset_is_found_by_its_ascii_name_or_its_start(typed, meant):
    with running_app(start_loop=False) as app:
        scene = open_scene(app, "heavy_top")
        assert scene.presets.resolve(typed) == meant
        assert scene.presets.choose(typed) and scene.presets.last == meant
        assert scene.presets.resolve("sleeping top") is None  # the start of two presets: which one?
        assert scene.presets.resolve("") is None and scene.presets.resolve("orbit") is None


def test_export_takes_a_preset_typed_in_ascii(tmp_path):
    written = export("heavy_top", tmp_path / "loops", 0.1, preset="loops", fps=10.0)
    assert written.frames >= 1 and written.csv.exists()
    with pytest.raises(ValueError, match="no preset 'sleeping top'"):
        export("heavy_top", tmp_path / "x", 0.1, preset="sleeping top", fps=10.0)


def test_help_shows_no_documentation_markup(capsys):
    with pytest.raises(SystemExit):
        main(["--help"])
    out = capsys.readouterr().out
    assert "``" not in out and ":mod:" not in out and "rigid-body-lab export --scene NAME" in out
    assert plain("see :mod:`app.rooms` and ``x``") == "see app.rooms and x"


@pytest.mark.parametrize(
    ("text", "why"),
    [
        (PREFIX + "eJzLSM3JyQcABiwCFQ"[:-3] + "QQQ", "some of its characters were changed or lost"),
        (PREFIX + "A", "a character a state text never has, or one too few"),
        (PREFIX + base64.urlsafe_b64encode(b"\x78\x9c" + b"\x00" * 12).decode(), "changed or lost"),
    ],
)
def test_a_damaged_state_text_says_so_plainly(text, why):
    with pytest.raises(ValueError) as caught:
        parse_state(text, ["wobble"])
    message = str(caught.value)
    assert message.startswith("this state text is damaged") and why in message and "Copy state" in message
    assert "Error -3" not in message and "decompress" not in message and "padding" not in message
