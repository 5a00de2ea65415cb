"""The constants of a free body's motion from its initial angular velocities, and the closed form that
evaluates them at any times (:class:`physics.free_body.FreeBody` and its trajectory use them).

``kind`` 0 is uniform rotation (ω along a principal axis, or a sphere), 1 a symmetric body (trigonometric
solution), 2 the elliptic motion of a triaxial body; docs/physics-notes.md explains the method.
"""

from __future__ import annotations

import math
from dataclasses import dataclass, field, replace

import numpy as np
from numpy.typing import ArrayLike, NDArray
from scipy.special import ellipkm1, elliprf

from physics.double_double import dd_add, dd_term, two_sum
from physics.elliptic import Ladder, carlson_rj, landen_ladder, reduced_jacobi
from physics.rotations import expm_so3_unchecked
from physics.validation import finite_array, finite_phase

Floats = NDArray[np.float64]

__all__ = [
    "LOG_KP_DEEP",
    "SWAP",
    "MotionConstants",
    "check_attitude0",
    "check_omega0",
    "check_times",
    "evaluate",
    "frame_from_momentum",
    "motion_constants",
    "sep_excess",
    "third_kind_excess",
]


def _none() -> Floats:
    return np.empty(0)


@dataclass(frozen=True, eq=False)
class MotionConstants:
    """The constants of the motions from k initial states (each array has k entries along its first axis).

    ``kind`` (k,) is 0, 1 or 2 (see the module). A symmetric body has ``Omega`` (k,), the body-frame
    precession rate (rad/s), and ``i_perp``, its repeated moment (kg m²). The elliptic states (``ell``,
    (k,) bool, picks them; the arrays below have one entry per elliptic state) have the rotation ``q_can``
    (e, 3, 3) to canonical axes (a, b, c) with moments ``ia, ib, ic`` (scaled), the parameter ``m`` and its
    complement ``mc`` with ``kp = √(1 − m)``, ``deep`` (within 1 − m < 1e-40 of the separatrix), the
    quarter period ``K``, the rate ``lam`` (1/s) and the initial phase ``u0`` of ``u = lam t + u0``, the
    characteristic ``n`` of the third-kind integral and ``Jc`` (3 Q(K)), the amplitudes ``amp`` (e, 3) of
    ω in canonical axes (rad/s), ``L`` = |L| / scale, the pole of the frame (``pole_c``), the rates
    ``rate0`` and ``coef`` of ψ, the Landen ``ladder`` of (m, mc) and ``P0``, the excess at u0.
    """

    kind: NDArray[np.int_]
    Omega: Floats = field(default_factory=_none)
    i_perp: float = 0.0
    ell: NDArray[np.bool_] = field(default_factory=lambda: np.empty(0, dtype=bool))
    q_can: Floats = field(default_factory=_none)
    ia: Floats = field(default_factory=_none)
    ib: Floats = field(default_factory=_none)
    ic: Floats = field(default_factory=_none)
    m: Floats = field(default_factory=_none)
    mc: Floats = field(default_factory=_none)
    kp: Floats = field(default_factory=_none)
    deep: NDArray[np.bool_] = field(default_factory=lambda: np.empty(0, dtype=bool))
    K: Floats = field(default_factory=_none)
    lam: Floats = field(default_factory=_none)
    u0: Floats = field(default_factory=_none)
    n: Floats = field(default_factory=_none)
    Jc: Floats = field(default_factory=_none)
    amp: Floats = field(default_factory=_none)
    L: Floats = field(default_factory=_none)
    pole_c: NDArray[np.bool_] = field(default_factory=lambda: np.empty(0, dtype=bool))
    rate0: Floats = field(default_factory=_none)
    coef: Floats = field(default_factory=_none)
    ladder: Ladder = field(default_factory=lambda: ([], np.empty(0)))
    P0: Floats = field(default_factory=_none)


def check_omega0(omega0: ArrayLike) -> NDArray[np.float64]:
    """``omega0`` as a finite (3,) array, rad/s, else a ValueError naming it."""
    w = finite_array(omega0, "the initial angular velocity omega0")
    if w.shape != (3,):
        raise ValueError(f"omega0 must have shape (3,) (rad/s in body axes), got shape {w.shape}")
    return w


def check_attitude0(attitude0: ArrayLike | None) -> NDArray[np.float64]:
    """``attitude0`` as a rotation (3, 3) (the identity for None), else a ValueError naming it."""
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


def check_times(t: ArrayLike) -> NDArray[np.float64]:
    """Times ``t`` (s) as a finite 1-D array (a scalar as one time), else a ValueError naming them."""
    tt = finite_array(t, "the times t")
    if tt.ndim > 1:
        raise ValueError(f"t must be a scalar or a 1-D array of times in seconds, got shape {tt.shape}")
    return np.atleast_1d(tt)


# Within 1 − m < 1e-40 of the separatrix (k' < 1e-20) the motion is, to double precision, a train of the
# separatrix's pulses 2K apart: sn = tanh, cn = dn = sech up to K/2 from a pulse's centre, and past it
# cn(K − w) = k' sinh w, dn(K − w) = k' cosh w, sn = 1 (the neglected terms are below k'/4 relative); the
# excess Q is the separatrix's, continued by (K − |v|)/(1 − n) near ±K, and K = ln(4/k') (its error is of
# order k'² K). Only k' enters, through its logarithm: nothing underflows, down to 1 − m far below 1e-308
# (a push of 1e-160 off the intermediate axis has 1 − m ≈ 1e-320). See third_kind_excess and motion_constants.
LOG_KP_DEEP = math.log(1e-20)


def _pair_exponent(x: Floats, y: Floats) -> NDArray[np.int_]:
    """``e`` with ``max(|x|, |y|) 2^-e`` in [0.5, 1) (0 where both are 0): the pair scaled to order 1."""
    return np.asarray(np.frexp(np.maximum(np.abs(x), np.abs(y)))[1], dtype=int)


SWAP = np.array([[0.0, 0.0, -1.0], [0.0, -1.0, 0.0], [-1.0, 0.0, 0.0]])  # proper: exchanges 1st and 3rd


def motion_constants(
    moments: Floats, sorted_moments: Floats, q_sort: Floats, symmetry_axis: int, w: Floats
) -> MotionConstants:
    """Constants of the motion for each initial ω (k, 3) of a body with these ``moments`` (kg m²), sorted
    and scaled to order 1 (``sorted_moments``, by the proper rotation ``q_sort``), whose symmetry axis is
    ``symmetry_axis`` (-1 for a triaxial body).

    ``kind``: 0 uniform rotation (ω along one principal axis, or a sphere), 1 symmetric body
    (trigonometric solution), 2 elliptic.
    """
    k = w.shape[0]
    kind = np.zeros(k, dtype=int)
    if symmetry_axis >= 0:
        s = symmetry_axis
        i_s = moments[s]
        i_perp = moments[(s + 1) % 3]
        kind[:] = 1
        return MotionConstants(kind=kind, Omega=w[:, s] * (i_perp - i_s) / i_perp, i_perp=float(i_perp))
    # Work with ω scaled by a power of two (exact) to a largest component of order 1. Only ω exactly
    # along one principal axis is uniform rotation: however small the other components, the motion
    # leaves it (about the intermediate axis, after ln(1/push)/rate seconds), see LOG_KP_DEEP.
    biggest = np.max(np.abs(w), axis=1)
    scale = np.where(biggest > 0.0, np.exp2(np.floor(np.log2(np.where(biggest > 0.0, biggest, 1.0)))), 1.0)
    ws = (w @ q_sort.T) / scale[:, None]
    nonzero = np.count_nonzero(ws, axis=1)
    ell = nonzero > 1
    kind[ell] = 2
    if not np.any(ell):
        return MotionConstants(kind=kind)
    i1, i2, i3 = sorted_moments
    ws_e = ws[ell]
    # Sign of L² − 2 E I2 (double-double, on the pair (ω1, ω3) scaled to order 1) picks the axis the
    # motion circulates around.
    d12 = two_sum(i1, -i2)
    d32 = two_sum(i3, -i2)
    e_mid = _pair_exponent(ws_e[:, 0], ws_e[:, 2])
    g_mid = dd_add(dd_term(i1, d12, np.ldexp(ws_e[:, 0], -e_mid)), dd_term(i3, d32, np.ldexp(ws_e[:, 2], -e_mid)))
    swap = g_mid[0] < 0.0
    q_can = np.where(swap[:, None, None], SWAP @ q_sort, q_sort)
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
    deep = ~sep & (log_kp < LOG_KP_DEEP)
    ang = np.sqrt(np.sum((sorted_moments * ws_e) ** 2, axis=1))
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
            v_deep = np.where(past_half, kk - np.arcsinh(c0_over_kp / np.abs(s0)), np.arcsinh(np.abs(s0) / np.abs(c0)))
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
        jc = np.where(deep, 3.0 * sep_excess(np.where(deep, kk, 0.0), n), jc)
    p = MotionConstants(
        kind=kind,
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
    p = replace(p, ladder=landen_ladder(np.where(sep | deep, 0.0, m), np.where(sep | deep, 1.0, mc)))
    return replace(p, P0=third_kind_excess(p, np.arange(len(m)), u0))


def evaluate(
    p: MotionConstants,
    moments: Floats,
    symmetry_axis: int,
    w: Floats,
    t: Floats,
    r0: Floats | None,
    which: NDArray[np.intp],
    want_attitude: bool,
    time_name: str = "t",
) -> tuple[Floats, Floats]:
    """Evaluate the motion of initial states ``w`` (k, 3), ``r0`` (k, 3, 3) at times ``t`` (n,);
    ``which`` (n,) says which state each time belongs to; ``p`` are their :func:`motion_constants`;
    ``time_name`` names the times in a refusal."""
    # Every phase (λ t, Ω t, L t / I, |ω| t) is below |ω| t times the spread of the moments.
    spread = float(np.max(moments) / np.min(moments[moments > 0.0]))
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
    kind = p.kind[which]
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
        s = symmetry_axis
        ws = w[which[sel]]
        ang = p.Omega[which[sel]] * t[sel]
        cs, sn = np.cos(ang), np.sin(ang)
        b, c = (s + 1) % 3, (s + 2) % 3
        res = ws.copy()
        res[:, b] = ws[:, b] * cs + ws[:, c] * sn
        res[:, c] = ws[:, c] * cs - ws[:, b] * sn
        out_w[sel] = res
        if want_attitude:
            rs = r0[which[sel]]
            l_space = np.einsum("kij,kj->ki", rs, moments * ws)
            axis = np.zeros((sel.size, 3))
            axis[:, s] = ang
            out_r[sel] = expm_so3_unchecked(t[sel, None] * l_space / p.i_perp) @ rs @ expm_so3_unchecked(axis)
    sel = np.nonzero(kind == 2)[0]
    if sel.size:
        if w.shape[0] == 1:
            # One state: its constants stay shape (1,) and broadcast against the times.
            e_index, ws, rs = np.zeros(1, dtype=int), w, r0
        else:
            e_index = (np.cumsum(p.kind == 2) - 1)[which[sel]]
            ws, rs = w[which[sel]], r0[which[sel]]
        wt, rt = _elliptic(p, e_index, t[sel], rs if want_attitude else None, ws)
        out_w[sel] = wt
        if rt is not None:
            out_r[sel] = rt
    return out_w, out_r


def _elliptic(
    p: MotionConstants, e: NDArray[np.intp], t: Floats, r0: Floats | None, w0: Floats
) -> tuple[Floats, Floats | None]:
    """The general motion for elliptic states ``e`` (indices into the setup arrays) at times t."""
    lam, u0 = p.lam[e], p.u0[e]
    u = lam * t + u0
    m, mc, kk = p.m[e], p.mc[e], p.K[e]
    roots, scale = p.ladder
    ladder = ([q[e] for q in roots], scale[e])
    j, v, s, c, d = reduced_jacobi(u, m, mc, kk, ladder, p.kp[e])
    sign = 1.0 - 2.0 * np.mod(j, 2.0)
    amp = p.amp[e]
    wc = np.stack([amp[:, 0] * d, amp[:, 1] * sign * s, amp[:, 2] * sign * c], axis=1)
    q = p.q_can[e]
    qt = np.swapaxes(q, 1, 2)
    omega = (qt @ wc[:, :, None])[:, :, 0]
    if r0 is None:
        return omega, None
    ia, ib, ic = p.ia[e], p.ib[e], p.ic[e]
    # Angle turned about L: ψ − ψ0 = L t / I_c + C [P(u) − P(u0)], P = Π(n; am u|m) − u.
    big_l = p.L[e]
    excess = third_kind_excess(p, e, u, (j, v, s, c, d))
    dpsi = big_l * t * p.rate0[e] + p.coef[e] * (excess - p.P0[e])
    pole_c = p.pole_c[e]
    frame_t = frame_from_momentum(wc, ia, ib, ic, pole_c)
    # Frame at t = 0 and M0 = R0 Qᵀ B(0) (its third column is L̂ in space).
    wc0 = (q @ w0[:, :, None])[:, :, 0]
    frame_0 = frame_from_momentum(wc0, ia, ib, ic, pole_c)
    m0 = r0 @ qt @ frame_0
    cp, sp = np.cos(dpsi), np.sin(dpsi)
    bt = np.swapaxes(frame_t, 1, 2)  # rows b1, b2, b3
    rot_bt = np.empty_like(bt)
    rot_bt[:, 0] = cp[:, None] * bt[:, 0] - sp[:, None] * bt[:, 1]
    rot_bt[:, 1] = sp[:, None] * bt[:, 0] + cp[:, None] * bt[:, 1]
    rot_bt[:, 2] = bt[:, 2]
    return omega, m0 @ rot_bt @ q


def third_kind_excess(
    p: MotionConstants, e: NDArray[np.intp], u: Floats, reduced: tuple[Floats, ...] | None = None
) -> Floats:
    """``Q(u) = ∫₀ᵘ sn²/(1 − n sn²) du = (Π(n; am u|m) − u)/n`` for elliptic states ``e`` at phases u.

    Carlson: ``Q = (1/3) sn³ R_J(cn², dn², 1, 1 − n sn²)`` for ``|u| ≤ K`` (no division by n), and
    ``Q(u + 2K) = Q(u) + (2/3) R_J(0, 1 − m, 1, 1 − n)``; on the separatrix (m = 1) the elementary
    ``Q = [u − atan(√|n| tanh u)/√|n|] / (1 − n)``.
    """
    n, m, mc, kk, jc = p.n[e], p.m[e], p.mc[e], p.K[e], p.Jc[e]
    if reduced is None:
        roots, scale = p.ladder
        reduced = reduced_jacobi(u, m, mc, kk, ([q[e] for q in roots], scale[e]), p.kp[e])
    j, v, s, c, d = reduced
    deep = p.deep[e]
    with np.errstate(all="ignore"):  # R_J's arguments underflow where deep: that branch is not used there
        out = (2.0 * j * jc + s**3 * carlson_rj(c * c, d * d, 1.0 - n * s * s)) / 3.0
    sep = ~np.isfinite(kk)
    if np.any(sep | deep):
        # The separatrix, and within 1 − m < 1e-40 of it (see LOG_KP_DEEP): pulses of the separatrix's Q.
        a = np.abs(np.where(sep, u, v))
        pulse = sep_excess(a, n)
        kfin = np.where(sep, 0.0, kk)
        far = ~sep & (a > 0.5 * kfin)
        near_k = (jc / 3.0) - (kfin - a) / (1.0 - n)  # Q(K) − (K − |v|)/(1 − n), sn = 1 there
        local = np.copysign(np.where(far, near_k, pulse), np.where(sep, u, v))
        out = np.where(sep | deep, np.where(sep, 0.0, 2.0 * j * jc / 3.0) + local, out)
    return np.asarray(out, dtype=float)


def sep_excess(a: Floats, n: Floats) -> Floats:
    """``Q(a) = [a − atan(√−n tanh a)/√−n] / (1 − n)``, ``a ≥ 0``: the excess on the separatrix (m = 1)."""
    rn = np.sqrt(-n)
    th = np.tanh(a)
    x = rn * th
    small = np.abs(x) < 1e-8
    atan_over = np.where(small, th * (1.0 - x * x / 3.0), np.arctan(x) / np.where(small, 1.0, rn))
    return np.asarray((a - atan_over) / (1.0 - n), dtype=float)


def frame_from_momentum(wc: Floats, ia: Floats, ib: Floats, ic: Floats, pole_c: NDArray[np.bool_]) -> Floats:
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
