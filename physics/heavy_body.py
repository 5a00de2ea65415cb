"""A heavy body on a fixed pivot integrated step by step: any body (e.g. an asymmetric top), spin
friction and air drag.

(R, L_body) is integrated with :mod:`physics.integrators` (no Euler angles, so θ = 0 and θ = π/2 are
ordinary points). :meth:`physics.heavy_top.HeavyTop.simulate` is the symmetric top's front end.
"""

from __future__ import annotations

import math
from collections.abc import Callable, Sequence
from dataclasses import dataclass
from typing import TYPE_CHECKING, Any

import numpy as np
from numpy.typing import ArrayLike, NDArray

from physics import G
from physics.euler_angles import euler_attitude, omega_body_from_euler
from physics.validation import MAX_RATE, MAX_STEPS, bounded_scalar, finite_scalar, rotation_array, vector_array

if TYPE_CHECKING:
    from physics.heavy_top import HeavyTop

Floats = NDArray[np.float64]

__all__ = ["FrictionRun", "TransverseAirDrag", "simulate_heavy_body"]


class TransverseAirDrag:
    """Air drag on the wobble: body torque ``−c_air (ω1, ω2, 0)`` (opposes the rotation of the symmetry
    axis, not the spin), N m. A torque object for :mod:`physics.integrators`.

    Parameters
    ----------
    coefficient : float
        ``c_air ≥ 0``, N m s.
    moments : array_like (3,)
        Principal moments about the pivot, kg m² (to get ω = L / I).
    """

    conservative = False

    def __init__(self, coefficient: float, moments: ArrayLike) -> None:
        self.coefficient = finite_scalar(coefficient, "air_drag")
        if self.coefficient < 0.0:
            raise ValueError(f"air_drag must be >= 0 (it removes energy), got {self.coefficient}")
        self.moments = np.asarray(moments, dtype=float).reshape(3)

    def __call__(self, R: NDArray[np.float64], L_body: NDArray[np.float64]) -> NDArray[np.float64]:
        w = np.asarray(L_body, dtype=float) / self.moments
        out: Floats = -self.coefficient * w
        out[..., 2] = 0.0
        return out


@dataclass(frozen=True)
class FrictionRun:
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


_METHOD_NAMES = ("LiePoissonStrang", "Yoshida4", "Suzuki4", "Yoshida6", "ExactFreeSplitting", "LieRK4")


def _method_class(method: str | type) -> type:
    from physics import integrators

    if isinstance(method, str):
        if method not in _METHOD_NAMES:
            raise ValueError(f"unknown method {method!r}; choose one of {', '.join(_METHOD_NAMES)}")
        cls: type = getattr(integrators, method)
        return cls
    return method


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
) -> FrictionRun:
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
    FrictionRun
    """
    from physics import integrators
    from physics.inertia import validate_moments

    I = validate_moments(moments)
    mass = bounded_scalar(mass, "mass")
    if mass <= 0.0:
        raise ValueError(f"mass must be positive, got {mass}")
    com = vector_array(center_of_mass_body, "center_of_mass_body", batched=False)
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
    g = finite_scalar(g, "g")
    all_torques = [integrators.GravityTorque(mass, com, g=g), *torques]
    stepper = _method_class(method)(I, all_torques)
    traj = integrators.integrate(stepper, R0, I * w0, h, n_steps, save_every=save_every)
    R = np.asarray(traj.attitude)
    L = np.asarray(traj.L_body)
    w = L / I
    axis = R[:, :, 2].copy()
    height = np.einsum("kij,j->ki", R, com)[:, 2]
    energy = 0.5 * np.sum(L * w, axis=1) + mass * g * height
    Lz = np.einsum("kij,kj->ki", R, L)[:, 2]
    theta = np.arctan2(np.hypot(axis[:, 0], axis[:, 1]), axis[:, 2])
    return FrictionRun(
        t=np.asarray(traj.t, dtype=float),
        attitude=R,
        L_body=L,
        omega_body=w,
        axis=axis,
        theta=theta,
        energy=energy,
        L3=L[:, 2].copy(),
        Lz=Lz,
        method=getattr(stepper, "name", type(stepper).__name__),
    )


def _simulate_symmetric(
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
) -> FrictionRun:
    from physics import integrators

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
    c = finite_scalar(spin_friction, "spin_friction")
    if c < 0.0:
        raise ValueError(f"spin_friction must be >= 0 (it removes energy), got {c}")
    moments = np.array([top.I1, top.I1, top.I3])
    R0 = euler_attitude(vals[4], vals[0], vals[5])
    w0 = omega_body_from_euler(vals[0], vals[5], vals[1], vals[2], vals[3])
    torques: list[Any] = []
    if c > 0.0:
        torques.append(integrators.SpinFriction(c, moments, axis_body=(0.0, 0.0, 1.0)))
    if air_drag:
        torques.append(TransverseAirDrag(air_drag, moments))
    # M g ℓ = mgl with a unit lever: the torque (and the energy) only depend on the product. Without
    # gravity (mgl = 0) the top is a free symmetric body: a unit mass with g = 0.
    weighs = top.mgl > 0.0
    return simulate_heavy_body(
        moments,
        top.mgl / G if weighs else 1.0,
        (0.0, 0.0, 1.0),
        R0,
        w0,
        t_final,
        dt,
        torques=torques,
        method=method,
        g=G if weighs else 0.0,
        save_every=save_every,
    )
