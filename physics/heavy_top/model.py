"""The heavy symmetric (Lagrange) top: :class:`HeavyTop`, its potentials, thresholds and rates, and the
entries to its exact motion (:meth:`HeavyTop.trajectory`) and to its stepped motion with friction
(:meth:`HeavyTop.simulate`).

Euler angles z-x-z, ``V = + M g ℓ cos θ`` (docs/conventions.md); the closed form, its accuracy and its
limits are in docs/physics-notes.md.
"""

from __future__ import annotations

import math
from typing import TYPE_CHECKING

import numpy as np
from numpy.typing import ArrayLike, NDArray

from physics.constants import G
from physics.heavy_top.motion import Motion, ScaledTop, motion_constants
from physics.heavy_top.nutation_cubic import NutationCubic
from physics.heavy_top.stepped import SteppedRun, simulate_symmetric
from physics.heavy_top.trajectory import HeavyTopSolution, HeavyTopTrajectory, times_array
from physics.validation import (
    bounded_scalar,
    broadcast,
    finite_array,
    finite_result,
    finite_scalar,
)

if TYPE_CHECKING:
    from physics.inertia import MassProperties

Floats = NDArray[np.float64]

__all__ = ["HeavyTop"]

_EPS = np.finfo(float).eps


class HeavyTop:
    """A heavy symmetric top with its tip fixed at the origin (the Lagrange top).

    Parameters
    ----------
    I1 : float
        Moment of inertia about the pivot, perpendicular to the symmetry axis, kg m².
    I3 : float
        Moment of inertia about the symmetry axis, kg m².
    mgl : float
        ``M g ℓ``, weight times pivot-to-centre-of-mass distance, J (≥ 0: the centre of mass is up the axis;
        0 is the symmetric free body turning about the fixed tip).

    Raises
    ------
    ValueError
        If a value is not positive and finite, or ``I3 > 2 I1`` (no rigid body: about the pivot
        ``I1 = I1_cm + M ℓ²`` and the triangle inequality of the moments gives ``I3 ≤ 2 I1``).
    """

    def __init__(self, I1: float, I3: float, mgl: float) -> None:
        self.I1 = finite_scalar(I1, "I1")
        self.I3 = finite_scalar(I3, "I3")
        self.mgl = finite_scalar(mgl, "mgl")
        if self.I3 == 0.0:
            raise ValueError(
                "I3 = 0 is a thin rod on a pivot (a spherical pendulum), not a top: its spin carries no "
                "angular momentum, so the Lagrange top's solution does not apply; use simulate_heavy_body"
            )
        for name, v in (("I1", self.I1), ("I3", self.I3)):
            if v <= 0.0:
                raise ValueError(f"{name} must be positive, got {v}")
        if self.mgl < 0.0:
            raise ValueError(
                f"mgl must be zero or positive (the centre of mass up the axis from the tip), got {self.mgl}"
            )
        if self.I3 > 2.0 * self.I1 * (1.0 + 4.0 * _EPS):
            raise ValueError(
                f"no rigid body has these moments: I3 = {self.I3} > 2 I1 = {2 * self.I1} "
                "(the moment about the symmetry axis cannot exceed the sum of the other two)"
            )

    def __repr__(self) -> str:
        return f"HeavyTop(I1={self.I1!r}, I3={self.I3!r}, mgl={self.mgl!r})"

    @classmethod
    def from_mass_properties(
        cls, body: MassProperties, tip: ArrayLike, *, g: float = G, rtol: float = 1e-9
    ) -> HeavyTop:
        """The top made of ``body`` (a :class:`physics.inertia.MassProperties`) spinning on ``tip``.

        The symmetry axis is the line from the tip to the centre of mass; the inertia tensor about the tip
        (parallel-axis theorem) must have that line as an axis with moment I3 and equal moments I1 about
        every perpendicular line.

        Parameters
        ----------
        body : MassProperties
            Mass, centre of mass and inertia tensor, modelling frame.
        tip : array_like (3,)
            The fixed point, modelling frame, m.
        g : float
            Gravitational acceleration, m/s².
        rtol : float
            Relative tolerance for the symmetry check.

        Raises
        ------
        ValueError
            If the tip is at the centre of mass, or the body is not symmetric about the tip–centre line.
        """
        tip = np.asarray(tip, dtype=float).reshape(3)
        if not np.all(np.isfinite(tip)):
            raise ValueError("tip must be finite")
        d = np.asarray(body.center_of_mass, dtype=float) - tip
        ell = float(np.linalg.norm(d))
        if ell == 0.0:
            raise ValueError("the tip is at the centre of mass: gravity exerts no torque (use physics.free_body)")
        e3 = d / ell
        tensor = np.asarray(body.tensor_about(tip), dtype=float)
        I3 = float(e3 @ tensor @ e3)
        P = np.eye(3) - np.outer(e3, e3)
        I1 = float(np.trace(P @ tensor @ P)) / 2.0
        scale = float(np.max(np.abs(tensor)))
        if (
            np.max(np.abs(tensor @ e3 - I3 * e3)) > rtol * scale
            or np.max(np.abs(P @ tensor @ P - I1 * P)) > rtol * scale
        ):
            raise ValueError(
                "the body is not symmetric about the line from the tip to its centre of mass "
                f"(tensor about the tip: {tensor.tolist()})"
            )
        return cls(I1, I3, finite_scalar(body.mass, "mass") * finite_scalar(g, "g") * ell)

    def threshold_crossing_time(self, L3: float, spin_friction: float) -> float:
        """When spin friction ``−c ω3`` (see :meth:`simulate`) takes ``L3`` down to :meth:`sleeping_threshold`,
        s: ``L3(t) = L3 exp(−c t / I3)`` gives ``t* = (I3 / c) ln(L3 / L3_threshold)``
        (0 if already below; inf without friction, or when so little friction takes longer than the float
        range, 1.8e308 s)."""
        L3 = abs(finite_scalar(L3, "L3"))
        c = finite_scalar(spin_friction, "spin_friction")
        if c < 0.0:
            raise ValueError(f"spin_friction must be >= 0 (it removes energy), got {c}")
        thr = self.sleeping_threshold()
        if thr == 0.0:  # mgl = 0: no gravity, the vertical is never unstable
            return math.inf
        if L3 <= thr:
            return 0.0
        if c == 0.0:
            return math.inf
        with np.errstate(over="ignore"):
            return float(np.float64(self.I3) / c * math.log(L3 / thr))

    # ------------------------------------------------------------------ conserved quantities
    @property
    def moments(self) -> NDArray[np.float64]:
        """The principal moments about the tip, ``[I1, I1, I3]``, kg m², shape (3,) (a new array each time:
        the caller may scale it in place)."""
        return np.array([self.I1, self.I1, self.I3])

    def energy(self, R: ArrayLike, L_body: ArrayLike) -> float:
        """Total energy at an attitude and body angular momentum, J.

        ``E = ½ L·I⁻¹L + M g ℓ cos θ`` with ``cos θ = R₃₃`` (the axis ê₃ = R[:, 2] against +z): the kinetic
        energy ½ ω·L of the lecture's Euler equations plus ``V = + M g ℓ cos θ`` (docs/conventions.md).
        Constant along the exact motion (gravity's torque is horizontal and does no work about the tip).

        Parameters
        ----------
        R : array_like (3, 3)
            Body-to-space rotation.
        L_body : array_like (3,)
            Angular momentum about the tip in the body frame, kg m²/s.

        Raises
        ------
        ValueError
            If the shapes are not (3, 3) and (3,).
        """
        R, L_body = np.asarray(R, dtype=float), np.asarray(L_body, dtype=float)
        if R.shape != (3, 3) or L_body.shape != (3,):
            raise ValueError(
                f"energy needs R of shape (3, 3) and L_body of shape (3,), got {R.shape} and {L_body.shape}"
            )
        return 0.5 * float(L_body @ (L_body / self.moments)) + self.mgl * float(R[2, 2])

    def nutation_rate_squared(self, theta: float, Lz: float, L3: float, omega_body: ArrayLike) -> float:
        """θ̇², 1/s², from the body angular velocity: ``|ω⊥|² = θ̇² + sin²θ φ̇²`` with ``sin θ φ̇ =
        (Lz − L3 cos θ)/(I1 sin θ)`` (the lecture's Lz), clipped at 0 against round-off. On the vertical
        (sin θ ≤ 1e-9) the precession term is taken as 0. With :meth:`effective_potential` it gives the energy
        per I1, ``ℰ = θ̇²/2 + U(θ)``.

        Parameters
        ----------
        theta : float
            Angle of the axis from +z, rad.
        Lz, L3 : float
            Angular momentum about +z and about the axis, kg m²/s.
        omega_body : array_like (3,)
            Angular velocity in the body frame, rad/s.
        """
        w = np.asarray(omega_body, dtype=float)
        if w.shape != (3,):
            raise ValueError(f"omega_body must have shape (3,), got {w.shape}")
        s = math.sin(theta)
        phidot_s = (Lz - L3 * math.cos(theta)) / (self.I1 * s) if s > 1e-9 else 0.0
        return max(float(w[0] ** 2 + w[1] ** 2) - phidot_s**2, 0.0)

    def angular_momenta(
        self, theta: ArrayLike, phidot: ArrayLike, psidot: ArrayLike
    ) -> tuple[NDArray[np.float64], NDArray[np.float64]]:
        """``L3 = I3 (ψ̇ + φ̇ cos θ)`` and ``Lz = I1 sin²θ φ̇ + L3 cos θ`` (docs/conventions.md, erratum 3), kg m²/s.

        Parameters
        ----------
        theta, phidot, psidot : array_like (n,) or scalars
            Angle from +z (rad) and the precession and spin rates (rad/s).
        """
        theta, phidot, psidot = (
            finite_array(v, n) for v, n in ((theta, "theta"), (phidot, "phidot"), (psidot, "psidot"))
        )
        broadcast(theta=theta, phidot=phidot, psidot=psidot)
        with np.errstate(over="ignore", invalid="ignore"):  # an overflow is refused by name just below
            L3 = self.I3 * (psidot + phidot * np.cos(theta))
            Lz = self.I1 * np.sin(theta) ** 2 * phidot + L3 * np.cos(theta)
        finite_result((L3, Lz), "the angular momentum", "rates (phidot, psidot)")
        return L3, Lz

    def energy_of(
        self, theta: ArrayLike, thetadot: ArrayLike, phidot: ArrayLike, psidot: ArrayLike
    ) -> NDArray[np.float64]:
        """Total energy ``½ I1 (θ̇² + sin²θ φ̇²) + ½ I3 ω3² + M g ℓ cos θ``, J (shapes broadcast)."""
        theta, td, phidot, psidot = (
            finite_array(v, n)
            for v, n in ((theta, "theta"), (thetadot, "thetadot"), (phidot, "phidot"), (psidot, "psidot"))
        )
        broadcast(theta=theta, thetadot=td, phidot=phidot, psidot=psidot)
        w3 = psidot + phidot * np.cos(theta)
        with np.errstate(over="ignore", invalid="ignore"):  # an overflow is refused by name just below
            energy: Floats = (
                0.5 * self.I1 * (td**2 + np.sin(theta) ** 2 * phidot**2)
                + 0.5 * self.I3 * w3**2
                + self.mgl * np.cos(theta)
            )
        finite_result(energy, "the energy", "rates (thetadot, phidot, psidot)")
        return energy

    @staticmethod
    def _potential_arguments(theta: ArrayLike, Lz: float, L3: float) -> tuple[NDArray[np.float64], float, float]:
        theta = finite_array(theta, "theta")
        if np.any((theta < 0.0) | (theta > math.pi)):
            raise ValueError("theta is the angle of the axis from +z and must lie in [0, pi]")
        return theta, bounded_scalar(Lz, "Lz"), bounded_scalar(L3, "L3")

    def effective_potential(self, theta: ArrayLike, Lz: float, L3: float) -> NDArray[np.float64]:
        """The lecture's effective potential per I1,
        ``U(θ) = (Lz − L3 cos θ)² / (2 I1² sin²θ) + (M g ℓ / I1) cos θ``, 1/s² (θ̈ = −dU/dθ).

        Parameters
        ----------
        theta : array_like (n,)
            Angle of the axis from +z, rad. At θ = 0 (π) the limit is returned when ``Lz = L3``
            (``Lz = −L3``); otherwise U is +inf there.
        Lz, L3 : float
            Conserved angular momenta, kg m²/s.
        """
        theta, Lz, L3 = self._potential_arguments(theta, Lz, L3)
        i1 = self.I1
        half_lo = np.sin(0.5 * theta) ** 2  # (1 − cos θ)/2 without cancellation
        half_hi = np.cos(0.5 * theta) ** 2
        # Lz − L3 cos θ = (Lz − L3) + 2 L3 sin²(θ/2); partial fractions remove the 0/0 at the poles.
        dm, dp = Lz - L3, Lz + L3
        with np.errstate(divide="ignore", invalid="ignore"):
            t1 = np.where(dm == 0.0, 0.0, dm**2 / (8.0 * i1**2 * half_lo))
            t2 = np.where(dp == 0.0, 0.0, dp**2 / (8.0 * i1**2 * half_hi))
        # (Lz − L3 u)²/(1 − u²) = dm²/(2(1−u)) + dp²/(2(1+u)) − ... exactly:
        # (Lz − L3 u)² / (1 − u²) = dm²/(2(1−u)) + dp²/(2(1+u)) − L3², dm, dp = Lz ∓ L3.
        return t1 + t2 - L3**2 / (2.0 * i1**2) + (self.mgl / i1) * np.cos(theta)

    def effective_potential_derivative(self, theta: ArrayLike, Lz: float, L3: float) -> NDArray[np.float64]:
        """``dU/dθ`` of :meth:`effective_potential`, 1/s²; ``θ̈ = −dU/dθ`` (lecture's θ equation).

        ``dU/dθ = (Lz − L3 cos θ)(L3 sin²θ − cos θ (Lz − L3 cos θ)) / (I1² sin³θ) − (Mgℓ/I1) sin θ``.
        """
        theta, Lz, L3 = self._potential_arguments(theta, Lz, L3)
        i1 = self.I1
        s2, c2 = np.sin(0.5 * theta) ** 2, np.cos(0.5 * theta) ** 2
        dm, dp = Lz - L3, Lz + L3
        # From the partial-fraction form U = dm²/(8 I1² s2) + dp²/(8 I1² c2) + const + a cos θ:
        # d(s2)/dθ = sin θ / 2, d(c2)/dθ = −sin θ / 2.
        st = np.sin(theta)
        with np.errstate(divide="ignore", invalid="ignore"):
            d1 = np.where(dm == 0.0, 0.0, -(dm**2) * st / (16.0 * i1**2 * s2**2))
            d2 = np.where(dp == 0.0, 0.0, dp**2 * st / (16.0 * i1**2 * c2**2))
        return d1 + d2 - (self.mgl / i1) * st

    def sleeping_threshold(self) -> float:
        """Least spin angular momentum ``L3 = 2 sqrt(M g ℓ I1)`` for which the vertical spin is stable,
        kg m²/s (lecture: U''(0) = L3²/(4 I1²) − Mgℓ/I1 changes sign there)."""
        product = self.mgl * self.I1
        if math.isfinite(product):
            return 2.0 * math.sqrt(product)
        return 2.0 * math.sqrt(self.mgl) * math.sqrt(self.I1)  # mgl I1 overflows where its root does not

    def below_sleeping_threshold(self, L3: float) -> bool:
        """True when ``|L3|`` is at or below :meth:`sleeping_threshold`: the vertical spin is unstable
        (U''(0) ≤ 0), a top set upright topples from any small tilt.

        Parameters
        ----------
        L3 : float
            Angular momentum about the symmetry axis, kg m²/s.
        """
        return abs(finite_scalar(L3, "L3")) <= self.sleeping_threshold()

    def vertical_curvature(self, L3: float) -> float:
        """``U''(0) = L3²/(4 I1²) − M g ℓ / I1`` for a top spinning about the vertical (Lz = L3), 1/s²."""
        L3 = bounded_scalar(L3, "L3")
        curvature = (L3 / (2.0 * self.I1)) ** 2 - self.mgl / self.I1
        finite_result(curvature, "U''(0)", "values of L3 and the moments")
        return curvature

    def steady_precession_rates(self, theta: float, L3: float) -> tuple[float, float]:
        """The slow and the fast rate φ̇ of steady precession at angle θ, rad/s.

        With θ̇ = θ̈ = 0 the θ equation gives ``I1 cos θ φ̇² − L3 φ̇ + M g ℓ = 0``. The slow root tends to
        ``M g ℓ / L3`` for a fast top. For θ = π/2 only the slow rate exists (the fast one is returned as
        ±inf); for θ > π/2 the second root is negative. Start a steady precession with
        ``thetadot0 = 0, phidot0 = rate, psidot0 = L3/I3 − rate cos θ``.

        Raises
        ------
        ValueError
            If the spin is too slow: ``L3² < 4 I1 M g ℓ cos θ`` (no steady precession at that θ).
        """
        theta = finite_scalar(theta, "theta")
        L3 = bounded_scalar(L3, "L3")
        if not 0.0 < theta < math.pi:
            raise ValueError(f"steady precession needs 0 < theta < pi, got theta = {theta}")
        ct = math.cos(theta)
        disc = L3 * L3 - 4.0 * self.I1 * self.mgl * ct
        if disc < 0.0:
            raise ValueError(
                f"no steady precession at theta = {theta}: L3 = {L3} is below 2 sqrt(I1 M g l cos theta) = "
                f"{2 * math.sqrt(self.I1 * self.mgl * ct)}"
            )
        q = 0.5 * (L3 + math.copysign(math.sqrt(disc), L3 if L3 != 0.0 else 1.0))
        slow = self.mgl / q
        fast = q / (self.I1 * ct) if ct != 0.0 else math.copysign(math.inf, q)
        return (slow, fast) if abs(slow) <= abs(fast) else (fast, slow)

    # ------------------------------------------------------------------ the exact motion
    def _motion(
        self,
        theta0: float,
        thetadot0: float,
        phidot0: float,
        psidot0: float,
        phi0: float = 0.0,
        psi0: float = 0.0,
    ) -> Motion:
        # The motion depends on I3/I1 and M g ℓ/I1 only: computed for the moments scaled by a power of two
        # (exactly) to order 1, then L3, Lz and E scaled back, so that 1e-300 or 1e300 kg m² work alike.
        exponent = math.frexp(self.I1)[1]
        scaled = ScaledTop(*(math.ldexp(x, -exponent) for x in (self.I1, self.I3, self.mgl)))
        motion = motion_constants(scaled, theta0, thetadot0, phidot0, psidot0, phi0, psi0)
        motion.L3, motion.Lz = math.ldexp(motion.L3, exponent), math.ldexp(motion.Lz, exponent)
        motion.energy = math.ldexp(motion.energy, exponent)
        return motion

    def trajectory(
        self, theta0: float, thetadot0: float, phidot0: float, psidot0: float, *, phi0: float = 0.0, psi0: float = 0.0
    ) -> HeavyTopTrajectory:
        """The exact motion from these initial Euler angles and rates, solved once: evaluate it with
        :meth:`HeavyTopTrajectory.at` at any times.

        Parameters
        ----------
        theta0 : float
            Initial angle of the axis from +z, rad: 0, or in [1e-100, π] (see the module's Limits).
        thetadot0, phidot0, psidot0 : float
            Initial θ̇, φ̇, ψ̇, rad/s, each at most 1e100 in magnitude. At θ0 = 0 only ``phidot0 + psidot0``
            matters (the spin ω3), and at or below the sleeping threshold ``thetadot0`` must be 0 or at least
            1e-100 of the top's own rate (above it a smaller one is taken as 0).
        phi0, psi0 : float, keyword-only
            Initial precession and spin angles, rad.

        Returns
        -------
        HeavyTopTrajectory

        Raises
        ------
        ValueError
            Naming the argument: not finite, θ0 outside [0, π] or within 1e-100 rad of the vertical without
            being on it, a rate beyond 1e100 rad/s, or from θ0 = 0 at or below the sleeping threshold a θ̇0
            below 1e-100 of the top's own rate.

        Examples
        --------
        >>> top = HeavyTop(1.0, 0.5, 2.0)
        >>> motion = top.trajectory(0.5, 0.0, 0.0, 20.0)
        >>> float(motion.at(0.0).theta)
        0.5
        """
        return HeavyTopTrajectory(self, self._motion(theta0, thetadot0, phidot0, psidot0, phi0, psi0))

    # Questions about one motion: its trajectory answers them (these take the same initial data).
    def nutation_cubic(self, theta0: float, thetadot0: float, phidot0: float, psidot0: float) -> NutationCubic | None:
        """:attr:`HeavyTopTrajectory.nutation_cubic` of the motion from these initial data."""
        return self.trajectory(theta0, thetadot0, phidot0, psidot0).nutation_cubic

    def turning_points(self, theta0: float, thetadot0: float, phidot0: float, psidot0: float) -> tuple[float, float]:
        """:attr:`HeavyTopTrajectory.turning_points` ``(θ_min, θ_max)``, rad, of the motion from these data."""
        return self.trajectory(theta0, thetadot0, phidot0, psidot0).turning_points

    def conserved_quantities(self, theta0: float, thetadot0: float, phidot0: float, psidot0: float) -> dict[str, float]:
        """``{"L3", "Lz", "energy"}`` from the initial data (kg m²/s, kg m²/s, J)."""
        motion = self.trajectory(theta0, thetadot0, phidot0, psidot0)
        return {"L3": motion.L3, "Lz": motion.Lz, "energy": motion.energy}

    def nutation_period(self, theta0: float, thetadot0: float, phidot0: float, psidot0: float) -> float:
        """:attr:`HeavyTopTrajectory.nutation_period` of the motion from these initial data, s."""
        return self.trajectory(theta0, thetadot0, phidot0, psidot0).nutation_period

    def precession_rate(self, theta0: float, thetadot0: float, phidot0: float, psidot0: float) -> float:
        """:attr:`HeavyTopTrajectory.precession_rate` of the motion from these initial data, rad/s."""
        return self.trajectory(theta0, thetadot0, phidot0, psidot0).precession_rate

    def solve(
        self,
        theta0: float,
        thetadot0: float,
        phidot0: float,
        psidot0: float,
        t: ArrayLike,
        *,
        phi0: float = 0.0,
        psi0: float = 0.0,
    ) -> HeavyTopSolution:
        """Exact motion of the top from the given initial Euler angles and rates.

        ``u = cos θ = u1 + (u2 − u1) sn²(λ t + c | m)``; φ(t), ψ(t) in closed form through the incomplete
        elliptic integral of the third kind (Carlson R_J). Vectorised over t; negative t allowed.

        Parameters
        ----------
        theta0 : float
            Initial angle of the axis from +z, rad: 0, or in [1e-100, π] (see the module's Limits).
        thetadot0, phidot0, psidot0 : float
            Initial θ̇, φ̇, ψ̇, rad/s, each at most 1e100 in magnitude. At θ0 = 0 only ``phidot0 + psidot0``
            matters (the spin ω3), and at or below the sleeping threshold ``thetadot0`` must be 0 or at least
            1e-100 of the top's own rate (above it a smaller one is taken as 0).
        t : array_like (n,)
            Times, s.
        phi0, psi0 : float, keyword-only
            Initial precession and spin angles, rad.

        Returns
        -------
        HeavyTopSolution
        """
        return self.trajectory(theta0, thetadot0, phidot0, psidot0, phi0=phi0, psi0=psi0).at(times_array(t))

    def simulate(
        self,
        theta0: float,
        thetadot0: float,
        phidot0: float,
        psidot0: float,
        t_final: float,
        dt: float,
        *,
        spin_friction: float = 0.0,
        air_drag: float = 0.0,
        method: str | type = "LieRK4",
        save_every: int = 1,
        phi0: float = 0.0,
        psi0: float = 0.0,
    ) -> SteppedRun:
        """The top with friction, integrated step by step on (R, L_body) by :mod:`physics.integrators`.

        Friction model (both at the tip, both only remove energy):

        * spin friction at the tip: body torque ``−c ω3 e3`` about the symmetry axis
          (:class:`physics.integrators.SpinFriction`), so ``dL3/dt = −c L3 / I3`` and
          ``dE/dt = −c ω3² ≤ 0``; L3 decays as ``exp(−c t / I3)``;
        * optional air drag on the wobble: ``−c_air (ω1, ω2, 0)`` (:class:`TransverseAirDrag`),
          ``dE/dt = −c_air (ω1² + ω2²)``.

        The lecture's story: a sleeping top (θ0 ≈ 0) with ``L3 > 2 sqrt(M g ℓ I1)`` stays up; as friction
        takes L3 below :meth:`sleeping_threshold` the vertical turns unstable (U''(0) < 0), the top starts
        to wobble and falls. No Euler angles are integrated, so θ = 0 and θ = π/2 are ordinary points.

        Parameters
        ----------
        theta0, thetadot0, phidot0, psidot0 : float
            Initial Euler angle θ (rad, in [0, π]) and rates (rad/s), as in :meth:`solve`.
        t_final, dt : float
            Duration and step, s (the step is shortened to fit a whole number of steps).
        spin_friction : float
            ``c ≥ 0``, N m s.
        air_drag : float
            ``c_air ≥ 0``, N m s.
        method : str or integrator class
            ``"LieRK4"`` (default), ``"Yoshida4"``, ``"LiePoissonStrang"`` or ``"ExactFreeSplitting"``.
        save_every : int
            Keep every this many steps.
        phi0, psi0 : float
            Initial precession and spin angles, rad.

        Returns
        -------
        SteppedRun
        """
        return simulate_symmetric(
            self,
            theta0,
            thetadot0,
            phidot0,
            psidot0,
            t_final,
            dt,
            spin_friction,
            air_drag,
            method,
            save_every,
            phi0,
            psi0,
        )
