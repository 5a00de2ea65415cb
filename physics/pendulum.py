"""The physical pendulum: a rigid body constrained to rotate about a fixed axis.

The exact swing (libration, rotation over the top, the separatrix) by Jacobi elliptic functions from
:mod:`physics.elliptic`, the centre of percussion and the response to a sharp blow. The model, its
conventions and its accuracy near the separatrix are in docs/physics-notes.md.

Examples
--------
>>> from physics.inertia import rod
>>> from physics.pendulum import PhysicalPendulum
>>> bat = PhysicalPendulum(rod(1.0, 0.9), pivot=[0, 0, 0.45], axis=[1, 0, 0])
>>> bat.effective_length                      # 2/3 of the rod: 0.6 m
>>> theta, theta_dot = bat.solve(theta0=2.0, thetadot0=0.0, t=[0.0, 0.5, 1.0])
>>> bat.strike([0, 1.0, 0], bat.center_of_percussion()).reaction_impulse   # ≈ 0
"""

from __future__ import annotations

import math
from dataclasses import dataclass
from typing import NamedTuple

import numpy as np
from numpy.typing import ArrayLike, NDArray
from scipy.special import ellipkm1, elliprf

from physics.constants import G
from physics.elliptic import incomplete_first_kind, jacobi_amplitude, jacobi_amplitude_one
from physics.inertia import MassProperties
from physics.rotations import expm_so3_unchecked, frame_from_axis
from physics.validation import broadcast, finite_array, finite_phase, finite_result, finite_scalar

Floats = NDArray[np.float64]

__all__ = ["PhysicalPendulum", "Swing", "Strike", "LIBRATION", "ROTATION", "SEPARATRIX", "UNIFORM"]

LIBRATION = "libration"
"""Swinging to and fro between ``±amplitude`` (energy below the top)."""
ROTATION = "rotation"
"""Going over the top, the angle growing (or falling) without bound."""
SEPARATRIX = "separatrix"
"""Exactly the energy of the inverted position: the body approaches the top as ``t → ±∞``."""
UNIFORM = "uniform"
"""No restoring torque (vertical axis, ``g = 0`` or ``a⊥ = 0``): ``θ = θ0 + θ̇0 t``."""


MAX_RATE = 1e100
"""Largest angular rate accepted, rad/s: far beyond any body, well inside the float range of its square."""


class Swing(NamedTuple):
    """The angle and the angular rate along a swing (unpacks as ``theta, theta_dot``)."""

    theta: NDArray[np.float64]
    """Angle θ from the hanging position about the axis, rad, shape of the broadcast inputs."""
    theta_dot: NDArray[np.float64]
    """Angular velocity θ̇ about the axis, rad/s, same shape."""


@dataclass(frozen=True)
class Strike:
    """What a sharp blow does to a body on a fixed axis (at rest or swinging: the same changes).

    Attributes
    ----------
    delta_omega : float
        Change of the angular velocity about the axis ``n̂``, rad/s (positive: right-hand about ``n̂``).
    delta_velocity_cm : ndarray, shape (3,)
        Change of the centre-of-mass velocity, m/s: ``Δω n̂ × a⊥``.
    reaction_impulse : ndarray, shape (3,)
        Impulse the pivot (the axis) exerts on the body, N s: ``M Δv_cm − J`` (the lecture's
        ``ΔP − F Δt``). Zero for a blow at the centre of percussion perpendicular to the plane of
        ``(n̂, a⊥)``.
    reaction_angular_impulse : ndarray, shape (3,)
        Angular impulse (a couple, N m s) the bearing exerts about the pivot, perpendicular to the
        axis: ``I_pivot Δω n̂ − (r − pivot) × J`` (its n̂ part is zero). It vanishes when the axis is
        a principal axis at the pivot and the blow (point and direction) lies in the plane through
        the pivot perpendicular to the axis; otherwise a hinge must supply it.
    """

    delta_omega: float
    delta_velocity_cm: NDArray[np.float64]
    reaction_impulse: NDArray[np.float64]
    reaction_angular_impulse: NDArray[np.float64]


class PhysicalPendulum:
    """A rigid body on a fixed axis under gravity ``−g ẑ``: the lecture's physical pendulum.

    Parameters
    ----------
    mass_properties : physics.inertia.MassProperties
        The body (mass, centre of mass, tensor about it) in its modelling frame, which is also the
        space frame when the body is at :attr:`model_angle`.
    pivot : array_like, shape (3,)
        A point on the fixed axis, m.
    axis : array_like, shape (3,)
        Direction of the fixed axis (any length > 0). Only gravity's component perpendicular to it,
        ``g⊥ = g |n̂ × ẑ|``, swings the body; a vertical axis gives no restoring torque (see the
        module docstring).
    g : float
        Gravitational acceleration, m/s² (>= 0), default :data:`physics.G`.

    Raises
    ------
    ValueError
        For a ``mass_properties`` that is not a :class:`MassProperties`, non-finite or misshapen
        ``pivot`` or ``axis``, a zero axis, a negative or non-finite ``g``, or a body with no moment
        of inertia about the axis (a point mass or a thin rod lying on the axis cannot be turned).

    Notes
    -----
    A pivot on the line through the centre of mass along the axis (``a⊥ = 0``) is accepted: the body
    is balanced at every angle and turns uniformly; :attr:`effective_length` and the periods are
    ``inf`` and :meth:`center_of_percussion` raises (it is at infinity).

    The derived quantities are computed once, here: build a new pendulum to change the body, pivot,
    axis or ``g`` rather than assigning to the attributes.
    """

    def __init__(self, mass_properties: MassProperties, pivot: ArrayLike, axis: ArrayLike, g: float = G) -> None:
        if not isinstance(mass_properties, MassProperties):
            raise ValueError(
                f"mass_properties must be a physics.inertia.MassProperties, got {type(mass_properties).__name__}"
            )
        self.mass_properties = mass_properties
        self.pivot = finite_array(pivot, "pivot", (3,)).copy()
        axis_arr = finite_array(axis, "axis", (3,))
        norm = float(np.linalg.norm(axis_arr))
        if norm == 0.0:
            raise ValueError("axis must be a non-zero vector: it is the direction of the fixed rotation axis")
        self.axis = axis_arr / norm
        self.g = float(finite_array(g, "g", ()))
        if self.g < 0.0:
            raise ValueError(f"g must not be negative (gravity is -g z), got {self.g}")
        for arr in (self.pivot, self.axis):
            arr.flags.writeable = False

        n = self.axis
        a = mass_properties.center_of_mass - self.pivot
        a_perp = a - (a @ n) * n
        self.a_perp_vector: NDArray[np.float64] = a_perp
        """Perpendicular from the axis to the centre of mass, shape (3,), m (the lecture's ``a⊥``)."""
        self.a_perp_vector.flags.writeable = False
        self.a_perp: float = float(np.linalg.norm(a_perp))
        """Distance of the centre of mass from the axis ``|a⊥|``, m."""
        self.moment_of_inertia: float = mass_properties.moment_about(n, self.pivot)
        """Moment of inertia about the axis ``I = I_cm,nn + M |a⊥|²`` (parallel-axis theorem), kg m²."""
        if not self.moment_of_inertia > 0.0:
            raise ValueError(
                "the body has no moment of inertia about this axis (all its mass lies on the axis, like a "
                "point mass or a thin rod along it), so it cannot be turned about it; choose another axis "
                "or pivot"
            )
        # |n × z| without cancellation; exactly 0 for a vertical axis.
        self.gravity_in_plane: float = self.g * float(np.hypot(n[0], n[1]))
        """``g⊥ = g |n̂ × ẑ|``: the part of gravity that swings the body, m/s²."""

        # Reference direction θ = 0: straight down in the swing plane; if the axis is vertical, the
        # model's own a⊥ (or any perpendicular if that is zero).
        # −(ẑ − n_z n̂) / |n̂ × ẑ|, written with 1 − n_z² = h², so a nearly vertical axis loses nothing.
        h = float(np.hypot(n[0], n[1]))
        if h > 0.0:
            self._down = np.array([n[2] * n[0] / h, n[2] * n[1] / h, -h])
        elif self.a_perp > 0.0:
            self._down = a_perp / self.a_perp
        else:
            self._down = frame_from_axis(n)[:, 0]
        self._side = np.cross(n, self._down)
        self.model_angle: float = float(np.arctan2(a_perp @ self._side, a_perp @ self._down))
        """θ of the body exactly as ``mass_properties`` describes it, rad (0 if it hangs)."""

    # -- lecture quantities ---------------------------------------------------------------------
    @property
    def mass(self) -> float:
        """Total mass M, kg."""
        return self.mass_properties.mass

    @property
    def radius_of_gyration(self) -> float:
        """``k = sqrt(I / M)`` about the axis, m (lecture: ``I^{zz} = M k²``)."""
        return float(np.sqrt(self.moment_of_inertia / self.mass))

    @property
    def effective_length(self) -> float:
        """``ℓ = k² / |a⊥|``, m: the simple pendulum with the same motion; ``inf`` if ``a⊥ = 0``."""
        if self.a_perp == 0.0:
            return float("inf")
        return self.moment_of_inertia / (self.mass * self.a_perp)

    @property
    def omega0(self) -> float:
        """Small-oscillation angular frequency ``ω0 = sqrt(g⊥ / ℓ) = sqrt(M g⊥ |a⊥| / I)``, rad/s."""
        return float(np.sqrt(self.mass * self.gravity_in_plane * self.a_perp / self.moment_of_inertia))

    @property
    def small_oscillation_period(self) -> float:
        """``2π sqrt(ℓ / g⊥)``, s; ``inf`` without a restoring torque."""
        w = self.omega0
        return 2.0 * np.pi / w if w > 0.0 else float("inf")

    def energy(self, theta: ArrayLike, theta_dot: ArrayLike) -> NDArray[np.float64]:
        """Total energy ``½ I θ̇² − M g⊥ |a⊥| cos θ``, J (potential zero with ``a⊥`` level, θ = ±π/2).

        Parameters
        ----------
        theta, theta_dot : array_like, broadcastable
            rad, rad/s.
        """
        th = finite_array(theta, "theta")
        thd = finite_array(theta_dot, "theta_dot")
        broadcast(theta=th, theta_dot=thd)
        with np.errstate(over="ignore"):  # an overflow is refused by name just below
            energy = 0.5 * self.moment_of_inertia * thd**2 - self.mass * self.gravity_in_plane * self.a_perp * np.cos(
                th
            )
        finite_result(energy, "the energy", "rates (theta_dot)")
        return energy

    # -- exact swing ----------------------------------------------------------------------------
    def _energy_parameter(
        self, theta0: NDArray[np.float64], thetadot0: NDArray[np.float64]
    ) -> tuple[NDArray[np.float64], ...]:
        """Wrapped angle, turns, ``x = θ̇0/2ω0``, ``κ²`` and ``κ² − 1`` (computed without cancellation)."""
        turns = np.round(theta0 / (2.0 * np.pi))
        wrapped = theta0 - 2.0 * np.pi * turns  # in [-π, π]
        half_sin, half_cos = np.sin(0.5 * wrapped), np.cos(0.5 * wrapped)  # half_cos >= 0
        two_w = 2.0 * self.omega0
        x = thetadot0 / two_w
        m = half_sin**2 + x**2
        # κ² − 1, the scaled energy above the top, as a product of a difference taken before dividing
        # by 2ω0 (exact by Sterbenz near the separatrix): it is what the float inputs really mean.
        speed, top = np.abs(thetadot0), two_w * half_cos
        excess = ((speed - top) / two_w) * ((speed + top) / two_w)
        return wrapped, turns, half_sin, half_cos, x, m, excess

    def regime(self, theta0: ArrayLike, thetadot0: ArrayLike) -> NDArray[np.str_]:
        """Which motion the initial state starts: :data:`LIBRATION`, :data:`ROTATION`,
        :data:`SEPARATRIX` or :data:`UNIFORM` (no restoring torque).

        Parameters
        ----------
        theta0, thetadot0 : array_like, broadcastable
            Initial angle (rad) and rate (rad/s).

        Returns
        -------
        ndarray of str, the broadcast shape
        """
        th0, thd0 = np.broadcast_arrays(finite_array(theta0, "theta0"), finite_array(thetadot0, "thetadot0"))
        if self.omega0 == 0.0:
            return np.full(th0.shape, UNIFORM)
        excess = self._energy_parameter(th0, thd0)[-1]
        return np.where(excess < 0.0, LIBRATION, np.where(excess > 0.0, ROTATION, SEPARATRIX))

    def solve(self, theta0: ArrayLike, thetadot0: ArrayLike, t: ArrayLike) -> Swing:
        """The exact swing at any amplitude (lecture: ``M k² θ̈ = −|a⊥| M g sin θ``).

        Libration ``sin(θ/2) = κ sn(ω0 t + c | κ²)`` (the returned θ via ``2 atan2(κ sn, dn)``,
        accurate to the top), rotation ``θ/2 = am(κ ω0 t + c | 1/κ²)``, separatrix ``θ/2 = gd(ω0 t + c)``,
        uniform turning without a restoring torque. The elliptic argument is reduced modulo its
        period before evaluation. Time may be negative (the solution is exact both ways).

        Parameters
        ----------
        theta0 : array_like
            Angle at ``t = 0`` from the hanging position, rad. Whole turns are kept: a swing about
            ``2π`` stays about ``2π``.
        thetadot0 : array_like
            Angular velocity about the axis at ``t = 0``, rad/s.
        t : array_like
            Times, s. ``theta0``, ``thetadot0`` and ``t`` broadcast together (e.g. scalars and (n,)).

        Returns
        -------
        Swing
            ``theta`` (rad) and ``theta_dot`` (rad/s), each the broadcast shape (e.g. (n,)).
        """
        return self.trajectory(theta0, thetadot0).at(finite_array(t, "t"))

    def trajectory(self, theta0: ArrayLike, thetadot0: ArrayLike) -> PendulumTrajectory:
        """The exact swing from ``theta0`` (rad) and ``thetadot0`` (rad/s), solved once: evaluate it with
        :meth:`PendulumTrajectory.at` at any times (see :meth:`solve` for the closed forms).

        ``theta0`` and ``thetadot0`` may be arrays (several swings at once); the times given to ``at``
        broadcast against them.
        """
        return PendulumTrajectory(self, theta0, thetadot0)

    def period(self, amplitude: ArrayLike) -> NDArray[np.float64]:
        """Period of libration with the given amplitude: ``4 K(sin²(θ_max/2)) / ω0``, s.

        ``K`` is evaluated from the complement ``cos²(θ_max/2)`` (``scipy.special.ellipkm1``), so it
        stays accurate as the amplitude approaches π, where the period diverges like
        ``(4/ω0) ln(4 / cos(θ_max/2))``.

        Parameters
        ----------
        amplitude : array_like
            θ_max, rad, in ``[0, π]`` (π gives ``inf``: the separatrix).

        Returns
        -------
        ndarray, the shape of ``amplitude``
        """
        amp = finite_array(amplitude, "amplitude")
        if np.any((amp < 0.0) | (amp > np.pi)):
            raise ValueError(
                f"a libration amplitude lies in [0, pi] rad, got {amp.tolist()}; larger energies go over the top"
            )
        if self.omega0 == 0.0:
            return np.full(amp.shape, np.inf)
        m1 = np.cos(0.5 * amp) ** 2
        m1 = np.where(amp == np.pi, 0.0, m1)  # cos(π/2) in floats is 6e-17, not 0
        out: NDArray[np.float64] = 4.0 * ellipkm1(m1) / self.omega0
        return out

    def motion_period(self, theta0: ArrayLike, thetadot0: ArrayLike) -> NDArray[np.float64]:
        """Time after which the state repeats, s: a full swing (libration), one turn of ``2π``
        (rotation, ``2 K(1/κ²) / (κ ω0)``); ``inf`` on the separatrix or without a restoring torque.

        Parameters
        ----------
        theta0, thetadot0 : array_like, broadcastable
            rad, rad/s.
        """
        th0, thd0 = np.broadcast_arrays(finite_array(theta0, "theta0"), finite_array(thetadot0, "thetadot0"))
        w = self.omega0
        if w == 0.0:
            return np.full(th0.shape, np.inf)
        m, excess = self._energy_parameter(th0, thd0)[-2:]
        out = np.full(th0.shape, np.inf)
        lib, rot = excess < 0.0, excess > 0.0
        out[lib] = 4.0 * ellipkm1(-excess[lib]) / w
        out[rot] = 2.0 * ellipkm1(excess[rot] / m[rot]) / (np.sqrt(m[rot]) * w)
        return out

    # -- configuration --------------------------------------------------------------------------
    def attitude(self, theta: ArrayLike) -> NDArray[np.float64]:
        """Rotation of the body from its modelling pose to angle θ, about the axis through the pivot.

        A body point moves as ``x_space = pivot + R @ (x_model − pivot)``.

        Parameters
        ----------
        theta : array_like, shape () or (n,)
            rad.

        Returns
        -------
        ndarray, shape (3, 3) or (n, 3, 3)
        """
        th = finite_array(theta, "theta")
        return expm_so3_unchecked((th - self.model_angle)[..., None] * self.axis)  # the axis: unit, checked when built

    def center_of_mass_at(self, theta: ArrayLike) -> NDArray[np.float64]:
        """Centre-of-mass position at angle θ, m, shape (3,) or (n, 3)."""
        rot = self.attitude(theta)
        return self.pivot + rot @ (self.mass_properties.center_of_mass - self.pivot)

    # -- percussion -----------------------------------------------------------------------------
    def _pose(self, theta: float | None) -> NDArray[np.float64]:
        """Rotation from the modelling pose to angle ``theta`` (identity for ``None``), shape (3, 3)."""
        if theta is None:
            return np.eye(3)
        return self.attitude(finite_array(theta, "theta", ()))

    def strike(self, impulse: ArrayLike, point: ArrayLike, theta: float | None = None) -> Strike:
        """A sharp blow: impulse ``J`` at ``point``, and the pivot's reaction (lecture, centre of percussion).

        The axis is fixed, so only the moment of ``J`` about it turns the body:
        ``I Δω = n̂ · ((r − pivot) × J)``; the centre of mass then gains ``Δv = Δω n̂ × a⊥``, and the
        pivot supplies the rest of the momentum, ``R = M Δv − J`` (the lecture's ``ΔP − F Δt``).
        Gravity and the centripetal force are finite, so during the blow they add nothing: the
        result is the same whether the body is at rest or swinging.

        Parameters
        ----------
        impulse : array_like, shape (3,)
            ``J = F Δt``, N s, in the frame of ``pivot`` and ``axis``.
        point : array_like, shape (3,)
            Where it lands, m.
        theta : float, optional
            The body's angle when struck, rad; default: the modelling pose (:attr:`model_angle`).

        Returns
        -------
        Strike
        """
        j = finite_array(impulse, "impulse", (3,))
        r = finite_array(point, "point", (3,)) - self.pivot
        rot = self._pose(theta)
        n = self.axis
        delta_omega = float(n @ np.cross(r, j)) / self.moment_of_inertia
        delta_v = delta_omega * np.cross(n, rot @ self.a_perp_vector)
        reaction = self.mass * delta_v - j
        tensor_pivot = rot @ self.mass_properties.tensor_about(self.pivot) @ rot.T
        couple = tensor_pivot @ (delta_omega * n) - np.cross(r, j)
        couple = couple - (couple @ n) * n  # its n̂ part is zero by construction; drop round-off
        return Strike(delta_omega, delta_v, reaction, couple)

    def center_of_percussion(self, theta: float | None = None) -> NDArray[np.float64]:
        """The point ``pivot + ℓ a⊥/|a⊥|``, m, shape (3,): struck there perpendicular to the plane of
        ``(n̂, a⊥)``, the body needs no impulse from the pivot (docs/conventions.md erratum 2).

        Any point on the line through it parallel to the axis does the same for the reaction
        *force*; a general body on a hinge may still need a reaction couple
        (:attr:`Strike.reaction_angular_impulse`).

        Parameters
        ----------
        theta : float, optional
            The body's angle, rad; default: the modelling pose (:attr:`model_angle`).

        Raises
        ------
        ValueError
            If ``a⊥ = 0``: the centre of percussion is at infinity.
        """
        if self.a_perp == 0.0:
            raise ValueError(
                "the centre of mass is on the axis (a_perp = 0): every blow pushes on the pivot and the "
                "centre of percussion is at infinity"
            )
        rot = self._pose(theta)
        return self.pivot + self.effective_length * (rot @ self.a_perp_vector) / self.a_perp


class PendulumTrajectory:
    """Swings of a :class:`PhysicalPendulum` from given initial states, ready to be evaluated.

    Made by :meth:`PhysicalPendulum.trajectory`. Everything that does not depend on t (the regime,
    κ, the complete integral K and the phase of each swing) is computed here, once.
    """

    def __init__(self, model: PhysicalPendulum, theta0: ArrayLike, thetadot0: ArrayLike) -> None:
        th0, thd0 = np.broadcast_arrays(finite_array(theta0, "theta0"), finite_array(thetadot0, "thetadot0"))
        if np.any(np.abs(thd0) > MAX_RATE):
            raise ValueError(f"thetadot0 must be at most {MAX_RATE:g} rad/s (its square would overflow)")
        self.model = model
        self.theta0, self.thetadot0 = th0, thd0
        w = self._w = model.omega0
        # A bound on every phase per second of t (ω0 t, κ ω0 t with κ ω0 ≤ |θ̇0|/2 + ω0; θ̇0 t without gravity).
        self._reach = 2.0 * (w + float(np.max(np.abs(thd0), initial=0.0)))
        if w == 0.0:
            return
        wrapped, turns, half_sin, half_cos, x, m, excess = model._energy_parameter(th0, thd0)
        self._turns = turns
        self._sign = np.where(thd0 < 0.0, -1.0, 1.0)
        self._lib, self._rot, self._sep = excess < 0.0, excess > 0.0, excess == 0.0
        lib, rot, sep = self._lib, self._rot, self._sep
        # Libration: sin(θ/2) = κ sn(ω0 t + c | κ²); am(c) has sin = sn0, cos = cn0.
        mm, m1 = m[lib], -excess[lib]
        kappa = np.sqrt(mm)
        safe = np.where(kappa > 0.0, kappa, 1.0)
        sn0 = np.where(kappa > 0.0, half_sin[lib] / safe, 0.0)
        cn0 = np.where(kappa > 0.0, x[lib] / safe, 1.0)
        k_complete = ellipkm1(m1)
        f0 = sn0 * elliprf(cn0**2, half_cos[lib] ** 2, 1.0)  # F on (π/2, π] by F(π − φ) = 2K − F(φ)
        self._libration = (mm, m1, kappa, k_complete, np.where(cn0 < 0.0, 2.0 * k_complete - f0, f0))
        # Rotation: θ/2 = am(κ ω0 t + c | 1/κ²).
        q1 = excess[rot] / m[rot]  # 1 − 1/κ²
        psi0 = self._sign[rot] * 0.5 * wrapped[rot]  # in [-π/2, π/2]
        self._rotation = (
            np.sqrt(m[rot]),
            1.0 / m[rot],
            q1,
            ellipkm1(q1),
            incomplete_first_kind(np.sin(psi0), np.cos(psi0), q1),
        )
        # Separatrix: θ/2 = gd(ω0 t + c).
        self._separatrix = np.arcsinh(np.tan(self._sign[sep] * 0.5 * wrapped[sep]))  # gd⁻¹

    @property
    def phase(self) -> tuple[float, float, float] | None:
        """``(rate, offset, K)`` of one swing: its elliptic phase ``u = rate t + offset`` (rate in 1/s) reaches
        an odd multiple of the quarter period ``K`` at each turning point (libration: ``θ = +θ_max`` at
        ``u = K (mod 4K)``, ``−θ_max`` at ``3K``) or each passage over the top (rotation, ``θ ≡ π mod 2π``).
        None on the separatrix and without a restoring torque (no such instants); ValueError for several
        initial states (one phase each: make one trajectory per state)."""
        if self.theta0.ndim:
            raise ValueError(f"the phase belongs to one initial state; this trajectory holds {self.theta0.shape}")
        if self._w == 0.0 or self._sep:
            return None
        if self._lib:
            return self._w, float(self._libration[4][0]), float(self._libration[3][0])
        kappa, _, _, k_complete, c = (float(v[0]) for v in self._rotation)
        return kappa * self._w, c, k_complete

    def at(self, t: ArrayLike) -> Swing:
        """The angle and rate at the times ``t`` (s), broadcast against the initial states.

        Returns
        -------
        Swing
            ``theta`` (rad) and ``theta_dot`` (rad/s), each the broadcast shape.
        """
        if isinstance(t, (float, int)) and not isinstance(t, bool) and self.theta0.ndim == 0 and self._w != 0.0:
            tf = finite_scalar(t, "t")
            with np.errstate(over="ignore"):
                finite_phase(self._reach * abs(tf))
            return self._at_one_time(tf)
        tt = finite_array(t, "t")
        with np.errstate(over="ignore"):
            finite_phase(self._reach * float(np.max(np.abs(tt), initial=0.0)))
        w = self._w
        if w == 0.0:
            th0, thd0, tt = np.broadcast_arrays(self.theta0, self.thetadot0, tt)
            return Swing(th0 + thd0 * tt, thd0.astype(float, copy=True))
        shape = np.broadcast_shapes(self.theta0.shape, tt.shape)
        if shape != self.theta0.shape:
            if self.theta0.ndim:  # several swings and times of another shape: evaluate them broadcast
                return self.model.trajectory(*np.broadcast_arrays(self.theta0, self.thetadot0, tt)[:2]).at(tt)
            return self._at_one_state(tt)
        tt = np.broadcast_to(tt, shape)
        theta = np.empty(shape)
        theta_dot = np.empty(shape)
        lib, rot, sep = self._lib, self._rot, self._sep
        if np.any(lib):
            theta[lib], theta_dot[lib] = self._librate(tt[lib], *self._libration)
        if np.any(rot):
            theta[rot], theta_dot[rot] = self._rotate(tt[rot], self._sign[rot], *self._rotation)
        if np.any(sep):
            theta[sep], theta_dot[sep] = self._creep(tt[sep], self._sign[sep], self._separatrix)
        theta += 2.0 * np.pi * self._turns
        return Swing(theta, theta_dot)

    def _at_one_time(self, t: float) -> Swing:
        """One state, one time (a frame of an animation): the same formulas on Python floats."""
        w = self._w
        s = float(self._sign)
        if self._lib:
            mm, m1, kappa, k_complete, c = (float(v[0]) for v in self._libration)
            u = w * t + c
            u = u - 4.0 * k_complete * round(u / (4.0 * k_complete))
            phi = jacobi_amplitude_one(u, mm, m1)
            sn, cn = math.sin(phi), math.cos(phi)
            theta = 2.0 * math.atan2(kappa * sn, math.sqrt(cn * cn + m1 * sn * sn))
            theta_dot = 2.0 * kappa * w * cn
        elif self._rot:
            kappa, q, q1, k_complete, c = (float(v[0]) for v in self._rotation)
            u = kappa * w * t + c
            half_turns = round(u / (2.0 * k_complete))
            phi = jacobi_amplitude_one(u - 2.0 * k_complete * half_turns, q, q1)
            sn, cn = math.sin(phi), math.cos(phi)
            theta = 2.0 * s * (phi + math.pi * half_turns)
            theta_dot = 2.0 * s * kappa * w * math.sqrt(cn * cn + q1 * sn * sn)
        else:
            u = w * t + float(self._separatrix[0])
            e = math.exp(-abs(u))
            theta, theta_dot = 4.0 * s * math.atan(math.tanh(0.5 * u)), 2.0 * s * w * (2.0 * e / (1.0 + e * e))
        return Swing(np.array(theta + 2.0 * math.pi * float(self._turns)), np.array(theta_dot))

    def _at_one_state(self, tt: NDArray[np.float64]) -> Swing:
        """One initial state (0-d), many times: its regime's formula over all of them."""
        if self._lib:
            theta, theta_dot = self._librate(tt, *self._libration)
        elif self._rot:
            theta, theta_dot = self._rotate(tt, self._sign, *self._rotation)
        else:
            theta, theta_dot = self._creep(tt, self._sign, self._separatrix)
        return Swing(theta + 2.0 * np.pi * self._turns, theta_dot)

    def _librate(
        self, t: Floats, mm: Floats, m1: Floats, kappa: Floats, k_complete: Floats, c: Floats
    ) -> tuple[Floats, Floats]:
        w = self._w
        u = w * t + c
        u = u - 4.0 * k_complete * np.round(u / (4.0 * k_complete))  # sn, cn have period 4K
        phi = jacobi_amplitude(u, np.broadcast_to(mm, u.shape), np.broadcast_to(m1, u.shape))
        sn, cn = np.sin(phi), np.cos(phi)
        dn = np.sqrt(cn * cn + m1 * sn * sn)  # = cos(θ/2) > 0, no cancellation near the top
        return 2.0 * np.arctan2(kappa * sn, dn), 2.0 * kappa * w * cn

    def _rotate(
        self, t: Floats, s: Floats, kappa: Floats, q: Floats, q1: Floats, k_complete: Floats, c: Floats
    ) -> tuple[Floats, Floats]:
        w = self._w
        u = kappa * w * t + c
        half_turns = np.round(u / (2.0 * k_complete))  # am(u + 2K) = am(u) + π
        r = u - 2.0 * k_complete * half_turns
        phi = jacobi_amplitude(r, np.broadcast_to(q, r.shape), np.broadcast_to(q1, r.shape))
        sn, cn = np.sin(phi), np.cos(phi)
        return 2.0 * s * (phi + np.pi * half_turns), 2.0 * s * kappa * w * np.sqrt(cn * cn + q1 * sn * sn)

    def _creep(self, t: Floats, s: Floats, c: Floats) -> tuple[Floats, Floats]:
        u = self._w * t + c
        # gd(u) = 2 atan(tanh(u/2)) and sech u = 2 e^-|u| / (1 + e^-2|u|): no overflow however long the
        # creep towards the top lasts.
        e = np.exp(-np.abs(u))
        return 4.0 * s * np.arctan(np.tanh(0.5 * u)), 2.0 * s * self._w * (2.0 * e / (1.0 + e * e))
