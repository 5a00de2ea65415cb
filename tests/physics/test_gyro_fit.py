"""Finding and fitting tosses (physics.gyro.free_flights, fit_free_body) on recordings the project makes with
its own model (physics.gyro.synthetic_recording): a phone-like body of known moments, misalignment and drag,
sampled at 100 Hz with noise, clipping, a pause and the hand's spin-up and catch at both ends."""

from __future__ import annotations

import numpy as np
import pytest

from physics.free_body import FreeBody
from physics.gyro import Segment, Toss, fit_free_body, free_flights, synthetic_recording
from physics.gyro.kernel import drag_omega
from physics.gyro.model import rotation_from_vector

MOMENTS = np.array([0.8, 0.21, 1.0])  # a bare phone: x intermediate, y smallest, z largest (the README's)
TILT = np.array([0.02, -0.01, 0.015])  # rad, |θ| = 0.027
DRAG = np.array([0.1, 0.02, 0.05])  # 1/s on the scale I_max = 1: 6-10% of |L| in a toss, as measured
NOISE = 0.02  # rad/s, a phone gyroscope's
# About the intermediate axis, each with a flip; the second starts past the gyroscope's limit (clipped).
TOSSES = [Toss(1.0, 0.8, (18.0, 1.0, 0.6)), Toss(3.0, 0.9, (36.5, 0.5, -0.8)), Toss(8.0, 0.7, (-25.0, -0.7, 0.9))]


@pytest.fixture(scope="module")
def recorded() -> tuple:
    return synthetic_recording(MOMENTS, TOSSES, misalignment=TILT, drag=DRAG, noise=NOISE, pause_at=5.5, pause_skip=2.0)


@pytest.fixture(scope="module")
def flights(recorded: tuple) -> list[Segment]:
    return free_flights(recorded[0])


@pytest.fixture(scope="module")
def joint(flights: list[Segment]):
    return fit_free_body(flights)


def test_the_recording_has_its_pause_clipping_and_jolts(recorded: tuple) -> None:
    rec, windows = recorded
    assert len(rec.breaks) == 1 and rec.pieces()[0][1] < len(rec.times)
    assert np.any(np.abs(rec.omega) >= 0.99 * 34.9)  # clipped
    assert windows[2][0] == pytest.approx(6.0)  # the third toss, after the 2 s pause


def test_windows_are_found_inside_each_toss(recorded: tuple, flights: list[Segment]) -> None:
    """Each flight starts after the release and ends before the catch: by the margin (25 and 20 ms), the
    samples a jolt spoils (its second difference sits on the sample before the contact, which takes its
    neighbour along: 20 ms) and the sampling's phase (up to 10 ms and one sample more at the margin)."""
    windows = recorded[1]
    assert len(flights) == len(windows)
    for seg, (release, catch) in zip(flights, windows):
        assert 0.02 <= seg.start - release <= 0.065
        assert 0.015 <= catch - seg.end <= 0.065
        assert not any(seg.start < b <= seg.end for b in recorded[0].breaks)


def test_joint_fit_recovers_the_body(joint) -> None:
    """Tolerances: the fit's own standard deviations are ~1e-4 on the ratios (noise 0.02 rad/s over ~240
    samples of ~25 rad/s); the RK4 inside it is good to 1e-6 of |ω|. 0.003 on the ratios, 2 mrad on the
    misalignment and 15% on each drag coefficient are what three tosses of 0.7-0.9 s resolve (a toss
    is too short to tell drag on one axis apart from a small change of the others by more)."""
    assert joint.axes == "zxy"
    assert np.max(np.abs(joint.moments - MOMENTS)) < 0.003
    assert np.all(joint.moments_sigma[:2] < 0.002) and joint.moments_sigma[2] == 0.0
    assert abs(joint.misalignment - np.linalg.norm(TILT)) < 0.002
    assert np.allclose(joint.rotation, rotation_from_vector(TILT), atol=0.003)
    assert np.allclose(joint.drag, DRAG, rtol=0.15, atol=0.005)
    # The residual is the noise: sqrt(mean of squares) of white noise of 0.02 rad/s per component.
    assert NOISE * 0.85 < joint.residual < NOISE * 1.2
    assert np.all(joint.relative_residuals < 0.002)
    for k in range(3):
        assert 0.04 < joint.momentum_loss(k) < 0.15


def test_predict_is_the_exact_solution_or_the_integrator(joint, flights: list[Segment]) -> None:
    seg = flights[0]
    u0 = joint.rotation.T @ joint.omega0[0]
    stepped = drag_omega(joint.moments, joint.drag, u0, seg.times - seg.start) @ joint.rotation.T
    assert np.max(np.abs(joint.predict(seg.times) - stepped)) < 1e-5 * 25.0
    # Without drag: the exact free body, the same numbers.
    free = fit_free_body(seg, drag="none", misalignment=False)
    u0 = free.omega0[0]
    assert np.array_equal(free.predict(seg.times), FreeBody(free.moments).omega(u0, seg.times - seg.start))
    assert np.all(free.drag == 0.0) and free.misalignment == 0.0
    with pytest.raises(ValueError, match="toss must be 0 to 2"):
        joint.predict(seg.times, toss=3)
    with pytest.raises(ValueError, match="finite"):
        joint.predict([np.nan])


def test_half_turns_predicted_where_measured(joint) -> None:
    """The flip's half turns (the intermediate component's sign changes): the model and the noisy samples
    agree within 2 ms (noise 0.02 rad/s over a slope of ~400 rad/s² shifts a crossing by 0.05 ms)."""
    for turns in joint.half_turn_times:
        assert len(turns.predicted) == len(turns.measured) >= 1
        assert np.max(np.abs(turns.predicted - turns.measured)) < 0.002


def test_one_toss_alone_and_without_misalignment() -> None:
    """An aligned body without drag: the misalignment is not kept (not 3 σ), the drag fitted is ~0."""
    rec, _ = synthetic_recording(MOMENTS, [Toss(1.0, 0.9, (20.0, 0.8, -0.5))], noise=NOISE, seed=4)
    (seg,) = free_flights(rec)
    fit = fit_free_body(seg)
    assert fit.misalignment == 0.0 and np.array_equal(fit.rotation, np.eye(3))
    assert np.max(np.abs(fit.moments - MOMENTS)) < 0.003
    assert np.all(fit.drag < 0.01)


def segment(duration: float, spin: float, clip: float = 34.9) -> Segment:
    t = np.arange(0.0, duration, 0.01)
    w = FreeBody(MOMENTS).omega(np.array([spin, 0.05 * spin, 0.0]), t)
    return Segment(0.0, float(t[-1]), t, np.clip(w, -clip, clip), clip)


def test_every_refusal_says_why() -> None:
    with pytest.raises(ValueError, match=r"lasts 0.190 s; at least 0.2 s"):
        fit_free_body(segment(0.2, 20.0))
    with pytest.raises(ValueError, match=r"spins too slowly to fit: its median \|ω\| is 2"):
        fit_free_body(segment(0.8, 2.0))
    with pytest.raises(ValueError, match=r"mostly clipped: 100% of its samples"):
        fit_free_body(segment(0.8, 20.0, clip=5.0))
    with pytest.raises(ValueError, match="segment 1 lasts"):
        fit_free_body([segment(0.8, 20.0), segment(0.1, 20.0)])
    with pytest.raises(ValueError, match="no segment to fit"):
        fit_free_body([])
    with pytest.raises(ValueError, match="must be a physics.gyro.Segment"):
        fit_free_body([np.zeros((10, 3))])  # type: ignore[list-item]
    with pytest.raises(ValueError, match="drag must be 'linear' or 'none'"):
        fit_free_body(segment(0.8, 20.0), drag="cubic")  # type: ignore[arg-type]
    with pytest.raises(ValueError, match="must be a physics.gyro.Recording"):
        free_flights("toss.csv")  # type: ignore[arg-type]


def test_a_recording_without_a_toss_has_no_flight() -> None:
    rec, _ = synthetic_recording(MOMENTS, [Toss(1.0, 0.1, (2.0, 0.1, 0.1))], noise=NOISE, total=3.0)
    assert free_flights(rec) == []
