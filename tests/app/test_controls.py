"""The shared GUI pieces of app.controls: a refused dropdown choice snaps back and says why."""

from __future__ import annotations

from types import SimpleNamespace

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
