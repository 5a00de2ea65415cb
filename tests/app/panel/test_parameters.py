"""The shared GUI pieces of app.controls: a refused dropdown choice snaps back and says why."""

from __future__ import annotations

from types import SimpleNamespace

import numpy as np
import pytest

from app import controls


def test_refused_dropdown_choice_snaps_back_and_notifies(app):
    ctx = SimpleNamespace(server=app.server, guarded=app.simulation.guarded, notify=app.simulation.notify)
    adopted = {"value": "box"}
    applied = []

    def apply() -> bool:
        value = handle.value
        applied.append(value)
        if value == "impossible":
            raise ValueError("no rigid body has these moments")
        if value == "refused":
            return False  # as ParameterPanel.offer does, having told the browser itself
        adopted["value"] = value
        return True

    handle = controls.refusable_dropdown(ctx, "Body", ("box", "rod", "impossible", "refused"), "box", apply=apply)
    try:
        handle.value = "rod"  # as a browser would: the callback runs
        assert adopted["value"] == "rod" and handle.value == "rod"
        before = len(app.messages)
        handle.value = "impossible"
        assert handle.value == "rod"  # snapped back to the last accepted choice
        assert adopted["value"] == "rod"
        assert app.messages[before:] == [("Refused", "no rigid body has these moments")]
        assert applied == ["rod", "impossible"]  # the snap-back does not offer "rod" again
        handle.value = "refused"
        assert handle.value == "rod" and applied == ["rod", "impossible", "refused"]
    finally:
        handle.remove()


def test_offer_is_transactional_for_any_exception_and_reset_still_works(app, monkeypatch):
    from tests.harness import open_scene

    scene = open_scene(app, "heavy_top")
    panel = scene.params
    top, values = scene.top, dict(panel.values)
    real_apply = type(scene).apply

    def half_then_crash(self, candidate):
        self.top = "half-built"  # what a scene might have assigned before failing
        raise ZeroDivisionError("|ω| = 0")

    monkeypatch.setattr(type(scene), "apply", half_then_crash)
    panel._apply = scene.apply  # the panel holds the bound method it was built with
    assert panel.offer({"spin": values["spin"] + 1.0}) is False
    assert scene.top is top and panel.values == values
    assert app.messages[-1] == ("Refused: the scene could not take these values", "ZeroDivisionError: |ω| = 0")
    monkeypatch.setattr(type(scene), "apply", real_apply)
    panel._apply = scene.apply
    app.restart()  # Reset works, and the clock runs the previous model
    app.frame(1 / 60)
    assert scene.top is top and app.time > 0


@pytest.mark.parametrize(
    ("value", "message"),
    [(float("nan"), "finite"), (10**400, "finite"), ("fast", "must be a number"), (1e6, "must be between")],
)
def test_offer_checks_type_finiteness_and_the_slider_range(app, value, message):
    from tests.harness import open_scene

    scene = open_scene(app, "heavy_top")
    before = dict(scene.params.values)
    assert scene.params.offer({"spin": value}) is False
    assert scene.params.values == before and message in app.messages[-1][1]


def test_a_preset_name_is_cleared_when_a_slider_moves_away_from_it(app):
    from app.controls import Presets
    from tests.harness import open_scene

    scene = open_scene(app, "heavy_top")
    assert scene.presets.choose("cusps (released from rest)")
    assert scene.presets.handle.value == "cusps (released from rest)"
    assert scene.params.offer({"theta0": 45.0})  # the sliders left the preset
    assert scene.presets.handle.value == Presets.NONE and scene.presets.last is None
    # Choosing from the page (the dropdown's value arrives first) applies it and keeps the name shown.
    scene.presets.handle.value = "loops (φ̇0 = −1 × steady)"
    assert scene.presets.last == "loops (φ̇0 = −1 × steady)" and scene.params.values["phidot0"] < 0
    assert scene.presets.handle.value == "loops (φ̇0 = −1 × steady)"


def _panel_state(scene):
    """Every control's value and every text in the scene's folder (what a browser's panel shows)."""
    first = next(iter(scene.params.sliders.values()))._impl
    folder = first.gui_api._container_handle_from_uuid[first.parent_container_id]
    shown = {}

    def walk(container):
        for handle in list(container._children.values()):
            impl = handle._impl
            if getattr(impl, "props", None) is not None:
                props = {k: v for k, v in vars(impl.props).items() if k in ("content", "label", "visible", "options")}
                value = None if getattr(impl, "is_button", False) else getattr(impl, "value", None)
                shown[impl.uuid] = (props, getattr(value, "name", value))
            walk(handle) if hasattr(handle, "_children") else None

    walk(folder)
    assert len(shown) > 10
    return shown


def _friction_top_running(app):
    from tests.harness import open_scene

    scene = open_scene(app, "heavy_top")
    assert scene.params.offer({"friction": 0.01, "theta0": 30.0, "spin": 1.0})
    for _ in range(30):
        app.frame(1 / 60)
    return scene


def test_an_exception_after_side_effects_leaves_parameters_state_and_panel_exactly_as_before(app, monkeypatch):
    scene = _friction_top_running(app)
    panel = scene.params
    values, top, motion = dict(panel.values), scene.top, scene.motion
    t, R, L_body, frames = app.time, scene.R.copy(), scene.L_body.copy(), app.frames
    shown, note = _panel_state(scene), scene.note.content
    assert t > 0.4 and note == ""

    def broken(self):
        raise ZeroDivisionError("|ω| = 0")

    # Every apply fails after its side effects: the nudge note is written, the model assigned, the
    # clock not yet restarted. Re-applying the accepted values fails too: only the rollback restores.
    monkeypatch.setattr(type(scene), "_start_ghost", broken)
    slider = panel.sliders["theta0"]
    slider.value = 0.0  # as a browser would set it: upright, with a spin too slow to sleep (the nudge note)
    assert panel.values == values and scene.top is top and scene.motion is motion
    assert scene.note.content == note  # the note the failed apply wrote is gone
    assert _panel_state(scene) == shown
    assert slider.value == values["theta0"]
    assert app.time == t
    np.testing.assert_array_equal(scene.R, R)
    np.testing.assert_array_equal(scene.L_body, L_body)
    assert app.messages[-1] == ("Refused: the scene could not take these values", "ZeroDivisionError: |ω| = 0")
    # The clock goes on from where it was, and Reset works.
    app.frame(1 / 60)
    assert app.frames == frames + 1 and app.time > t
    monkeypatch.undo()
    app.restart()
    assert app.time == 0.0 and app.frame(1 / 60) and app.time > 0.0
    assert scene.params.offer({"theta0": 45.0}) and scene.values["theta0"] == 45.0


def test_a_failure_for_the_candidate_only_redoes_the_side_effects_of_the_accepted_values(app, monkeypatch):
    scene = _friction_top_running(app)
    panel = scene.params
    values, top, t = dict(panel.values), scene.top, app.time
    shown = _panel_state(scene)
    real = type(scene)._start_ghost
    started = []

    def fails_upright(self):
        started.append(self.values["theta0"])
        if self.values["theta0"] == 0.0:
            raise ZeroDivisionError("upright")
        real(self)

    monkeypatch.setattr(type(scene), "_start_ghost", fails_upright)
    assert panel.offer({"theta0": 0.0}) is False
    assert started == [0.0, values["theta0"]]  # the accepted values were applied again
    assert panel.values == values and scene.top is top and app.time == t
    assert _panel_state(scene) == shown


def test_a_refusal_before_any_change_does_not_restart_anything(app, monkeypatch):
    scene = _friction_top_running(app)
    t, trail = app.time, len(scene.trace.points())
    assert trail > 10
    ghost_starts = []
    monkeypatch.setattr(scene.ghost, "start", lambda *a, **k: ghost_starts.append(a))
    assert scene.params.offer({"I3": 1.0, "I1": 0.05}) is False  # no such body: refused in its constructor
    assert not ghost_starts and app.time == t  # nothing was applied again: the trail and the ghost go on
    assert len(scene.trace.points()) == trail


def test_a_dropdown_refused_by_an_exception_snaps_back_with_the_scene_as_it_was(app, monkeypatch):
    from physics.free_body import FreeBody
    from tests.harness import open_scene

    scene = open_scene(app, "tennis_racket")
    for _ in range(20):
        app.frame(1 / 60)
    axis, index, model, t = scene.axis.value, scene.axis_index, scene.model, app.time
    shown = _panel_state(scene)
    real = FreeBody.stability

    def fails_for_axis_3(self, axis_index, spin_rate):
        if axis_index == 2:
            raise FloatingPointError("overflow")
        return real(self, axis_index, spin_rate)

    monkeypatch.setattr(FreeBody, "stability", fails_for_axis_3)  # after the mesh and the ghost are sent
    other = next(a for a in scene.axis.options if a.startswith("3"))
    scene.axis.value = other  # as a browser would choose it
    assert scene.axis.value == axis and scene.axis_index == index and scene.model is model
    assert app.time == t and _panel_state(scene) == shown
    # The ghost, restarted by the failed apply for axis 3, was restarted again for the accepted axis.
    R0, L0 = scene.ghost.exact(0.0)
    np.testing.assert_allclose(L0, scene.moments * scene.motion.at(0.0).omega, rtol=1e-12)
    assert app.messages[-1][1] == "FloatingPointError: overflow"


def test_presets_and_dropdowns_refuse_any_exception(app):
    from types import SimpleNamespace

    from tests.harness import open_scene

    scene = open_scene(app, "heavy_top")
    presets = scene.presets
    presets.presets["broken (test)"] = lambda values: {"spin": 1.0 / 0.0}
    try:
        assert presets.choose("broken (test)") is False
        assert presets.handle.value == presets.last or presets.handle.value == presets.NONE
        assert app.messages[-1][1] == "ZeroDivisionError: float division by zero"
    finally:
        del presets.presets["broken (test)"]
    ctx = SimpleNamespace(server=app.server, guarded=app.simulation.guarded, notify=app.simulation.notify)

    def apply() -> bool:
        raise RuntimeError("no such body")

    handle = controls.refusable_dropdown(ctx, "Body (test)", ("box", "rod"), "box", apply=apply)
    try:
        handle.value = "rod"
        assert handle.value == "box" and app.messages[-1] == ("Refused", "RuntimeError: no such body")
    finally:
        handle.remove()
