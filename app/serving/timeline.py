"""A simulation's timeline: its clock moved by hand (scrub, Step back, a jump of a second) and a slow replay.

An exact scene evaluates its closed form at any time; a stepped one (the friction top) shows the state of
its bounded history (:class:`physics.history.SteppedHistory`) at the grid time at or before it, so going
back then forward shows the same states bit for bit. A move by hand pauses the clock (the body stays at the
instant chosen); Play goes on from there. The slider (:mod:`app.panel.timeline_panel`) spans from the
scene's earliest reachable time (:meth:`app.scenes.base.Scene.earliest`) to the furthest time reached.
"""

from __future__ import annotations

import math
from dataclasses import dataclass
from typing import TYPE_CHECKING

from app.language.words import say

if TYPE_CHECKING:  # annotations only: the simulation imports this module
    from app.serving.simulation import Simulation

__all__ = ["MAX_JUMP", "REPLAY_SPAN", "REPLAY_SPEED", "Replay", "Timeline"]

REPLAY_SPAN = 2.0
"""What Replay shows again by default: the last this many seconds of simulated time."""
REPLAY_SPEED = 0.1
"""The speed a replay runs at by default (× real time): a flip of half a second takes five."""
MAX_JUMP = 300.0
"""The furthest a move by hand may reach beyond the furthest time reached, s: what a stepped scene's
history computes ahead in one go (:data:`app.scenes.heavy_top.KEPT`); the slider's end is never more than
a second ahead, and a time beyond this is refused."""


@dataclass
class Replay:
    """A replay under way: from ``start`` to ``end`` (s of simulated time) at ``speed``; afterwards the
    clock goes back to ``speed_before`` and ``playing_before``. ``wall`` counts the wall time (s) the clock
    ran for it (each frame's advance over the clock's speed), ``frames`` the frames drawn."""

    start: float
    end: float
    speed: float
    speed_before: float
    playing_before: bool
    wall: float = 0.0
    frames: int = 0


class Timeline:
    """The timeline of one simulation (:class:`app.serving.simulation.Simulation`).

    Attributes
    ----------
    reached : float
        The furthest time the clock has shown since the last restart, s: the slider's end.
    replay : Replay or None
        The replay under way.
    last_replay : Replay or None
        The last replay that ended (what it ran: its wall time and frames).
    """

    def __init__(self, sim: Simulation) -> None:
        self.sim = sim
        self.reached = 0.0
        self.replay: Replay | None = None
        self.last_replay: Replay | None = None

    # ------------------------------------------------------------------ what it spans
    def earliest(self) -> float:
        """The earliest time the clock can be moved back to, s."""
        scene = self.sim.scene
        return 0.0 if scene is None else float(scene.earliest())

    def restart(self) -> None:
        """The clock went back to t = 0 (Reset, a new parameter or scene): a new timeline."""
        self.reached = 0.0
        self.sim.panel.timeline.forget()
        if self.replay is not None:  # the replay is over: the speed of before
            self.sim.set_speed(self.replay.speed_before)
            self.replay = None

    # ------------------------------------------------------------------ moves by hand
    def seek(self, t: float) -> float:
        """Pause and put the body at time ``t`` (s), clamped to what the scene can reach (from
        :meth:`earliest`); returns the time shown. A still scene stays at 0.

        Raises
        ------
        ValueError
            ``t`` not a finite number, or more than :data:`MAX_JUMP` beyond the furthest time reached.
        """
        value = float(t)
        if not math.isfinite(value):
            raise ValueError(f"the time must be a finite number of seconds, got {t!r}")
        sim = self.sim
        with sim.lock:
            if value > max(self.reached, sim.time) + MAX_JUMP:
                raise ValueError(
                    say(
                        "the time may go at most {most:g} s beyond the furthest reached ({reached:.3f} s), got {t} s",
                        most=MAX_JUMP,
                        reached=self.reached,
                        t=value,
                    )
                )
            scene = sim.scene
            if scene is None or scene.static:
                return sim.time
            if self.replay is not None:  # a move by hand ends a replay: the speed of before, paused
                self._end_replay(self.replay, playing=False)
            sim.set_playing(False)
            sim.clock.steps = 0
            value = max(value, self.earliest())
            sim.clock.t = value
            scene.rewind(value)
            sim.request_redraw()
            return value

    def step_back(self) -> float:
        """Pause and go back one frame's worth of simulation time (1/fps × speed), as Step goes on one."""
        sim = self.sim
        return self.seek(sim.time - sim.speed / sim.fps)

    def jump(self, seconds: float) -> float:
        """Pause and move the clock by ``seconds`` (s; negative: back)."""
        return self.seek(self.sim.time + float(seconds))

    # ------------------------------------------------------------------ replay
    def start_replay(self, span: float = REPLAY_SPAN, speed: float = REPLAY_SPEED) -> Replay | None:
        """Replay the last ``span`` seconds (from now back, or from the earliest reachable) at ``speed``,
        then go back to the speed and the play or pause of before; None in a still scene.

        Raises
        ------
        ValueError
            A span that is not a positive finite number of seconds; a speed the clock does not take.
        """
        length, slow = float(span), float(speed)
        if not (math.isfinite(length) and length > 0.0):
            raise ValueError(f"the replay's span must be a positive number of seconds, got {span!r}")
        sim = self.sim
        with sim.lock:
            scene = sim.scene
            if scene is None or scene.static:
                return None
            before = self.replay
            speed_before = before.speed_before if before is not None else sim.speed
            playing_before = before.playing_before if before is not None else sim.playing
            end = before.end if before is not None else sim.time
            start = max(end - length, self.earliest())
            if start >= end:
                raise ValueError(
                    say("there is nothing to replay yet: the motion is at its start (t = {t:.3f} s)", t=end)
                )
            self.seek(start)
            sim.set_speed(slow)  # ValueError for a speed the slider does not have
            self.replay = Replay(start, end, slow, speed_before, playing_before)
            sim.set_playing(True)
            return self.replay

    def clamp(self, t: float) -> float:
        """The time a frame may advance to: a replay stops at its end."""
        replay = self.replay
        return min(t, replay.end) if replay is not None else t

    def after_frame(self, wall_dt: float, advanced: float) -> None:
        """A frame was drawn at the clock's time after advancing ``advanced`` s (``wall_dt`` s of wall time):
        the furthest time reached grows; a replay counts it, and at its end the clock goes back to the speed
        and the play or pause of before."""
        sim = self.sim
        self.reached = max(self.reached, sim.time)
        replay = self.replay
        if replay is None:
            return
        if not sim.playing:  # paused during the replay (Pause, a scrub): the replay is over
            self._end_replay(replay, playing=False)
            return
        if advanced > 0.0:  # the wall time this advance took at the clock's speed now
            replay.wall += advanced / sim.speed
            replay.frames += 1
        if sim.time >= replay.end:
            self._end_replay(replay, playing=replay.playing_before)

    def _end_replay(self, replay: Replay, *, playing: bool) -> None:
        sim = self.sim
        self.replay, self.last_replay = None, replay
        sim.set_speed(replay.speed_before)
        sim.set_playing(playing)
