"""Finding the free flights in a gyroscope recording: :func:`free_flights`.

A toss is a stretch of fast spin between two jolts: the hand's release and the catch. A jolt shows in the
second difference of the samples, ``|ω_{k+1} − 2 ω_k + ω_{k−1}|``, which in free flight is ``|ω̈| dt²``, a
few hundredths of |ω| at 100 Hz (the hand-marked real tosses: 0.05 |ω| or less in 90% of them), and at a
catch is of the order of |ω| itself. The throw's own spin-up is smooth, so the window found from the jolts
is then tested against the physics: the torque-free model is fitted to the stretch's middle and the window
is cut where the samples leave it (the hand still turning the phone at the start, the fingers touching it
at the end). Samples at the gyroscope's limit are neither jolts nor fitted.
"""

from __future__ import annotations

import numpy as np

from physics.gyro.fit import MIN_DURATION, MIN_SPIN, check_segment, fit_free_body
from physics.gyro.recording import CLIP_RATE, Recording, Segment, clipped

JOLT = 0.1
"""A sample whose second difference exceeds this share of |ω| (or of 1 rad/s) is a jolt."""
SPIN_ON = 4.0
"""rad/s: below this |ω| the phone is in the hand or at rest."""
MIDDLE_SHARE = 0.35
"""Share of the jolt-free stretch trimmed from its start for the fit that tests it: the throw's spin-up is
smooth (no jolt) and lasts up to a third of the stretch."""
END_TRIM = 0.04
"""s: trimmed from the stretch's end for that fit (the fingers touch before the catch's jolt)."""
DEPART = 0.06
"""A sample whose |L| is this share off the free flight's (or its energy twice this share) is not free."""

MARGIN = (0.025, 0.02)
"""s cut inside the found release and catch: the sample that straddles a contact, and the next, still carry
the hand (a gyroscope sample averages over its 10 ms)."""

__all__ = ["free_flights"]


def free_flights(recording: Recording, *, clip_rate: float = CLIP_RATE, refine: bool = True) -> list[Segment]:
    """The free flights of a recording, from release to catch, in time order.

    Parameters
    ----------
    recording : Recording
        From :func:`physics.gyro.read_gyroscope`. A flight never spans a pause (``recording.breaks``).
    clip_rate : float, keyword-only
        The gyroscope's limit, rad/s (default :data:`physics.gyro.recording.CLIP_RATE`).
    refine : bool, keyword-only
        Cut each window where the samples leave the fitted torque-free model (default); False keeps the
        windows between the jolts.

    Returns
    -------
    list of Segment
        Each at least :data:`physics.gyro.fit.MIN_DURATION` long with a median |ω| of at least
        :data:`physics.gyro.fit.MIN_SPIN`; a window that is mostly clipped is returned unrefined (the fit
        refuses it, saying so).
    """
    if not isinstance(recording, Recording):
        raise ValueError(f"recording must be a physics.gyro.Recording (read_gyroscope), got {type(recording).__name__}")
    found = []
    for first, stop in recording.pieces():
        times, omega = recording.times[first:stop], recording.omega[first:stop]
        for a, b in _calm_runs(times, omega, clip_rate):
            seg = Segment(float(times[a]), float(times[b - 1]), times[a:b], omega[a:b], clip_rate)
            if seg.duration < MIN_DURATION or np.median(np.linalg.norm(seg.omega, axis=1)) < MIN_SPIN:
                continue
            found.append(_refined(seg, times, omega, a, b) if refine else seg)
    return [s for s in found if s.duration >= MIN_DURATION]


def _calm_runs(times: np.ndarray, omega: np.ndarray, clip_rate: float) -> list[tuple[int, int]]:
    """``(first, stop)`` of the stretches of spin above :data:`SPIN_ON` without a jolt."""
    n = len(times)
    if n < 3:
        return []
    spin = np.linalg.norm(omega, axis=1)
    second = np.zeros(n)
    second[1:-1] = np.linalg.norm(omega[2:] - 2.0 * omega[1:-1] + omega[:-2], axis=1)
    # A step at the limit is the limit's, not a jolt: no second difference that touches a clipped sample.
    at_limit = np.any(clipped(omega, clip_rate), axis=1)
    touched = at_limit.copy()
    touched[1:] |= at_limit[:-1]
    touched[:-1] |= at_limit[1:]
    second[touched] = 0.0
    calm = (spin > SPIN_ON) & (second <= JOLT * np.maximum(spin, 1.0))
    # A jolt spoils the samples on both sides of it: its second difference sits on the middle one.
    jolt = ~calm & (spin > SPIN_ON)
    calm[1:] &= ~jolt[:-1]
    calm[:-1] &= ~jolt[1:]
    edges = np.diff(np.concatenate([[0], calm.astype(int), [0]]))
    return list(zip(np.nonzero(edges == 1)[0].tolist(), np.nonzero(edges == -1)[0].tolist()))


def _refined(seg: Segment, times: np.ndarray, omega: np.ndarray, a: int, b: int) -> Segment:
    """The window ``[a, b)`` cut to the samples that follow the model fitted to its middle."""
    middle_start = seg.start + MIDDLE_SHARE * seg.duration
    middle = Segment.between_arrays(times, omega, middle_start, seg.end - END_TRIM, seg.clip_rate)
    try:
        check_segment(middle)
        fit = fit_free_body(middle)
    except ValueError:
        return seg
    window_t, window_w = times[a:b], omega[a:b]
    bad = _departures(fit.moments, fit.rotation, middle, window_t, window_w)
    # Two samples in a row: one sample off is noise or a small knock, the hand stays longer.
    pair = bad[:-1] & bad[1:]
    inside = np.nonzero((window_t >= middle.start) & (window_t <= middle.end))[0]
    lo, hi = int(inside[0]), int(inside[-1])
    before = np.nonzero(pair[: max(lo - 1, 0)])[0]
    after = np.nonzero(pair[hi + 1 :])[0]
    first = int(before[-1]) + 2 if before.size else 0
    last = hi + int(after[0]) if after.size else len(window_t) - 1
    keep = np.arange(first, last + 1)
    keep = keep[(window_t[keep] >= window_t[first] + MARGIN[0]) & (window_t[keep] <= window_t[last] - MARGIN[1])]
    if keep.size == 0:
        return seg
    return Segment(float(window_t[keep[0]]), float(window_t[keep[-1]]), window_t[keep], window_w[keep], seg.clip_rate)


def _departures(moments: np.ndarray, rotation: np.ndarray, middle: Segment, t: np.ndarray, w: np.ndarray) -> np.ndarray:
    """Samples (n,) whose angular momentum or energy (with the fitted moments) is off the free flight's.

    Torque-free, |L| and E are constant; with drag they fall by a few percent per second, a trend fitted
    over the middle. Unlike ω itself they do not depend on the phase of the motion, which near the
    separatrix no extrapolation keeps across a flip; a hand spinning the phone up, or fingers touching it,
    change them by tens of percent in a few samples.
    """

    def invariants(omega: np.ndarray) -> tuple[np.ndarray, np.ndarray]:
        body = omega @ rotation
        return np.linalg.norm(body * moments, axis=1), np.sum(moments * body**2, axis=1)

    usable = ~np.any(middle.clipped, axis=1)
    mid_l, mid_e = invariants(middle.omega[usable])
    l_now, e_now = invariants(w)
    off_l = np.abs(l_now / np.polyval(np.polyfit(middle.times[usable], mid_l, 1), t) - 1.0)
    off_e = np.abs(e_now / np.polyval(np.polyfit(middle.times[usable], mid_e, 1), t) - 1.0)
    return np.asarray(((off_l > DEPART) | (off_e > 2.0 * DEPART)) & ~np.any(clipped(w, middle.clip_rate), axis=1))
