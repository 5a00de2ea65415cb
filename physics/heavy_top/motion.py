"""Constants of one motion of the heavy top, computed once per initial condition.

With ``u = cos θ``, ``u̇² = f(u) = 2 (ℰ − a u)(1 − u²) − (α − β u)²`` (``a = Mgℓ/I1``, ``α = Lz/I1``,
``β = L3/I1``; lecture, "the heavy symmetric top"), a cubic with roots ``−1 ≤ u1 ≤ u2 ≤ 1 ≤ u3``, and
``u = u1 + (u2 − u1) sn²(λ t + c | m)``, ``m = (u2 − u1)/(u3 − u1)``, ``λ = sqrt(a (u3 − u1)/2)``. This
module finds the roots (:mod:`physics.heavy_top.nutation_cubic`), the modulus, rate and phase, and the two
pole terms of φ (:class:`physics.heavy_top.pole_terms.PoleTerm`); :mod:`physics.heavy_top.trajectory`
evaluates them.
"""

from __future__ import annotations

import math
from dataclasses import dataclass, field
from typing import TYPE_CHECKING, Any, NamedTuple

from scipy.special import ellipkm1

from physics.double_double import dd_add, dd_mul, two_prod, two_sum
from physics.elliptic import complete_q, complete_third_kind, incomplete_first_kind_one
from physics.heavy_top.nutation_cubic import NutationCubic, Root, local_roots, root_gap
from physics.heavy_top.pole_terms import PoleTerm
from physics.validation import MAX_RATE, finite_scalar

if TYPE_CHECKING:
    from physics.heavy_top.model import HeavyTop


@dataclass
class Motion:
    """Everything the closed form needs, computed once per initial condition."""

    kind: str  # "vertical", "steady" or "nutating"
    theta0: float
    phi0: float
    psi0: float
    phidot0: float
    psidot0: float
    L3: float
    Lz: float
    energy: float
    cubic: NutationCubic | None = None
    m: float = 0.0
    lam: float = 0.0
    K: float = 0.0
    one_m: float = 1.0
    c: float = 0.0
    spin_rate: float = 0.0  # L3/I3 − L3/I1: the constant part of ψ̇
    terms: list[PoleTerm] = field(default_factory=list)  # two of them
    period: float = math.inf
    precession_rate: float = 0.0
    free: FreeTerms | None = None  # mgl = 0: the symmetric free body (elementary closed form)
    smooth: SmoothPhi | None = None  # the pole terms summed without cancellation (see SmoothPhi)


_THROUGH_POLE = 1e-300
"""A pole term whose 1 − n is below this is taken as passing through the pole (see motion_constants)."""

MIN_THETA0 = 1e-100
"""Smallest distance from the vertical (rad) a start may have without being on it. The motion near the
vertical depends on θ0² (from θ0 = 0, on (θ̇0/ν)², ν the top's own rate), and the closed form multiplies
it by other small quantities (the distance of the opposite pole); above 1e-100 every such product is a
normal float. Closer starts are refused with a ValueError rather than rounded to the vertical: below the
sleeping threshold the top leaves any start off the vertical, however close, and falls."""


class ScaledTop(NamedTuple):
    """The moments a motion is computed with (kg m², J): a :class:`physics.heavy_top.HeavyTop`'s, scaled."""

    I1: float
    I3: float
    mgl: float


def motion_constants(
    top: HeavyTop | ScaledTop,
    theta0: float,
    thetadot0: float,
    phidot0: float,
    psidot0: float,
    phi0: float = 0.0,
    psi0: float = 0.0,
) -> Motion:
    """The constants of one motion from its initial Euler angles and rates (roots of the cubic, phase,
    pole terms): everything the closed form needs that does not depend on t."""
    th0 = finite_scalar(theta0, "theta0")
    thd0 = finite_scalar(thetadot0, "thetadot0")
    phd0 = finite_scalar(phidot0, "phidot0")
    psd0 = finite_scalar(psidot0, "psidot0")
    phi0 = finite_scalar(phi0, "phi0")
    psi0 = finite_scalar(psi0, "psi0")
    if not 0.0 <= th0 <= math.pi:
        raise ValueError(f"theta0 is the angle of the axis from +z and must lie in [0, pi], got {th0}")
    if max(abs(thd0), abs(phd0), abs(psd0)) > MAX_RATE:
        raise ValueError(
            f"angular rates must be at most {MAX_RATE:g} rad/s (their squares would overflow); got "
            f"thetadot0 = {thd0:g}, phidot0 = {phd0:g}, psidot0 = {psd0:g}"
        )
    if 0.0 < th0 < MIN_THETA0:
        raise ValueError(
            f"theta0 = {th0:g} rad is closer to the vertical than {MIN_THETA0:g} rad without being on it: the "
            "closed form there needs powers of theta0 below the float range; theta0 must be 0 or lie in "
            f"[{MIN_THETA0:g}, pi]"
        )
    # Squares of these would underflow: to every digit the cubic can see they are 0 (no rate). Not θ̇0: near
    # the vertical its square competes with θ0² (≥ 1e-200), and the roots are found without forming it.
    phd0, psd0 = (0.0 if abs(x) < 1e-150 else x for x in (phd0, psd0))
    if th0 == math.pi and abs(thd0) < 1e-150:
        thd0 = 0.0  # hanging straight down (stable): a swing below 1e-150 rad is no swing
    if th0 == 0.0 and thd0 != 0.0:
        # Leaving the exact vertical with θ̇0: the motion depends on (θ̇0/ν)², ν the top's own rate. Below
        # 1e-100 of it: above the sleeping threshold (or without gravity) the axis stays within ~1e-100 rad
        # of the vertical, taken as on it; at or below, the top falls after a time the floats cannot hold.
        nu = math.sqrt(top.mgl / top.I1 + 0.25 * (top.I3 * (psd0 + phd0) / top.I1) ** 2)
        if abs(thd0) < MIN_THETA0 * nu:
            if top.mgl == 0.0 or _threshold_gap(top, phd0, psd0, 1.0) < 0.0:
                thd0 = 0.0
            else:
                raise ValueError(
                    f"thetadot0 = {thd0:g} rad/s from the exact vertical (theta0 = 0) at or below the sleeping "
                    f"threshold is below {MIN_THETA0:g} times the top's own rate sqrt(M g l/I1 + (L3/2I1)²) = "
                    f"{nu:g} rad/s: the top would fall after a time the closed form cannot represent; from "
                    f"theta0 = 0, |thetadot0| must be 0 or at least {MIN_THETA0 * nu:g} rad/s here"
                )
    # At a pole θ̇ < 0 means leaving towards the opposite azimuth: same state, θ̇ > 0.
    if th0 == 0.0 and thd0 < 0.0:
        thd0, phi0, psi0 = -thd0, phi0 + math.pi, psi0 - math.pi
    if th0 == math.pi and thd0 > 0.0:
        thd0, phi0, psi0 = -thd0, phi0 + math.pi, psi0 + math.pi
    at_pole = th0 == 0.0 or th0 == math.pi
    s0 = 0.0 if at_pole else math.sin(th0)
    u0 = 1.0 if th0 == 0.0 else (-1.0 if th0 == math.pi else math.cos(th0))
    w0 = 2.0 * math.sin(0.5 * th0) ** 2 if th0 != math.pi else 2.0  # 1 − u0
    z0 = 2.0 * math.cos(0.5 * th0) ** 2 if th0 != math.pi else 0.0  # 1 + u0
    I1, I3 = top.I1, top.I3
    L3 = I3 * (psd0 + phd0 * u0)
    Lz = I1 * s0 * s0 * phd0 + L3 * u0
    K0 = 0.5 * thd0 * thd0 + 0.5 * s0 * s0 * phd0 * phd0  # ℰ − a u0
    energy = I1 * K0 + L3 * L3 / (2.0 * I3) + top.mgl * u0
    base: dict[str, Any] = dict(
        theta0=th0, phi0=phi0, psi0=psi0, phidot0=phd0, psidot0=psd0, L3=L3, Lz=Lz, energy=energy
    )
    if at_pole and thd0 == 0.0:
        # Sleeping (or hanging) top exactly vertical: an equilibrium of θ, stable or not.
        mo = Motion(kind="vertical", **base)
        mo.precession_rate = phd0
        mo.period = _vertical_period(top, L3, u0)
        return mo

    a = top.mgl / I1
    beta = L3 / I1
    dm = (I1 * s0 * s0 * phd0 - L3 * w0) / I1  # α − β = (Lz − L3)/I1 without cancellation
    dp = (I1 * s0 * s0 * phd0 + L3 * z0) / I1  # α + β
    if a == 0.0:
        return _free_motion(base, u0, w0, z0, s0, thd0, K0, beta, dm, dp, L3 / I3)
    c3 = 2.0 * a
    # 4a − β² = (4 M g ℓ I1 − L3²)/I1² vanishes at the sleeping threshold: formed in double-double from
    # the inputs, so that the roots near u = 1 are those of the data given, however close to it.
    gap = _threshold_gap(top, phd0, psd0, u0)
    # f expanded about three points where it is known exactly from the data: u0 (v = u − u0), the top pole
    # (x = u − 1) and the bottom pole (y = u + 1). Each constant term is a signed square d², passed as d:
    # near the vertical d is ~θ0² and its square would underflow.
    loc0 = [
        s0 * thd0,
        -4.0 * u0 * K0 - 2.0 * a * s0 * s0 + 2.0 * beta * s0 * s0 * phd0,
        -2.0 * K0 + (gap - 4.0 * a * w0),  # −2K0 + 4a u0 − β²
        c3,
    ]
    k1 = K0 - a * w0  # ℰ − a
    loc_p = [dm, -4.0 * k1 + 2.0 * beta * dm, -2.0 * k1 + gap, c3]
    k2 = K0 + a * z0  # ℰ + a
    loc_m = [dp, 4.0 * k2 + 2.0 * beta * dp, -2.0 * k2 - 4.0 * a - beta * beta, c3]
    # The roots in each expansion, each group at its own scale (nutation_cubic.local_roots), ascending in
    # u in all three. Each root is then taken from the expansion in which it is smallest: there it has its
    # full relative precision, and so have its distances to u0 and to the poles. (Two roots that nearly
    # coincide always have an anchor between them, u0 or a pole, which tells them apart.)
    found = (
        local_roots(1.0, *loc0),
        local_roots(-1.0, *loc_p),
        local_roots(-1.0, *loc_m),
    )
    roots = []
    for v, x, y in zip(*found):
        best = min((abs(v), 0), (abs(x), 1), (abs(y), 2))[1]
        if best == 0:
            roots.append(Root(v, w0 - v, z0 + v))
        elif best == 1:
            roots.append(Root(w0 + x, -x, 2.0 + x))
        else:
            roots.append(Root(y - z0, 2.0 - y, y))
    roots.sort(key=lambda r_: r_.u)
    r1, r2, r3 = roots
    # Rounding may push a root across u0 or a pole by an ulp; the motion lies in [u1, u2] ∋ u0.
    if r1.v > 0.0:
        r1 = Root(0.0, w0, z0)
    if r2.v < 0.0:
        r2 = Root(0.0, w0, z0)
    if r2.p < 0.0:
        r2 = Root(w0, 0.0, 2.0)
    if r1.q < 0.0:
        r1 = Root(-z0, 2.0, 0.0)
    u21, u31, u32 = root_gap(r2, r1), root_gap(r3, r1), root_gap(r3, r2)
    r0 = Root(0.0, w0, z0)
    cubic = NutationCubic(
        u0=u0,
        u1=r1.u,
        u2=r2.u,
        u3=r3.u,
        one_minus_u1=r1.p,
        one_minus_u2=r2.p,
        one_plus_u1=r1.q,
        one_plus_u2=r2.q,
        u2_minus_u1=u21,
        u3_minus_u1=u31,
        u3_minus_u2=u32,
        u0_minus_u1=root_gap(r0, r1),
        u2_minus_u0=root_gap(r2, r0),
    )
    if u21 <= 0.0:
        mo = Motion(kind="steady", cubic=cubic, **base)
        mo.precession_rate = phd0
        mo.lam = math.sqrt(a * u31 / 2.0)
        mo.period = math.pi / mo.lam if mo.lam > 0 else math.inf
        return mo

    mo = Motion(kind="nutating", cubic=cubic, **base)
    m = u21 / u31
    # Exactly on a separatrix (u2 = u3: the axis creeps up to an unstable position for ever) K = inf;
    # with 1 − m = 1e-300 instead the approach takes ~350/λ and differs by e^-350: invisible.
    one_m = max(u32 / u31, 1e-300)
    mo.one_m = one_m
    mo.m = m
    mo.lam = lam = math.sqrt(a * u31 / 2.0)
    mo.K = K = float(ellipkm1(one_m))  # accurate even as m → 1 (near a separatrix)
    # Phase: sn²(c) = (u0 − u1)/(u2 − u1), cn²(c) = (u2 − u0)/(u2 − u1), sign from u̇0 = −sin θ0 θ̇0.
    sn2 = cubic.u0_minus_u1 / u21
    cn2 = cubic.u2_minus_u0 / u21
    if cn2 <= 0.0:
        c = K
    elif sn2 <= 0.0:
        c = 0.0
    else:
        c = incomplete_first_kind_one(sn2, cn2, m, one_m)
    udot0 = -s0 * thd0
    mo.c = -c if udot0 < 0.0 else c
    mo.spin_rate = L3 / I3 - beta
    mo.period = 2.0 * K / lam
    # The two pole terms of φ̇: (α ∓ β) / (2 (1 ∓ u)); their time integrals are elliptic integrals of
    # the third kind (Carlson R_J). See PoleTerm.
    terms = []
    for pole, d in ((+1, dm), (-1, dp)):
        half_d = 0.5 * d
        if pole == +1:
            # 1 − u = (1 − u1)(1 − n sn²τ), n = (u2 − u1)/(1 − u1) ≤ 1.
            d1, d2 = r1.p, r2.p
            n, one_n, shift = u21 / d1, d2 / d1, 0.0
            a0, a1 = 0.0, half_d / (lam * d1)
        elif u21 <= r1.q:
            # 1 + u = (1 + u1)(1 − n sn²τ), n = −(u2 − u1)/(1 + u1) ∈ [−1, 0].
            n = -u21 / r1.q
            one_n, shift = 1.0 - n, 0.0
            a0, a1 = 0.0, half_d / (lam * r1.q)
        else:
            # Near the bottom pole n → −∞ and Π(n) cancels; instead 1 + u = (1 + u2)(1 − n' cn²τ) and with
            # x = τ − K, ∫ dτ/(1 − n' cn²) = (m/N) x + (1 − m/N) Π(N; x), N = m + n'(1 − m) ∈ [m, 1]:
            # the same well-conditioned form as the top pole.
            npr = u21 / r2.q
            n = m + npr * (1.0 - m)
            one_n = one_m * r1.q / r2.q
            shift = K
            scale = half_d / (lam * r2.q)
            a0, a1 = scale * m / n, scale * npr * one_m / n
        # The axis passes through this pole, or so close that its closest approach, ~(1 − n)^½ rad, is below
        # 1e-150: then the term is its limit, a turn of ±π at each passage (within 1e-150 rad of the exact
        # one; 1 − n itself, below the normal floats, would have lost its digits).
        through = one_n < _THROUGH_POLE
        jump = (math.copysign(1.0, d) if d != 0.0 else 1.0) if through else 0.0
        pic = 0.0 if through else complete_third_kind(n, one_n, m, one_m, K)
        terms.append(PoleTerm(pole, half_d, jump, shift, a0, a1, n, one_n, pic))
    mo.terms = terms
    # Mean φ̇ over one period: each pole term advances by 2K a0 + 2 a1 Π(n|m), or by ±π per passage.
    adv = sum(tm.jump * math.pi if tm.jump else 2.0 * K * tm.a0 + 2.0 * tm.a1 * tm.pic for tm in terms)
    if all(tm.jump == 0.0 and tm.shift == 0.0 for tm in terms):
        # The two pole terms a1± Π(n±; τ) are each ~β/λ τ and cancel down to the slow precession of a fast
        # top (their sum is 1e-17 of each at 1e9 rad/s). Summed before integrating they need no cancellation:
        # Π(n; τ) = τ + n Q(n; τ), Q = ∫ sn²/(1 − n sn²) dτ, and a1+ + a1− = (α − β u1) / ((1 − u1²) λ), with
        # α − β u1 = sin²θ0 φ̇0 + β (u0 − u1) from the data. The b± = a1± n± terms have one sign: no cancellation.
        C = s0 * s0 * phd0 + beta * cubic.u0_minus_u1
        rate = C / (r1.p * r1.q * lam)
        qc = tuple(complete_q(tm.one_n, one_m) for tm in terms)
        mo.smooth = SmoothPhi(
            rate=rate,
            C=C,
            D=beta * u21,
            b=(terms[0].a1 * terms[0].n, terms[1].a1 * terms[1].n),
            n=(terms[0].n, terms[1].n),
            one_n=(terms[0].one_n, terms[1].one_n),
            qc=(qc[0], qc[1]),
            u1=r1.u,
        )
        adv = rate * 2.0 * K + sum(2.0 * b * q for b, q in zip(mo.smooth.b, qc))
    mo.precession_rate = adv / mo.period
    return mo


@dataclass(frozen=True)
class SmoothPhi:
    """φ and ψ of a nutating top whose axis passes through neither pole, in a form without cancellation:
    ``φ − φ0 = rate (τ − c) + Σ b± [Q(n±; τ) − Q(n±; c)]``, ``ψ − ψ0 = (L3/I3) t − u1 rate (τ − c)
    − b+ ΔQ(n+) + b− ΔQ(n−)``, and the rates ``φ̇ = (C − D sn²) / ((1 − u)(1 + u))``, ``ψ̇ = ω3 − u φ̇``.
    ``qc`` is ``Q`` over a quarter period (τ from 0 to K)."""

    rate: float
    C: float
    D: float
    b: tuple[float, float]
    n: tuple[float, float]
    one_n: tuple[float, float]
    qc: tuple[float, float]
    u1: float


def _threshold_gap(top: HeavyTop | ScaledTop, phidot0: float, psidot0: float, u0: float) -> float:
    """``4a − β² = (4 M g ℓ I1 − L3²) / I1²`` with ``L3 = I3 (ψ̇0 + φ̇0 u0)``, the numerator in double-double."""
    spin = two_sum(psidot0, 0.0)
    spin = dd_add(spin, two_prod(phidot0, u0))
    L3 = dd_mul((top.I3, 0.0), spin)
    numerator = dd_add(two_prod(4.0 * top.mgl, top.I1), dd_mul((-L3[0], -L3[1]), L3))
    return float(numerator[0] + numerator[1]) / (top.I1 * top.I1)


def _vertical_period(top: HeavyTop | ScaledTop, L3: float, u0: float) -> float:
    # Limit of the nutation period of motions with Lz = ±L3 close to the vertical: π/λ with the
    # remaining root of the cubic; infinite when the vertical is unstable (separatrix).
    a, beta = top.mgl / top.I1, L3 / top.I1
    if a == 0.0:  # no gravity: the free body's nutation about L at L / I1
        return 2.0 * math.pi / abs(beta) if beta != 0.0 else math.inf
    if u0 > 0:  # sleeping top: roots 1, 1, β²/(2a) − 1
        u31 = beta * beta / (2.0 * a) - 2.0
    else:  # hanging: roots −1, −1, 1 + ... always stable
        u31 = beta * beta / (2.0 * a) + 2.0
    if u31 <= 0.0:
        return math.inf
    return math.pi / math.sqrt(a * u31 / 2.0)


@dataclass
class FreeTerms:
    """mgl = 0 (lecture: the symmetric free body about the pivot): ``u = ū + A cos x``, ``x = ν t + c``,
    ``ν = L / I1``, and each pole term of φ is elementary (see :func:`_free_motion`)."""

    nu: float
    c: float
    amplitude: float  # A = (u2 − u1)/2
    gap_top: float  # 1 − u2 ≥ 0
    gap_bottom: float  # 1 + u1 ≥ 0
    # Per pole (+1 top, −1 bottom): coefficient of ∫ dx/(p ∓ A cos x) in φ, its ρ, and s = √(p² − A²).
    coefficients: tuple[float, float]
    rhos: tuple[float, float]
    one_minus_rhos: tuple[float, float]
    jumps: tuple[float, float]
    half_d: tuple[float, float]  # (α ∓ β)/2, formed without cancellation: φ̇ = Σ half_d / (1 ∓ u)


def _free_motion(
    base: dict[str, Any],
    u0: float,
    w0: float,
    z0: float,
    s0: float,
    thd0: float,
    K0: float,
    beta: float,
    dm: float,
    dp: float,
    omega3: float,
) -> Motion:
    """Constants of the motion without gravity (mgl = 0): the symmetric free body seen in Euler angles.

    With a = 0 the nutation cubic is the parabola ``f(u) = −ν² (u − u1)(u − u2)``, ``ν² = 2ℰ + β² = L²/I1²``,
    so ``u = ū + A cos(ν t + c)``. φ̇'s pole terms ``(α ∓ β)/(2 (1 ∓ u))`` integrate in elementary form,
    ``∫ dx / (p − A cos x) = [x + 2 atan(ρ sin x / (1 − ρ cos x))] / s`` with ``p = 1 − ū``,
    ``s = √(p² − A²) = √((1 − u1)(1 − u2))``, ``ρ = A / (p + s)`` (and A → −A for the bottom pole): continuous
    in x, no branch to track. ψ̇ = L3/I3 − β ∓ (the same terms), as with gravity.
    """
    nu2 = 2.0 * K0 + beta * beta
    mo = Motion(kind="steady", **base)
    mo.precession_rate = base["phidot0"]
    if nu2 == 0.0:  # at rest
        return mo
    nu = math.sqrt(nu2)
    # In v = u − u0: −ν² v² + c1 v + c0 with c0 = sin²θ0 θ̇0² ≥ 0, c1 = f'(u0) (the loc0 expansion at a = 0).
    c1 = -4.0 * u0 * K0 + 2.0 * beta * s0 * s0 * base["phidot0"]
    # (c0 = (sin θ0 θ̇0)² is passed as its root: near the vertical the square underflows.)
    v1, v2 = local_roots(1.0, s0 * thd0, c1, -nu2, 0.0)
    v1, v2 = min(v1, 0.0), max(v2, 0.0)  # u0 lies between the roots
    # f(±1) = −(α ∓ β)²: a pole is an exact root when α ∓ β = 0 (the axis passes through it).
    if dm == 0.0:
        v2 = w0
    if dp == 0.0:
        v1 = -z0
    amplitude = 0.5 * (v2 - v1)
    mo.period = 2.0 * math.pi / nu
    if amplitude <= 0.0:  # θ constant: uniform precession about z (L along z, or the axis along L)
        return mo
    # The pole distances 1 − u2 and 1 + u1 from f written about each pole (no difference of nearby
    # numbers): f(1 − g) = −ν² g² + (4ℰ − 2β(α − β)) g − (α − β)², f(h − 1) likewise with α + β.
    gap_top = 0.0 if dm == 0.0 else local_roots(1.0, dm, -(4.0 * K0 - 2.0 * beta * dm), nu2, 0.0)[0]
    gap_bottom = 0.0 if dp == 0.0 else local_roots(1.0, dp, -(4.0 * K0 + 2.0 * beta * dp), nu2, 0.0)[0]
    # That quadratic's roots (1 ∓ u2 and 1 ∓ u1) are 2A apart: far from a pole compared with the amplitude
    # they nearly coincide and its discriminant cancels (a sphere started at the top pole lost 2e-10 of its
    # precession rate). There the gap is (1 ∓ u0) ∓ v, a difference of numbers of very unequal size.
    if dm != 0.0 and w0 - v2 > 4.0 * amplitude:
        gap_top = w0 - v2
    if dp != 0.0 and z0 + v1 > 4.0 * amplitude:
        gap_bottom = z0 + v1
    gap_top, gap_bottom = max(gap_top, 0.0), max(gap_bottom, 0.0)
    # Phase: u − ū = A cos c, u̇0 = −A ν sin c = −sin θ0 θ̇0.
    c = math.atan2(s0 * thd0 / nu, -0.5 * (v1 + v2))
    coefficients, rhos, one_minus_rhos, jumps = [], [], [], []
    for half_d, gap in ((0.5 * dm, gap_top), (0.5 * dp, gap_bottom)):
        # Through this pole, or closer to it than 1e-150 rad (a gap below the normal floats, which would
        # have lost its digits): ±π at each passage, the limit of the term.
        if gap < _THROUGH_POLE:
            coefficients.append(0.0)
            rhos.append(0.0)
            one_minus_rhos.append(1.0)
            jumps.append(1.0 if half_d == 0.0 else math.copysign(1.0, half_d))
            continue
        p = gap + amplitude  # 1 − ū (top) or 1 + ū (bottom), a sum: no cancellation
        root = math.sqrt(gap) * math.sqrt(gap + 2.0 * amplitude)  # √((1 − u2)(1 − u1)) or √((1 + u1)(1 + u2))
        coefficients.append(half_d / (nu * root))
        rhos.append(amplitude / (p + root))
        one_minus_rhos.append((gap + root) / (p + root))  # 1 − ρ without cancellation (ρ → 1 at a pole)
        jumps.append(0.0)
    mo.kind = "free"
    mo.c = c
    mo.free = FreeTerms(
        nu,
        c,
        amplitude,
        gap_top,
        gap_bottom,
        (coefficients[0], coefficients[1]),
        (rhos[0], rhos[1]),
        (one_minus_rhos[0], one_minus_rhos[1]),
        (jumps[0], jumps[1]),
        (0.5 * dm, 0.5 * dp),
    )
    mo.spin_rate = omega3 - beta
    # Mean φ̇: each term advances 2π coefficient ν per period 2π/ν, a jump π per period.
    mo.precession_rate = nu * (coefficients[0] + coefficients[1]) + 0.5 * nu * (jumps[0] + jumps[1])
    return mo
