"""The heavy top's exact motion from one initial condition, evaluated at any times.

Solve once, evaluate often: :class:`HeavyTopTrajectory` holds the constants of the motion
(:func:`physics.heavy_top.motion.motion_constants`); :meth:`HeavyTopTrajectory.at` only evaluates
``u = cos θ = u1 + (u2 − u1) sn²(λ t + c | m)`` and the pole terms of φ and ψ. An array of times is
evaluated vectorised; one time (a frame of an animation) on Python floats, the same expressions in the
same order, so both give the same numbers.
"""

from __future__ import annotations

import math
from dataclasses import dataclass
from typing import TYPE_CHECKING, Any

import numpy as np
from numpy.typing import ArrayLike, NDArray

from physics.elliptic import jacobi_half_period, jacobi_half_period_one, q_integral, q_integral_one, reduce_half_period
from physics.euler_angles import attitude_from_trig, theta_from
from physics.heavy_top.motion import Motion
from physics.validation import finite_array, finite_phase, finite_scalar

if TYPE_CHECKING:
    from physics.heavy_top.model import HeavyTop
    from physics.heavy_top.nutation_cubic import NutationCubic

Floats = NDArray[np.float64]

__all__ = ["HeavyTopSolution", "HeavyTopTrajectory"]


@dataclass(frozen=True)
class HeavyTopSolution:
    """Exact motion of the heavy symmetric top sampled at times ``t``.

    Attributes
    ----------
    t : ndarray (n,)
        Times, s.
    theta, phi, psi : ndarray (n,)
        Euler angles, rad (φ, ψ unwrapped; jumps of ±π only where the axis passes exactly through a pole).
    thetadot, phidot, psidot : ndarray (n,)
        Their rates, rad/s.
    axis : ndarray (n, 3)
        Unit symmetry axis in space.
    attitude : ndarray (n, 3, 3)
        Body-to-space rotation ``R = Rz(φ) Rx(θ) Rz(ψ)``.
    omega_body : ndarray (n, 3)
        Body-frame angular velocity, rad/s (``Ṙ = R hat(ω_body)``).
    L3, Lz : float
        Conserved angular momenta about the symmetry axis and about +z, kg m²/s.
    energy : float
        Conserved total energy from the initial data, J.
    nutation_period : float
        Period of θ, s (``inf`` for a vertical top that cannot leave the vertical in finite time).
    precession_rate : float
        Mean φ̇ over a nutation period, rad/s.
    theta_min, theta_max : float
        Turning points of θ, rad.
    """

    t: NDArray[np.float64]
    theta: NDArray[np.float64]
    phi: NDArray[np.float64]
    psi: NDArray[np.float64]
    thetadot: NDArray[np.float64]
    phidot: NDArray[np.float64]
    psidot: NDArray[np.float64]
    axis: NDArray[np.float64]
    attitude: NDArray[np.float64]
    omega_body: NDArray[np.float64]
    L3: float
    Lz: float
    energy: float
    nutation_period: float
    precession_rate: float
    theta_min: float
    theta_max: float

    def energy_along(self, top: HeavyTop) -> NDArray[np.float64]:
        """Total energy evaluated from the sampled state (a check of the solution), J, shape (n,)."""
        return top.energy_of(self.theta, self.thetadot, self.phidot, self.psidot)

    def angular_momenta_along(self, top: HeavyTop) -> tuple[NDArray[np.float64], NDArray[np.float64]]:
        """``(L3, Lz)`` evaluated from the sampled state, kg m²/s, each shape (n,)."""
        return top.angular_momenta(self.theta, self.phidot, self.psidot)


def times_array(t: ArrayLike) -> NDArray[np.float64]:
    tt = np.atleast_1d(finite_array(t, "t"))
    if tt.ndim != 1:
        raise ValueError(f"t must be a scalar or a 1-D array of times, got shape {tt.shape}")
    return tt


_STATE_FIELDS = ("t", "theta", "phi", "psi", "thetadot", "phidot", "psidot", "axis", "attitude", "omega_body")


class HeavyTopTrajectory:
    """One motion of a :class:`physics.heavy_top.HeavyTop`, ready to be evaluated at any time.

    Made by :meth:`physics.heavy_top.HeavyTop.trajectory`; everything that does not depend on t (the
    roots of the nutation cubic, the modulus, the phase, the pole terms) is computed once here.

    Attributes
    ----------
    top : HeavyTop
    L3, Lz : float
        Conserved angular momenta, kg m²/s.
    energy : float
        Conserved total energy, J.
    nutation_period : float
        Period of θ(t), ``2 K(m) / λ``, s. For a steady precession the limit ``π/λ`` (the period of small
        nutations about it); for a top exactly vertical the same limit for nearby motions with
        ``Lz = ±L3`` (inf below the sleeping threshold, where the vertical is unstable).
    precession_rate : float
        Mean precession rate ``⟨φ̇⟩`` over one nutation period, rad/s (exact, complete Π); for a fast top it
        tends to the pseudo-regular ``M g ℓ / (I3 ω3)``.
    theta_min, theta_max : float
        Turning points of θ, rad.
    """

    def __init__(self, top: HeavyTop, motion: Motion) -> None:
        self.top = top
        self._mo = mo = motion
        self.L3, self.Lz, self.energy = mo.L3, mo.Lz, mo.energy
        self.nutation_period, self.precession_rate = mo.period, mo.precession_rate
        self._omega3 = mo.L3 / top.I3
        if mo.kind == "free":
            fr = mo.free
            assert fr is not None  # a free motion has its terms
            self.theta_min = float(theta_from(fr.gap_top, fr.gap_bottom + 2.0 * fr.amplitude))
            self.theta_max = float(theta_from(fr.gap_top + 2.0 * fr.amplitude, fr.gap_bottom))
            self._offsets = [float(v[0]) for v in self._free_terms(np.array([mo.c]))]
        elif mo.kind == "nutating":
            cu = mo.cubic
            assert cu is not None  # a nutating motion has its cubic
            self.theta_min = float(theta_from(cu.one_minus_u2, cu.one_plus_u2))
            self.theta_max = float(theta_from(cu.one_minus_u1, cu.one_plus_u1))
            # Each pole term's value at t = 0 (φ and ψ start at φ0, ψ0), and Q(n±; c) for the smooth form.
            sm = mo.smooth
            if sm is not None:
                k0, r0 = reduce_half_period(np.array([mo.c]), mo.K)
                sn0, cn0, dn0 = jacobi_half_period(r0, mo.m, mo.one_m, mo.K)
                self._q_offsets = [
                    float(q_integral(k0, sn0, cn0 * cn0, dn0 * dn0, n, one_n, qc)[0])
                    for n, one_n, qc in zip(sm.n, sm.one_n, sm.qc)
                ]
            self._offsets = [float(tm.integral(np.array([mo.c]), mo.K, mo.m, mo.one_m)[0]) for tm in mo.terms]
        else:
            self.theta_min = self.theta_max = mo.theta0
            self._offsets = []
        self._constants = {
            "L3": self.L3,
            "Lz": self.Lz,
            "energy": self.energy,
            "nutation_period": self.nutation_period,
            "precession_rate": self.precession_rate,
            "theta_min": self.theta_min,
            "theta_max": self.theta_max,
        }
        th0 = mo.theta0
        # cos θ, sin θ of a motion at fixed θ: exact at the poles.
        self._cs0 = (1.0, 0.0) if th0 == 0.0 else (-1.0, 0.0) if th0 == math.pi else (math.cos(th0), math.sin(th0))

    def __repr__(self) -> str:
        return f"HeavyTopTrajectory({self.top!r}, kind={self._mo.kind!r}, L3={self.L3!r}, Lz={self.Lz!r})"

    @property
    def nutation_cubic(self) -> NutationCubic | None:
        """Roots of ``f(u) = u̇²`` (u = cos θ), None for a top exactly vertical at rest in θ (whose θ never
        moves)."""
        return self._mo.cubic

    @property
    def turning_points(self) -> tuple[float, float]:
        """``(θ_min, θ_max)``: the turning points of θ, rad (roots u2, u1 of the cubic in u = cos θ).

        Starting at a turning point (``thetadot0 = 0``) the known root is deflated, so θ0 is returned
        exactly.
        """
        mo = self._mo
        cu = mo.cubic
        if mo.kind == "free":  # without gravity: the parabola's roots, kept by the constructor
            return self.theta_min, self.theta_max
        if mo.kind in ("vertical", "steady") or cu is None:
            return mo.theta0, mo.theta0
        return theta_from(cu.one_minus_u2, cu.one_plus_u2), theta_from(cu.one_minus_u1, cu.one_plus_u1)

    @property
    def nutation_phase(self) -> tuple[float, float, float] | None:
        """``(rate, offset, half)`` of θ's oscillation: θ = θ_max where the phase ``rate t + offset`` is an
        even multiple of ``half``, θ = θ_min where it is an odd one (rate in 1/s; times in s). Nutating:
        ``(λ, c, K)`` of ``u = u1 + (u2 − u1) sn²(λ t + c | m)``; without gravity ``(ν, c + π, π)`` of
        ``u = ū + A cos(ν t + c)``. None when θ never moves (vertical, steady precession)."""
        mo = self._mo
        if mo.kind == "nutating":
            return mo.lam, mo.c, mo.K
        if mo.kind == "free" and mo.free is not None:
            return mo.free.nu, mo.free.c + math.pi, math.pi
        return None

    @property
    def kind(self) -> str:
        """``"vertical"`` (exactly upright or hanging, θ never moves), ``"steady"`` (steady precession)
        or ``"nutating"``."""
        return self._mo.kind

    def at(self, t: ArrayLike) -> HeavyTopSolution:
        """The state at the times ``t``.

        Parameters
        ----------
        t : float or array_like (n,)
            Times, s (any sign, any order).

        Returns
        -------
        HeavyTopSolution
            Arrays of length n for an array of times; for a scalar t, floats (``theta``, ``phi``, ...)
            with ``axis`` (3,), ``attitude`` (3, 3) and ``omega_body`` (3,).
        """
        if isinstance(t, (float, int)) and not isinstance(t, bool):
            tf = finite_scalar(t, "t")
            return self._one(tf)
        if np.ndim(t) == 0:  # a numpy scalar or 0-d array
            return self.at(finite_scalar(t, "t"))
        return self._many(times_array(t))

    # ------------------------------------------------------------------ many times (vectorised)
    def _many(self, tt: Floats) -> HeavyTopSolution:
        mo = self._mo
        n = tt.size
        if mo.kind in ("vertical", "steady"):
            th = np.full(n, mo.theta0)
            with np.errstate(over="ignore", invalid="ignore"):  # refused just below
                phi = mo.phi0 + mo.phidot0 * tt
                psi = mo.psi0 + mo.psidot0 * tt
            finite_phase(phi)
            finite_phase(psi)
            thd = np.zeros(n)
            fd = np.full(n, mo.phidot0)
            pd = np.full(n, mo.psidot0)
            ct, st = np.full(n, self._cs0[0]), np.full(n, self._cs0[1])
        elif mo.kind == "free":
            th, phi, psi, thd, fd, pd, ct, st = self._free(tt)
        else:
            th, phi, psi, thd, fd, pd, ct, st = self._nutating(tt)
        cf, sf, cp, sp = np.cos(phi), np.sin(phi), np.cos(psi), np.sin(psi)
        attitude = attitude_from_trig(cf, sf, ct, st, cp, sp)
        axis = attitude[:, :, 2].copy()
        omega = np.stack([fd * st * sp + thd * cp, fd * st * cp - thd * sp, np.full(n, self._omega3)], axis=-1)
        return self._solution(tt, th, phi, psi, thd, fd, pd, axis, attitude, omega)

    def _solution(self, *values: Any) -> HeavyTopSolution:
        # A frame asks for one time 60 times a second: fill the frozen dataclass's fields directly
        # (its __init__ sets 17 fields one by one through object.__setattr__).
        solution = object.__new__(HeavyTopSolution)
        fields = solution.__dict__
        fields.update(zip(_STATE_FIELDS, values))
        fields.update(self._constants)
        return solution

    def _free_terms(self, x: Floats) -> list[Floats]:
        """The two pole terms of φ − φ0 (before their value at t = 0 is taken off) at phases x = ν t + c."""
        fr = self._mo.free
        assert fr is not None  # only free motions are evaluated here
        terms = []
        for sign, coefficient, rho, one_rho, jump in zip(
            (1.0, -1.0), fr.coefficients, fr.rhos, fr.one_minus_rhos, fr.jumps
        ):
            if jump:  # through the pole: ±π at each passage (cos x = 1 at the top pole, −1 at the bottom)
                shift = 0.0 if sign > 0 else math.pi
                terms.append(jump * math.pi * np.floor((x - shift) / (2.0 * math.pi)))
                continue
            sx = np.sin(x)
            # 1 ∓ ρ cos x = (1 − ρ) + ρ (1 ∓ cos x) ≥ 1 − ρ > 0 (1 ∓ cos x as 2 sin² or 2 cos² of x/2, so that
            # it keeps its digits where the axis passes close to the pole): the atan is continuous in x.
            half = np.sin(0.5 * x) if sign > 0 else np.cos(0.5 * x)
            den = one_rho + rho * (2.0 * half * half)
            terms.append(coefficient * (x + 2.0 * np.arctan(sign * rho * sx / den)))
        return terms

    def _free(self, t: Floats) -> tuple[Floats, ...]:
        """mgl = 0: ``u = ū + A cos(ν t + c)``, φ and ψ from the elementary pole terms (motion._free_motion)."""
        mo = self._mo
        fr = mo.free
        assert fr is not None  # only free motions are evaluated here
        with np.errstate(over="ignore", invalid="ignore"):  # refused just below
            x = fr.nu * t + fr.c
        finite_phase(x)
        half = 0.5 * x
        # 1 − u = (1 − u2) + 2A sin²(x/2), 1 + u = (1 + u1) + 2A cos²(x/2): sums, exact at the poles.
        one_mu = fr.gap_top + 2.0 * fr.amplitude * np.sin(half) ** 2
        one_pu = fr.gap_bottom + 2.0 * fr.amplitude * np.cos(half) ** 2
        u = np.where(one_mu < one_pu, 1.0 - one_mu, one_pu - 1.0)
        st = np.sqrt(one_mu * one_pu)
        th = theta_from(one_mu, one_pu)
        with np.errstate(divide="ignore", invalid="ignore"):
            thd = np.where(st > 0.0, fr.amplitude * fr.nu * np.sin(x) / st, 0.0)
        # Exactly at a pole: the one-sided limit, leaving it (as for the nutating top).
        top, bot = one_mu == 0.0, one_pu == 0.0
        root = math.sqrt(2.0 * fr.amplitude) * fr.nu
        if np.any(top):
            thd[top] = root * np.abs(np.cos(half[top])) / np.sqrt(one_pu[top])
        if np.any(bot):
            thd[bot] = -root * np.abs(np.sin(half[bot])) / np.sqrt(one_mu[bot])
        phi = np.full_like(t, mo.phi0)
        psi = mo.psi0 + mo.spin_rate * t
        fd = np.zeros_like(t)
        pdd = np.full_like(t, mo.spin_rate)
        for pole, term, offset, hd, dist in zip(
            (1, -1), self._free_terms(x), self._offsets, fr.half_d, (one_mu, one_pu)
        ):
            dphi = term - offset
            phi = phi + dphi
            psi = psi - pole * dphi
            with np.errstate(divide="ignore", invalid="ignore"):
                rate = np.where(dist > 0.0, hd / dist, 0.0)
            fd = fd + rate
            pdd = pdd - pole * rate
        return th, phi, psi, thd, fd, pdd, u, st

    def _phidot(self, sm: Any, sn2: Floats, one_mu: Floats, one_pu: Floats) -> Floats:
        """φ̇ = (α − β u)/(1 − u²) from whichever form rounds least: the pole form Σ half_d/(1 ∓ u) (exact
        next to a pole, whose term carries it) or (C − D sn²)/((1 − u)(1 + u)) (no cancellation between
        the poles' large terms for a fast top)."""
        half_top, half_bottom = self._mo.terms[0].half_d, self._mo.terms[1].half_d
        with np.errstate(divide="ignore", invalid="ignore", over="ignore"):
            top = np.where(one_mu > 0.0, half_top / one_mu, 0.0)
            bottom = np.where(one_pu > 0.0, half_bottom / one_pu, 0.0)
            product = one_mu * one_pu
            smooth = np.where(product > 0.0, (sm.C - sm.D * sn2) / product, 0.0)
            error_smooth = np.where(product > 0.0, (abs(sm.C) + abs(sm.D) * sn2) / product, np.inf)
        pole: Floats = top + bottom
        return np.where(np.abs(top) + np.abs(bottom) <= error_smooth, pole, smooth)

    def _phidot_one(self, sm: Any, sn2: float, one_mu: float, one_pu: float) -> float:
        """:meth:`_phidot` for one time (floats)."""
        top = self._mo.terms[0].half_d / one_mu if one_mu > 0.0 else 0.0
        bottom = self._mo.terms[1].half_d / one_pu if one_pu > 0.0 else 0.0
        product = one_mu * one_pu
        if product > 0.0 and abs(top) + abs(bottom) > (abs(sm.C) + abs(sm.D) * sn2) / product:
            return float((sm.C - sm.D * sn2) / product)
        return top + bottom

    def _nutating(self, t: Floats) -> tuple[Floats, ...]:
        mo = self._mo
        cu, m, K, lam = mo.cubic, mo.m, mo.K, mo.lam
        assert cu is not None  # only nutating motions are evaluated here
        with np.errstate(over="ignore", invalid="ignore"):  # refused just below
            tau = lam * t + mo.c
        finite_phase(tau)
        k, r = reduce_half_period(tau, K)
        sn, cn, dn = jacobi_half_period(r, m, mo.one_m, K)
        sn2, cn2 = sn * sn, cn * cn
        u21 = cu.u2_minus_u1
        # 1 ∓ u as sums of non-negative terms: no cancellation near the poles.
        one_mu = cu.one_minus_u2 + u21 * cn2
        one_pu = cu.one_plus_u1 + u21 * sn2
        u = np.where(one_mu < one_pu, 1.0 - one_mu, one_pu - 1.0)
        st = np.sqrt(one_mu * one_pu)
        th = theta_from(one_mu, one_pu)
        udot = 2.0 * u21 * lam * sn * cn * dn
        with np.errstate(divide="ignore", invalid="ignore"):
            thd = np.where(st > 0.0, -udot / st, 0.0)
        # Exactly at a pole (only when the axis passes through it): the one-sided limit, leaving the pole.
        top, bot = one_mu == 0.0, one_pu == 0.0
        if np.any(top):
            thd[top] = 2.0 * math.sqrt(u21) * lam * np.abs(sn[top]) * dn[top] / np.sqrt(one_pu[top])
        if np.any(bot):
            thd[bot] = -2.0 * math.sqrt(u21) * lam * np.abs(cn[bot]) * dn[bot] / np.sqrt(one_mu[bot])
        sm = mo.smooth
        if sm is not None:  # the pole terms summed without cancellation (motion.SmoothPhi)
            dn2 = dn * dn
            dq = [
                q_integral(k, sn, cn2, dn2, n, one_n, qc) - q0
                for n, one_n, qc, q0 in zip(sm.n, sm.one_n, sm.qc, self._q_offsets)
            ]
            dtau = tau - mo.c
            phi = mo.phi0 + (sm.rate * dtau + (sm.b[0] * dq[0] + sm.b[1] * dq[1]))
            psi = mo.psi0 + (self._omega3 * t - sm.u1 * sm.rate * dtau - sm.b[0] * dq[0] + sm.b[1] * dq[1])
            fd = self._phidot(sm, sn2, one_mu, one_pu)
            return th, phi, psi, thd, fd, self._omega3 - u * fd, u, st
        fd = np.zeros_like(t)
        phi = np.full_like(t, mo.phi0)
        psi = mo.psi0 + mo.spin_rate * t
        pdd = np.full_like(t, mo.spin_rate)
        one_m = mo.one_m
        for tm, offset in zip(mo.terms, self._offsets):
            dphi = tm.integral(tau, K, m, one_m, (k, r, sn, cn2, dn * dn)) - offset
            phi = phi + dphi
            psi = psi - tm.pole * dphi
            if tm.half_d != 0.0:
                dist = one_mu if tm.pole == +1 else one_pu
                with np.errstate(divide="ignore", invalid="ignore"):
                    rate = np.where(dist > 0.0, tm.half_d / dist, 0.0)
                fd = fd + rate
                pdd = pdd - tm.pole * rate
        return th, phi, psi, thd, fd, pdd, u, st

    # ------------------------------------------------------------------ one time (floats)
    def _one(self, t: float) -> HeavyTopSolution:
        mo = self._mo
        if mo.kind == "free":  # no gravity (rare in a frame loop): the vectorised form for one time
            many = self._many(np.array([t]))
            values = [getattr(many, name) for name in _STATE_FIELDS[1:]]
            return self._solution(t, *(float(v[0]) for v in values[:6]), *(v[0] for v in values[6:]))
        if mo.kind != "nutating":
            th, phi, psi = mo.theta0, mo.phi0 + mo.phidot0 * t, mo.psi0 + mo.psidot0 * t
            finite_phase([phi, psi])
            thd, fd, pdd = 0.0, mo.phidot0, mo.psidot0
            ct, st = self._cs0
        else:
            th, phi, psi, thd, fd, pdd, ct, st = self._nutating_one(t)
        cf, sf, cp, sp = math.cos(phi), math.sin(phi), math.cos(psi), math.sin(psi)
        attitude = np.array(
            [
                [cf * cp - sf * ct * sp, -cf * sp - sf * ct * cp, sf * st],
                [sf * cp + cf * ct * sp, -sf * sp + cf * ct * cp, -cf * st],
                [st * sp, st * cp, ct],
            ]
        )
        omega = np.array([fd * st * sp + thd * cp, fd * st * cp - thd * sp, self._omega3])
        return self._solution(t, th, phi, psi, thd, fd, pdd, attitude[:, 2].copy(), attitude, omega)

    def _nutating_one(self, t: float) -> tuple[float, ...]:
        """:meth:`_nutating` for one time, on floats (same expressions, same order)."""
        mo = self._mo
        cu, m, K, lam, one_m = mo.cubic, mo.m, mo.K, mo.lam, mo.one_m
        assert cu is not None  # only nutating motions are evaluated here
        tau = lam * t + mo.c
        finite_phase(tau)
        k = math.floor((tau + K) / (2.0 * K))
        r = tau - 2.0 * K * k
        sn, cn, dn = jacobi_half_period_one(r, m, one_m, K)
        sn2, cn2 = sn * sn, cn * cn
        u21 = cu.u2_minus_u1
        one_mu = cu.one_minus_u2 + u21 * cn2
        one_pu = cu.one_plus_u1 + u21 * sn2
        u = 1.0 - one_mu if one_mu < one_pu else one_pu - 1.0
        st = math.sqrt(one_mu * one_pu)
        th = 2.0 * math.atan2(math.sqrt(max(one_mu, 0.0)), math.sqrt(max(one_pu, 0.0)))
        if one_mu == 0.0:
            thd = 2.0 * math.sqrt(u21) * lam * abs(sn) * dn / math.sqrt(one_pu)
        elif one_pu == 0.0:
            thd = -2.0 * math.sqrt(u21) * lam * abs(cn) * dn / math.sqrt(one_mu)
        else:
            thd = -(2.0 * u21 * lam * sn * cn * dn) / st if st > 0.0 else 0.0
        dn2 = dn * dn
        sm = mo.smooth
        if sm is not None:  # as in _nutating
            dq0 = q_integral_one(k, sn, cn2, dn2, sm.n[0], sm.one_n[0], sm.qc[0]) - self._q_offsets[0]
            dq1 = q_integral_one(k, sn, cn2, dn2, sm.n[1], sm.one_n[1], sm.qc[1]) - self._q_offsets[1]
            dtau = tau - mo.c
            phi = mo.phi0 + (sm.rate * dtau + (sm.b[0] * dq0 + sm.b[1] * dq1))
            psi = mo.psi0 + (self._omega3 * t - sm.u1 * sm.rate * dtau - sm.b[0] * dq0 + sm.b[1] * dq1)
            fd = self._phidot_one(sm, sn2, one_mu, one_pu)
            return th, phi, psi, thd, fd, self._omega3 - u * fd, u, st
        fd = 0.0
        phi = mo.phi0
        psi = mo.psi0 + mo.spin_rate * t
        pdd = mo.spin_rate
        for tm, offset in zip(mo.terms, self._offsets):
            dphi = tm.integral_one(tau, K, m, one_m, k, r, sn, cn2, dn2) - offset
            phi = phi + dphi
            psi = psi - tm.pole * dphi
            if tm.half_d != 0.0:
                dist = one_mu if tm.pole == +1 else one_pu
                rate = tm.half_d / dist if dist > 0.0 else 0.0
                fd = fd + rate
                pdd = pdd - tm.pole * rate
        return th, phi, psi, thd, fd, pdd, u, st
