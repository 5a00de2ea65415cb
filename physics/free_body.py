"""The torque-free rigid body, in closed form.

A body with no torque about its centre of mass obeys Euler's equations (lecture, "Euler's equations")

    I1 ω̇1 = ω2 ω3 (I2 − I3),   I2 ω̇2 = ω3 ω1 (I3 − I1),   I3 ω̇3 = ω1 ω2 (I1 − I2),

and its attitude ``R`` (body to space) obeys ``Ṙ = R hat(ω)``. The energy ``E = ½ Σ I_i ω_i²`` and the
spatial angular momentum ``L_space = R I ω`` are constant. Everything here is evaluated in closed form
at any time (also negative), vectorised over the times, never step by step:

* ``ω(t)`` by Jacobi elliptic functions. Let ``a`` be the principal axis that the angular momentum
  circulates around (the largest moment if ``L² > 2 E I2``, the smallest if ``L² < 2 E I2``; the
  middle axis is ``b``, the third ``c``). Then ``ω_a = ± A_a dn(u|m)``, ``ω_b = A_b sn(u|m)``,
  ``ω_c = A_c cn(u|m)`` with ``u = λ t + u0`` and, writing ``G_x = |L² − 2 E I_x|``,
  ``m = (I_b − I_c) G_a / ((I_a − I_b) G_c)``, ``1 − m = (I_a − I_c) G_b / ((I_a − I_b) G_c)``,
  ``λ² = (I_a − I_b) G_c / (I_a I_b I_c)`` (Landau & Lifshitz, Mechanics §37).
* The attitude as ``R(t) = Rot(L̂_space, ψ(t) − ψ(0)) R(0) B(0) B(t)ᵀ``, where the columns of ``B(t)``
  (body coordinates) are ``e_p × L̂``, ``L̂ × (e_p × L̂)`` (normalised) and ``L̂ = I ω / L`` for a pole
  ``p`` (``a`` or ``c``, see below). The angle
  turned about ``L`` obeys ``ψ̇ = L (2E − L_p ω_p) / (L² − L_p²)``, which integrates to the elliptic
  integral of the third kind ``Π(n; am u | m)``; for the pole ``a``,
  ``n = −I_a (I_b − I_c) / (I_c (I_a − I_b)) ≤ 0``. It is evaluated through Carlson's ``R_J``
  (:func:`scipy.special.elliprj`; ``u0`` through ``R_F``).
* A body with two equal moments ("symmetric", the lecture's case ``I1 = I2``) uses the lecture's
  trigonometric solution: ``ω_⊥`` turns about the symmetry axis ``s`` in the body at
  ``Ω = ω_s (I_⊥ − I_s) / I_⊥`` and the body turns about ``L`` at ``φ̇ = L / I_⊥``; exactly
  ``R(t) = exp(t hat(L_space) / I_⊥) R(0) exp(t Ω hat(e_s))``. A sphere is the case ``Ω = 0``.
* A rod (one moment zero, the other two equal) is a symmetric body with ``I_s = 0``. Spin about the
  rod's own axis is kinematic: that component of ω carries no angular momentum and no energy, Euler's
  third equation reads ``0 = 0``, and we define it to stay constant. It then only turns the body frame
  about the rod (the rod itself moves the same whatever its value).

Accuracy
--------
Differences of the invariants (``L² − 2 E I_x``) are formed in double-double arithmetic from the
moments and ``ω0`` as given, so ``1 − m`` keeps full relative precision down to the separatrix
(``1 − m → 0``) instead of losing ``log10(1/(1 − m))`` digits to cancellation. The Jacobi functions are
our own (descending Gauss–Landen transformation, A&S 16.12, driven by ``m`` *and* ``1 − m``), after
reducing ``u`` modulo the period ``4K`` and, above ``K/2``, shifting by the quarter period; scipy's
``ellipj`` takes only ``m`` and is wrong near ``m = 1`` for large arguments (scipy issue 8480). The
separatrix itself (``m = 1``) uses ``tanh``/``sech`` and the elementary ``Π(n; ·|1)``.

Each ``G_x`` is a quadratic form in two components of ω and is formed from that pair scaled by a power of
two to order 1, so no square underflows: a push ``ε`` off the intermediate axis has ``1 − m ∝ ε²``, which
leaves the float range below ``ε ≈ 1e-154``. The complementary modulus ``k' = √(1 − m) ∝ ε`` is kept
instead, with its logarithm exact in the exponent, and within ``1 − m < 1e-40`` of the separatrix the
motion is evaluated as what it is to double precision there, the separatrix's pulses ``2K`` apart with
``K = ln(4/k')``, ``cn(K − w) = k' sinh w``, ``dn(K − w) = k' cosh w`` (see ``_LOG_KP_DEEP``). Only ω
exactly along a principal axis is uniform rotation (until issue 15 a component below 1e-140 of the largest
counted as 0: a push of 1e-150 about the intermediate axis reversed ω after ~1000 s).

Measured against mpmath at 30 digits, and near the separatrix at 30 more than ``1 − m`` has zeros
(``python -m tests.physics.test_free_body_reference`` prints the table; tests/physics/test_free_body.py
asserts the bounds), over ±1,000 rotation periods ``2π/|ω0|``: the relative error of ω is at most 3e-13
and the attitude error at most 3e-12 rad in every regime, including ``1 − m`` = 2e-6, 1e-10, 2e-14,
1e-40, 1e-140, 1e-300, 3e-320 and 3e-600 (below the float range) and exactly 0, near-symmetric
(``ΔI/I = 1e-12``), lamina, rod, sphere;
``|L_space|`` and ``E`` are constant to 2e-15 relative and ``R`` is orthonormal to 2e-15. The error
grows like ``eps × (phase)``, the rounding of ``λ t`` itself.

Near the separatrix the *evaluation* stays that accurate relative to the exact solution for the
floating-point ``ω0`` given, but the *problem* becomes ill-conditioned: the period ``4K/λ`` grows like
``ln(16/(1 − m))``, and a relative change ``δ`` of ω0 changes ``1 − m`` by up to ``δ/(1 − m)``, hence
the phase after ``N`` periods by about ``N δ / ((1 − m) ln(16/(1 − m)))``. Any computed motion near the
separatrix (ours, or an integrator's) is only as good as ``ω0`` is known.

The pole of the frame ``B`` is ``e_a`` or ``e_c``, whichever ``L̂`` stays farther from (compared at
``sn u = 0``): then ``ψ̇`` has no spikes and its two terms do not cancel, also for a body close to a
rod (measured 9e-13 rad after 1,000 turns for ``I3/I1 = 1e-3``); the pole-c form is
``ψ̇ = L/I_a + L κ sn²/(1 − n' sn²)``, ``κ = G_a (I_a − I_c)/(I_a² G_c)``, ``n' = −I_c G_a/(I_a G_c)``.

Cost (median, 1,000 times, one initial state; the setup of the last state is cached): ``omega``
≈ 0.15 ms, ``attitude`` ≈ 0.75 ms; ``flow`` ≈ 3 µs per state for 1,000 states, ≈ 0.14 ms per call.
"""

from __future__ import annotations

import math
from dataclasses import dataclass
from typing import TYPE_CHECKING, Any, Literal

import numpy as np
from numpy.typing import ArrayLike, NDArray
from scipy.special import ellipkm1, elliprf

from physics.double_double import dd_add, dd_term, two_sum
from physics.elliptic import carlson_rj, jacobi_sn_cn_dn, landen_ladder, reduced_jacobi
from physics.inertia import validate_moments
from physics.rotations import expm_so3_unchecked
from physics.validation import (
    MAX_RATE,
    bounded_scalar,
    finite_array,
    finite_phase,
    finite_result,
    rotation_array,
    vector_array,
)

if TYPE_CHECKING:
    from physics.free_body_trajectory import FreeBodyTrajectory

Floats = NDArray[np.float64]

__all__ = [  # noqa: F822 - the trajectory names come from __getattr__ below
    "FreeBody",
    "FreeBodyState",
    "FreeBodyTrajectory",
    "Stability",
    "PrecessionRates",
    "jacobi_sn_cn_dn",
]


# Within 1 − m < 1e-40 of the separatrix (k' < 1e-20) the motion is, to double precision, a train of the
# separatrix's pulses 2K apart: sn = tanh, cn = dn = sech up to K/2 from a pulse's centre, and past it
# cn(K − w) = k' sinh w, dn(K − w) = k' cosh w, sn = 1 (the neglected terms are below k'/4 relative); the
# excess Q is the separatrix's, continued by (K − |v|)/(1 − n) near ±K, and K = ln(4/k') (its error is of
# order k'² K). Only k' enters, through its logarithm: nothing underflows, down to 1 − m far below 1e-308
# (a push of 1e-160 off the intermediate axis has 1 − m ≈ 1e-320). See _third_kind_excess and _setup.
_LOG_KP_DEEP = math.log(1e-20)


def _pair_exponent(x: Floats, y: Floats) -> NDArray[np.int_]:
    """``e`` with ``max(|x|, |y|) 2^-e`` in [0.5, 1) (0 where both are 0): the pair scaled to order 1."""
    return np.asarray(np.frexp(np.maximum(np.abs(x), np.abs(y)))[1], dtype=int)


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


_SWAP = np.array([[0.0, 0.0, -1.0], [0.0, -1.0, 0.0], [-1.0, 0.0, 0.0]])  # proper: exchanges 1st and 3rd


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
        self._cache: tuple[bytes, dict[str, Any]] | None = None
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
            self._kind, self._sym_axis = "spherical", 0
        elif i1 == i2 or i2 == i3:
            self._kind = "symmetric"
            self._sym_axis = int(order[2] if i1 == i2 else order[0])
        else:
            self._kind, self._sym_axis = "triaxial", -1

    # --- invariants --------------------------------------------------------------------------------
    def _omega0(self, omega0: ArrayLike) -> NDArray[np.float64]:
        w = finite_array(omega0, "the initial angular velocity omega0")
        if w.shape != (3,):
            raise ValueError(f"omega0 must have shape (3,) (rad/s in body axes), got shape {w.shape}")
        return w

    def energy(self, omega0: ArrayLike) -> float:
        """Kinetic energy ``E = ½ Σ I_i ω_i²``, J (constant in time).

        Parameters
        ----------
        omega0 : array_like, shape (3,)
            Body-frame angular velocity, rad/s.
        """
        w = self._omega0(omega0)
        with np.errstate(over="ignore"):  # an overflow is refused by name just below
            energy = float(0.5 * np.sum(self.moments * w * w))
        finite_result(energy, "the energy", "values of omega0 and the moments")
        return energy

    def angular_momentum_body(self, omega0: ArrayLike) -> NDArray[np.float64]:
        """Angular momentum in body axes ``L_body = I ω``, kg m²/s, shape (3,)."""
        return self.moments * self._omega0(omega0)

    def angular_momentum(self, omega0: ArrayLike, attitude0: ArrayLike | None = None) -> NDArray[np.float64]:
        """Spatial angular momentum ``L_space = R I ω``, kg m²/s, shape (3,) (constant in time).

        Parameters
        ----------
        omega0 : array_like, shape (3,)
            Body-frame angular velocity at the same instant as ``attitude0``, rad/s.
        attitude0 : array_like, shape (3, 3), optional
            Body-to-space rotation at that instant; default identity.
        """
        r0 = self._attitude0(attitude0)
        return r0 @ self.angular_momentum_body(omega0)

    def _attitude0(self, attitude0: ArrayLike | None) -> NDArray[np.float64]:
        if attitude0 is None:
            return np.eye(3)
        r = finite_array(attitude0, "attitude0")
        if r.shape != (3, 3):
            raise ValueError(f"attitude0 must be a 3x3 rotation matrix, got shape {r.shape}")
        err = np.max(np.abs(r.T @ r - np.eye(3)))
        if err > 1e-9 or np.linalg.det(r) < 0:
            raise ValueError(
                "attitude0 must be a rotation matrix (orthonormal, det +1); "
                f"|RᵀR − I| = {err:.3g}, det = {np.linalg.det(r):.6g}"
            )
        return r

    def _times(self, t: ArrayLike) -> NDArray[np.float64]:
        tt = finite_array(t, "the times t")
        if tt.ndim > 1:
            raise ValueError(f"t must be a scalar or a 1-D array of times in seconds, got shape {tt.shape}")
        return np.atleast_1d(tt)

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
        p = self._setup(self._omega0(omega0)[None, :])
        if p["kind"][0] != 2:
            return 0.0, 1.0
        return float(p["m"][0]), float(p["mc"][0])

    def period(self, omega0: ArrayLike) -> float:
        """Period of ``ω(t)`` in the body, s: ``4K/|λ|`` (``2π/|Ω|`` if symmetric).

        Infinite for uniform rotation about a principal axis, for a sphere, and on the separatrix.
        """
        w = self._omega0(omega0)
        p = self._setup(w[None, :])
        kind = p["kind"][0]
        if kind == 2:
            return float(4.0 * p["K"][0] / abs(p["lam"][0]))  # K = ∞ on the separatrix
        if kind == 1 and p["Omega"][0] != 0.0:
            return float(2.0 * np.pi / abs(p["Omega"][0]))
        return np.inf

    # --- setup per initial state (vectorised over states) -------------------------------------------
    def _setup(self, w: NDArray[np.float64]) -> dict[str, Any]:
        """Constants of the motion for each initial ω (k, 3).

        ``kind``: 0 uniform rotation (ω along one principal axis, or a sphere), 1 symmetric body
        (trigonometric solution), 2 elliptic.
        """
        k = w.shape[0]
        p: dict[str, Any] = {"kind": np.zeros(k, dtype=int)}
        if self._kind in ("spherical", "symmetric"):
            s = self._sym_axis
            i_s = self.moments[s]
            i_perp = self.moments[(s + 1) % 3]
            p["kind"][:] = 1
            p["Omega"] = w[:, s] * (i_perp - i_s) / i_perp
            p["i_perp"] = i_perp
            return p
        # Work with ω scaled by a power of two (exact) to a largest component of order 1. Only ω exactly
        # along one principal axis is uniform rotation: however small the other components, the motion
        # leaves it (about the intermediate axis, after ln(1/push)/rate seconds), see _LOG_KP_DEEP.
        biggest = np.max(np.abs(w), axis=1)
        scale = np.where(biggest > 0.0, np.exp2(np.floor(np.log2(np.where(biggest > 0.0, biggest, 1.0)))), 1.0)
        ws = (w @ self._q_sort.T) / scale[:, None]
        nonzero = np.count_nonzero(ws, axis=1)
        ell = nonzero > 1
        p["kind"][ell] = 2
        if not np.any(ell):
            return p
        i1, i2, i3 = self._sorted
        ws_e = ws[ell]
        # Sign of L² − 2 E I2 (double-double, on the pair (ω1, ω3) scaled to order 1) picks the axis the
        # motion circulates around.
        d12 = two_sum(i1, -i2)
        d32 = two_sum(i3, -i2)
        e_mid = _pair_exponent(ws_e[:, 0], ws_e[:, 2])
        g_mid = dd_add(dd_term(i1, d12, np.ldexp(ws_e[:, 0], -e_mid)), dd_term(i3, d32, np.ldexp(ws_e[:, 2], -e_mid)))
        swap = g_mid[0] < 0.0
        q_can = np.where(swap[:, None, None], _SWAP @ self._q_sort, self._q_sort)
        sc = scale[ell]
        wc = np.einsum("kij,kj->ki", q_can, w[ell]) / sc[:, None]
        ia = np.where(swap, i3, i1)
        ib = np.full_like(ia, i2)
        ic = np.where(swap, i1, i3)
        wa, wb, wcc = wc[:, 0], wc[:, 1], wc[:, 2]
        dab = two_sum(ia, -ib)
        dac = two_sum(ia, -ic)
        dbc = two_sum(ib, -ic)
        # G_b = L² − 2E I_b, G_a = 2E I_a − L², G_c = L² − 2E I_c; signed like (I_a − I_b). Each is a
        # quadratic form in two components of ω: it is formed (double-double) from that pair scaled by
        # 2^-e_x to order 1, G_x = G̃_x 4^e_x, so that no square underflows however small the pair.
        # G_b is the L² − 2E I2 above (the same pair, scaled alike).
        e_b, e_a, e_c = e_mid, _pair_exponent(wb, wcc), _pair_exponent(wa, wb)
        gb_dd = g_mid
        ga_dd = dd_add(dd_term(ib, dab, np.ldexp(wb, -e_a)), dd_term(ic, dac, np.ldexp(wcc, -e_a)))
        gc_dd = dd_add(dd_term(ia, dac, np.ldexp(wa, -e_c)), dd_term(ib, dbc, np.ldexp(wb, -e_c)))
        gb, ga, gc = gb_dd[0] + gb_dd[1], ga_dd[0] + ga_dd[1], gc_dd[0] + gc_dd[1]
        dab_f, dac_f, dbc_f = dab[0] + dab[1], dac[0] + dac[1], dbc[0] + dbc[1]
        with np.errstate(under="ignore"):  # a ratio below the float range is 0 to double precision
            # G_a / G_c and G_b / G_c as (scaled ratio) · 4^(exponent difference).
            ratio_a = np.ldexp(ga / gc, 2 * (e_a - e_c))
            m = np.clip(dbc_f / dab_f * ratio_a, 0.0, 1.0)
            mc = np.clip(np.ldexp(dac_f * gb / (dab_f * gc), 2 * (e_b - e_c)), 0.0, 1.0)
            # The complementary modulus k' = √(1 − m) = k̃' 2^(e_b − e_c) without forming 1 − m: it is of the
            # order of the push off the intermediate axis, 1 − m of its square (below 1e-308 for a push
            # below 1e-154); log k' is exact in the exponent.
            kp_scaled = np.sqrt(np.clip(dac_f * gb / (dab_f * gc), 0.0, None))
            kp = np.ldexp(kp_scaled, e_b - e_c)
        sep = gb == 0.0
        with np.errstate(divide="ignore"):
            log_kp = np.log(kp_scaled) + (e_b - e_c) * math.log(2.0)
        deep = ~sep & (log_kp < _LOG_KP_DEEP)
        ang = np.sqrt(np.sum((self._sorted * ws_e) ** 2, axis=1))
        sqrt_gc = np.sqrt(np.abs(gc)) * np.ldexp(1.0, e_c)
        sqrt_ga = np.sqrt(np.abs(ga)) * np.ldexp(1.0, e_a)
        lam_abs = np.sqrt(dab_f * gc / (ia * ib * ic)) * np.ldexp(1.0, e_c)
        pa = np.where(wa < 0.0, -1.0, 1.0)
        lam = -pa * np.sign(dab_f) * lam_abs
        # Initial phase: sn, cn, dn at u0 read off ω0 (normalised so sn² + cn² = 1 exactly).
        xb = np.sqrt(np.abs(ib * dab_f)) * wb
        xc = np.sqrt(np.abs(ic * dac_f)) * wcc
        h = np.hypot(xb, xc)
        s0, c0 = xb / h, xc / h
        d0 = np.sqrt(np.abs(ia * dac_f)) * np.abs(wa) / sqrt_gc
        with np.errstate(divide="ignore"):
            kk = np.where(sep, np.inf, np.where(deep, math.log(4.0) - log_kp, ellipkm1(np.where(sep | deep, 0.5, mc))))
        # On the separatrix cn = sech > 0 never changes sign: the branch with ω_c < 0 is
        # ω_c = −A_c sech u, which Euler's equations pair with −λ.
        flip_c = sep & (c0 < 0.0)
        c0 = np.where(flip_c, -c0, c0)
        lam = np.where(flip_c, -lam, lam)
        pc = np.where(flip_c, -1.0, 1.0)
        with np.errstate(all="ignore"):  # R_F's arguments underflow where deep: that branch is not used there
            v0 = s0 * elliprf(c0 * c0, d0 * d0, 1.0)
        if np.any(deep):
            # Where deep, sn = tanh, cn = dn = sech up to |v| = K/2 (dn(K/2) = √k'), and past it
            # cn(K − w) = k' sinh w, dn(K − w) = k' cosh w: |v0| = asinh(|s0/c0|), or K − asinh(|c0|/(|s0| k')).
            # |c0|/k' and d0²/k' are formed from the pair (ω_a, ω_c) scaled by 2^-e_b: the push and k' are
            # both of its order, and may be below the float range.
            with np.errstate(all="ignore"):
                xc_scaled = np.sqrt(np.abs(ic * dac_f)) * np.ldexp(wcc, -e_b)
                d0_scaled = np.sqrt(np.abs(ia * dac_f)) * np.abs(np.ldexp(wa, -e_b)) / sqrt_gc
                past_half = np.ldexp(d0_scaled * d0_scaled, e_b + e_c) <= kp_scaled
                c0_over_kp = np.ldexp(np.abs(xc_scaled) / (h * kp_scaled), e_c)
                v_deep = np.where(
                    past_half, kk - np.arcsinh(c0_over_kp / np.abs(s0)), np.arcsinh(np.abs(s0) / np.abs(c0))
                )
            v0 = np.where(deep, np.copysign(v_deep, s0), v0)
        u0 = np.where(c0 >= 0.0, v0, np.where(s0 >= 0.0, 2.0 * kk, -2.0 * kk) - v0)
        # Pole of the frame B: the axis L̂ stays farther from (compare at sn = 0, where
        # (I_a A_a)² + (I_c A_c)² = L²). Pole a: ψ̇ = L/I_c + L (I_a − I_c) n / (I_a I_c) · sn²/(1 − n sn²)
        # with n = −I_a (I_b − I_c) / (I_c (I_a − I_b)); pole c: ψ̇ = L/I_a + L κ sn²/(1 − n' sn²) with
        # κ = G_a (I_a − I_c) / (I_a² G_c) and n' = −I_c G_a / (I_a G_c). Both n ≤ 0 and bounded rates.
        amp_a = sqrt_gc / np.sqrt(np.abs(ia * dac_f))
        amp_b = sqrt_ga / np.sqrt(np.abs(ib * dab_f))
        amp_c = sqrt_ga / np.sqrt(np.abs(ic * dac_f))
        pole_c = ia * amp_a > ic * amp_c
        n_a = -ia * dbc_f / (ic * dab_f)
        n = np.where(pole_c, -ic * ratio_a / ia, n_a)
        rate0 = np.where(pole_c, 1.0 / ia, 1.0 / ic)
        # coef multiplies Q(u) = ∫ sn²/(1 − n sn²) du; it is L/λ times the coefficient of that term.
        coef = np.where(pole_c, ratio_a * dac_f / (ia * ia), dac_f * n_a / (ia * ic)) * ang / lam
        # Q(K) over R_J(0, 1 − m, 1, 1 − n) / 3; where deep, the separatrix's Q at K (see _third_kind_excess).
        with np.errstate(all="ignore"):
            jc = np.where(sep | deep, 0.0, carlson_rj(0.0, np.where(sep | deep, 1.0, mc), 1.0 - n))
        if np.any(deep):
            jc = np.where(deep, 3.0 * _sep_excess(np.where(deep, kk, 0.0), n), jc)
        p.update(
            ell=ell,
            q_can=q_can,
            ia=ia,
            ib=ib,
            ic=ic,
            m=m,
            mc=mc,
            kp=kp,
            deep=deep,
            K=kk,
            lam=lam * sc,
            u0=u0,
            n=n,
            Jc=jc,
            amp=sc[:, None] * np.stack([pa * amp_a, amp_b, pc * amp_c], axis=1),
            L=ang * sc,
            pole_c=pole_c,
            rate0=rate0,
            coef=coef,
        )
        p["ladder"] = landen_ladder(np.where(sep | deep, 0.0, m), np.where(sep | deep, 1.0, mc))
        p["P0"] = _third_kind_excess(p, np.arange(len(m)), u0)
        return p

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
        state = self.trajectory(omega0, attitude0).at(self._times(t))
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
        return self.trajectory(omega0)._omega(self._times(t))

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
        from physics.free_body_trajectory import FreeBodyTrajectory

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
        om, rr = self._evaluate(w, step, r, np.arange(k), want_attitude=True, time_name="dt")
        return rr, om * self.moments

    def _setup_of(self, w: Floats) -> dict[str, Any]:
        """:meth:`_setup`, remembered for the last single initial state (repeated calls of the
        wrappers with the same ω0 do not redo it)."""
        if w.shape[0] != 1:
            return self._setup(w)
        key = w.tobytes()
        cached = self._cache
        if cached is not None and cached[0] == key:
            return cached[1]
        p = self._setup(w)
        self._cache = (key, p)
        return p

    def _evaluate(
        self,
        w: Floats,
        t: Floats,
        r0: Floats | None,
        which: NDArray[np.intp],
        want_attitude: bool,
        setup: dict[str, Any] | None = None,
        time_name: str = "t",
    ) -> tuple[Floats, Floats]:
        """Evaluate the motion of initial states ``w`` (k, 3), ``r0`` (k, 3, 3) at times ``t`` (n,);
        ``which`` (n,) says which state each time belongs to; ``setup`` is their :meth:`_setup`;
        ``time_name`` names the times in a refusal."""
        p = self._setup_of(w) if setup is None else setup
        # Every phase (λ t, Ω t, L t / I, |ω| t) is below |ω| t times the spread of the moments.
        spread = float(np.max(self.moments) / np.min(self.moments[self.moments > 0.0]))
        with np.errstate(over="ignore"):
            finite_phase(
                4.0 * spread * float(np.max(np.abs(w), initial=0.0)) * float(np.max(np.abs(t), initial=0.0)), time_name
            )
        n = t.shape[0]
        out_w = np.empty((n, 3))
        # Without attitudes, out_r stays empty and r0 is never read.
        out_r = np.empty((n if want_attitude else 0, 3, 3))
        if r0 is None:
            r0 = np.broadcast_to(np.eye(3), (w.shape[0], 3, 3))
        kind = p["kind"][which]
        # Uniform rotation about a principal axis: ω constant, R = R0 exp(t hat ω).
        sel = np.nonzero(kind == 0)[0]
        if sel.size:
            ws = w[which[sel]]
            out_w[sel] = ws
            if want_attitude:
                out_r[sel] = r0[which[sel]] @ expm_so3_unchecked(t[sel, None] * ws)
        # Symmetric body (lecture): ω_⊥ turns by −Ω t about e_s; R = exp(t hat(L)/I⊥) R0 exp(Ω t hat e_s).
        sel = np.nonzero(kind == 1)[0]
        if sel.size:
            s = self._sym_axis
            ws = w[which[sel]]
            ang = p["Omega"][which[sel]] * t[sel]
            cs, sn = np.cos(ang), np.sin(ang)
            b, c = (s + 1) % 3, (s + 2) % 3
            res = ws.copy()
            res[:, b] = ws[:, b] * cs + ws[:, c] * sn
            res[:, c] = ws[:, c] * cs - ws[:, b] * sn
            out_w[sel] = res
            if want_attitude:
                rs = r0[which[sel]]
                l_space = np.einsum("kij,kj->ki", rs, self.moments * ws)
                axis = np.zeros((sel.size, 3))
                axis[:, s] = ang
                out_r[sel] = expm_so3_unchecked(t[sel, None] * l_space / p["i_perp"]) @ rs @ expm_so3_unchecked(axis)
        sel = np.nonzero(kind == 2)[0]
        if sel.size:
            if w.shape[0] == 1:
                # One state: its constants stay shape (1,) and broadcast against the times.
                e_index, ws, rs = np.zeros(1, dtype=int), w, r0
            else:
                e_index = (np.cumsum(p["kind"] == 2) - 1)[which[sel]]
                ws, rs = w[which[sel]], r0[which[sel]]
            wt, rt = self._elliptic(p, e_index, t[sel], rs if want_attitude else None, ws)
            out_w[sel] = wt
            if rt is not None:
                out_r[sel] = rt
        return out_w, out_r

    def _elliptic(
        self, p: dict[str, Any], e: NDArray[np.intp], t: Floats, r0: Floats | None, w0: Floats
    ) -> tuple[Floats, Floats | None]:
        """The general motion for elliptic states ``e`` (indices into the setup arrays) at times t."""
        lam, u0 = p["lam"][e], p["u0"][e]
        u = lam * t + u0
        m, mc, kk = p["m"][e], p["mc"][e], p["K"][e]
        roots, scale = p["ladder"]
        ladder = ([q[e] for q in roots], scale[e])
        j, v, s, c, d = reduced_jacobi(u, m, mc, kk, ladder, p["kp"][e])
        sign = 1.0 - 2.0 * np.mod(j, 2.0)
        amp = p["amp"][e]
        wc = np.stack([amp[:, 0] * d, amp[:, 1] * sign * s, amp[:, 2] * sign * c], axis=1)
        q = p["q_can"][e]
        qt = np.swapaxes(q, 1, 2)
        omega = (qt @ wc[:, :, None])[:, :, 0]
        if r0 is None:
            return omega, None
        ia, ib, ic = p["ia"][e], p["ib"][e], p["ic"][e]
        # Angle turned about L: ψ − ψ0 = L t / I_c + C [P(u) − P(u0)], P = Π(n; am u|m) − u.
        big_l = p["L"][e]
        excess = _third_kind_excess(p, e, u, (j, v, s, c, d))
        dpsi = big_l * t * p["rate0"][e] + p["coef"][e] * (excess - p["P0"][e])
        pole_c = p["pole_c"][e]
        frame_t = _frame_from_momentum(wc, ia, ib, ic, pole_c)
        # Frame at t = 0 and M0 = R0 Qᵀ B(0) (its third column is L̂ in space).
        wc0 = (q @ w0[:, :, None])[:, :, 0]
        frame_0 = _frame_from_momentum(wc0, ia, ib, ic, pole_c)
        m0 = r0 @ qt @ frame_0
        cp, sp = np.cos(dpsi), np.sin(dpsi)
        bt = np.swapaxes(frame_t, 1, 2)  # rows b1, b2, b3
        rot_bt = np.empty_like(bt)
        rot_bt[:, 0] = cp[:, None] * bt[:, 0] - sp[:, None] * bt[:, 1]
        rot_bt[:, 1] = sp[:, None] * bt[:, 0] + cp[:, None] * bt[:, 1]
        rot_bt[:, 2] = bt[:, 2]
        return omega, m0 @ rot_bt @ q

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
        w = self._omega0(omega0)
        if self._kind == "triaxial":
            raise ValueError(
                f"precession rates need a symmetric body (two equal moments); these moments "
                f"{self.moments.tolist()} are all different"
            )
        s = self._sym_axis
        i_perp = self.moments[(s + 1) % 3]
        big_l = float(np.linalg.norm(self.moments * w))
        return PrecessionRates(float(w[s] * (i_perp - self.moments[s]) / i_perp), float(big_l / i_perp), s)


def _third_kind_excess(
    p: dict[str, Any], e: NDArray[np.intp], u: Floats, reduced: tuple[Floats, ...] | None = None
) -> Floats:
    """``Q(u) = ∫₀ᵘ sn²/(1 − n sn²) du = (Π(n; am u|m) − u)/n`` for elliptic states ``e`` at phases u.

    Carlson: ``Q = (1/3) sn³ R_J(cn², dn², 1, 1 − n sn²)`` for ``|u| ≤ K`` (no division by n), and
    ``Q(u + 2K) = Q(u) + (2/3) R_J(0, 1 − m, 1, 1 − n)``; on the separatrix (m = 1) the elementary
    ``Q = [u − atan(√|n| tanh u)/√|n|] / (1 − n)``.
    """
    n, m, mc, kk, jc = p["n"][e], p["m"][e], p["mc"][e], p["K"][e], p["Jc"][e]
    if reduced is None:
        roots, scale = p["ladder"]
        reduced = reduced_jacobi(u, m, mc, kk, ([q[e] for q in roots], scale[e]), p["kp"][e])
    j, v, s, c, d = reduced
    deep = p["deep"][e]
    with np.errstate(all="ignore"):  # R_J's arguments underflow where deep: that branch is not used there
        out = (2.0 * j * jc + s**3 * carlson_rj(c * c, d * d, 1.0 - n * s * s)) / 3.0
    sep = ~np.isfinite(kk)
    if np.any(sep | deep):
        # The separatrix, and within 1 − m < 1e-40 of it (see _LOG_KP_DEEP): pulses of the separatrix's Q.
        a = np.abs(np.where(sep, u, v))
        pulse = _sep_excess(a, n)
        kfin = np.where(sep, 0.0, kk)
        far = ~sep & (a > 0.5 * kfin)
        near_k = (jc / 3.0) - (kfin - a) / (1.0 - n)  # Q(K) − (K − |v|)/(1 − n), sn = 1 there
        local = np.copysign(np.where(far, near_k, pulse), np.where(sep, u, v))
        out = np.where(sep | deep, np.where(sep, 0.0, 2.0 * j * jc / 3.0) + local, out)
    return np.asarray(out, dtype=float)


def _sep_excess(a: Floats, n: Floats) -> Floats:
    """``Q(a) = [a − atan(√−n tanh a)/√−n] / (1 − n)``, ``a ≥ 0``: the excess on the separatrix (m = 1)."""
    rn = np.sqrt(-n)
    th = np.tanh(a)
    x = rn * th
    small = np.abs(x) < 1e-8
    atan_over = np.where(small, th * (1.0 - x * x / 3.0), np.arctan(x) / np.where(small, 1.0, rn))
    return np.asarray((a - atan_over) / (1.0 - n), dtype=float)


def _frame_from_momentum(wc: Floats, ia: Floats, ib: Floats, ic: Floats, pole_c: NDArray[np.bool_]) -> Floats:
    """Frame B (columns, canonical body coordinates (a, b, c)) with third column L̂ = I ω / |I ω| and
    first column ``e_p × L̂`` normalised, the pole ``p`` being ``c`` where ``pole_c`` else ``a``;
    shape (k, 3, 3)."""
    lv = np.stack([ia * wc[:, 0], ib * wc[:, 1], ic * wc[:, 2]], axis=1)
    lv = lv / np.max(np.abs(lv), axis=1)[:, None]  # no underflow in the norm for tiny ω
    lv = lv / np.linalg.norm(lv, axis=1)[:, None]
    la, lb, lc = lv[:, 0], lv[:, 1], lv[:, 2]
    frame = np.empty((wc.shape[0], 3, 3))
    zero = np.zeros_like(la)
    rho_a = np.hypot(lb, lc)
    rho_c = np.hypot(la, lb)
    pole = np.broadcast_to(pole_c, la.shape)[:, None]
    b1_a = np.stack([zero, -lc / rho_a, lb / rho_a], axis=1)
    b2_a = np.stack([rho_a, -la * lb / rho_a, -la * lc / rho_a], axis=1)
    with np.errstate(divide="ignore", invalid="ignore"):  # the unused pole may be singular
        b1_c = np.stack([-lb / rho_c, la / rho_c, zero], axis=1)
        b2_c = np.stack([-lc * la / rho_c, -lc * lb / rho_c, rho_c], axis=1)
    frame[:, :, 0] = np.where(pole, b1_c, b1_a)
    frame[:, :, 1] = np.where(pole, b2_c, b2_a)
    frame[:, :, 2] = lv
    return frame


def __getattr__(name: str) -> Any:
    # The trajectory lives in its own module (it evaluates one time on floats with this module's
    # pieces); its names are public here too, imported on first use to keep the import one-way.
    if name in ("FreeBodyState", "FreeBodyTrajectory"):
        from physics import free_body_trajectory

        return getattr(free_body_trajectory, name)
    raise AttributeError(f"module {__name__!r} has no attribute {name!r}")
