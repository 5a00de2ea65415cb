"""A bounded, deterministic history of a motion advanced step by step (the friction top, an integrator's
ghost, the drag): any instant of the last few minutes can be shown again, bit for bit.

A stepped motion has no closed form to evaluate at an earlier time, and keeping every state of minutes at
60 steps a second costs memory without bound. :class:`SteppedHistory` keeps one checkpoint every
``checkpoint_every`` steps in a ring of fixed size (allocated once: :attr:`SteppedHistory.nbytes` does not
grow) and recomputes the states between two checkpoints with the same step, which is a deterministic
function of the state: the state at a grid time is the same float64 bits whether it was reached playing
forward, after seeking back, or recomputed from a checkpoint. A seek costs at most ``checkpoint_every − 1``
steps.

Times live on the grid ``t_k = t0 + k dt``. A time before the oldest checkpoint kept (more than the
kept span ago) is refused with a ValueError rather than recomputed from the start: that could take
minutes of CPU for an hour-long run, and a scrubber can show the span it can reach
(:attr:`SteppedHistory.earliest`). A time ahead of the furthest state computed is reached by stepping on,
up to one kept span ahead per call.
"""

from __future__ import annotations

import math
from collections.abc import Callable

import numpy as np
from numpy.typing import ArrayLike, NDArray

from physics.integrators import Method, advance
from physics.validation import MAX_STEPS, finite_array, finite_scalar

Floats = NDArray[np.float64]
Step = Callable[[Floats], ArrayLike]
"""One step of the grid: the state after ``dt`` from a state (a 1-D float64 array), a deterministic
function of it alone (no clock, no randomness, no hidden state that changes between calls)."""

__all__ = ["GRID_SLACK", "Step", "SteppedHistory", "stepper_step"]

GRID_SLACK = 1e-6
"""A time within this fraction of a step before a grid time counts as that grid time (a slider's value
``k dt`` rounded to a decimal string and back must reach step k, not k − 1)."""


def stepper_step(method: Method, dt: float, substeps: int = 1) -> Step:
    """One grid step of ``dt`` seconds as ``substeps`` steps of ``dt / substeps`` of an integrator
    (:func:`physics.integrators.advance`), for the state ``(R row-major, L_body)``, shape (12,): what the
    friction top (:func:`physics.heavy_top.friction_stepper`) or an integrator's ghost steps.

    Parameters
    ----------
    method : physics.integrators.Method
        The integrator instance, torques included.
    dt : float
        The grid step, s (> 0).
    substeps : int
        Integrator steps per grid step (≥ 1).
    """
    h = _positive(dt, "dt")
    n = _whole(substeps, "substeps", 1)
    sub = h / n

    def step(state: Floats) -> Floats:
        return advance(method, state, sub, n)

    return step


def _whole(value: int, name: str, minimum: int) -> int:
    """A whole number of steps from ``minimum`` to ``MAX_STEPS``, else a ValueError naming it."""
    if isinstance(value, bool) or not isinstance(value, (int, np.integer)) or not minimum <= value <= MAX_STEPS:
        raise ValueError(f"{name} must be a whole number from {minimum} to {MAX_STEPS:,}, got {value!r:.60}")
    return int(value)


def _positive(value: float, name: str) -> float:
    v = finite_scalar(value, name)
    if v <= 0.0:
        raise ValueError(f"{name} must be a positive time in seconds, got {v!r}")
    return v


class SteppedHistory:
    """The states of a stepped motion on the grid ``t0 + k dt``, any of the last ``keep`` seconds on demand.

    Parameters
    ----------
    step : callable
        ``step(state) -> state``: one grid step (see :data:`Step`, :func:`stepper_step`). Must be
        deterministic: the history's promise (the same bits going back then forward) is only as good as it.
    state0 : array_like, shape (n,)
        The state at ``t0``.
    dt : float
        The grid step, s (> 0), e.g. 1/60 for a frame at 60 Hz.
    t0 : float
        The time of ``state0``, s.
    keep : float
        How far back a seek may go, s (> 0): the ring holds ``ceil(keep / (checkpoint_every dt)) + 1``
        checkpoints, so at least ``keep`` seconds behind the furthest state computed are kept.
    checkpoint_every : int
        Steps between checkpoints (≥ 1): a seek recomputes at most this many minus one steps; memory is
        ``state bytes × keep / (checkpoint_every dt)``.

    Attributes
    ----------
    dt, t0 : float
        The grid, s.
    checkpoint_every, capacity : int
        Steps between checkpoints; checkpoints the ring holds.

    Raises
    ------
    ValueError
        A non-finite or non-positive ``dt`` or ``keep``, a non-finite ``t0`` or ``state0``, a state that
        is not 1-D, a ``checkpoint_every`` that is not a whole number from 1 to ``MAX_STEPS``, or a ring
        of more than 100 million entries.
    """

    def __init__(
        self,
        step: Step,
        state0: ArrayLike,
        dt: float,
        *,
        t0: float = 0.0,
        keep: float = 300.0,
        checkpoint_every: int = 60,
    ) -> None:
        self.dt = _positive(dt, "dt")
        self.t0 = finite_scalar(t0, "t0")
        span = _positive(keep, "keep")
        self.checkpoint_every = _whole(checkpoint_every, "checkpoint_every", 1)
        state = finite_array(state0, "state0").copy()
        if state.ndim != 1 or state.size == 0:
            raise ValueError(f"state0 must be a 1-D array of numbers (one state), got shape {state.shape}")
        capacity = math.ceil(span / (self.checkpoint_every * self.dt)) + 1
        if capacity * state.size > 100_000_000:
            raise ValueError(
                f"keeping {span:g} s at a checkpoint every {self.checkpoint_every} steps of {self.dt:g} s needs "
                f"{capacity:,} checkpoints of {state.size} numbers: keep less or checkpoint less often"
            )
        self.capacity = capacity
        self._steps: list[tuple[int, Step]] = [(0, step)]  # (first step index, the step from there on)
        self._ring = np.empty((capacity, state.size))
        self._ring[0] = state
        self._newest = 0  # index j of the newest checkpoint (at step j · checkpoint_every)
        self._frontier, self._frontier_state = 0, state.copy()
        self._k, self._state = 0, state.copy()

    # --- what is kept ---------------------------------------------------------------------------------
    @property
    def nbytes(self) -> int:
        """Bytes of the states held: the ring of checkpoints (fixed when made) and the two current states."""
        return int(self._ring.nbytes + self._state.nbytes + self._frontier_state.nbytes)

    @property
    def time(self) -> float:
        """The time of the current state, s."""
        return self.t0 + self._k * self.dt

    @property
    def state(self) -> Floats:
        """A copy of the current state, shape (n,)."""
        return self._state.copy()

    @property
    def latest(self) -> float:
        """The furthest time computed so far, s."""
        return self.t0 + self._frontier * self.dt

    @property
    def earliest(self) -> float:
        """The earliest time a seek can reach, s (the oldest checkpoint kept)."""
        return self.t0 + self._oldest() * self.checkpoint_every * self.dt

    def _oldest(self) -> int:
        return max(0, self._newest - self.capacity + 1)

    # --- moving -----------------------------------------------------------------------------------------
    def step_forward(self, n: int = 1) -> Floats:
        """Advance the current state by ``n`` grid steps (a frame of play) and return a copy of it, shape (n,).

        Behind the furthest state computed this recomputes the same states; at it, it computes new ones
        (and checkpoints them)."""
        self._k, self._state = self._walk(self._k, self._state, self._k + _whole(n, "n", 0))
        return self._state.copy()

    def seek(self, t: float) -> Floats:
        """Make the state at time ``t`` (s) the current one and return a copy of it, shape (n,).

        ``t`` is taken to the grid time at or before it (:data:`GRID_SLACK`); see :meth:`state_at`."""
        self._k, self._state = self._reach(self._index(t))
        return self._state.copy()

    def state_at(self, t: float) -> Floats:
        """The state at time ``t`` (s), shape (n,), without moving the current state: the state at the grid
        time ``t0 + k dt`` at or before ``t``.

        Raises
        ------
        ValueError
            ``t`` not a finite number; before ``t0``; before :attr:`earliest` (older than the kept span:
            the message says which span is kept); more than one kept span beyond :attr:`latest`.
        """
        return self._reach(self._index(t))[1].copy()

    def truncate(self) -> None:
        """Forget every state after the current one: call it when what the step does changes at this instant
        (a new friction, a blow), so that the states after now, computed with the old step, are not shown."""
        self._frontier, self._frontier_state = self._k, self._state.copy()
        self._newest = self._k // self.checkpoint_every

    def replace_step(self, step: Step) -> None:
        """Step on from the current state with ``step`` from now on (forgetting the states after now,
        :meth:`truncate`); the states before now stay as they were computed, recomputed with the step they
        were computed with."""
        self.truncate()
        oldest = self._oldest() * self.checkpoint_every
        # Drop the steps that began after now, and those no kept state can reach any more.
        kept = [(k, s) for k, s in self._steps if k < self._k]
        while len(kept) > 1 and kept[1][0] <= oldest:
            kept.pop(0)
        self._steps = [*kept, (self._k, step)]

    # --- inside -----------------------------------------------------------------------------------------
    def _index(self, t: float) -> int:
        tf = finite_scalar(t, "t")
        x = (tf - self.t0) / self.dt
        if x < -GRID_SLACK:
            raise ValueError(f"t = {tf!r} s is before the start of this motion, t0 = {self.t0!r} s")
        k = max(0, math.floor(x + GRID_SLACK))
        oldest = self._oldest() * self.checkpoint_every
        if k < oldest:
            raise ValueError(
                f"t = {tf!r} s is older than the history keeps: it reaches back to {self.earliest!r} s "
                f"(the last {(self._frontier - oldest) * self.dt:g} s up to {self.latest!r} s)"
            )
        ahead = self.capacity * self.checkpoint_every
        if k - self._frontier > ahead:
            raise ValueError(
                f"t = {tf!r} s is more than {ahead * self.dt:g} s beyond the furthest state computed "
                f"({self.latest!r} s): step on in shorter stretches"
            )
        return k

    def _reach(self, k: int) -> tuple[int, Floats]:
        """(k, state at step k) from the latest known state at or before it: the furthest computed, else the
        checkpoint before k, or the current state if it lies between that checkpoint and k."""
        start, state = self._frontier, self._frontier_state
        if k < start:
            j = k // self.checkpoint_every
            start, state = j * self.checkpoint_every, self._ring[j % self.capacity]
        if start < self._k <= k:
            start, state = self._k, self._state
        return k, self._walk(start, state, k)[1]

    def _walk(self, k: int, state: Floats, target: int) -> tuple[int, Floats]:
        """Step from ``state`` at step k to step ``target``, checkpointing new states beyond the frontier."""
        state = state.copy()
        every = self.checkpoint_every
        steps = self._steps
        while k < target:
            i = len(steps) - 1
            while steps[i][0] > k:  # the step in force at k (a handful of segments at most)
                i -= 1
            nxt = np.asarray(steps[i][1](state), dtype=float)
            if nxt.shape != state.shape or not np.all(np.isfinite(nxt)):
                raise ValueError(
                    f"the step from t = {self.t0 + k * self.dt!r} s gave a state of shape {nxt.shape} with "
                    f"non-finite entries or another shape than {state.shape}: the motion cannot go on"
                )
            state = nxt.copy() if nxt is state else nxt
            k += 1
            if k > self._frontier:
                self._frontier, self._frontier_state = k, state.copy()
                if k % every == 0:
                    self._newest = k // every
                    self._ring[self._newest % self.capacity] = state
        return k, state
