"""The events of an exact motion, from its closed form (not from frames): each half-turn of the tennis
racket's flip, each turning point of a heavy top's nutation, each swing of a pendulum.

Every exact motion here has a phase that grows linearly in time, and its events are where that phase is a
multiple of a constant (a quarter or half period of the elliptic functions, or π): their times are solved
for directly, ``t_j = (j · half − offset) / rate``, so consecutive events are exactly the physics API's
half period apart (:meth:`physics.free_body.FreeBody.period`,
:attr:`physics.heavy_top.HeavyTopTrajectory.nutation_period`,
:meth:`physics.pendulum.PhysicalPendulum.motion_period`).

- The flip (torque-free body with three different moments): a **half-turn** where ω along the intermediate
  axis passes through zero, i.e. the instant that axis is perpendicular to L (``L₂ = I₂ ω₂ = 0``; lecture,
  the end of the free-body section: the axis the linearised ``η̈₂`` equation finds unstable). There the flip
  is at its fastest and ``ω₁``, ``ω₃`` are extremal; in the Jacobi form ``ω₂ ∝ sn(λ t + u0)`` it is
  ``λ t + u0 = 2jK``, every half period ``T/2 = 2K/|λ|``. A symmetric body, a sphere or a uniform spin
  about a principal axis has none; on the separatrix there is exactly one.
- The heavy top: **θ max** and **θ min** where ``u = cos θ = u1 + (u2 − u1) sn²(λ t + c)`` reaches a root
  of the nutation cubic (lecture, "the heavy symmetric top"), half a nutation period apart.
- The pendulum: a **turning point** where the swing reverses (``θ̇ = 0``, ``θ = ±θ_max``), half a period
  apart; going over the top, **over the top** at each passage through ``θ ≡ π (mod 2π)`` (the slowest
  instant), one turn apart. None on the separatrix (it reaches the top only as ``t → ±∞``).

:func:`events_between` takes any of the three trajectories; each has its own function too.
"""

from __future__ import annotations

import math
from dataclasses import dataclass

import numpy as np
from numpy.typing import NDArray

from physics.free_body_trajectory import FreeBodyTrajectory
from physics.heavy_top import HeavyTopTrajectory
from physics.pendulum import LIBRATION, PendulumTrajectory
from physics.validation import finite_scalar

__all__ = [
    "HALF_TURN",
    "MAX_EVENTS",
    "OVER_THE_TOP",
    "THETA_MAX",
    "THETA_MIN",
    "TURNING_POINT",
    "MotionEvent",
    "events_between",
    "flip_events",
    "nutation_events",
    "phase_times",
    "swing_events",
]

HALF_TURN = "half-turn"
THETA_MAX = "θ max"
THETA_MIN = "θ min"
TURNING_POINT = "turning point"
OVER_THE_TOP = "over the top"

MAX_EVENTS = 100_000
"""Most events one call returns: a span holding more is refused (a list a person reads is far shorter)."""


@dataclass(frozen=True)
class MotionEvent:
    """One event of a motion.

    Attributes
    ----------
    time : float
        When it happens, s (on the motion's clock, ``t = 0`` at its initial state).
    kind : str
        :data:`HALF_TURN`, :data:`THETA_MAX`, :data:`THETA_MIN`, :data:`TURNING_POINT` or
        :data:`OVER_THE_TOP`.
    value : float
        What the event reached, in ``unit``: for a half-turn the body-frame ω along the intermediate axis
        the flip turns to (its extremum half a half-period later, rad/s, sign included); for the top the
        turning angle θ_max or θ_min (rad); for the pendulum the angle θ at the event (rad, unwrapped).
    unit : str
        ``"rad/s"`` or ``"rad"``.
    """

    time: float
    kind: str
    value: float
    unit: str


def _span(t0: float, t1: float) -> tuple[float, float]:
    a, b = finite_scalar(t0, "t0"), finite_scalar(t1, "t1")
    if b < a:
        raise ValueError(f"the span [t0, t1] must have t0 <= t1, got t0 = {a!r} s, t1 = {b!r} s")
    return a, b


def phase_times(
    rate: float, offset: float, half: float, t0: float, t1: float
) -> tuple[NDArray[np.float64], NDArray[np.int64]]:
    """The times in ``[t0, t1]`` at which the phase ``rate t + offset`` is a whole multiple ``j half``.

    Parameters
    ----------
    rate : float
        Rate of the phase, 1/s (either sign, not 0).
    offset : float
        The phase at ``t = 0``.
    half : float
        The spacing of the events in phase (> 0; ``inf``: only ``j = 0``).
    t0, t1 : float
        The span, s, ``t0 <= t1``.

    Returns
    -------
    times : ndarray, shape (n,)
        Increasing, s: ``(j half − offset) / rate``.
    j : ndarray of int, shape (n,)
        The multiple of each.

    Raises
    ------
    ValueError
        Non-finite or reversed span; a span holding more than :data:`MAX_EVENTS` events.
    """
    a, b = _span(t0, t1)
    if math.isinf(half):
        j = np.zeros(1, dtype=np.int64)
    else:
        ends = sorted(((rate * a + offset) / half, (rate * b + offset) / half))
        if not all(math.isfinite(e) for e in ends):
            raise ValueError(f"the span [{a!r}, {b!r}] s is too far from 0: the motion's phase overflows there")
        # One multiple beyond each end: the times are filtered below, so rounding at an end drops none.
        lo, hi = math.floor(ends[0]) - 1, math.ceil(ends[1]) + 1
        if hi - lo > MAX_EVENTS:
            raise ValueError(
                f"the span [{a!r}, {b!r}] s holds about {float(hi - lo):.3g} events, more than {MAX_EVENTS:,}: ask for a shorter one"
            )
        j = np.arange(lo, hi + 1, dtype=np.int64)
    multiple = 0.0 if math.isinf(half) else j * half  # the separatrix: only j = 0 (0 · inf is NaN)
    times = np.asarray((multiple - offset) / rate * np.ones(j.shape), dtype=np.float64)
    keep = (times >= a) & (times <= b)
    order = np.argsort(times[keep], kind="stable")
    return times[keep][order], j[keep][order]


def flip_events(motion: FreeBodyTrajectory, t0: float, t1: float) -> list[MotionEvent]:
    """The half-turns of a torque-free body's flip in ``[t0, t1]`` (s): see the module docstring.

    Parameters
    ----------
    motion : FreeBodyTrajectory
        From :meth:`physics.free_body.FreeBody.trajectory`.
    t0, t1 : float
        The span, s (any sign, ``t0 <= t1``).

    Returns
    -------
    list of MotionEvent
        Kind :data:`HALF_TURN`, in time order, ``T/2`` apart (``T`` = ``FreeBody.period``); empty for a
        body with two equal moments and for a uniform spin about a principal axis (no flip).
    """
    _span(t0, t1)
    p = motion.body.constants(motion.omega0[None, :])
    if int(p.kind[0]) != 2:
        return []
    lam, u0, quarter = float(p.lam[0]), float(p.u0[0]), float(p.K[0])
    times, j = phase_times(lam, u0, 2.0 * quarter, t0, t1)
    # ω in canonical axes is (A_a dn u, A_b sn u, A_c cn u), b the intermediate axis; q_can's row b is ± the
    # body axis it is. Leaving u = 2jK in the direction of λ, sn reaches sign(λ) (−1)^j a quarter period on.
    row = p.q_can[0][1]
    axis = int(np.argmax(np.abs(row)))
    spin = float(p.amp[0][1] * row[axis]) * math.copysign(1.0, lam)
    return [MotionEvent(float(t), HALF_TURN, spin * (1.0 - 2.0 * float(k % 2)), "rad/s") for t, k in zip(times, j)]


def nutation_events(motion: HeavyTopTrajectory, t0: float, t1: float) -> list[MotionEvent]:
    """The turning points of a heavy top's nutation in ``[t0, t1]`` (s): :data:`THETA_MAX` and
    :data:`THETA_MIN` alternately, half a :attr:`~physics.heavy_top.HeavyTopTrajectory.nutation_period`
    apart, each with its angle (rad, :attr:`~physics.heavy_top.HeavyTopTrajectory.turning_points`). Empty
    when θ never moves (a steady precession, a top exactly vertical) or its turning points are the same
    float (a nutation below θ's rounding: a steady precession started from rounded rates)."""
    _span(t0, t1)
    phase = motion.nutation_phase
    if phase is None:
        return []
    theta_min, theta_max = (float(v) for v in motion.turning_points)
    if theta_min == theta_max:  # a nutation below the rounding of θ (a steady precession up to rounding)
        return []
    times, j = phase_times(*phase, t0, t1)
    return [
        MotionEvent(float(t), THETA_MIN, theta_min, "rad")
        if k % 2
        else MotionEvent(float(t), THETA_MAX, theta_max, "rad")
        for t, k in zip(times, j)
    ]


def swing_events(motion: PendulumTrajectory, t0: float, t1: float) -> list[MotionEvent]:
    """The turning points (libration) or passages over the top (rotation) of one pendulum swing in
    ``[t0, t1]`` (s), each with its exact angle θ (rad) at that instant, half a period (libration) or one
    turn (rotation) apart (:meth:`physics.pendulum.PhysicalPendulum.motion_period`). Empty on the
    separatrix and without a restoring torque; ValueError for a trajectory of several initial states."""
    _span(t0, t1)
    phase = motion.phase
    if phase is None:
        return []
    rate, offset, quarter = phase
    # Odd multiples of K: the phase shifted by K is an even one, j = 2i.
    times, j = phase_times(rate, offset - quarter, 2.0 * quarter, t0, t1)
    if times.size == 0:
        return []
    kind = TURNING_POINT if str(motion.model.regime(motion.theta0, motion.thetadot0)) == LIBRATION else OVER_THE_TOP
    theta = np.atleast_1d(motion.at(times).theta)
    return [MotionEvent(float(t), kind, float(th), "rad") for t, th in zip(times, theta)]


def events_between(
    motion: FreeBodyTrajectory | HeavyTopTrajectory | PendulumTrajectory, t0: float, t1: float
) -> list[MotionEvent]:
    """The events of ``motion`` in ``[t0, t1]`` (s), in time order: :func:`flip_events`,
    :func:`nutation_events` or :func:`swing_events` by the kind of trajectory (ValueError naming any other)."""
    if isinstance(motion, FreeBodyTrajectory):
        return flip_events(motion, t0, t1)
    if isinstance(motion, HeavyTopTrajectory):
        return nutation_events(motion, t0, t1)
    if isinstance(motion, PendulumTrajectory):
        return swing_events(motion, t0, t1)
    raise ValueError(
        "events come from an exact trajectory (FreeBody.trajectory, HeavyTop.trajectory or "
        f"PhysicalPendulum.trajectory), got {type(motion).__name__}"
    )
