"""Driving a method: ``integrate`` (saved states, one body or a batch) and ``advance`` (one body, any state)."""

from __future__ import annotations

import math
from dataclasses import dataclass
from typing import Any

import numpy as np
from numpy.typing import ArrayLike, NDArray

from physics.integrators._base import _Method
from physics.integrators._state import _check_dt, _check_state, _from_state, _to_state

__all__ = ["advance", "Trajectory", "integrate"]


def advance(method: _Method, state: ArrayLike, dt: float, n_steps: int) -> NDArray[np.float64]:
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
        Number of steps (≥ 0).

    Returns
    -------
    ndarray, shape (12,)
    """
    if not isinstance(method, _Method):
        raise ValueError(f"method must be an integrator instance such as LiePoissonStrang(moments), got {method!r}")
    try:
        values = np.asarray(state, dtype=float)
    except (TypeError, ValueError):
        raise ValueError(f"state must be twelve numbers (R row-major, then L_body), got {state!r:.60}") from None
    if values.shape != (12,) or not np.all(np.isfinite(values)):
        raise ValueError(f"state must be twelve finite numbers (R row-major, then L_body), got shape {values.shape}")
    dt = _check_dt(dt)
    if int(n_steps) != n_steps or n_steps < 0:
        raise ValueError(f"n_steps must be a non-negative integer, got {n_steps}")
    kernel = compiled_step(method)
    if kernel is not None:
        rows = values.reshape(1, 12).copy()
        kernel.run(rows, dt, int(n_steps))
        return rows[0]
    s = tuple(float(x) for x in values)
    step = method._step
    for _ in range(int(n_steps)):
        s = step(s, dt, math)
    return np.array(s)


def compiled_step(method: _Method) -> Any:
    """The method's compiled step (:mod:`physics.integrators.compiled`), made on first use and kept on the
    instance; None when it runs interpreted (a Python torque, a triaxial exact free flow, ClassicalRK4)."""
    if "_kernel" not in vars(method):
        from physics.integrators.compiled import compile_method  # numba loads on first use only

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
    method: _Method, R0: ArrayLike, L0_body: ArrayLike, dt: float, n_steps: int, *, save_every: int = 1
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
        Number of steps (≥ 0).
    save_every : int, keyword-only
        Save the state every this many steps (the initial state is always saved, and the final one).

    Returns
    -------
    Trajectory
        ``t`` (k,), ``attitude`` (k, 3, 3) or (k, n, 3, 3), ``L_body`` (k, 3) or (k, n, 3).
    """
    if not isinstance(method, _Method):
        raise ValueError(f"method must be an integrator instance such as LiePoissonStrang(moments), got {method!r}")
    R, L, batched = _check_state(R0, L0_body)
    dt = _check_dt(dt)
    if int(n_steps) != n_steps or n_steps < 0:
        raise ValueError(f"n_steps must be a non-negative integer, got {n_steps}")
    if int(save_every) != save_every or save_every < 1:
        raise ValueError(f"save_every must be a positive integer, got {save_every}")
    n_steps, save_every = int(n_steps), int(save_every)
    kernel = compiled_step(method)
    if kernel is not None:
        # Compiled: the whole batch (or the one body) as rows of 12, stepped in place between saves.
        s0 = method._project(_to_state(R, L))
        rows = np.array(s0, dtype=float).T.reshape(-1, 12) if batched else np.array([s0], dtype=float)
        saved, steps = [rows.copy()], [0]
        done = 0
        while done < n_steps:
            chunk = min(save_every, n_steps - done)
            kernel.run(rows, dt, chunk)
            done += chunk
            saved.append(rows.copy())
            steps.append(done)
        t = np.asarray(steps, dtype=float) * dt
        arr = np.stack(saved)  # (k, n, 12)
        if not batched:
            arr = arr[:, 0]
        return Trajectory(t=t, attitude=arr[..., :9].reshape(arr.shape[:-1] + (3, 3)), L_body=arr[..., 9:].copy())
    xp = np if batched else math
    s = method._project(_to_state(R, L))
    states = [s]
    steps = [0]
    step = method._step
    done = 0
    while done < n_steps:
        chunk = min(save_every, n_steps - done)
        for _ in range(chunk):
            s = step(s, dt, xp)
        done += chunk
        states.append(s)
        steps.append(done)
    t = np.asarray(steps, dtype=float) * dt
    if batched:
        Rs, Ls = zip(*(_from_state(x, True) for x in states))
        return Trajectory(t=t, attitude=np.stack(Rs), L_body=np.stack(Ls))
    arr = np.array(states, dtype=float)
    return Trajectory(t=t, attitude=arr[:, :9].reshape(-1, 3, 3), L_body=arr[:, 9:].copy())
