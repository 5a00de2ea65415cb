"""The torque-free rigid body in closed form: ``ω(t)`` and ``R(t)`` at any times, its exact flow, the
stability of uniform rotation and the precession rates of a symmetric body.

:class:`FreeBody` is the model; the constants of one motion and their evaluation are in
:mod:`physics.free_body_motion`, one motion evaluated at any times in :mod:`physics.free_body_trajectory`.
The method (Jacobi functions from ``m`` and ``1 − m``, Carlson's ``R_J``) and its measured accuracy are in
docs/physics-notes.md.
"""

from __future__ import annotations

import math
from dataclasses import dataclass
from typing import Literal

import numpy as np
from numpy.typing import ArrayLike, NDArray

from physics.elliptic import jacobi_sn_cn_dn
from physics.free_body_motion import (
    MotionConstants,
    check_attitude0,
    check_omega0,
    check_times,
    evaluate,
    motion_constants,
)
from physics.free_body_trajectory import FreeBodyState, FreeBodyTrajectory
from physics.inertia import validate_moments
from physics.validation import (
    MAX_RATE,
    bounded_scalar,
    finite_array,
    finite_result,
    rotation_array,
    vector_array,
)

Floats = NDArray[np.float64]

__all__ = [
    "FreeBody",
    "FreeBodyState",
    "FreeBodyTrajectory",
    "Stability",
    "PrecessionRates",
    "jacobi_sn_cn_dn",
]


# ---------------------------------------------------------------------------------------------------
# Results
# ---------------------------------------------------------------------------------------------------
@dataclass(frozen=True)
class Stability:
    """Linear stability of uniform rotation about one principal axis (lecture, last part of the
    free-body section: ``η̈2 = −[Ω² (I1 − I2)(I1 − I3) / (I2 I3)] η2``).

    Attributes
    ----------
    kind : {"stable", "unstable", "neutral"}
        Bracket positive: small wobbles oscillate; negative: they grow exponentially (the intermediate
        axis); zero: two moments equal, perturbations neither oscillate nor grow exponentially.
    rate : float
        ``|Ω| sqrt(|(I_i − I_j)(I_i − I_k) / (I_j I_k)|)``: the angular frequency of the oscillation
        (rad/s) when stable, the exponential growth rate (1/s) when unstable, 0 when neutral.
    """

    kind: Literal["stable", "unstable", "neutral"]
    rate: float


@dataclass(frozen=True)
class PrecessionRates:
    """Precession of a symmetric body (lecture: ``Ω = ω3 (I1 − I3)/I1``, ``φ̇ = L/I1``).

    Attributes
    ----------
    body : float
        ``Ω``, rad/s: ω turns about the symmetry axis, seen in the body, as
        ``(ω1, ω2) = ω⊥ (sin Ω t, cos Ω t)``.
    space : float
        ``φ̇ = L / I_⊥``, rad/s: the symmetry axis turns about the fixed ``L`` in space.
    symmetry_axis : int
        Index (0, 1, 2) of the body axis whose moment differs from the other two.
    """

    body: float
    space: float
    symmetry_axis: int


# ---------------------------------------------------------------------------------------------------
# The body
# ---------------------------------------------------------------------------------------------------
def _lamina_within_slack(moments: Floats) -> Floats:
    """The moments with a largest one above the sum of the other two (inside the triangle inequality's
    round-off slack, which :func:`physics.inertia.validate_moments` accepts) lowered to that sum.

    No rigid body has ``I_max > I_j + I_k``; the closed form's constants (``n``, the amplitudes) assume it
    and lose every digit when it fails by more than the third moment (``FreeBody([1, 1 + 1e-13, 1e-300])``
    gave ``ω(0) = (0.5, 0.3, 3.6e127)`` for ``ω0 = (0.5, 0.3, 0.2)``). The lamina is what the slack stands for.
    """
    out = np.array(moments, dtype=float)
    big = int(np.argmax(out))
    rest = float(out[(big + 1) % 3] + out[(big + 2) % 3])
    if out[big] > rest:
        out[big] = rest
    return out


class FreeBody:
    """A rigid body without torque, solved exactly (see the module docstring for the method).

    Parameters
    ----------
    moments : array_like, shape (3,)
        Principal moments of inertia about the centre of mass, kg m², in the order of the body axes
        (any order). Validated by :func:`physics.inertia.validate_moments` (triangle inequality; one
        zero moment is a rod). A largest moment above the sum of the other two by less than the
        validation's slack (1e-12 relative, round-off) is taken as that sum: the flat lamina those
        moments round (``moments`` then holds the clamped value; with a zero or tiny third moment the
        body is the symmetric lamina or the rod).

    Attributes
    ----------
    moments : ndarray, shape (3,)
        The principal moments, kg m².
    symmetry_axis : int
        The body axis of a symmetric body (two equal moments), 0 for a sphere, -1 for a triaxial body.

    Raises
    ------
    ValueError
        Impossible moments ("no rigid body has these moments: ..."), or all zero.

    Notes
    -----
    Methods: :meth:`omega`, :meth:`attitude`, :meth:`motion` (both at once), :meth:`energy`,
    :meth:`angular_momentum` (space), :meth:`angular_momentum_body`, :meth:`flow` (batched exact step
    of ``(R, L_body)``), :meth:`stability`, :meth:`precession_rates`, :meth:`elliptic_parameter`,
    :meth:`period`. Times may be negative; every result is exact up to rounding (module docstring).
    """

    def __init__(self, moments: ArrayLike) -> None:
        self.moments = _lamina_within_slack(validate_moments(moments))
        self._cache: tuple[bytes, MotionConstants] | None = None
        inertia = self.moments
        order = np.argsort(-inertia, kind="stable")
        perm = np.eye(3)[order]
        # Sorting must be a proper rotation so that Euler's equations keep their cyclic form.
        self._q_sort = perm if np.linalg.det(perm) > 0 else -perm
        # The motion depends on the moments' ratios only: the sorted moments are scaled by a power of two
        # (exactly) to order 1, so that the invariants' squares neither overflow nor underflow.
        self._sorted = np.ldexp(inertia[order], -math.frexp(float(inertia.max()))[1])
        i1, i2, i3 = self._sorted
        if i1 == i3:
            self._kind, self.symmetry_axis = "spherical", 0
        elif i1 == i2 or i2 == i3:
            self._kind = "symmetric"
            self.symmetry_axis = int(order[2] if i1 == i2 else order[0])
        else:
            self._kind, self.symmetry_axis = "triaxial", -1

    # --- invariants --------------------------------------------------------------------------------
    def energy(self, omega0: ArrayLike) -> float:
        """Kinetic energy ``E = ½ Σ I_i ω_i²``, J (constant in time).

        Parameters
        ----------
        omega0 : array_like, shape (3,)
            Body-frame angular velocity, rad/s.
        """
        w = check_omega0(omega0)
        with np.errstate(over="ignore"):  # an overflow is refused by name just below
            energy = float(0.5 * np.sum(self.moments * w * w))
        finite_result(energy, "the energy", "values of omega0 and the moments")
        return energy

    def angular_momentum_body(self, omega0: ArrayLike) -> NDArray[np.float64]:
        """Angular momentum in body axes ``L_body = I ω``, kg m²/s, shape (3,)."""
        return self.moments * check_omega0(omega0)

    def angular_momentum(self, omega0: ArrayLike, attitude0: ArrayLike | None = None) -> NDArray[np.float64]:
        """Spatial angular momentum ``L_space = R I ω``, kg m²/s, shape (3,) (constant in time).

        Parameters
        ----------
        omega0 : array_like, shape (3,)
            Body-frame angular velocity at the same instant as ``attitude0``, rad/s.
        attitude0 : array_like, shape (3, 3), optional
            Body-to-space rotation at that instant; default identity.
        """
        r0 = check_attitude0(attitude0)
        return r0 @ self.angular_momentum_body(omega0)

    def elliptic_parameter(self, omega0: ArrayLike) -> tuple[float, float]:
        """The parameter ``m`` of the Jacobi functions and ``1 − m`` (computed without cancellation).

        ``1 − m = 0`` on the separatrix ``L² = 2 E I2`` (and where it is below the float range, 1e-308: a
        push below about 1e-154 off the intermediate axis; the motion still uses its exact size, see
        :meth:`period`); ``m = 0`` for a symmetric or spherical body and for uniform rotation about a
        principal axis.

        Parameters
        ----------
        omega0 : array_like, shape (3,)
            Body-frame angular velocity, rad/s.

        Returns
        -------
        (m, 1 − m) : tuple of float
        """
        p = self._solve(check_omega0(omega0)[None, :])
        if p.kind[0] != 2:
            return 0.0, 1.0
        return float(p.m[0]), float(p.mc[0])

    def period(self, omega0: ArrayLike) -> float:
        """Period of ``ω(t)`` in the body, s: ``4K/|λ|`` (``2π/|Ω|`` if symmetric).

        Infinite for uniform rotation about a principal axis, for a sphere, and on the separatrix.
        """
        w = check_omega0(omega0)
        p = self._solve(w[None, :])
        kind = p.kind[0]
        if kind == 2:
            return float(4.0 * p.K[0] / abs(p.lam[0]))  # K = ∞ on the separatrix
        if kind == 1 and p.Omega[0] != 0.0:
            return float(2.0 * np.pi / abs(p.Omega[0]))
        return np.inf

    # --- setup per initial state (vectorised over states) -------------------------------------------
    # --- evaluation ---------------------------------------------------------------------------------
    def motion(
        self, omega0: ArrayLike, t: ArrayLike, attitude0: ArrayLike | None = None
    ) -> tuple[NDArray[np.float64], NDArray[np.float64]]:
        """Angular velocity and attitude at the times ``t`` (both at once, sharing the work).

        Parameters
        ----------
        omega0 : array_like, shape (3,)
            Body-frame angular velocity at ``t = 0``, rad/s.
        t : array_like, shape (n,) or scalar
            Times, s (any sign, any order). A scalar counts as ``n = 1``.
        attitude0 : array_like, shape (3, 3), optional
            Body-to-space rotation at ``t = 0``; default identity.

        Returns
        -------
        omega : ndarray, shape (n, 3)
            Body-frame angular velocity, rad/s.
        attitude : ndarray, shape (n, 3, 3)
            Body-to-space rotations ``R(t)``.
        """
        state = self.trajectory(omega0, attitude0).at(check_times(t))
        return state.omega, state.attitude

    def omega(self, omega0: ArrayLike, t: ArrayLike) -> NDArray[np.float64]:
        """Body-frame angular velocity ``ω(t)`` solving Euler's equations exactly.

        Parameters
        ----------
        omega0 : array_like, shape (3,)
            ``ω(0)`` in body axes, rad/s.
        t : array_like, shape (n,) or scalar
            Times, s (negative allowed). A scalar counts as ``n = 1``.

        Returns
        -------
        ndarray, shape (n, 3)
            ``ω(t)``, rad/s.
        """
        w = check_omega0(omega0)[None, :]
        tt = check_times(t)
        which = np.zeros(tt.shape, dtype=int)
        return evaluate(self.constants(w), self.moments, self.symmetry_axis, w, tt, None, which, want_attitude=False)[0]

    def attitude(self, omega0: ArrayLike, t: ArrayLike, attitude0: ArrayLike | None = None) -> NDArray[np.float64]:
        """Body-to-space rotations ``R(t)`` with ``Ṙ = R hat(ω)`` and ``R(0) = attitude0``.

        Parameters
        ----------
        omega0 : array_like, shape (3,)
            ``ω(0)`` in body axes, rad/s.
        t : array_like, shape (n,) or scalar
            Times, s (negative allowed). A scalar counts as ``n = 1``.
        attitude0 : array_like, shape (3, 3), optional
            ``R(0)``; default identity.

        Returns
        -------
        ndarray, shape (n, 3, 3)
        """
        return self.motion(omega0, t, attitude0)[1]

    def trajectory(self, omega0: ArrayLike, attitude0: ArrayLike | None = None) -> FreeBodyTrajectory:
        """The motion from ``ω(0) = omega0`` (rad/s, body axes, shape (3,)) and ``R(0) = attitude0``
        ((3, 3), default identity), solved once: evaluate it with :meth:`FreeBodyTrajectory.at`."""
        return FreeBodyTrajectory(self, omega0, attitude0)

    def flow(
        self, attitude: ArrayLike, L_body: ArrayLike, dt: ArrayLike
    ) -> tuple[NDArray[np.float64], NDArray[np.float64]]:
        """Advance many free-body states by ``dt`` exactly (the exact flow map, batched).

        The state is ``(R, L_body)``: attitude and body-frame angular momentum; ``ω = L_body / I``. For
        a rod the component of ω along its own axis is not part of this state (it carries no L) and is
        taken as 0. Useful as the torque-free sub-step of a splitting integrator.

        Parameters
        ----------
        attitude : array_like, shape (k, 3, 3) or (3, 3)
            Body-to-space rotations.
        L_body : array_like, shape (k, 3) or (3,)
            Angular momentum in body axes, kg m²/s.
        dt : float or array_like, shape (k,)
            Time step(s), s (any sign). An unbatched attitude or L_body is shared by all k states; the
            batched arguments must agree on k (else ValueError naming them).

        Returns
        -------
        attitude : ndarray, shape (k, 3, 3)
        L_body : ndarray, shape (k, 3)
        """
        r = rotation_array(attitude, "attitude")
        lb = vector_array(L_body, "L_body")
        step = finite_array(dt, "dt")
        if step.ndim > 1:
            raise ValueError(f"dt must be one time step or shape (k,), one per state, got shape {step.shape}")
        # The batch size k: from whichever argument is batched; all batched ones must agree.
        sizes = {
            name: a.shape[0] for name, a, n in (("attitude", r, 3), ("L_body", lb, 2), ("dt", step, 1)) if a.ndim == n
        }
        if len(set(sizes.values())) > 1:
            given = ", ".join(f"{name} {k}" for name, k in sizes.items())
            raise ValueError(
                "attitude (k, 3, 3), L_body (k, 3) and dt (k,) must hold the same number k of states where "
                f"they are batched; got {given}"
            )
        if list(sizes) == ["dt"] and sizes["dt"] != 1:
            raise ValueError(
                f"dt has {sizes['dt']} steps for one state: dt must be one number, or shape (k,) when attitude "
                "(k, 3, 3) or L_body (k, 3) holds k states"
            )
        k = next(iter(sizes.values()), 1)
        r = np.broadcast_to(r.reshape(-1, 3, 3), (k, 3, 3))
        lb = np.broadcast_to(lb.reshape(-1, 3), (k, 3))
        step = np.broadcast_to(step.reshape(-1), (k,))
        zero = self.moments == 0.0
        if np.any(zero) and np.any(np.abs(lb[:, zero]) > 1e-12 * np.linalg.norm(lb, axis=1)[:, None]):
            raise ValueError("a rod has no angular momentum along its own axis: L_body must be 0 there")
        safe = np.where(self.moments > 0.0, self.moments, 1.0)
        w = np.where(self.moments > 0.0, lb / safe, 0.0)
        p = self.constants(w)
        om, rr = evaluate(
            p, self.moments, self.symmetry_axis, w, step, r, np.arange(k), want_attitude=True, time_name="dt"
        )
        return rr, om * self.moments

    def _solve(self, w: Floats) -> MotionConstants:
        return motion_constants(self.moments, self._sorted, self._q_sort, self.symmetry_axis, w)

    def constants(self, w: Floats) -> MotionConstants:
        """The constants of the motions from the initial angular velocities ``w`` (k, 3), rad/s
        (:func:`physics.free_body_motion.motion_constants`); remembered for the last single initial state
        (repeated calls of the wrappers with the same ω0 do not redo them)."""
        if w.shape[0] != 1:
            return self._solve(w)
        key = w.tobytes()
        cached = self._cache
        if cached is not None and cached[0] == key:
            return cached[1]
        p = self._solve(w)
        self._cache = (key, p)
        return p

    # --- stability and precession -------------------------------------------------------------------
    def stability(self, axis_index: int, spin_rate: float) -> Stability:
        """Linear stability of uniform rotation at ``spin_rate`` about body axis ``axis_index``.

        Lecture's linearisation: ``η̈ = −[Ω² (I_i − I_j)(I_i − I_k) / (I_j I_k)] η``. Positive bracket:
        stable (largest or smallest moment), small wobbles oscillate at ``sqrt(bracket)``; negative:
        unstable (intermediate moment), they grow like ``exp(sqrt(−bracket) t)``; zero: neutral.

        Parameters
        ----------
        axis_index : int
            0, 1 or 2: the body axis (principal axis in the order of ``moments``).
        spin_rate : float
            Ω, rad/s.

        Returns
        -------
        Stability
            ``kind`` and ``rate`` (rad/s for an oscillation, 1/s for growth, 0 if neutral or Ω = 0).
        """
        if isinstance(axis_index, bool) or not isinstance(axis_index, (int, np.integer)) or not 0 <= axis_index <= 2:
            raise ValueError(f"axis_index must be 0, 1 or 2 (a principal axis), got {axis_index!r}")
        omega = bounded_scalar(spin_rate, "spin_rate", MAX_RATE)
        i = self.moments[axis_index]
        ij, ik = self.moments[(axis_index + 1) % 3], self.moments[(axis_index + 2) % 3]
        numerator = (i - ij) * (i - ik)
        if numerator == 0.0:
            # Two equal moments (or a rod spun about a transverse axis): no restoring, no exponential growth.
            return Stability("neutral", 0.0)
        # ij * ik > 0 here: a zero moment belongs to a rod, whose two other moments are equal.
        # The kind depends on the moments only; the rate scales with |Ω| (0 when not spinning).
        # |Ω| sqrt(|(I − Ij)(I − Ik)| / (Ij Ik)): the square root taken before the rate multiplies it (no overflow).
        rate = abs(omega) * math.sqrt(abs(numerator) / (ij * ik))
        return Stability("stable" if numerator > 0 else "unstable", rate)

    def precession_rates(self, omega0: ArrayLike) -> PrecessionRates:
        """Body- and space-frame precession rates of a symmetric body (two equal moments).

        Lecture: ``Ω = ω3 (I1 − I3) / I1`` (ω turning about the symmetry axis in the body) and
        ``φ̇ = L / I1`` (the symmetry axis turning about L in space), with ``I1`` the repeated moment and
        3 the symmetry axis.

        Parameters
        ----------
        omega0 : array_like, shape (3,)
            Body-frame angular velocity, rad/s.

        Raises
        ------
        ValueError
            If no two moments are equal (the motion is then not a uniform precession).
        """
        w = check_omega0(omega0)
        if self._kind == "triaxial":
            raise ValueError(
                f"precession rates need a symmetric body (two equal moments); these moments "
                f"{self.moments.tolist()} are all different"
            )
        s = self.symmetry_axis
        i_perp = self.moments[(s + 1) % 3]
        big_l = float(np.linalg.norm(self.moments * w))
        return PrecessionRates(float(w[s] * (i_perp - self.moments[s]) / i_perp), float(big_l / i_perp), s)
