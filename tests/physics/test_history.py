"""The bounded history of a stepped motion (physics.history): going back then forward again gives the same
states bit for bit (np.array_equal against an uninterrupted run, never allclose), memory is fixed, and a
time it cannot give is refused by name."""

from __future__ import annotations

import math

import numpy as np
import pytest

from physics.euler_angles import euler_attitude, omega_body_from_euler
from physics.heavy_top import HeavyTop, TransverseAirDrag, friction_stepper
from physics.history import SteppedHistory, stepper_step
from physics.integrators import BlanesMoan6, LieRK4, SpinFriction
from physics.integrators.torques import GravityTorque

DT = 1.0 / 60.0
TOP = HeavyTop(1.0, 0.5, 2.0)


def friction_top_state() -> np.ndarray:
    R0 = euler_attitude(0.0, 0.5, 0.0)
    w0 = omega_body_from_euler(0.5, 0.0, 0.1, 0.3, 20.0)
    return np.concatenate([R0.ravel(), TOP.moments * w0])


def uninterrupted(step, state0: np.ndarray, n: int) -> list[np.ndarray]:
    """Every state of an uninterrupted run of n steps (the reference)."""
    states = [state0.copy()]
    for _ in range(n):
        states.append(np.asarray(step(states[-1])))
    return states


STEPS = {
    "friction top (Blanes–Moan 6, 4 substeps)": lambda: stepper_step(
        friction_stepper(TOP, 0.05, method=BlanesMoan6), DT, 4
    ),
    "top with air drag (Lie RK4)": lambda: stepper_step(friction_stepper(TOP, 0.02, 0.1, method=LieRK4), DT, 2),
    "asymmetric body, a torque stepped interpreted": lambda: stepper_step(
        LieRK4(
            np.array([1.0, 1.4, 0.6]),
            [GravityTorque(0.2, (0.0, 0.1, 0.3)), SpinFriction(0.03, np.array([1.0, 1.4, 0.6]))],
        ),
        DT,
        1,
    ),
}


@pytest.mark.parametrize("name", STEPS)
def test_back_then_forward_reproduces_an_uninterrupted_run_bit_for_bit(name):
    step = STEPS[name]()
    state0 = friction_top_state()
    reference = uninterrupted(step, state0, 900)  # 15 s at 60 Hz
    history = SteppedHistory(step, state0, DT, keep=10.0, checkpoint_every=30)
    for k in range(1, 601):  # play 10 s frame by frame
        assert np.array_equal(history.step_forward(), reference[k])
    # Scrub back and forth, inside a checkpoint interval and across them, then play on from a scrubbed instant.
    rng = np.random.default_rng(3)
    for k in [599, 0, 1, 29, 30, 31, 300, 299, 600, 451, *rng.integers(0, 600, 40)]:
        k = int(k)
        assert np.array_equal(history.seek(k * DT), reference[k]), k
        assert history.time == pytest.approx(k * DT, abs=1e-12)
        assert np.array_equal(history.state_at(k * DT), reference[k])
    history.seek(200 * DT)
    for k in range(201, 901):  # on from there, past the furthest state computed before
        assert np.array_equal(history.step_forward(), reference[k])
    assert np.array_equal(history.seek(900 * DT), reference[900])
    assert np.array_equal(history.seek(700 * DT), reference[700])


def test_state_at_leaves_the_current_state_and_seeking_ahead_steps_on():
    step = STEPS["friction top (Blanes–Moan 6, 4 substeps)"]()
    state0 = friction_top_state()
    reference = uninterrupted(step, state0, 300)
    history = SteppedHistory(step, state0, DT, keep=60.0)
    assert np.array_equal(history.state_at(250 * DT), reference[250])  # ahead: computed, not moved to
    assert history.time == 0.0 and history.latest == pytest.approx(250 * DT)
    assert np.array_equal(history.seek(300 * DT), reference[300])
    assert np.array_equal(history.step_forward(0), reference[300])


def test_a_time_between_grid_times_is_the_grid_time_before_it():
    step = STEPS["friction top (Blanes–Moan 6, 4 substeps)"]()
    state0 = friction_top_state()
    reference = uninterrupted(step, state0, 20)
    history = SteppedHistory(step, state0, DT)
    assert np.array_equal(history.state_at(10.7 * DT), reference[10])
    # A slider's decimal string of k dt reaches step k, not k − 1 (0.1 s is 6 steps: 6/60 rounds below 0.1).
    assert np.array_equal(history.state_at(float("0.1")), reference[6])
    assert np.array_equal(history.state_at(float(repr(17 * DT))), reference[17])


def test_memory_is_fixed_and_the_kept_span_is_the_last_keep_seconds():
    step = STEPS["friction top (Blanes–Moan 6, 4 substeps)"]()
    history = SteppedHistory(step, friction_top_state(), DT, keep=5.0, checkpoint_every=60)
    # ceil(5 s / 1 s) + 1 checkpoints of 12 float64, and the current and furthest states.
    assert history.capacity == 6
    assert history.nbytes == (6 + 2) * 12 * 8
    before = history.nbytes
    history.step_forward(60 * 20)  # 20 s
    assert history.nbytes == before
    assert history.earliest == pytest.approx(15.0) and history.latest == pytest.approx(20.0)
    with pytest.raises(ValueError, match=r"older than the history keeps: it reaches back to 15.0 s"):
        history.seek(14.99)
    history.seek(15.0)  # the oldest kept: fine


def test_truncate_and_a_new_step_forget_the_states_after_now():
    step = STEPS["friction top (Blanes–Moan 6, 4 substeps)"]()
    state0 = friction_top_state()
    history = SteppedHistory(step, state0, DT, keep=30.0, checkpoint_every=30)
    history.step_forward(600)
    history.seek(100 * DT)
    stiffer = stepper_step(friction_stepper(TOP, 0.5, method=BlanesMoan6), DT, 4)
    history.replace_step(stiffer)
    assert history.latest == pytest.approx(100 * DT)
    branch = uninterrupted(stiffer, history.state, 200)
    for k in (150, 300, 120, 101):
        assert np.array_equal(history.seek(k * DT), branch[k - 100])
    assert np.array_equal(history.seek(40 * DT), uninterrupted(step, state0, 40)[40])  # before: as computed


@pytest.mark.parametrize(
    ("t", "message"),
    [
        (math.nan, "t must be finite"),
        (math.inf, "t must be finite"),
        (-math.inf, "t must be finite"),
        (-0.5, r"t = -0.5 s is before the start of this motion, t0 = 0.0 s"),
        ("now", "t must be a real number"),
        (10**400, "t must be within the float range"),
        (1e9, "beyond the furthest state computed"),
    ],
)
def test_times_it_cannot_give_are_refused_by_name(t, message):
    step = STEPS["friction top (Blanes–Moan 6, 4 substeps)"]()
    history = SteppedHistory(step, friction_top_state(), DT, keep=10.0)
    with pytest.raises(ValueError, match=message):
        history.seek(t)
    with pytest.raises(ValueError, match=message):
        history.state_at(t)
    assert history.time == 0.0  # a refusal moves nothing


def test_bad_construction_and_a_diverging_step_are_refused_by_name():
    step = STEPS["friction top (Blanes–Moan 6, 4 substeps)"]()
    state0 = friction_top_state()
    with pytest.raises(ValueError, match="dt must be a positive time"):
        SteppedHistory(step, state0, 0.0)
    with pytest.raises(ValueError, match="dt must be finite"):
        SteppedHistory(step, state0, math.nan)
    with pytest.raises(ValueError, match="keep must be a positive time"):
        SteppedHistory(step, state0, DT, keep=-1.0)
    with pytest.raises(ValueError, match="checkpoint_every must be a whole number"):
        SteppedHistory(step, state0, DT, checkpoint_every=0)
    with pytest.raises(ValueError, match="checkpoint_every must be a whole number"):
        SteppedHistory(step, state0, DT, checkpoint_every=2.5)  # type: ignore[arg-type]
    with pytest.raises(ValueError, match="state0 must be finite"):
        SteppedHistory(step, [math.nan] * 12, DT)
    with pytest.raises(ValueError, match="state0 must be a 1-D array"):
        SteppedHistory(step, np.eye(3), DT)
    with pytest.raises(ValueError, match="needs .* checkpoints"):
        SteppedHistory(step, state0, 1e-9, keep=1e6, checkpoint_every=1)
    with pytest.raises(ValueError, match="substeps must be a whole number"):
        stepper_step(friction_stepper(TOP, 0.0), DT, 0)
    history = SteppedHistory(lambda s: np.full_like(s, np.nan), state0, DT)
    with pytest.raises(ValueError, match="the step from t = 0.0 s gave .* non-finite"):
        history.step_forward(3)
    with pytest.raises(ValueError, match="n must be a whole number"):
        history.step_forward(-1)


def test_air_drag_history_matches_the_uninterrupted_run_after_the_ring_turns():
    """The ring overwrites its oldest checkpoints: what it still holds is still the run's."""
    step = stepper_step(friction_stepper(TOP, 0.0, 0.2, method=BlanesMoan6), DT, 1)
    assert isinstance(friction_stepper(TOP, 0.0, 0.2).torques[-1], TransverseAirDrag)
    state0 = friction_top_state()
    reference = uninterrupted(step, state0, 1200)
    history = SteppedHistory(step, state0, DT, keep=2.0, checkpoint_every=20)
    history.step_forward(1200)  # 20 s: the ring of 7 checkpoints turned many times
    for k in (1200, 1080, 1081, 1199, 1100, 1139, 1140):
        assert np.array_equal(history.seek(k * DT), reference[k]), k
