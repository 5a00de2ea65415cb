"""The words in the panel: no raw LaTeX, units and four significant digits, and what the
captions and labels say is what the scene shows."""

from __future__ import annotations

import math
import re

import numpy as np
import pytest

from app.scenes import scene_names
from tests.harness import FRAME, open_scene


def _texts(app) -> list[str]:
    """Every label, markdown and readout text of the panel (the scene's folder and the rest)."""
    out = []
    for handle in app.server.gui._gui_input_handle_from_uuid.values():
        props = handle._impl.props
        for field in ("label", "content", "hint"):
            value = getattr(props, field, None)
            if isinstance(value, str):
                out.append(value)
        if isinstance(getattr(handle, "value", None), str):
            out.append(handle.value)
    return out


@pytest.mark.parametrize("name", scene_names())
def test_no_raw_latex_in_the_panel(app, name):
    open_scene(app, name)
    for _ in range(3):
        app.frame(FRAME)
    for text in _texts(app):
        assert not re.search(r"\^\{|_\{|\\[a-z]+|\$", text), f"raw LaTeX in {text!r}"


def test_the_wobble_arrows_are_as_long_as_the_caption_says(app):
    scene = open_scene(app, "wobble")
    assert "drawn 1.1 m long" in scene.caption
    for _ in range(30):
        app.frame(FRAME)
        for arrow in (scene.L_arrow, scene.omega_arrow):
            points = np.asarray(arrow.handle.points, dtype=float)
            assert np.linalg.norm(points[0, 1] - points[0, 0]) == pytest.approx(1.1, abs=1e-6)


def test_the_explorer_says_what_each_body_weighs_with_four_digits(app):
    from assets import ASSETS

    scene = open_scene(app, "inertia_explorer")
    lightest, heaviest = min(a.mass for a in ASSETS.values()), max(a.mass for a in ASSETS.values())
    assert "1 kg" in scene.caption and f"{lightest:.2g} to {heaviest:.2g} kg" in scene.caption
    for choice in ("Box (L × 2a × a)", "Tennis racket", "Spinning top"):
        with app.simulation.lock:
            scene.choice.value = choice
        note = scene.note.content
        assert f"{scene.props.mass:.4g} kg" in note and f"{scene.display_scale:.4g}× its size" in note
        d = float(np.linalg.norm([scene.params.values[k] for k in ("px", "py", "pz")]))
        assert f"d = {d:.4g} m" in note and f"M d² = {scene.props.mass * d * d:.4g} kg m²" in note
        # Four significant digits at most, everywhere in the note.
        for number in re.findall(r"\d+\.\d+", note):
            assert len(number.replace(".", "").lstrip("0")) <= 4, number
    assert "(kg m²)" in scene.pivot_readout.handle.label


def test_the_heavy_top_theta_readout_is_labelled_for_what_it_shows(app):
    from app.scenes.heavy_top import TOUCH

    scene = open_scene(app, "heavy_top")
    app.frame(FRAME)
    label, text = scene.theta_readout.handle.label, scene.theta_readout.text
    assert label == "θ turns between (°)" and re.fullmatch(r"[\d.]+ and [\d.]+", text)
    assert scene.presets.choose("sleeping top with friction: falls")
    app.set_speed(10.0)
    for _ in range(40):
        app.frame(0.1)
        label, text = scene.theta_readout.handle.label, scene.theta_readout.text
        assert label == "θ now (°)"
        if scene.landed:
            break
    assert scene.landed and text.endswith(", lying on the table")
    assert text == f"{math.degrees(TOUCH):.4g}, lying on the table"
    assert scene.presets.choose("cusps (released from rest)")
    app.frame(FRAME)
    assert scene.theta_readout.handle.label == "θ turns between (°)"


def test_the_racket_readouts_say_estimate_and_the_legend_has_its_axes_and_ghost(app):
    scene = open_scene(app, "tennis_racket")
    assert "estimated from the linear growth" in scene.first_flip_readout.handle.label
    assert "lecture's first flip" not in scene.first_flip_readout.handle.label
    assert "exp(λt)" in scene.caption
    legend = app.simulation.legend.content
    assert "principal axes" in legend and "ghost" in legend
