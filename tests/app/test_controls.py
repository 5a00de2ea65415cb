"""The shared GUI pieces of app.controls: a refused dropdown choice snaps back and says why."""

from __future__ import annotations

from types import SimpleNamespace

import pytest

from app import controls


def test_refused_dropdown_choice_snaps_back_and_notifies(app):
    ctx = SimpleNamespace(server=app.server, guarded=app.guarded, notify=app.notify)
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
