"""The pendulum scene headless: the exact swing about the pivot, a⊥, strike and centre of percussion."""

from __future__ import annotations

import math

import numpy as np
import pytest

from app import draw
from physics.pendulum import PhysicalPendulum
from tests.harness import FRAME, matrix, open_scene


def test_pendulum_swings_exactly_about_the_fixed_pivot(app):
    sc = open_scene(app, "pendulum")
    for _ in range(40):
        app.frame(FRAME)
    R = matrix(sc.body.handle)
    # The pivot does not move: R pivot + position = pivot (float32 handle values: 1e-6).
    np.testing.assert_allclose(R @ sc.pivot + np.asarray(sc.body.handle.position), sc.pivot, atol=1e-6)
    theta, _ = sc.model.solve(math.radians(sc.params.values["amplitude"]), 0.0, [app.time])
    np.testing.assert_allclose(R, sc.model.attitude(float(theta[0])), atol=1e-6)
    m = sc.model
    assert float(sc.k_readout.text) == pytest.approx(m.radius_of_gyration, rel=1e-3)
    assert float(sc.l_readout.text) == pytest.approx(m.radius_of_gyration**2 / m.a_perp, rel=1e-3)
    assert float(sc.a_readout.text) == pytest.approx(m.a_perp, rel=1e-3)
    np.testing.assert_allclose(sc.cop_marker.position, m.center_of_percussion(float(theta[0])), atol=1e-6)


def test_pendulum_pivot_slider_changes_a_perp(app):
    sc = open_scene(app, "pendulum")
    a0 = sc.model.a_perp
    assert sc.params.offer({"pivot": sc.params.values["pivot"] + 0.1})
    assert sc.model.a_perp == pytest.approx(a0 - 0.1, abs=1e-12)  # the bat hangs straight: a⊥ shrinks by 0.1 m


def test_pendulum_strike_at_centre_of_percussion_needs_no_pivot_impulse(app, monkeypatch):
    from app.scenes import pendulum

    wall = [0.0]
    monkeypatch.setattr(pendulum, "wall_clock", lambda: wall[0])
    sc = open_scene(app, "pendulum")
    l = sc.model.effective_length
    assert sc.params.offer({"strike": l})
    result = sc.strike()
    # J = 1 N s at the centre of percussion: the reaction vanishes to round-off.
    assert np.linalg.norm(result.reaction_impulse) < 1e-12
    app.frame(FRAME)
    assert sc.impulse_arrow.handle.visible and not sc.reaction_arrow.handle.visible  # zero arrow hidden
    assert sc.params.offer({"strike": 0.2})
    t0 = app.time
    _, thetadot_before = sc.state_at(t0)
    result = sc.strike()
    assert np.linalg.norm(result.reaction_impulse) > 0.1
    # The reaction is M Δv_cm − J, and the swing continues from the struck state.
    _, thetadot_after = sc.state_at(t0)
    assert thetadot_after == pytest.approx(thetadot_before + result.delta_omega, rel=1e-12)
    app.frame(FRAME)
    assert sc.reaction_arrow.handle.visible
    for _ in range(int(2.0 / FRAME)):
        app.frame(FRAME)
    assert sc.impulse_arrow.handle.visible  # a fast machine did this in no time: a person saw nothing yet
    wall[0] += pendulum.ARROW_SECONDS + 0.01
    app.frame(FRAME)
    assert not sc.impulse_arrow.handle.visible  # gone after ARROW_SHOW s of the clock and ARROW_SECONDS of ours


def test_strike_arrows_stay_a_second_at_ten_times_speed(app, monkeypatch):
    from app.scenes import pendulum

    wall = [0.0]
    monkeypatch.setattr(pendulum, "wall_clock", lambda: wall[0])
    sc = open_scene(app, "pendulum")
    app.set_speed(10.0)
    sc.strike()
    for _ in range(50):  # 50 frames of 1/60 s at 10×: 8.3 s of simulation, 0.83 s of wall time
        wall[0] += FRAME
        app.frame(FRAME)
        assert sc.impulse_arrow.handle.visible
    for _ in range(30):
        wall[0] += FRAME
        app.frame(FRAME)
    assert not sc.impulse_arrow.handle.visible


def test_pendulum_strike_point_slider_does_not_restart_the_swing(app):
    sc = open_scene(app, "pendulum")
    for _ in range(20):
        app.frame(FRAME)
    t, model = app.time, sc.model
    assert sc.params.offer({"strike": 0.3, "impulse": 2.0})
    assert app.time == t and sc.model is model
    assert sc.params.offer({"amplitude": 45.0})  # a new release angle does restart
    assert app.time == 0.0 and sc.model is not model


def test_pendulum_refuses_pivot_off_or_at_the_centre_of_mass(app):
    sc = open_scene(app, "pendulum")
    sc.choice.value = "Uniform rod 0.84 m, 0.9 kg"
    pend = sc.model
    assert isinstance(pend, PhysicalPendulum)
    assert not sc.params.offer({"pivot": 0.42})  # the rod's centre of mass
    assert "balanced" in app.messages[-1][1]
    assert sc.model is pend
    assert not sc.params.offer({"strike": 0.84})  # beyond the end of the rod below the pivot
    assert "on the body" in app.messages[-1][1]
    # A uniform rod hung from its end: ℓ = 2/3 of its length (lecture).
    assert sc.params.offer({"pivot": 0.0, "strike": 0.3})
    assert sc.model.effective_length == pytest.approx(2 * 0.84 / 3, rel=1e-12)


def test_the_path_in_the_legend_is_the_centre_of_mass(app):
    sc = open_scene(app, "pendulum")
    for _ in range(30):
        app.frame(FRAME)
    theta, _ = sc.state_at(app.time)
    np.testing.assert_allclose(sc.trace.points()[-1], sc.model.center_of_mass_at(theta), atol=1e-12)
    assert "path" in sc.quantities and "centre of mass" in draw.LABELS["path"]


def test_the_period_readout_follows_the_swing_a_strike_starts(app):
    """'this swing' is the period of the swing now: after a strike, the struck swing's (its amplitude
    measured on the exact motion, independently of the readout's energy formula), or 'over the top'."""
    sc = open_scene(app, "pendulum")
    m = sc.model
    small, before = sc.period_readout.text.split(" / ")
    assert float(small) == pytest.approx(m.small_oscillation_period, rel=1e-3)
    assert float(before) == pytest.approx(float(m.period(math.radians(sc.params.values["amplitude"]))), rel=1e-3)
    for _ in range(10):
        app.frame(FRAME)
    assert sc.params.offer({"impulse": 0.5})
    sc.strike()
    theta0, thetadot0, _ = sc.start
    swing = m.solve(theta0, thetadot0, np.linspace(0.0, 2.0 * float(m.period(math.pi * 0.99)), 20001))[0]
    amplitude = float(np.max(np.abs(swing)))
    after = float(sc.period_readout.text.split(" / ")[1])
    assert after == pytest.approx(float(m.period(amplitude)), rel=1e-3)
    assert after != pytest.approx(float(before), rel=1e-3)  # the blow changed the swing, and the readout
    assert sc.params.offer({"impulse": 5.0})
    for _ in range(3):
        sc.strike()  # blow after blow: it goes over the top
    assert sc.period_readout.text.endswith("over the top: no swing back")
