"""Every scene driven by dynamics plots the relative drift of its invariants: flat at
the roundoff level for the exact solutions, rising for the friction top, cleared by Reset."""

from __future__ import annotations

import math

import numpy as np
import pytest

from tests.harness import running_app

FRAME = 1.0 / 60.0
EXACT = {
    "heavy_top": ("E", "L_z", "L₃"),
    "wobble": ("E", "|L|"),
    "free_fall": ("E", "|L|"),
    "tennis_racket": ("E", "|L|"),
    "pendulum": ("E",),
}


@pytest.mark.parametrize("scene", list(EXACT))
def test_exact_scenes_keep_their_invariants_to_roundoff(scene):
    with running_app(scene, start_loop=False) as app:
        app.set_playing(True)
        app.set_speed(5.0)
        for _ in range(300):  # 25 s of motion at 5×
            app.frame(FRAME)
        drift = app.scene.drift
        assert drift.names == EXACT[scene]
        latest = drift.latest()
        # Each invariant is recomputed from the drawn state (a sum of a few products): 1e-13 of its scale.
        assert all(value <= -13.0 for value in latest.values()), latest
        assert all(max(series) <= -13.0 for series in drift.drifts)
        times, *series = drift.handle.data
        assert len(series) == len(EXACT[scene]) and all(np.all(np.isfinite(s)) for s in (times, *series))


def test_friction_shows_the_energy_leaving_and_reset_starts_again():
    with running_app("heavy_top", start_loop=False) as app:
        assert app.scene.presets.choose("sleeping top with friction: falls")
        app.set_playing(True)
        for _ in range(240):
            app.frame(FRAME)
        latest = app.scene.drift.latest()
        assert latest["L₃"] > -6.0 and latest["E"] > -8.0  # friction takes L₃ and E away
        app.restart()
        assert app.scene.drift.times == [] and app.scene.drift.reference is None
        app.frame(FRAME)
        assert len(app.scene.drift.times) == 1 and math.isclose(app.scene.drift.latest()["E"], -17.0)


def test_a_strike_starts_the_pendulums_energy_reference_afresh():
    with running_app("pendulum", start_loop=False) as app:
        app.set_playing(True)
        for _ in range(30):
            app.frame(FRAME)
        app.scene.strike()
        for _ in range(30):
            app.frame(FRAME)
        assert app.scene.drift.latest()["E"] <= -13.0
