"""A simulation's timeline: its clock moved by hand (scrub, Step back, a jump of a second) and a slow replay.

An exact scene evaluates its closed form at any time; a stepped one (the friction top) shows the state of
its bounded history (:class:`physics.history.SteppedHistory`) at the grid time at or before it, so going
back then forward shows the same states bit for bit. A move by hand pauses the clock (the body stays at the
instant chosen); Play goes on from there. The slider (:mod:`app.panel.timeline_panel`) spans from the
scene's earliest reachable time (:meth:`app.scenes.base.Scene.earliest`) to the furthest time reached.
"""

from __future__ import annotations

import math
import time
from dataclasses import dataclass
from typing import TYPE_CHECKING

from app.language.words import say

if TYPE_CHECKING:  # annotations only: the simulation imports this module
    from app.serving.simulation import Simulation

__all__ = ["GLIDE_SECONDS", "GLIDE_WINDOW", "MAX_JUMP", "REPLAY_SPAN", "REPLAY_SPEED", "Glide", "Replay", "Timeline"]

REPLAY_SPAN = 2.0
"""What Replay shows again by default: the last this many seconds of simulated time."""
REPLAY_SPEED = 0.1
"""The speed a replay runs at by default (× real time): a flip of half a second takes five."""
MAX_JUMP = 300.0
"""The furthest a move by hand may reach beyond the furthest time reached, s: what a stepped scene's
history computes ahead in one go (:data:`app.scenes.heavy_top.KEPT`); the slider's end is never more than
a second ahead, and a time beyond this is refused."""


GLIDE_SECONDS = 0.05
"""The shortest glide to an instant the slider is dragged to (s of wall time): the interval of a dragged
slider's messages (viser's page sends a control's changes at most every 50 ms; a busy page, further apart,
and the glide then lasts as long as that interval), so a drag is drawn at the loop's frame rate, each
frame an exact instant between two of the slider's, not in a few jumps a second."""
GLIDE_WINDOW = 0.25
"""A slider move this soon after the last (s of wall time) is part of a drag and glides; a lone move (a
click on the track) jumps at once."""


@dataclass
class Glide:
    """The body gliding from ``start`` to ``end`` (s of simulated time) over ``seconds`` of wall time from the
    monotonic time ``began``."""

    start: float
    end: float
    began: float
    seconds: float = GLIDE_SECONDS

    def at(self, now: float) -> tuple[float, bool]:
        """The instant to show at monotonic time ``now``, and whether the glide has arrived."""
        share = (now - self.began) / self.seconds
        if share >= 1.0:
            return self.end, True
        return self.start + max(share, 0.0) * (self.end - self.start), False


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
        self.glide: Glide | None = None
        self.now = time.monotonic
        """The wall clock glides are timed by (s, monotonic)."""
        self._dragged_at = -math.inf  # monotonic time of the slider's last move

    # ------------------------------------------------------------------ what it spans
    def earliest(self) -> float:
        """The earliest time the clock can be moved back to, s."""
        scene = self.sim.scene
        return 0.0 if scene is None else float(scene.earliest())

    def restart(self) -> None:
        """The clock went back to t = 0 (Reset, a new parameter or scene): a new timeline."""
        self.reached = 0.0
        self.glide, self._dragged_at = None, -math.inf
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
            self.glide = None
            sim.set_playing(False)
            sim.clock.steps = 0
            value = max(value, self.earliest())
            sim.clock.t = value
            scene.rewind(value)
            sim.request_redraw()
            return value

    def drag_to(self, t: float) -> float:
        """The slider dragged to time ``t`` (s): as :meth:`seek`, but within a drag (a move less than
        :data:`GLIDE_WINDOW` after the last) the body glides there, drawn at every frame of the loop, over
        the wall time since the last move (at least :data:`GLIDE_SECONDS`); returns the time it arrives at.
        ValueError as :meth:`seek`."""
        sim = self.sim
        now = self.now()
        with sim.lock:
            interval, self._dragged_at = now - self._dragged_at, now
            start = sim.time
            end = self.seek(t)
            if interval < GLIDE_WINDOW and end != start and sim.scene is not None and not sim.scene.static:
                # Over the time the page took to send this move since the last (a busy page sends them
                # further apart than 50 ms): the body moves on every frame until the next is due.
                self.glide = Glide(start, end, now, max(interval, GLIDE_SECONDS))
                self._show(start)
            return end

    def glide_frame(self) -> None:
        """Move a glide under way to this frame's instant (the simulation's frame calls it, holding its
        lock); a glide ends where the slider was dragged to, exactly."""
        glide = self.glide
        if glide is None:
            return
        if self.sim.playing or self.replay is not None:  # Play (or a replay) took over: the glide is over
            self.glide = None
            return
        t, arrived = glide.at(self.now())
        if arrived:
            self.glide = None
        self._show(t)

    def _show(self, t: float) -> None:
        """Put the (paused) body at time ``t``, drawn at the next frame."""
        sim = self.sim
        scene = sim.scene
        if scene is None:
            return
        sim.clock.t = t
        scene.rewind(t)
        sim.request_redraw()

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
