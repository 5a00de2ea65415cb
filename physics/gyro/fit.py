"""The torque-free body with air drag fitted to measured angular velocity: :func:`fit_free_body`.

Unknowns: the principal moments' ratios (largest 1: the scale cannot be seen in ω), a small rotation between
the phone's axes and the principal axes (kept when the data ask for it: larger than three standard
deviations), one drag coefficient (:mod:`physics.gyro.model`), all shared by the tosses of one object, and
each toss's initial ω. The moments are parametrised as a rigid body's always are (each at most the sum of
the other two): the intermediate ``I_b ∈ [½, 1]`` and the excess ``e = I_b + I_c − 1 ≥ 0`` (zero for a flat
plate, so ``e`` measures the phone's thickness). Least squares (scipy's trust-region reflective) with
finite-difference Jacobians; several tosses share their columns sparsely. Uncertainties are the Jacobian's
``s² (JᵀJ)⁻¹``: they assume independent noise and so understate what model error (residuals correlated in
time) leaves.
"""

from __future__ import annotations

import math
from collections.abc import Sequence
from dataclasses import dataclass

import numpy as np
from numpy.typing import ArrayLike, NDArray
from scipy.optimize import least_squares
from scipy.sparse import lil_matrix

from physics.free_body import FreeBody
from physics.gyro.model import DragLaw, euler_ratios, model_omega, rotation_from_vector
from physics.gyro.recording import Segment
from physics.integrators import BlanesMoan6, SpinFriction, advance

Floats = NDArray[np.float64]

MIN_DURATION = 0.2
"""s: a shorter segment holds too little of the motion to fit."""
MIN_SPIN = 3.0
"""rad/s: a segment whose median |ω| is lower turns too little in its time to show its moments."""
MAX_CLIPPED = 0.5
"""Largest share of a segment's samples with a clipped component that is still fitted."""
PREDICT_STEP = 1e-3
"""s: the largest step of the integrator that ``predict`` steps a drag with."""
MAX_DRAG = 20.0
"""1/s: the largest drag coefficient ``c_i / I_max`` fitted (real phones: below 1)."""
MAX_TILT = 0.2
"""rad: the largest misalignment fitted along each axis (a phone's principal axes are near its own)."""
CONTINUATION = (0.3, 0.6, 1.0)
"""Shares of a toss fitted in turn to reach its start (:func:`_continued`)."""
AXES = "xyz"

__all__ = ["FreeBodyFit", "HalfTurns", "fit_free_body", "check_segment"]


@dataclass(frozen=True)
class HalfTurns:
    """Times (s) at which ω's component along the intermediate principal axis changes sign: each is half a
    turn of the flip (the phone has turned over). ``predicted`` by the fitted model, ``measured`` from the
    samples (linear interpolation between the two samples of opposite sign)."""

    predicted: Floats
    measured: Floats


@dataclass(frozen=True)
class FreeBodyFit:
    """A fitted free body (made by :func:`fit_free_body`).

    Attributes
    ----------
    moments : ndarray (3,)
        Principal moments along the phone's x, y, z (each the moment about the principal axis nearest it),
        largest 1.
    moments_sigma : ndarray (3,)
        Their standard deviations (0 for the largest, which is fixed).
    axes : str
        The phone axes from the largest moment to the smallest, e.g. ``"zxy"``.
    rotation : ndarray (3, 3)
        The principal axes as columns in the phone's axes (identity when no misalignment is fitted).
    misalignment, misalignment_sigma : float
        The angle of ``rotation``, rad, and its standard deviation (0 when not fitted).
    drag_law : {"linear", "none"}
    drag, drag_sigma : ndarray (3,)
        The drag coefficient about the principal axis nearest each phone axis, ``c_i / I_max`` in 1/s
        (torque ``−c_i ω_i``), and their standard deviations.
    omega0 : ndarray (k, 3)
        ω at each segment's first sample in the phone's axes, rad/s.
    segments : tuple of Segment
    residual : float
        RMS of measured − model over every unclipped component of every segment, rad/s.
    residuals : ndarray (k,)
        The same per segment, rad/s.
    relative_residuals : ndarray (k,)
        ``residuals`` over each segment's RMS |ω|.
    """

    moments: Floats
    moments_sigma: Floats
    axes: str
    rotation: Floats
    misalignment: float
    misalignment_sigma: float
    drag_law: DragLaw
    drag: Floats
    drag_sigma: Floats
    omega0: Floats
    segments: tuple[Segment, ...]
    residual: float
    residuals: Floats
    relative_residuals: Floats

    def _body_start(self, toss: int) -> Floats:
        return np.asarray(self.rotation.T @ self.omega0[toss], dtype=float)

    def predict(self, times: ArrayLike, toss: int = 0) -> Floats:
        """ω (n, 3) in the phone's axes, rad/s, of toss ``toss`` at ``times`` (n,) s in the recording's time.

        Without drag the exact solution (:class:`physics.free_body.FreeBody`, at the round-off floor); with
        drag the project's compiled integrators (:class:`physics.integrators.BlanesMoan6`, order 6, with the
        drag as three :class:`~physics.integrators.SpinFriction` flows) at steps of at most 1 ms.
        """
        if not 0 <= toss < len(self.segments):
            raise ValueError(f"toss must be 0 to {len(self.segments) - 1}, got {toss}")
        t = np.atleast_1d(np.asarray(times, dtype=float)) - self.segments[toss].start
        if t.ndim != 1 or not np.all(np.isfinite(t)) or np.max(np.abs(t), initial=0.0) > 1e4:
            raise ValueError("times must be a 1-d array of finite times in s, within 1e4 s of the toss")
        u0 = self._body_start(toss)
        if not np.any(self.drag > 0.0):
            body = FreeBody(self.moments).omega(u0, t)
        else:
            body = np.empty((t.shape[0], 3))
            for part in (np.nonzero(t >= 0.0)[0], np.nonzero(t < 0.0)[0][::-1]):
                body[part] = _stepped(self.moments, self.drag, u0, t[part])
        return np.asarray(body @ self.rotation.T, dtype=float)

    def momentum_loss(self, toss: int = 0) -> float:
        """The share of |L| the drag took over toss ``toss``."""
        seg = self.segments[toss]
        w = self.rotation.T @ self.predict([seg.start, seg.end], toss).T
        big_l = np.linalg.norm(self.moments[:, None] * w, axis=0)
        return float(1.0 - big_l[1] / big_l[0])

    @property
    def half_turn_times(self) -> list[HalfTurns]:
        """Per segment, the predicted and the measured half turns of the flip (:class:`HalfTurns`)."""
        axis = self.rotation[:, AXES.index(self.axes[1])]
        out = []
        for k, seg in enumerate(self.segments):
            fine = np.linspace(seg.start, seg.end, 5 * len(seg.times))
            out.append(
                HalfTurns(_crossings(fine, self.predict(fine, k) @ axis), _crossings(seg.times, seg.omega @ axis))
            )
        return out


def _stepped(moments: Floats, drag: Floats, omega0: Floats, t: Floats) -> Floats:
    """ω (n, 3) in principal axes at times t (n,) from 0, all of one sign, by the compiled integrator."""
    torques = [SpinFriction(float(drag[i]), moments, np.eye(3)[i]) for i in range(3) if drag[i] > 0.0]
    method = BlanesMoan6(moments, torques)
    state = np.concatenate([np.eye(3).ravel(), moments * omega0])
    out, now = np.empty((t.shape[0], 3)), 0.0
    for k, target in enumerate(t):
        n = int(np.ceil(abs(target - now) / PREDICT_STEP))
        if n:
            state = advance(method, state, (target - now) / n, n)
        now = float(target)
        out[k] = state[9:] / moments
    return out


def _crossings(times: Floats, values: Floats) -> Floats:
    change = np.nonzero(np.sign(values[:-1]) * np.sign(values[1:]) < 0.0)[0]
    t0, t1, v0, v1 = times[change], times[change + 1], values[change], values[change + 1]
    return np.asarray(t0 + (t1 - t0) * v0 / (v0 - v1), dtype=float)


def check_segment(segment: Segment, name: str = "the segment") -> None:
    """Refuse a segment that cannot be fitted, saying why (ValueError)."""
    if not isinstance(segment, Segment):
        raise ValueError(
            f"{name} must be a physics.gyro.Segment (e.g. from free_flights), got {type(segment).__name__}"
        )
    if segment.duration < MIN_DURATION:
        raise ValueError(
            f"{name} lasts {segment.duration:.3f} s; at least {MIN_DURATION} s of free flight are needed to fit"
        )
    share = float(np.mean(np.any(segment.clipped, axis=1)))
    if share > MAX_CLIPPED:
        raise ValueError(
            f"{name} is mostly clipped: {share:.0%} of its samples reach the gyroscope's limit "
            f"({segment.clip_rate:g} rad/s); at most {MAX_CLIPPED:.0%} can be fitted"
        )
    spin = float(np.median(np.linalg.norm(segment.omega, axis=1)))
    if spin < MIN_SPIN:
        raise ValueError(
            f"{name} spins too slowly to fit: its median |ω| is {spin:.2g} rad/s, at least {MIN_SPIN:g} is needed"
        )


class _Problem:
    """The fit's parameter vector: ``[I_b, e, (θ × 3), (c × 3)]`` then 3 per segment (initial ω, principal axes).

    ``I_b`` is the larger of the two moments that are not the largest (so ``I_b ≥ ½`` for any rigid body),
    ``I_c = 1 − I_b + e``."""

    def __init__(self, segments: tuple[Segment, ...], moments: Floats, law: DragLaw, tilt: bool) -> None:
        self.segments, self.law, self.tilt = segments, law, tilt
        order = np.argsort(-moments, kind="stable")
        self.big, self.b, self.c = (int(i) for i in order)
        self.n_shared = 2 + (3 if tilt else 0) + (3 if law != "none" else 0)
        self.masks = [~s.clipped for s in segments]
        self.t = [s.times - s.start for s in segments]

    def unpack(self, p: Floats) -> tuple[Floats, Floats, Floats | None, list[Floats]]:
        moments = np.empty(3)
        moments[self.big], moments[self.b], moments[self.c] = 1.0, p[0], 1.0 - p[0] + p[1]
        k = 2
        theta = np.zeros(3)
        if self.tilt:
            theta, k = p[2:5], 5
        beta = np.asarray(p[k : k + 3], dtype=float) if self.law != "none" else None
        u0 = [p[self.n_shared + 3 * i : self.n_shared + 3 * i + 3] for i in range(len(self.segments))]
        return moments, rotation_from_vector(theta), beta, u0

    def pack(
        self, moments: Floats, theta: Floats, beta: Floats | None, u0: Sequence[Floats]
    ) -> tuple[Floats, Floats, Floats]:
        """Start, lower and upper bounds from moments (largest 1), rotation vector, drag and initial ω's."""
        ib = float(np.clip(moments[self.b] / moments[self.big], 0.5, 0.999))
        excess = float(np.clip((moments[self.b] + moments[self.c]) / moments[self.big] - 1.0, 0.0, 0.9))
        x, lo, hi = [ib, excess], [0.5, 0.0], [1.0, 1.0]
        if self.tilt:
            x += list(theta)
            lo += [-MAX_TILT] * 3
            hi += [MAX_TILT] * 3
        if self.law != "none":
            x += list(beta if beta is not None else np.zeros(3))
            lo += [0.0] * 3
            hi += [MAX_DRAG] * 3
        for w in u0:
            x += list(w)
            lo += [-np.inf] * 3
            hi += [np.inf] * 3
        low, high = np.array(lo), np.array(hi)
        return np.clip(np.array(x), low + 1e-9, high - 1e-9), low, high

    def residuals(self, p: Floats) -> Floats:
        moments, rot, beta, u0 = self.unpack(p)
        parts = []
        for seg, t, mask, w in zip(self.segments, self.t, self.masks, u0):
            parts.append(((model_omega(moments, rot, beta, w, t) - seg.omega) * mask).ravel())
        # A trial far off (a huge drag stepped backwards, a body the solver tried at a bound) can overflow:
        # it is a large, finite misfit, so that the solver steps back from it.
        return np.nan_to_num(np.clip(np.concatenate(parts), -1e6, 1e6), nan=1e6)

    def sparsity(self) -> lil_matrix:
        rows = sum(3 * len(s.times) for s in self.segments)
        pattern = lil_matrix((rows, self.n_shared + 3 * len(self.segments)), dtype=int)
        pattern[:, : self.n_shared] = 1
        r = 0
        for i, seg in enumerate(self.segments):
            n = 3 * len(seg.times)
            pattern[r : r + n, self.n_shared + 3 * i : self.n_shared + 3 * i + 3] = 1
            r += n
        return pattern

    def solve(self, x0: Floats, low: Floats, high: Floats) -> tuple[Floats, Floats, Floats]:
        """Least squares from x0: (parameters, their covariance ``s² (JᵀJ)⁻¹``, residuals)."""
        result = least_squares(
            self.residuals,
            x0,
            bounds=(low, high),
            jac_sparsity=self.sparsity() if len(self.segments) > 1 else None,
            x_scale="jac",
            method="trf",
            xtol=1e-8,
            ftol=1e-8,
        )
        jac = result.jac.toarray() if hasattr(result.jac, "toarray") else np.asarray(result.jac)
        dof = max(result.fun.size - result.x.size, 1)
        cov = float(result.fun @ result.fun) / dof * np.linalg.pinv(jac.T @ jac)
        return np.asarray(result.x, dtype=float), cov, np.asarray(result.fun, dtype=float)


def _euler_guess(segments: tuple[Segment, ...]) -> Floats:
    return euler_ratios([(s.times[~np.any(s.clipped, axis=1)], s.omega[~np.any(s.clipped, axis=1)]) for s in segments])


def _first_sample(seg: Segment) -> Floats:
    good = np.nonzero(~np.any(seg.clipped, axis=1))[0]
    return np.asarray(seg.omega[good[0]] if good.size else seg.omega[0], dtype=float)


def _prefix(seg: Segment, n: int) -> Segment:
    return Segment(seg.start, float(seg.times[n - 1]), seg.times[:n], seg.omega[:n], seg.clip_rate)


def _continued(seg: Segment, moments: Floats, law: DragLaw) -> tuple[Floats, Floats | None, Floats]:
    """Moments, drag and initial ω (principal axes) of one toss, fitted over its first 30%, 60%, then all of
    its samples. Near the separatrix the time of each flip hangs on ω0's small components and on which
    side of the separatrix the motion lies; over a short start the flip is not yet reached and the fit
    cannot fall onto the wrong side, and each longer stretch starts from where the shorter one ended."""
    w = _first_sample(seg)
    n = len(seg.times)
    drag: Floats | None = None
    for share in CONTINUATION:
        part = _prefix(seg, min(n, max(int(share * n), 20)))
        problem = _Problem((part,), moments, law, tilt=False)
        x, _, _ = problem.solve(*problem.pack(moments, np.zeros(3), drag, [w]))
        moments, _, drag, (w,) = problem.unpack(x)
    return moments, drag, w


def fit_free_body(
    segments: Segment | Sequence[Segment],
    *,
    drag: DragLaw = "linear",
    misalignment: bool | None = None,
) -> FreeBodyFit:
    """Fit the torque-free body with air drag to one free flight or to several of the same object.

    Parameters
    ----------
    segments : Segment or sequence of Segment
        Free flights (:func:`physics.gyro.free_flights`, or :meth:`Segment.between` hand-marked windows).
        Several share moments, misalignment and drag; each has its own initial ω.
    drag : {"linear", "none"}, keyword-only
        The drag: a linear coefficient per principal axis (default; :mod:`physics.gyro.model` explains the
        choice) or none.
    misalignment : bool or None, keyword-only
        Fit a rotation between the phone's and the principal axes: True always, False never, None (default)
        when it exceeds three standard deviations.

    Returns
    -------
    FreeBodyFit

    Raises
    ------
    ValueError
        No segment; a segment shorter than :data:`MIN_DURATION`, mostly clipped (:data:`MAX_CLIPPED`) or
        spinning too slowly (:data:`MIN_SPIN`): the message names the segment and the reason.
    """
    segs = (segments,) if isinstance(segments, Segment) else tuple(segments)
    if not segs:
        raise ValueError("no segment to fit: pass one Segment or a list of them")
    for i, seg in enumerate(segs):
        check_segment(seg, "the segment" if len(segs) == 1 else f"segment {i}")
    if drag not in ("linear", "none"):
        raise ValueError(f"drag must be 'linear' or 'none', got {drag!r}")
    guess = _euler_guess(segs)
    # Each toss alone first (its own moments), then all together from the median moments.
    starts = [_continued(seg, guess, drag) for seg in segs]
    moments = np.median([m for m, _, _ in starts], axis=0)
    coefficients = None if drag == "none" else np.median([c for _, c, _ in starts], axis=0)
    u0 = [w for _, _, w in starts]
    problem = _Problem(segs, moments, drag, tilt=misalignment is not False)
    x, cov, fun = problem.solve(*problem.pack(moments, np.zeros(3), coefficients, u0))
    if misalignment is None and not _tilt_significant(x[2:5], cov[2:5, 2:5]):
        moments, _, beta, u0 = problem.unpack(x)
        problem = _Problem(segs, moments, drag, tilt=False)
        x, cov, fun = problem.solve(*problem.pack(moments, np.zeros(3), beta, u0))
    return _result(problem, x, cov, fun)


def _tilt_significant(theta: Floats, cov: Floats) -> bool:
    """The misalignment's angle exceeds three standard deviations."""
    angle = float(np.linalg.norm(theta))
    return angle > 0.0 and angle > 3.0 * math.sqrt(max(float(theta @ cov @ theta), 0.0)) / angle


def _result(problem: _Problem, x: Floats, cov: Floats, fun: Floats) -> FreeBodyFit:
    moments, rot, beta, u0 = problem.unpack(x)
    # I_c = 1 − I_b + e: its variance from the 2×2 block of (I_b, e).
    sig = np.zeros(3)
    sig[problem.b] = np.sqrt(max(cov[0, 0], 0.0))
    sig[problem.c] = np.sqrt(max(cov[0, 0] + cov[1, 1] - 2.0 * cov[0, 1], 0.0))
    scale = float(np.max(moments))
    moments, sig = moments / scale, sig / scale
    angle, angle_sigma = 0.0, 0.0
    if problem.tilt:
        theta = x[2:5]
        angle = float(np.linalg.norm(theta))
        if angle > 0.0:
            angle_sigma = math.sqrt(max(float(theta @ cov[2:5, 2:5] @ theta), 0.0)) / angle
    k = problem.n_shared - 3
    drag = np.zeros(3) if beta is None else beta
    drag_sigma = np.zeros(3) if beta is None else np.sqrt(np.maximum(np.diag(cov)[k : k + 3], 0.0))
    rms, rel, start = [], [], 0
    for seg, mask in zip(problem.segments, problem.masks):
        n = 3 * len(seg.times)
        part, good = fun[start : start + n], mask.ravel()
        start += n
        value = float(np.sqrt(np.mean(part[good] ** 2))) if np.any(good) else 0.0
        rms.append(value)
        rel.append(value / float(np.sqrt(np.mean(np.sum(seg.omega**2, axis=1)))))
    good_all = np.concatenate([m.ravel() for m in problem.masks])
    return FreeBodyFit(
        moments=moments,
        moments_sigma=sig,
        axes="".join(AXES[i] for i in np.argsort(-moments, kind="stable")),
        rotation=rot,
        misalignment=angle,
        misalignment_sigma=angle_sigma,
        drag_law=problem.law,
        drag=drag,
        drag_sigma=drag_sigma,
        omega0=np.array([rot @ w for w in u0]),
        segments=problem.segments,
        residual=float(np.sqrt(np.mean(fun[good_all] ** 2))),
        residuals=np.array(rms),
        relative_residuals=np.array(rel),
    )
