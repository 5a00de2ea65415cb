"""A gyroscope recording made with the project's own model: tosses of a body of known moments, misalignment
and drag, with the hand's spin-up before each and a catch after, sampled like a phone (100 Hz, noise,
clipping, a pause). What the tests fit, knowing the answer."""

from __future__ import annotations

from collections.abc import Sequence
from dataclasses import dataclass

import numpy as np
from numpy.typing import NDArray

from physics.gyro.kernel import drag_omega
from physics.gyro.model import rotation_from_vector
from physics.gyro.recording import CLIP_RATE, Recording

Floats = NDArray[np.float64]

__all__ = ["Toss", "synthetic_recording"]


@dataclass(frozen=True)
class Toss:
    """One toss of a synthetic recording.

    Attributes
    ----------
    release : float
        Time the hand lets go, s.
    duration : float
        Free flight, s (the catch follows).
    omega0 : tuple of 3 floats
        ω at the release in the principal axes, rad/s.
    """

    release: float
    duration: float
    omega0: tuple[float, float, float]


def synthetic_recording(
    moments: Sequence[float],
    tosses: Sequence[Toss],
    *,
    misalignment: Sequence[float] = (0.0, 0.0, 0.0),
    drag: Sequence[float] = (0.0, 0.0, 0.0),
    noise: float = 0.02,
    rate: float = 100.0,
    clip_rate: float = CLIP_RATE,
    pause_at: float | None = None,
    pause_skip: float = 3.0,
    total: float | None = None,
    seed: int = 0,
) -> tuple[Recording, list[tuple[float, float]]]:
    """A recording and the true free-flight windows ``(release, catch)`` in its time, s.

    Parameters
    ----------
    moments : 3 floats
        Principal moments along the phone's x, y, z (any scale).
    tosses : sequence of Toss
        In time order, at least 0.5 s apart.
    misalignment : 3 floats, keyword-only
        Rotation vector (rad) from the phone's axes to the principal axes: the principal axes are the columns
        of ``exp(hat θ)`` in phone axes.
    drag : 3 floats, keyword-only
        Linear drag ``c_i`` on the principal axes, on the scale of the moments per second.
    noise : float, keyword-only
        Standard deviation of the gyroscope's white noise, rad/s.
    rate : float, keyword-only
        Sampling rate, Hz; the sample times jitter by 0.1 ms as a phone's do.
    clip_rate : float, keyword-only
        |ω_i| is clipped here, rad/s.
    pause_at : float or None, keyword-only
        A pause: the samples from this time on are those ``pause_skip`` s later, with time not advancing
        (phyphox's pause); it appears in ``Recording.breaks``.
    total : float or None, keyword-only
        Length of the recording, s (default: 1 s after the last catch).
    seed : int, keyword-only
        Seed of the noise.
    """
    inertia = np.asarray(moments, dtype=float)
    rot = rotation_from_vector(np.asarray(misalignment, dtype=float))
    c = np.asarray(drag, dtype=float)
    rng = np.random.default_rng(seed)
    end = total if total is not None else tosses[-1].release + tosses[-1].duration + 1.0
    skip = pause_skip if pause_at is not None else 0.0
    n = int(end * rate) + int(skip * rate)
    t_true = np.arange(n) / rate + 0.0001 * rng.standard_normal(n) + 0.5 / rate
    body = 0.05 * rng.standard_normal((n, 3))  # the phone at rest in a hand
    windows = []
    for toss in tosses:
        w0 = np.asarray(toss.omega0, dtype=float)
        spin_up = 0.15
        # The hand spins the phone up smoothly over 0.15 s (a torque), then lets go.
        ramp = (t_true >= toss.release - spin_up) & (t_true < toss.release)
        share = (t_true[ramp] - (toss.release - spin_up)) / spin_up
        body[ramp] = np.outer(share**2, w0 * [1.0, 0.3, 0.3]) + np.outer(share**2 * (1 - share), [2.0, -1.5, 1.0])
        free = (t_true >= toss.release) & (t_true <= toss.release + toss.duration)
        body[free] = drag_omega(inertia, c, w0, t_true[free] - toss.release)
        # The catch: a hard stop over 30 ms with a jolt, then rest.
        catch = (t_true > toss.release + toss.duration) & (t_true <= toss.release + toss.duration + 0.03)
        last = body[free][-1]
        body[catch] = np.outer(np.linspace(-0.6, 0.0, int(catch.sum())), last) + [8.0, -12.0, 5.0]
        windows.append((toss.release, toss.release + toss.duration))
    omega = body @ rot.T + noise * rng.standard_normal((n, 3))
    omega = np.clip(omega, -clip_rate, clip_rate)
    if pause_at is None:
        return Recording(t_true, omega), windows
    keep = (t_true < pause_at) | (t_true >= pause_at + skip)
    shifted = np.where(t_true >= pause_at + skip, t_true - skip, t_true)
    resume = float(shifted[keep][np.argmax(t_true[keep] >= pause_at + skip)])
    moved = [(a - skip, b - skip) if a >= pause_at + skip else (a, b) for a, b in windows]
    return Recording(shifted[keep], omega[keep], breaks=(resume,)), moved
