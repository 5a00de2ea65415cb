"""Driving a method: ``integrate`` (saved states, one body or a batch) and ``advance`` (one body, any state)."""

from __future__ import annotations

import math
from dataclasses import dataclass
from typing import Any

import numpy as np
from numpy.typing import ArrayLike, NDArray

from physics.integrators._base import CHECK_EVERY, Method, check_finite, diverged, interpreted, refuse_unstable
from physics.integrators._state import check_dt, check_state, from_state, to_state
from physics.integrators.compiled import compile_method
from physics.validation import MAX_STEPS

__all__ = ["advance", "Trajectory", "integrate"]


def advance(method: Method, state: ArrayLike, dt: float, n_steps: int) -> NDArray[np.float64]:
    """Take ``n_steps`` steps of ``dt`` from one body's state, without requiring ``R`` to be a rotation.

    For stepping a motion frame by frame (the app's integrator "ghost"), and for :class:`ClassicalRK4`,
    whose ``R`` leaves SO(3) as it goes: the state is carried as it is, never projected.

    Parameters
    ----------
    method : a method instance
    state : array_like, shape (12,)
        ``R`` row-major (nine entries), then ``L_body`` (kg m²/s).
    dt : float
        Step, s.
    n_steps : int
        Number of steps, 0 to :data:`physics.validation.MAX_STEPS`.

    Returns
    -------
    ndarray, shape (12,)
    """
    if not isinstance(method, Method):
        raise ValueError(f"method must be an integrator instance such as LiePoissonStrang(moments), got {method!r}")
    try:
        values = np.asarray(state, dtype=float)
    except (TypeError, ValueError, OverflowError):
        raise ValueError(f"state must be twelve numbers (R row-major, then L_body), got {state!r:.60}") from None
    if values.shape != (12,) or not np.all(np.isfinite(values)):
        raise ValueError(f"state must be twelve finite numbers (R row-major, then L_body), got shape {values.shape}")
    dt = check_dt(dt)
    n_steps = _count(n_steps, "n_steps", 0)
    refuse_unstable(method, values[9:], dt, "state[9:]")
    kernel = compiled_step(method)
    if kernel is not None:
        rows = values.reshape(1, 12).copy()
        for done, chunk in _chunks(n_steps, n_steps):
            kernel.run(rows, dt, chunk)
            check_finite(rows, method, dt, done, chunk)
        return rows[0]
    s = tuple(float(x) for x in values)
    step = method.step_state
    for done, chunk in _chunks(n_steps, n_steps):
        s = interpreted(step, s, dt, math, chunk, method, done)
    return np.array(s)


def _count(value: Any, name: str, minimum: int) -> int:
    """A whole number of steps from ``minimum`` to :data:`MAX_STEPS` (an int, or a float or 0-d array with an
    integral value)."""
    try:
        arr = np.asarray(value)
    except Exception:  # noqa: BLE001 - anything numpy cannot hold is not a count
        arr = np.asarray(None, dtype=object)
    ok = not isinstance(value, (bool, np.bool_)) and arr.ndim == 0 and arr.dtype.kind in "iuf"
    number = float(arr) if ok else math.nan
    if not (ok and math.isfinite(number) and number == math.floor(number) and minimum <= number <= MAX_STEPS):
        words = "a non-negative" if minimum == 0 else "a positive"
        raise ValueError(
            f"{name} must be {words} integer (a whole number from {minimum} to {MAX_STEPS:,}), got {value!r:.60}"
        )
    return int(arr)


def _chunks(n_steps: int, size: int) -> Any:
    """``(steps done before, steps in this chunk)`` for chunks of ``size`` steps that make ``n_steps``."""
    return ((done, min(size, n_steps - done)) for done in range(0, n_steps, max(size, 1)))


def _check_saved(saved: list[Any], steps: list[int], first: int, method: Method, dt: float, offset: int = 0) -> None:
    """The saved states from ``saved[first]`` on (``steps[offset + k]`` for ``saved[k]``) are finite; else
    name the chunk where the first one that is not was reached."""
    finite = np.isfinite(np.stack(saved[first:])).reshape(len(saved) - first, -1).all(axis=1)
    if not np.all(finite):
        k = first + offset + int(np.argmin(finite))
        raise diverged(method, dt, steps[k - 1], steps[k] - steps[k - 1])


def compiled_step(method: Method) -> Any:
    """The method's compiled step (:mod:`physics.integrators.compiled`), made on first use and kept on the
    instance; None when it runs interpreted (a Python torque, a triaxial exact free flow, ClassicalRK4)."""
    if "_kernel" not in vars(method):
        method._kernel = compile_method(method)  # type: ignore[attr-defined]
    return vars(method)["_kernel"]


@dataclass(frozen=True)
class Trajectory:
    """Sampled motion.

    Attributes
    ----------
    t : ndarray, shape (k,)
        Times, s.
    attitude : ndarray, shape (k, 3, 3) (or (k, n, 3, 3) for a batch)
        Body-to-space rotations.
    L_body : ndarray, shape (k, 3) (or (k, n, 3))
        Body-frame angular momenta, kg m²/s.
    """

    t: NDArray[np.float64]
    attitude: NDArray[np.float64]
    L_body: NDArray[np.float64]


def integrate(
    method: Method, R0: ArrayLike, L0_body: ArrayLike, dt: float, n_steps: int, *, save_every: int = 1
) -> Trajectory:
    """Take ``n_steps`` steps of ``dt`` from ``(R0, L0_body)``, saving every ``save_every`` steps.

    Parameters
    ----------
    method : a method instance (:class:`LiePoissonStrang`, :class:`Yoshida4`, ...)
    R0 : array_like, shape (3, 3) or (n, 3, 3)
        Initial attitude(s), body to space.
    L0_body : array_like, shape (3,) or (n, 3)
        Initial body-frame angular momentum, kg m²/s.
    dt : float
        Step, s.
    n_steps : int
        Number of steps, 0 to :data:`physics.validation.MAX_STEPS`.
    save_every : int, keyword-only
        Save the state every this many steps (the initial state is always saved, and the final one).

    Returns
    -------
    Trajectory
        ``t`` (k,), ``attitude`` (k, 3, 3) or (k, n, 3, 3), ``L_body`` (k, 3) or (k, n, 3).
    """
    if not isinstance(method, Method):
        raise ValueError(f"method must be an integrator instance such as LiePoissonStrang(moments), got {method!r}")
    R, L, batched = check_state(R0, L0_body)
    dt = check_dt(dt)
    n_steps = _count(n_steps, "n_steps", 0)
    save_every = _count(save_every, "save_every", 1)
    refuse_unstable(method, L, dt, "L0_body")
    kernel = compiled_step(method)
    if kernel is not None:
        # Compiled: the whole batch (or the one body) as rows of 12, stepped in place between saves.
        s0 = method.project(to_state(R, L))
        rows = np.array(s0, dtype=float).T.reshape(-1, 12) if batched else np.array([s0], dtype=float)
        saved, steps = [rows.copy()], [0]
        checked = 1
        for done, chunk in _chunks(n_steps, save_every):
            kernel.run(rows, dt, chunk)
            saved.append(rows.copy())
            steps.append(done + chunk)
            if steps[-1] - steps[checked - 1] >= CHECK_EVERY or steps[-1] == n_steps:
                _check_saved(saved, steps, checked, method, dt)
                checked = len(saved)
        t = np.asarray(steps, dtype=float) * dt
        arr = np.stack(saved)  # (k, n, 12)
        if not batched:
            arr = arr[:, 0]
        return Trajectory(t=t, attitude=arr[..., :9].reshape(arr.shape[:-1] + (3, 3)), L_body=arr[..., 9:].copy())
    xp = np if batched else math
    s = method.project(to_state(R, L))
    states = [s]
    steps = [0]
    step = method.step_state
    checked = 1
    for done, chunk in _chunks(n_steps, save_every):
        s = interpreted(step, s, dt, xp, chunk, method, done, check=False)
        states.append(s)
        steps.append(done + chunk)
        if steps[-1] - steps[checked - 1] >= CHECK_EVERY or steps[-1] == n_steps:
            _check_saved([np.asarray(x, dtype=float) for x in states[checked:]], steps, 0, method, dt, checked)
            checked = len(states)
    t = np.asarray(steps, dtype=float) * dt
    if batched:
        Rs, Ls = zip(*(from_state(x, True) for x in states))
        return Trajectory(t=t, attitude=np.stack(Rs), L_body=np.stack(Ls))
    arr = np.array(states, dtype=float)
    return Trajectory(t=t, attitude=arr[:, :9].reshape(-1, 3, 3), L_body=arr[:, 9:].copy())
