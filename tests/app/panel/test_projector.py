"""Projector mode on the server (app.panel.projector, Simulation.set_projector): the region it frames the body
in, the caption it shows (the lecture step's as the class may see it, sanitised), the large copy of the key
plot fed with the scene's own data, held-back answers kept back in both, each private browser's own switch,
``--projector``, and everything back as it was when switched off."""

from __future__ import annotations

import math

import numpy as np
import pytest

from app.__main__ import main as cli_main
from app.guards.text import lecturer_markdown
from app.panel.projector import (
    CAPTION_HEIGHT_PX,
    LEAVE,
    MARGIN_PX,
    PLOT_WIDTH_PX,
    projector_region,
)
from app.scenes import REGISTRY, load_all
from app.serving.framing import PANEL_PX, framed, free_region
from tests.harness import project, raw_client, running_app, wait_for

FOV = math.radians(50.0)
PENDULUM_QUESTION, RACKET_QUESTION = 2, 6  # the shipped lecture's pendulum and racket questions (0-based)


def _frame(app, n: int = 3) -> None:
    with app.simulation.lock:
        app.simulation.request_redraw()
        for _ in range(n):
            app.frame(1.0 / 60.0)


@pytest.mark.parametrize("plot", [False, True])
def test_the_body_is_framed_below_the_caption_and_beside_the_plot_over_the_panels_width(plot):
    width, height = 1280, 800
    region = free_region(width, height, projector=True, plot=plot)
    assert region == projector_region(width, height, plot)
    left, top, right, bottom = region
    assert top == pytest.approx(2 * MARGIN_PX + CAPTION_HEIGHT_PX)  # below the caption's panel
    assert bottom == height and left == 0.0
    # Without a plot the whole width, the panel's 400 px included; with one, all but the plot's column.
    assert right == (width - PLOT_WIDTH_PX - 2 * MARGIN_PX if plot else width)
    assert free_region(width, height)[2] == width - PANEL_PX  # the panel's 400 px, given back without a plot
    # The scene's look-at point is drawn at the centre of that region.
    load_all()
    scene = REGISTRY["tennis_racket"]
    eye, target = framed(*scene.camera, width, height, FOV, scene.view, projector=True, plot=plot)
    x, y = project([np.array(scene.camera[1], dtype=float)], eye, target, width, height, FOV)[0]
    assert x == pytest.approx(0.5 * (left + right), abs=1e-6) and y == pytest.approx(0.5 * (top + bottom), abs=1e-6)
    # A phone keeps its bottom sheet: projector mode is for the lecture hall's screen.
    assert free_region(390, 844, projector=True, plot=plot) == free_region(390, 844)


def test_the_switch_shows_the_caption_and_the_key_plot_and_switching_off_restores_the_panel():
    with running_app("tennis_racket", start_loop=False) as app:
        assert not app.shared.projector.on and app.shared.panel.projector_button.label == "Projector"
        app.shared.set_projector(True)
        projector = app.shared.projector
        assert projector.on and app.shared.panel.projector_button.label == "Leave projector mode"
        _frame(app)
        scene = app.scene
        # Outside a lecture, the scene's caption, through the lecturer's sanitiser.
        assert projector.caption.content == lecturer_markdown(scene.caption)
        # The key plot, fed with the very arrays the scene's own plot holds.
        app.set_playing(True)
        _frame(app, 40)
        assert projector.plot is not None and len(scene.plot.data[0]) > 20
        assert projector.plot.series == scene.plot.series and projector.plot.title == scene.plot.title
        assert len(projector.plot.data) == len(scene.plot.data) == 4
        for big, own in zip(projector.plot.data, scene.plot.data, strict=True):
            np.testing.assert_array_equal(big, own)
        # A scene without a key plot shows none; its caption follows the scene.
        app.switch_scene("free_fall")
        _frame(app)
        assert projector.plot is None and projector.caption.content == lecturer_markdown(app.scene.caption)
        app.shared.set_projector(False)
        assert not projector.on and projector.caption is None and projector.plot is None
        assert app.shared.panel.projector_button.label == "Projector"


def test_the_caption_is_sanitised_and_a_hidden_plot_is_not_copied():
    with running_app("tennis_racket", start_loop=False) as app:
        app.shared.set_projector(True)
        projector = app.shared.projector
        projector.sync('**Look** <img src=x onerror="alert(1)"><script>alert(2)</script>', None)
        content = projector.caption.content
        assert "<img" not in content and "<script" not in content and "alert(2)" not in content
        assert "**Look**" in content
        with app.simulation.lock:
            app.scene.plot.visible = False  # as a held-back answer hides it
        _frame(app)
        assert projector.plot is None
        with app.simulation.lock:
            app.scene.plot.visible = True
        _frame(app)
        assert projector.plot is not None


def test_a_question_keeps_its_answer_out_of_the_projectors_caption_until_the_reveal():
    with running_app(presenter=True, pin="8642", lecture="rigid-body-motion", projector=True, start_loop=False) as app:
        app.go_to_step(RACKET_QUESTION)
        _frame(app)
        projector = app.shared.projector
        caption = projector.caption.content
        period = app.scene.flip_period
        assert "Spun about its middle axis" in caption  # the question
        for leak in (f"{period:.4g}", f"{period:.3g}", "flips over and back, again"):
            assert leak not in caption, f"{leak!r} in the projector's caption while the question is open"
        app.questions.reveal(None)
        _frame(app)
        assert "flips over and back, again" in projector.caption.content
        assert f"{period:.4g}" in projector.caption.content


def test_every_private_browser_has_its_own_switch():
    with running_app("tennis_racket", private=True, projector=True) as app:
        with raw_client(app) as _first, raw_client(app) as _second:
            wait_for(lambda: len(app.sessions) == 2, 30, what="two sessions")
            first, second = list(app.sessions.values())
            assert first.projector.on and second.projector.on  # --projector: every browser starts in it
            first.set_projector(False)
            assert not first.projector.on and second.projector.on
            assert first.projector.gui is not second.projector.gui  # each on its own browser's GUI


def test_the_command_line_starts_in_projector_mode(monkeypatch):
    made = {}

    class Stop(Exception):
        pass

    def fake_app(**kwargs):
        made.update(kwargs)
        raise Stop

    monkeypatch.setattr("app.serving.app.App", fake_app)
    with pytest.raises(Stop):
        cli_main(["--projector", "--dark", "--scene", "tennis_racket"])
    assert made["projector"] is True and made["dark"] is True and made["scene"] == "tennis_racket"


def test_the_pendulums_swing_is_its_key_plot_and_is_held_back_with_the_centre_of_percussion():
    with running_app(presenter=True, pin="8642", lecture="rigid-body-motion", projector=True, start_loop=False) as app:
        app.go_to_step(PENDULUM_QUESTION)
        _frame(app)
        scene, projector = app.scene, app.shared.projector
        assert scene.name == "pendulum" and scene.key_plot_handle() is scene.swing_plot
        # The swing's period states ℓ: held back while the question is open, on the projector too.
        assert not scene.swing_plot.visible and projector.plot is None
        app.questions.reveal(None)
        with app.simulation.lock:
            app.set_playing(True)
        _frame(app, 120)
        assert scene.swing_plot.visible and projector.plot is not None
        times, angles = scene.swing_plot.data
        assert len(times) >= 10 and np.all(np.diff(times) > 0)
        # Each sample is the swing's own angle at its time (the closed-form motion the scene draws), in degrees.
        for t, shown in zip(times[::5], angles[::5], strict=False):
            assert shown == pytest.approx(math.degrees(scene.state_at(float(t))[0]), abs=1e-9)
        for big, own in zip(projector.plot.data, scene.swing_plot.data, strict=True):
            np.testing.assert_array_equal(big, own)


def test_the_captions_row_steps_the_lecture_runs_the_clock_and_leaves_projector_mode():
    with running_app(lecture="rigid-body-motion", projector=True, start_loop=False) as app:
        projector = app.shared.projector
        _frame(app, 1)
        assert projector.row.options == ("Previous", "Next", LEAVE)  # the still explorer: no clock

        def press(name: str) -> None:
            projector.row.value = name  # viser runs the row's click callback, as for a browser's click

        app.go_to_step(2)  # the pendulum's question waits, paused
        _frame(app, 1)
        assert projector.row.options == ("Previous", "Play", "Reset", "Next", LEAVE)
        press("Play")
        _frame(app, 1)
        assert app.simulation.playing and projector.row.options[1] == "Pause"
        press("Next")
        assert app.simulation.step_index == 3
        press("Previous")
        assert app.simulation.step_index == 2
        press(LEAVE)
        assert not projector.on and projector.row is None


def test_the_heavy_tops_key_plot_is_theta_of_t_between_its_turning_points():
    """The top's key plot is its nutation θ(t): each sample the exact solution's θ at its time, in degrees, and
    the samples sweep from one turning point to the other (θ_min, θ_max of the elliptic solution)."""
    with running_app("heavy_top", projector=True, start_loop=False) as app:
        scene, projector = app.scene, app.shared.projector
        assert scene.key_plot_handle() is scene.nutation.handle
        with app.simulation.lock:
            app.set_playing(True)
        _frame(app, 240)  # 4 s at 1×: more than one nutation period of the default top
        times, thetas = scene.nutation.handle.data
        assert len(times) >= 30 and np.all(np.diff(times) > 0)
        exact = scene.motion.at(np.asarray(times))
        np.testing.assert_allclose(thetas, np.degrees(exact.theta), rtol=0, atol=1e-9)
        period = exact.nutation_period
        assert times[-1] - times[0] > period, "the plot should span a whole nutation"
        # Sampled every 0.1 s, the extremes come within a sample's swing of the turning points.
        step = float(np.max(np.abs(np.diff(thetas))))
        assert max(thetas) == pytest.approx(math.degrees(exact.theta_max), abs=step)
        assert min(thetas) == pytest.approx(math.degrees(exact.theta_min), abs=step)
        for big, own in zip(projector.plot.data, scene.nutation.handle.data, strict=True):
            np.testing.assert_array_equal(big, own)
