"""A gyroscope recording and the pieces of it that are free flights (plain data, no reading or fitting)."""

from __future__ import annotations

from dataclasses import dataclass, field

import numpy as np
from numpy.typing import NDArray

Floats = NDArray[np.float64]

CLIP_RATE = 34.9
"""rad/s: where the phones' gyroscopes saturate (±2000 °/s); a sample within 1% of it counts as clipped."""

__all__ = ["CLIP_RATE", "Recording", "Segment", "clipped"]


@dataclass(frozen=True)
class Recording:
    """Angular velocity measured by a phone's gyroscope.

    Attributes
    ----------
    times : ndarray (n,)
        Sample times, s, strictly increasing.
    omega : ndarray (n, 3)
        Angular velocity in the phone's axes (x right across the screen, y up its long side, z out of the
        screen), rad/s.
    device : str or None
        The phone's model name when the export says it (phyphox's ``meta/device.csv``).
    breaks : tuple of float
        Times of the first sample after each pause (phyphox's time does not advance while paused, so a pause
        is invisible in ``times``), or after a gap of more than 5 sampling steps: motion is not continuous
        across them.
    """

    times: Floats
    omega: Floats
    device: str | None = None
    breaks: tuple[float, ...] = ()

    def pieces(self) -> list[tuple[int, int]]:
        """``(first, stop)`` sample indices of the continuous pieces between breaks."""
        cuts = sorted({int(np.searchsorted(self.times, b)) for b in self.breaks} - {0, len(self.times)})
        edges = [0, *cuts, len(self.times)]
        return [(a, b) for a, b in zip(edges[:-1], edges[1:]) if b > a]


@dataclass(frozen=True)
class Segment:
    """One free flight, from release to catch.

    Attributes
    ----------
    start, end : float
        Times of the first and last sample, s (in the recording's time).
    times : ndarray (n,)
        Sample times, s.
    omega : ndarray (n, 3)
        Angular velocity in the phone's axes, rad/s.
    clip_rate : float
        Rate at which the gyroscope saturates, rad/s: components within 1% of it are not fitted.
    """

    start: float
    end: float
    times: Floats
    omega: Floats
    clip_rate: float = CLIP_RATE
    clipped: NDArray[np.bool_] = field(init=False, repr=False, compare=False)

    def __post_init__(self) -> None:
        object.__setattr__(self, "clipped", clipped(self.omega, self.clip_rate))

    @classmethod
    def between(cls, recording: Recording, start: float, end: float, clip_rate: float = CLIP_RATE) -> Segment:
        """The samples of ``recording`` with ``start ≤ t ≤ end`` (s) as a segment."""
        return cls.between_arrays(recording.times, recording.omega, start, end, clip_rate)

    @classmethod
    def between_arrays(
        cls, times: Floats, omega: Floats, start: float, end: float, clip_rate: float = CLIP_RATE
    ) -> Segment:
        """The samples ``times`` (n,) s, ``omega`` (n, 3) rad/s with ``start ≤ t ≤ end`` as a segment."""
        keep = (times >= start) & (times <= end)
        if not np.any(keep):
            raise ValueError(f"no samples between {start:g} s and {end:g} s (there are {times.size})")
        return cls(float(times[keep][0]), float(times[keep][-1]), times[keep], omega[keep], clip_rate)

    @property
    def duration(self) -> float:
        """``end − start``, s."""
        return self.end - self.start


def clipped(omega: Floats, clip_rate: float = CLIP_RATE) -> NDArray[np.bool_]:
    """Components (n, 3) within 1% of the saturation rate ``clip_rate`` (rad/s)."""
    return np.asarray(np.abs(omega) >= 0.99 * clip_rate)
