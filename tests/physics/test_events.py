"""The events of the exact motions (physics.events): where the closed form says, half a period apart by
the physics API's own period, and where a dense evaluation of the exact solution finds the quantity's
zero or extremum (bisected on the exact solution to 1e-13 s, compared to 1e-9 s)."""

from __future__ import annotations

import math
from collections.abc import Callable

import numpy as np
import pytest

from physics.events import (
    HALF_TURN,
    MAX_EVENTS,
    OVER_THE_TOP,
    THETA_MAX,
    THETA_MIN,
    TURNING_POINT,
    events_between,
    flip_events,
    phase_times,
    swing_events,
)
from physics.free_body import FreeBody
from physics.heavy_top import HeavyTop
from physics.inertia import box
from physics.pendulum import PhysicalPendulum
from physics.rotations import angle_between

# Event times are solved for from the phase, t = (j half − offset)/rate: a few roundings of t. The dense
# search bisects the exact solution's sign change to 1e-13 s; 1e-9 s is the promise, far above both.
TIME_TOL = 1e-9


def zeros_by_dense_search(
    q: Callable[[float], float], t0: float, t1: float, n: int = 20001, sample: Callable[..., object] | None = None
) -> list[float]:
    """Every sign change of ``q`` on [t0, t1] found on n samples (``sample(times)``, q vectorised, if given),
    then bisected on q itself to 1e-13 s or to adjacent floats."""
    ts = np.linspace(t0, t1, n)
    values = np.asarray(sample(ts)) if sample is not None else np.array([q(float(t)) for t in ts])
    found = []
    for i in np.nonzero(np.signbit(values[:-1]) != np.signbit(values[1:]))[0]:
        a, b, qa = float(ts[i]), float(ts[i + 1]), values[i]
        while b - a > 1e-13:
            mid = 0.5 * (a + b)
            if mid in (a, b):  # adjacent floats (past 1000 s their spacing exceeds 1e-13 s)
                break
            qm = q(mid)
            if np.signbit(qm) == np.signbit(qa):
                a, qa = mid, qm
            else:
                b = mid
        found.append(0.5 * (a + b))
    return found


# --- the flip -----------------------------------------------------------------------------------------------
FLIPS = {
    # moments, ω0, body index of the intermediate axis
    "racket near the intermediate axis": ([2.0, 1.5, 1.0], [1e-3, 2.0, 1e-3], 1),
    "the other side of the separatrix": ([2.0, 1.5, 1.0], [1e-3, -2.0, 2e-3], 1),
    "negative spin, unsorted moments": ([1.5, 2.0, 1.0], [-3.0, 2e-2, -1e-2], 0),
    "wobble about the largest axis": ([2.0, 1.5, 1.0], [1.0, 0.3, 0.2], 1),
    # 1 − m far below the float range: the separatrix's pulses, K = ln(4/k'), flips every ~1300 s.
    "pushed 1e-200 off the intermediate axis": ([2.0, 1.5, 1.0], [1e-200, 2.0, 1e-200], 1),
}


@pytest.mark.parametrize("name", FLIPS)
def test_half_turns_are_half_the_free_body_period_apart(name):
    moments, w0, _ = FLIPS[name]
    body = FreeBody(moments)
    period = body.period(w0)
    t0 = 0.37 * period
    events = flip_events(body.trajectory(w0), t0, t0 + 3.0 * period * (1.0 - 1e-9))
    assert len(events) == 6  # two half-turns per period of ω
    times = np.array([e.time for e in events])
    assert all(e.kind == HALF_TURN and e.unit == "rad/s" for e in events)
    # The spacing is the API's T/2 to the rounding of t (a few ulps of t).
    np.testing.assert_allclose(np.diff(times), 0.5 * period, rtol=0, atol=1e-13 * period)


@pytest.mark.parametrize("name", FLIPS)
def test_half_turns_are_where_the_intermediate_axis_is_perpendicular_to_L(name):
    moments, w0, axis = FLIPS[name]
    body = FreeBody(moments)
    motion = body.trajectory(w0)
    period = body.period(w0)
    events = flip_events(motion, 0.0, 2.0 * period)
    expected = zeros_by_dense_search(
        lambda t: float(motion.at(t).omega[axis]), 0.0, 2.0 * period, sample=lambda ts: motion.at(ts).omega[:, axis]
    )
    assert len(expected) == len(events) >= 3
    np.testing.assert_allclose([e.time for e in events], expected, rtol=0, atol=TIME_TOL)
    for event in events:
        now = motion.at(event.time)
        # ω₂ = 0 there to rounding of |ω| (its slope times the time's rounding).
        assert abs(now.omega[axis]) < 1e-12 * np.max(np.abs(now.omega))
        assert abs(angle_between(now.attitude[:, axis], motion.angular_momentum) - math.pi / 2) < 1e-12
        # The value: ω along that axis a quarter period on, the extremum the flip turns to.
        later = motion.at(event.time + 0.25 * period).omega[axis]
        assert event.value == pytest.approx(later, rel=1e-12)
    signs = np.sign([e.value for e in events])
    assert np.all(signs[1:] == -signs[:-1])  # over and back


def test_the_racket_flips_over_at_each_half_turn():
    """Spun near +axis 2, the first half-turn takes ω₂ to about −2 rad/s, the next back to +2."""
    body = FreeBody([2.0, 1.5, 1.0])
    w0 = [1e-3, 2.0, 1e-3]
    first, second = flip_events(body.trajectory(w0), 0.0, body.period(w0))
    assert first.value == pytest.approx(-2.0, rel=1e-6)
    assert second.value == pytest.approx(2.0, rel=1e-6)


def test_no_half_turns_without_an_intermediate_axis_or_off_it():
    assert flip_events(FreeBody([2.0, 1.0, 2.0]).trajectory([0.3, -1.0, 0.7]), 0.0, 100.0) == []
    assert flip_events(FreeBody([2.0, 1.5, 1.0]).trajectory([0.0, 3.0, 0.0]), 0.0, 100.0) == []


def test_the_separatrix_has_one_half_turn():
    """On the separatrix ω₂ = A tanh(λ (t − t*)): one sign change, ever."""
    body = FreeBody([1.40625, 1.15625, 1.0])
    w0 = [1.0, -0.3, 1.5]  # L² = 2 E I₂ exactly in these binary fractions
    assert math.isinf(body.period(w0))
    motion = body.trajectory(w0)
    events = flip_events(motion, -50.0, 50.0)
    assert len(events) == 1
    expected = zeros_by_dense_search(
        lambda t: float(motion.at(t).omega[1]), -50.0, 50.0, sample=lambda ts: motion.at(ts).omega[:, 1]
    )
    assert expected == pytest.approx([events[0].time], abs=TIME_TOL)


# --- the heavy top ---------------------------------------------------------------------------------------
TOPS = {
    "nutating, cusps-like": (HeavyTop(1.0, 0.5, 2.0), (0.5, 0.1, 0.3, 20.0)),
    "big nutation": (HeavyTop(1.0, 0.5, 2.0), (1.0, 0.0, 0.0, 5.0)),
    "through the pole": (HeavyTop(1.0, 0.5, 2.0), (0.0, 0.8, 0.0, 5.0)),
    "without gravity": (HeavyTop(1.0, 0.5, 0.0), (0.5, 0.3, 0.2, 3.0)),
}


@pytest.mark.parametrize("name", TOPS)
def test_nutation_turning_points_agree_with_the_period_and_the_dense_solution(name):
    top, ic = TOPS[name]
    motion = top.trajectory(*ic)
    period = motion.nutation_period
    # From before t = 0: a motion started at a turning point has an event at 0, the dense search none there.
    t0, t1 = -0.1 * period, 3.0 * period
    events = events_between(motion, t0, t1)
    theta_min, theta_max = motion.turning_points
    assert theta_min < theta_max
    assert [e.kind for e in events][:2] in ([THETA_MAX, THETA_MIN], [THETA_MIN, THETA_MAX])
    assert all(e.kind != f.kind for e, f in zip(events, events[1:]))  # alternating
    times = np.array([e.time for e in events])
    np.testing.assert_allclose(np.diff(times), 0.5 * period, rtol=0, atol=1e-13 * max(period, times[-1]))
    for event in events:
        assert event.value == (theta_max if event.kind == THETA_MAX else theta_min)
        assert motion.at(event.time).theta == pytest.approx(event.value, abs=1e-12)

    # Where θ̇ changes sign (θ̇ is u̇'s multiple: through the pole θ never turns there, |θ̇| does not vanish).
    def rate(t: float) -> float:
        return float(motion.at(t).thetadot)

    sample = lambda ts: motion.at(ts).thetadot  # noqa: E731
    expected = [t for t in zeros_by_dense_search(rate, t0, t1, sample=sample) if motion.at(t).theta > 1e-6]
    interior = [e.time for e in events if e.value > 0.0]
    np.testing.assert_allclose(interior, expected, rtol=0, atol=TIME_TOL)


def test_a_steady_precession_has_no_turning_points():
    top = HeavyTop(1.0, 0.5, 2.0)
    slow = top.steady_precession_rates(0.5, 10.0)[0]
    motion = top.trajectory(0.5, 0.0, slow, 20.0 - slow * math.cos(0.5))
    assert events_between(motion, 0.0, 100.0) == []
    assert events_between(top.trajectory(0.0, 0.0, 0.0, 5.0), 0.0, 100.0) == []


def test_the_free_top_turning_points_are_its_extreme_angles():
    """Without gravity θ swings between the parabola's roots: turning_points gives them (not θ0)."""
    motion = HeavyTop(1.0, 0.5, 0.0).trajectory(0.5, 0.3, 0.2, 3.0)
    theta = motion.at(np.linspace(0.0, motion.nutation_period, 20001)).theta
    lo, hi = motion.turning_points
    assert lo == pytest.approx(theta.min(), abs=1e-9) and hi == pytest.approx(theta.max(), abs=1e-9)


# --- the pendulum -----------------------------------------------------------------------------------------
PENDULUM = PhysicalPendulum(box(1.0, [0.1, 0.2, 0.3]), [0.0, 0.0, 0.15], [1.0, 0.0, 0.0])
W0 = PENDULUM.omega0
SWINGS = {
    "libration, released at 3 rad": (3.0, 0.0, TURNING_POINT),
    "libration, pushed back": (0.3, -2.0, TURNING_POINT),
    "rotation": (0.0, 5.0 * W0, OVER_THE_TOP),
    "rotation, backwards from 7 rad": (7.0, -2.5 * W0, OVER_THE_TOP),
}


@pytest.mark.parametrize("name", SWINGS)
def test_swings_agree_with_the_period_and_the_dense_solution(name):
    th0, thd0, kind = SWINGS[name]
    motion = PENDULUM.trajectory(th0, thd0)
    period = float(PENDULUM.motion_period(th0, thd0))
    spacing = 0.5 * period if kind == TURNING_POINT else period
    events = swing_events(motion, -0.2 * period, 3.0 * period)
    assert all(e.kind == kind and e.unit == "rad" for e in events)
    times = np.array([e.time for e in events])
    assert len(times) >= 3
    np.testing.assert_allclose(np.diff(times), spacing, rtol=0, atol=1e-13 * period)
    if kind == TURNING_POINT:
        # θ̇ changes sign there, θ = ±θ_max alternately.
        def q(t: float) -> float:
            return float(motion.at(t).theta_dot)

        def sample(ts):
            return motion.at(ts).theta_dot

        amplitude = abs(events[0].value)
        assert [e.value for e in events] == pytest.approx([amplitude * math.copysign(1.0, e.value) for e in events])
        assert all(np.sign(e.value) != np.sign(f.value) for e, f in zip(events, events[1:]))
    else:
        # cos(θ/2) changes sign as θ passes π (mod 2π), where the speed is least.
        def q(t: float) -> float:
            return math.cos(0.5 * float(motion.at(t).theta))

        def sample(ts):
            return np.cos(0.5 * motion.at(ts).theta)

        for e in events:
            assert math.cos(0.5 * e.value) == pytest.approx(0.0, abs=1e-12)
    expected = zeros_by_dense_search(q, -0.2 * period, 3.0 * period, sample=sample)
    np.testing.assert_allclose(times, expected, rtol=0, atol=TIME_TOL)


def test_no_swing_events_on_the_separatrix_or_without_gravity():
    assert swing_events(PENDULUM.trajectory(0.0, 2.0 * W0), 0.0, 100.0) == []
    flat = PhysicalPendulum(box(1.0, [0.1, 0.2, 0.3]), [0.0, 0.0, 0.15], [1.0, 0.0, 0.0], g=0.0)
    assert swing_events(flat.trajectory(0.0, 1.0), 0.0, 100.0) == []


# --- refusals ---------------------------------------------------------------------------------------------
def test_bad_spans_are_refused_by_name():
    motion = FreeBody([2.0, 1.5, 1.0]).trajectory([1e-3, 2.0, 1e-3])
    with pytest.raises(ValueError, match="t0 must be finite"):
        events_between(motion, math.nan, 1.0)
    with pytest.raises(ValueError, match="t1 must be finite"):
        events_between(motion, 0.0, math.inf)
    with pytest.raises(ValueError, match="t0 <= t1"):
        events_between(motion, 2.0, 1.0)
    with pytest.raises(ValueError, match="t1 must be a real number"):
        events_between(motion, 0.0, "<b>soon</b>")
    with pytest.raises(ValueError, match=f"more than {MAX_EVENTS:,}"):
        events_between(motion, 0.0, 1e12)
    with pytest.raises(ValueError, match="phase overflows"):
        phase_times(10.0, 0.0, 1.0, 0.0, 1e308)
    with pytest.raises(ValueError, match="exact trajectory .* got str"):
        events_between("racket", 0.0, 1.0)  # type: ignore[arg-type]
    with pytest.raises(ValueError, match="one initial state"):
        swing_events(PENDULUM.trajectory([0.1, 0.2], 0.0), 0.0, 1.0)


def test_phase_times_with_a_falling_phase():
    """rate < 0: the multiples are met in reverse order, returned in time order."""
    times, j = phase_times(-2.0, 0.5, 1.0, 0.0, 3.0)
    np.testing.assert_allclose(times, [0.25, 0.75, 1.25, 1.75, 2.25, 2.75])
    assert list(j) == [0, -1, -2, -3, -4, -5]
    assert phase_times(1.0, 0.0, math.inf, -1.0, 1.0)[0].tolist() == [0.0]
