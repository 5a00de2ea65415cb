"""The clock's speed slider: logarithmic, 0.01× to 10×, with 1× in the middle.

More in docs/app-notes.md (``app.panel.speed``).
"""

from __future__ import annotations

import math

from app.language.words import keep, say

__all__ = [
    "SPEED_MIN",
    "SPEED_MAX",
    "POSITION_STEP",
    "POSITION_MARKS",
    "speed_at",
    "position_of",
    "speed_label",
]

SPEED_MIN, SPEED_MAX = 0.01, 10.0
POSITION_STEP = 0.05  # 20 steps per decade on the slow half, 20 per decade on the fast half
# Labelled at the ends and the middle (five labels overlap on a phone); ticks at 0.1× and 3.2×.
# Said (kept for the process's life): a language writes 0,01× with its own decimal mark.
POSITION_MARKS: tuple[float | tuple[float, str], ...] = (
    (-1.0, keep(say("{speed:g}×", speed=0.01))),
    -0.5,
    (0.0, keep(say("{speed:g}×", speed=1))),
    0.5,
    (1.0, keep(say("{speed:g}×", speed=10))),
)


def speed_at(position: float) -> float:
    """The speed (×) at a slider position in [−1, 1] (clamped): 100^p left of the middle, 10^p right."""
    p = min(max(float(position), -1.0), 1.0)
    return float(100.0**p if p <= 0.0 else 10.0**p)


def position_of(speed: float) -> float:
    """The slider position of a speed in [SPEED_MIN, SPEED_MAX] (×): the inverse of :func:`speed_at`."""
    s = min(max(float(speed), SPEED_MIN), SPEED_MAX)
    return math.log10(s) / 2.0 if s <= 1.0 else math.log10(s)


def speed_label(speed: float) -> str:
    """The slider's label: two significant digits, e.g. ``Speed 0.032×``, ``Speed 1×``, ``Speed 3.2×``."""
    return say("Speed {speed:.2g}×", speed=speed)
