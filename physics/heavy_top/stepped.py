"""A heavy body on a fixed pivot integrated step by step: any body (e.g. an asymmetric top), spin
friction and air drag.

(R, L_body) is integrated with :mod:`physics.integrators` (no Euler angles, so θ = 0 and θ = π/2 are
ordinary points). :func:`friction_stepper` builds the symmetric top's integrator (the app's heavy-top scene
steps it frame by frame); :meth:`physics.heavy_top.HeavyTop.simulate` runs it from Euler angles.
"""

from __future__ import annotations

import math
from collections.abc import Callable, Sequence
from dataclasses import dataclass
from typing import TYPE_CHECKING, Any

import numpy as np
from numpy.typing import ArrayLike, NDArray

from physics.constants import G
from physics.euler_angles import euler_attitude, omega_body_from_euler
from physics.inertia import validate_moments
from physics.integrators import REGISTRY, GravityTorque, Method, SpinFriction, integrate
from physics.integrators.torques import TransverseAirDrag
from physics.validation import MAX_RATE, MAX_STEPS, bounded_scalar, finite_scalar, rotation_array, vector_array

if TYPE_CHECKING:
    from physics.heavy_top.model import HeavyTop

Floats = NDArray[np.float64]

__all__ = [
    "FrictionRun",
    "SteppedRun",
    "TransverseAirDrag",
    "friction_stepper",
    "method_class",
    "run_stepper",
    "simulate_heavy_body",
    "simulate_symmetric",
]


@dataclass(frozen=True)
class SteppedRun:
    """A heavy body integrated step by step (attitude R and body angular momentum L).

    Attributes
    ----------
    t : ndarray (k,)
        Saved times, s.
    attitude : ndarray (k, 3, 3)
        Body-to-space rotations.
    L_body : ndarray (k, 3)
        Angular momentum about the pivot in the body frame, kg m²/s.
    omega_body : ndarray (k, 3)
        Angular velocity in the body frame, rad/s.
    axis : ndarray (k, 3)
        Body axis 3 in space (the symmetry axis of a symmetric top).
    theta : ndarray (k,)
        Angle of that axis from +z, rad (from the axis itself: no Euler-angle singularity).
    energy : ndarray (k,)
        Kinetic plus gravitational energy, J.
    L3 : ndarray (k,)
        Body component 3 of L (the spin angular momentum of a symmetric top), kg m²/s.
    Lz : ndarray (k,)
        Space z component of L, kg m²/s (conserved without friction: gravity's torque is horizontal).
    method : str
        Name of the integrator.
    """

    t: NDArray[np.float64]
    attitude: NDArray[np.float64]
    L_body: NDArray[np.float64]
    omega_body: NDArray[np.float64]
    axis: NDArray[np.float64]
    theta: NDArray[np.float64]
    energy: NDArray[np.float64]
    L3: NDArray[np.float64]
    Lz: NDArray[np.float64]
    method: str


FrictionRun = SteppedRun
"""Another name of :class:`SteppedRun` (a run with friction is one use of it)."""

_BY_CLASS_NAME = {cls.__name__: cls for cls in REGISTRY.values()}


def method_class(method: str | type) -> type:
    """The integrator class named by ``method``: a class name such as ``"LieRK4"``, a
    :data:`physics.integrators.REGISTRY` name such as ``"Lie RK4 (RKMK)"``, or the class itself."""
    if isinstance(method, str):
        cls = _BY_CLASS_NAME.get(method) or REGISTRY.get(method)
        if cls is None:
            raise ValueError(f"unknown method {method!r}; choose one of {', '.join(_BY_CLASS_NAME)}")
        return cls
    return method


def friction_stepper(
    top: HeavyTop, spin_friction: float, air_drag: float = 0.0, method: str | type = "LieRK4"
) -> Method:
    """The integrator of a symmetric top (moments ``I1, I1, I3``) under gravity, spin friction ``c`` about its
    axis and air drag on the wobble, built once so that a caller (the app's scene) only steps it.

    Gravity acts at a unit lever, with ``M g = mgl``: the torque and the energy depend on the product only.
    Without gravity (``mgl = 0``) the top is a free symmetric body.
    """
    c = finite_scalar(spin_friction, "spin_friction")
    if c < 0.0:
        raise ValueError(f"spin_friction must be >= 0 (it removes energy), got {c}")
    moments = np.array([top.I1, top.I1, top.I3])
    weighs = top.mgl > 0.0
    torques: list[Any] = [GravityTorque(top.mgl / G if weighs else 1.0, (0.0, 0.0, 1.0), g=G if weighs else 0.0)]
    if c > 0.0:
        torques.append(SpinFriction(c, moments, axis_body=(0.0, 0.0, 1.0)))
    if air_drag:
        torques.append(TransverseAirDrag(air_drag, moments))
    stepper: Method = method_class(method)(moments, torques)
    return stepper


def simulate_heavy_body(
    moments: ArrayLike,
    mass: float,
    center_of_mass_body: ArrayLike,
    attitude0: ArrayLike,
    omega_body0: ArrayLike,
    t_final: float,
    dt: float,
    *,
    torques: Sequence[Callable[..., Any]] = (),
    method: str | type = "LieRK4",
    g: float = G,
    save_every: int = 1,
) -> SteppedRun:
    """Any rigid body with one point (the origin, its pivot) fixed, under gravity ``−g ẑ`` and optional
    extra torques, integrated by :mod:`physics.integrators` on (R, L_body) — no Euler angles.

    Euler's equations with the gravity torque ``τ_body = c × (−M g Rᵀ ẑ)`` (c = centre of mass in the
    body frame) and ``Ṙ = R hat(ω_body)``.

    Parameters
    ----------
    moments : array_like (3,)
        Principal moments about the pivot, kg m²; the body frame is their principal frame.
    mass : float
        kg (> 0).
    center_of_mass_body : array_like (3,)
        Centre of mass relative to the pivot, body frame, m.
    attitude0 : array_like (3, 3)
        Initial body-to-space rotation.
    omega_body0 : array_like (3,)
        Initial angular velocity, body frame, rad/s.
    t_final, dt : float
        Duration and step, s; the step is shortened so that a whole number of steps reaches t_final.
    torques : sequence of torque objects
        Extra torques (e.g. :class:`physics.integrators.SpinFriction`, :class:`TransverseAirDrag`).
    method : str or integrator class
        ``"LieRK4"`` (default, order 4), ``"Yoshida4"``, ``"LiePoissonStrang"``, ``"ExactFreeSplitting"``.
    g : float
        Gravitational acceleration, m/s².
    save_every : int
        Keep every this many steps.

    Returns
    -------
    SteppedRun
    """
    I = validate_moments(moments)
    mass = bounded_scalar(mass, "mass")
    if mass <= 0.0:
        raise ValueError(f"mass must be positive, got {mass}")
    com = vector_array(center_of_mass_body, "center_of_mass_body", batched=False)
    R0 = rotation_array(attitude0, "attitude0", batched=False)
    w0 = vector_array(omega_body0, "omega_body0", batched=False)
    g = finite_scalar(g, "g")
    stepper = method_class(method)(I, [GravityTorque(mass, com, g=g), *torques])
    return run_stepper(stepper, R0, w0, t_final, dt, save_every=save_every)


def run_stepper(
    stepper: Method, attitude0: ArrayLike, omega_body0: ArrayLike, t_final: float, dt: float, *, save_every: int = 1
) -> SteppedRun:
    """Step a heavy body's integrator (its first torque the :class:`GravityTorque`) from an attitude and a
    body angular velocity (rad/s) for ``t_final`` seconds, the step ``dt`` shortened so that a whole number
    of steps reaches ``t_final``; the states every ``save_every`` steps as a :class:`SteppedRun`."""
    gravity = stepper.torques[0]
    if not isinstance(gravity, GravityTorque):
        raise ValueError(f"the stepper's first torque must be its GravityTorque, got {gravity!r}")
    I, com = stepper.moments, gravity.center_of_mass_body
    R0 = rotation_array(attitude0, "attitude0", batched=False)
    w0 = vector_array(omega_body0, "omega_body0", batched=False)
    t_final, dt = finite_scalar(t_final, "t_final"), finite_scalar(dt, "dt")
    if t_final <= 0.0 or dt <= 0.0:
        raise ValueError(f"t_final and dt must be positive, got t_final = {t_final}, dt = {dt}")
    if t_final / dt > MAX_STEPS:
        raise ValueError(
            f"t_final / dt = {t_final / dt:.3g} steps is more than {MAX_STEPS:,}: take a larger dt or a shorter run"
        )
    if np.max(np.abs(w0)) > MAX_RATE:
        raise ValueError(f"omega_body0 must be at most {MAX_RATE:g} rad/s in each component, got {w0.tolist()}")
    n_steps = max(1, int(math.ceil(t_final / dt - 1e-9)))
    h = t_final / n_steps
    traj = integrate(stepper, R0, I * w0, h, n_steps, save_every=save_every)
    R = np.asarray(traj.attitude)
    L = np.asarray(traj.L_body)
    w = L / I
    axis = R[:, :, 2].copy()
    height = np.einsum("kij,j->ki", R, com)[:, 2]
    energy = 0.5 * np.sum(L * w, axis=1) + gravity.mass * gravity.g * height
    Lz = np.einsum("kij,kj->ki", R, L)[:, 2]
    theta = np.arctan2(np.hypot(axis[:, 0], axis[:, 1]), axis[:, 2])
    return SteppedRun(
        t=np.asarray(traj.t, dtype=float),
        attitude=R,
        L_body=L,
        omega_body=w,
        axis=axis,
        theta=theta,
        energy=energy,
        L3=L[:, 2].copy(),
        Lz=Lz,
        method=stepper.name,
    )


def simulate_symmetric(
    top: HeavyTop,
    theta0: float,
    thetadot0: float,
    phidot0: float,
    psidot0: float,
    t_final: float,
    dt: float,
    spin_friction: float,
    air_drag: float,
    method: str | type,
    save_every: int,
    phi0: float,
    psi0: float,
) -> SteppedRun:
    """:meth:`HeavyTop.simulate`: the top from Euler angles and rates, stepped by :func:`friction_stepper`."""
    vals = [
        finite_scalar(v, n)
        for v, n in (
            (theta0, "theta0"),
            (thetadot0, "thetadot0"),
            (phidot0, "phidot0"),
            (psidot0, "psidot0"),
            (phi0, "phi0"),
            (psi0, "psi0"),
        )
    ]
    if not 0.0 <= vals[0] <= math.pi:
        raise ValueError(f"theta0 is the angle of the axis from +z and must lie in [0, pi], got {vals[0]}")
    stepper = friction_stepper(top, spin_friction, air_drag, method)
    R0 = euler_attitude(vals[4], vals[0], vals[5])
    w0 = omega_body_from_euler(vals[0], vals[5], vals[1], vals[2], vals[3])
    return run_stepper(stepper, R0, w0, t_final, dt, save_every=save_every)
