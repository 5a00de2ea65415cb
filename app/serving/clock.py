"""A simulation's clock: its time, whether it runs, its speed and the single steps asked for."""

from __future__ import annotations

__all__ = ["MAX_FRAME_DT", "Clock"]

MAX_FRAME_DT = 0.1
"""Wall time a frame may advance at most, s: a stalled frame does not make the simulation jump."""


class Clock:
    """Simulation time ``t`` (s), ``playing``, ``speed`` (× real time) and ``steps`` pending while paused.

    Parameters
    ----------
    fps : float
        Frames per second of the loop: a single step advances ``speed / fps`` s.
    """

    def __init__(self, fps: float) -> None:
        self.fps = float(fps)
        self.t = 0.0
        self.playing = True
        self.speed = 1.0
        self.steps = 0
        self.dropped = 0.0
        """Wall time, s, that playing frames did not simulate because each stalled beyond
        ``MAX_FRAME_DT``: how far behind the wall clock a loaded machine has left the simulation."""

    def advance(self, wall_dt: float) -> float:
        """Simulation time a frame ``wall_dt`` (s of wall time) after the last should advance by, s; the
        single steps pending are used up."""
        if self.playing:
            wall_dt = max(wall_dt, 0.0)
            self.dropped += max(wall_dt - MAX_FRAME_DT, 0.0)
            return min(wall_dt, MAX_FRAME_DT) * self.speed
        if self.steps:
            advance = self.steps * self.speed / self.fps
            self.steps = 0
            return advance
        return 0.0
