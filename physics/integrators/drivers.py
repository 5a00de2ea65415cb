"""Driving a method: ``integrate`` (saved states, one body or a batch) and ``advance`` (one body, any state)."""

from __future__ import annotations

import math
from dataclasses import dataclass
from typing import Any

import numpy as np
from numpy.typing import ArrayLike, NDArray

from physics.integrators._base import _Method
from physics.integrators._state import _check_dt, _check_state, _from_state, _to_state
from physics.validation import MAX_STEPS

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
        Number of steps, 0 to :data:`physics.validation.MAX_STEPS`.

    Returns
    -------
    ndarray, shape (12,)
    """
    if not isinstance(method, _Method):
        raise ValueError(f"method must be an integrator instance such as LiePoissonStrang(moments), got {method!r}")
    try:
        values = np.asarray(state, dtype=float)
    except (TypeError, ValueError, OverflowError):
        raise ValueError(f"state must be twelve numbers (R row-major, then L_body), got {state!r:.60}") from None
    if values.shape != (12,) or not np.all(np.isfinite(values)):
        raise ValueError(f"state must be twelve finite numbers (R row-major, then L_body), got shape {values.shape}")
    dt = _check_dt(dt)
    n_steps = _count(n_steps, "n_steps", 0)
    _refuse_unstable(method, values[9:], dt, "state[9:]")
    kernel = compiled_step(method)
    if kernel is not None:
        rows = values.reshape(1, 12).copy()
        for done, chunk in _chunks(n_steps, n_steps):
            kernel.run(rows, dt, chunk)
            _check_finite(rows, method, dt, done, chunk)
        return rows[0]
    s = tuple(float(x) for x in values)
    step = method._step
    for done, chunk in _chunks(n_steps, n_steps):
        s = _interpreted(step, s, dt, math, chunk, method, done)
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


def _refuse_unstable(method: _Method, L: NDArray[np.float64], dt: float, name: str) -> None:
    """Refuse up front a step beyond the method's stability (its ``max_rate_step``, if it states one) and an
    angular momentum whose rate of change ``L × ω`` is beyond the float range.

    The rate is the largest ``|ω|`` of the torque-free motion from ``L``, ``sqrt(2E / I_min)``
    (``|ω|² ≤ Σ (I_i / I_min) ω_i²``), taken over the batch; a torque may speed the body up later, which the
    check after each chunk catches (:func:`_check_finite`).
    """
    limit = getattr(method, "max_rate_step", None)
    if limit is None:
        return
    inv = np.asarray(method._inv, dtype=float)
    big, top = float(np.max(np.abs(L), initial=0.0)), float(np.max(inv))
    if big == 0.0:
        return
    # sqrt(Σ L_i² / I_i · max 1/I) with L and 1/I scaled to 1 first: no overflow or underflow on the way.
    with np.errstate(over="ignore"):
        rate = big * top * math.sqrt(float(np.max(np.sum((L / big) ** 2 * (inv / top), axis=-1))))
    if math.isfinite(rate) and rate * abs(dt) > limit:
        raise ValueError(
            f"dt = {dt:g} s is too large for {method.name} with the initial momentum {name} = "
            f"{np.asarray(L).tolist()!s:.80}: the body turns at up to |ω| = {rate:.4g} rad/s (sqrt(2E/I_min)), and "
            f"|ω|·|dt| = {rate * abs(dt):.3g} is beyond {limit:g}, the method's stability limit (RK4 diverges beyond "
            f"2√2 ≈ 2.83 on the imaginary axis); take |dt| ≤ {limit / rate:.3g} s"
        )
    if not math.isfinite(rate) or big * rate > 1e306:
        raise ValueError(
            f"{name} = {np.asarray(L).tolist()!s:.80} is too large for these moments {method.moments.tolist()}: "
            f"the body turns at up to |ω| = {rate:.3g} rad/s and L × ω overflows the float range; the motion "
            "is the same with the moments and L scaled down together"
        )


def _diverged(method: _Method, dt: float, done: int, chunk: int) -> ValueError:
    return ValueError(
        f"the integration diverged: {method.name} with dt = {dt:g} s reached a state that is not finite "
        f"between step {done} and step {done + chunk} (finite at step {done}); take a smaller dt"
    )


CHECK_EVERY = 1000
"""Steps between two checks that the saved states are finite (at least; and at the end): often enough to
stop a diverged run early, rarely enough that the check costs nothing per step, even saving every step."""


def _check_finite(rows: NDArray[np.float64], method: _Method, dt: float, done: int, chunk: int) -> None:
    """After a chunk (not each step: the compiled loop stays as fast): no NaN or inf in the state."""
    if not np.all(np.isfinite(rows)):
        raise _diverged(method, dt, done, chunk)


def _check_saved(saved: list[Any], steps: list[int], first: int, method: _Method, dt: float, offset: int = 0) -> None:
    """The saved states from ``saved[first]`` on (``steps[offset + k]`` for ``saved[k]``) are finite; else
    name the chunk where the first one that is not was reached."""
    finite = np.isfinite(np.stack(saved[first:])).reshape(len(saved) - first, -1).all(axis=1)
    if not np.all(finite):
        k = first + offset + int(np.argmin(finite))
        raise _diverged(method, dt, steps[k - 1], steps[k] - steps[k - 1])


def _interpreted(
    step: Any, s: Any, dt: float, xp: Any, chunk: int, method: _Method, done: int, check: bool = True
) -> Any:
    """``chunk`` interpreted steps; an overflow on the way (math's domain errors, numpy's warnings) is the
    divergence the check after the chunk (``check``, or the caller's) reports."""
    try:
        with np.errstate(all="ignore"):
            for _ in range(chunk):
                s = step(s, dt, xp)
    except (ValueError, OverflowError, ZeroDivisionError):
        raise _diverged(method, dt, done, chunk) from None
    if check:
        _check_finite(np.asarray(s, dtype=float), method, dt, done, chunk)
    return s


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
        Number of steps, 0 to :data:`physics.validation.MAX_STEPS`.
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
    n_steps = _count(n_steps, "n_steps", 0)
    save_every = _count(save_every, "save_every", 1)
    _refuse_unstable(method, L, dt, "L0_body")
    kernel = compiled_step(method)
    if kernel is not None:
        # Compiled: the whole batch (or the one body) as rows of 12, stepped in place between saves.
        s0 = method._project(_to_state(R, L))
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
    s = method._project(_to_state(R, L))
    states = [s]
    steps = [0]
    step = method._step
    checked = 1
    for done, chunk in _chunks(n_steps, save_every):
        s = _interpreted(step, s, dt, xp, chunk, method, done, check=False)
        states.append(s)
        steps.append(done + chunk)
        if steps[-1] - steps[checked - 1] >= CHECK_EVERY or steps[-1] == n_steps:
            _check_saved([np.asarray(x, dtype=float) for x in states[checked:]], steps, 0, method, dt, checked)
            checked = len(states)
    t = np.asarray(steps, dtype=float) * dt
    if batched:
        Rs, Ls = zip(*(_from_state(x, True) for x in states))
        return Trajectory(t=t, attitude=np.stack(Rs), L_body=np.stack(Ls))
    arr = np.array(states, dtype=float)
    return Trajectory(t=t, attitude=arr[:, :9].reshape(-1, 3, 3), L_body=arr[:, 9:].copy())
