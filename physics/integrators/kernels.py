"""Compiled steps (numba, ``cache=True``): the splitting methods and Lie RK4 with the project's torques.

A method's step is data here, not code: a splitting is its *program*, a sequence of sub-flows (the exact
axis rotations ``X``, ``Y``, ``Z``; the torque half-steps ``T0``/``T1``; the exact symmetric free flow
``E``) with the fraction of the step each takes, and the torques are arrays of coefficients. One compiled
loop runs any program over a batch of bodies, shape (n, 12): ``R`` row-major, then ``L_body``. The
sub-flows are the very formulas of :mod:`physics.integrators._state` and :mod:`.torques`, so the compiled
and the interpreted step agree to round-off.

Compiled torques (all of :mod:`physics.integrators.torques` and the air drag of
:class:`.torques.TransverseAirDrag`): gravity at the centre of mass (a kick, ``L ← L + h τ(R)``), spin friction
about an axis (its exact flow, linear in L), transverse air drag ``−c (ω1, ω2, 0)`` (its exact flow,
``L_i ← L_i e^{−c h / I_i}``). Any other torque runs on the interpreted path, slower.

Compensated splittings (``compensated``: the ``compensated=True`` methods) carry ``L_body`` in double-double
arithmetic (Dekker 1971: a high and a low part, :mod:`physics.double_double`) through the axis rotations of
one call, and rotate it by the exactly orthogonal rotation nearest to the rounded ``(cos θ, sin θ)``. Near
the separatrix the motion depends on ``L² − 2 E I2``, a difference of large terms that one rounding of
``L_body`` in the flip changes by 1e-3 of itself (docs/physics-notes.md, "Near the separatrix").
"""

from __future__ import annotations

import math
from typing import Any

import numpy as np
from llvmlite import ir
from numba import njit, types
from numba.extending import intrinsic

from physics.double_double import two_sum

__all__ = ["OP_X", "OP_Y", "OP_Z", "OP_T0", "OP_T1", "OP_E", "run_splitting", "run_lie_rk4", "run_classical_rk4"]

OP_X, OP_Y, OP_Z, OP_T0, OP_T1, OP_E = 0, 1, 2, 3, 4, 5

_two_sum = njit(cache=True, inline="always")(two_sum)


def _fma_typing(typingctx, a, b, c):
    sig = types.float64(types.float64, types.float64, types.float64)

    def codegen(context, builder, signature, args):
        d = ir.DoubleType()
        fn = builder.module.declare_intrinsic("llvm.fma", [d], ir.FunctionType(d, [d, d, d]))
        return builder.call(fn, args)

    return sig, codegen


_fma: Any = intrinsic(_fma_typing)
"""``_fma(a, b, c)``: ``a b + c`` rounded once (LLVM's fma: the processor's instruction, else libm's), so
``_fma(a, b, −a b)`` is the rounding error of the product exactly (the error-free product)."""


@njit(cache=True)
def _turn(s, j, k, c, sn, rows):
    """Entries j, k of the first ``rows`` triples of ``s`` (R's rows, then L_body as the fourth) turned by
    the angle whose cosine and sine are ``c``, ``sn``, in place."""
    for row in range(rows):
        a, b = s[3 * row + j], s[3 * row + k]
        s[3 * row + j] = c * a + sn * b
        s[3 * row + k] = c * b - sn * a


@njit(cache=True)
def _rotate(s, i, th):
    """The exact flow of ``L_i²/(2 I_i)``: R ← R exp(θ ê_i), L ← exp(−θ ê_i) L, in place."""
    j, k = (1, 2) if i == 0 else ((2, 0) if i == 1 else (0, 1))
    _turn(s, j, k, math.cos(th), math.sin(th), 4)


@njit(cache=True)
def _rotate_compensated(s, lo, i, th):
    """:func:`_rotate` with ``L_body`` in double-double (high parts in ``s[9:]``, low parts in ``lo``), in place.

    ``L`` is rotated by ``(c, s_n) / sqrt(c² + s_n²)`` (the rounded cosine and sine made exactly orthogonal):
    ``|L|`` is kept far below one float64 rounding and ``L² − 2 E I2`` moves only as the step's angle says, not by the
    1e-16 that a rotation of rounded ``(c, s_n)`` scales the ``(j, k)`` plane by. ``R`` is rotated as
    in :func:`_rotate` (its rounding does not feed back into the motion).
    """
    j, k = (1, 2) if i == 0 else ((2, 0) if i == 1 else (0, 1))
    c, sn = math.cos(th), math.sin(th)
    _turn(s, j, k, c, sn, 3)
    # η = c² + s_n² − 1 (about 1e-16) from the error-free squares; (1 − η/2) makes the rotation orthogonal.
    cc, ss = c * c, sn * sn
    t, et = _two_sum(cc, ss)
    half_eta = 0.5 * ((t - 1.0) + (et + _fma(c, c, -cc) + _fma(sn, sn, -ss)))
    a, b, al, bl = s[9 + j], s[9 + k], lo[j], lo[k]
    # L_j ← c L_j + s_n L_k and L_k ← c L_k − s_n L_j: the high part is the plain rotation's rounded sum
    # (so the next angle waits no longer than in :func:`_rotate`); its error, the products' errors (fma),
    # the rotated low parts and the orthogonality correction go to the low part, off that critical path.
    # The low part is not renormalised here (it grows by up to an ulp of the high part per rotation):
    # :func:`_renormalise` does it once a step.
    p, q = c * a, sn * b
    hi, e = _two_sum(p, q)
    s[9 + j] = hi
    lo[j] = e + _fma(c, a, -p) + _fma(sn, b, -q) + (c * al + sn * bl) - half_eta * hi
    p, q = c * b, sn * a
    hi, e = _two_sum(p, -q)
    s[9 + k] = hi
    lo[k] = e + _fma(c, b, -p) - _fma(sn, a, -q) + (c * bl - sn * al) - half_eta * hi


@njit(cache=True)
def _renormalise(s, lo):
    """Double-double ``L_body``: the high parts the nearest floats to ``s[9:] + lo`` (Dekker's fast two-sum)."""
    for i in range(3):
        hi = s[9 + i] + lo[i]
        lo[i] -= hi - s[9 + i]
        s[9 + i] = hi


@njit(cache=True)
def _fold(s, lo):
    """Round the double-double ``L_body`` to the state (``s[9:] + lo``) and clear ``lo``."""
    for i in range(3):
        s[9 + i] += lo[i]
        lo[i] = 0.0


@njit(cache=True)
def _right_exp(s, u0, u1, u2):
    """R ← R exp(hat u) by Rodrigues' formula (Taylor below |u| = 1e-4 rad), in place."""
    a2 = u0 * u0 + u1 * u1 + u2 * u2
    if a2 < 1e-8:
        sa, ca = 1.0 - a2 / 6.0 + a2 * a2 / 120.0, 0.5 - a2 / 24.0 + a2 * a2 / 720.0
    else:
        a = math.sqrt(a2)
        sa, ca = math.sin(a) / a, (1.0 - math.cos(a)) / a2
    e00 = 1.0 - ca * (u1 * u1 + u2 * u2)
    e11 = 1.0 - ca * (u0 * u0 + u2 * u2)
    e22 = 1.0 - ca * (u0 * u0 + u1 * u1)
    p01, p02, p12 = ca * u0 * u1, ca * u0 * u2, ca * u1 * u2
    q0, q1, q2 = sa * u0, sa * u1, sa * u2
    e01, e10 = p01 - q2, p01 + q2
    e02, e20 = p02 + q1, p02 - q1
    e12, e21 = p12 - q0, p12 + q0
    for row in range(3):
        x, y, z = s[3 * row], s[3 * row + 1], s[3 * row + 2]
        s[3 * row] = x * e00 + y * e10 + z * e20
        s[3 * row + 1] = x * e01 + y * e11 + z * e21
        s[3 * row + 2] = x * e02 + y * e12 + z * e22


@njit(cache=True)
def _kick(s, h, gravity):
    """Gravity kicks L ← L − h w × (third row of R), one per row of ``gravity`` (w = M g c, N m)."""
    for g in range(gravity.shape[0]):
        w0, w1, w2 = gravity[g, 0], gravity[g, 1], gravity[g, 2]
        r20, r21, r22 = s[6], s[7], s[8]
        s[9] -= h * (w1 * r22 - w2 * r21)
        s[10] -= h * (w2 * r20 - w0 * r22)
        s[11] -= h * (w0 * r21 - w1 * r20)


@njit(cache=True)
def _dissipate(s, h, friction, drag, backwards):
    """The exact flows of the spin frictions (rows c, s, a0, a1, a2, 1/I0, 1/I1, 1/I2 of its own moments)
    and of the transverse air drags (rows c, 1/I0, 1/I1), in place: frictions then drags, or (``backwards``,
    the second half of a symmetric step) drags then frictions, each in reverse order. They need not commute
    (a friction axis off z mixes L0, L1 with L2): only this mirror order keeps the base step symmetric, so
    that its compositions keep their order."""
    nf, nd = friction.shape[0], drag.shape[0]
    for q in range(nf + nd):
        r = nf + nd - 1 - q if backwards else q
        if r < nf:
            c, sf, a0, a1, a2 = friction[r, 0], friction[r, 1], friction[r, 2], friction[r, 3], friction[r, 4]
            if sf > 0.0 and c > 0.0:
                wa = a0 * friction[r, 5] * s[9] + a1 * friction[r, 6] * s[10] + a2 * friction[r, 7] * s[11]
                k = math.expm1(-c * sf * h) / sf * wa
                s[9] += k * a0
                s[10] += k * a1
                s[11] += k * a2
        else:
            d = r - nf
            for i in range(2):
                s[9 + i] *= math.exp(-drag[d, 0] * h * drag[d, 1 + i])


@njit(cache=True)
def _hold_zero_axes(s, zero):
    for i in range(3):
        if zero[i]:
            s[9 + i] = 0.0 * s[9 + i]


@njit(cache=True)
def run_splitting(states, dt, n, ops, fracs, inv, zero, gravity, friction, drag, sym, compensated):
    """Take ``n`` steps of ``dt`` of a splitting program for every body of ``states`` (k, 12), in place.

    ``ops``/``fracs``: the program; ``inv`` (3,) the inverse moments (0 on a zero moment), ``zero`` (3,)
    the zero-moment axes; ``gravity`` (g, 3), ``friction`` (f, 8), ``drag`` (d, 3) the torques; ``sym``
    (axis, 1/I⊥, 1/I_s − 1/I⊥) of a symmetric body for the exact free flow ``E``; ``compensated``: carry
    ``L_body`` in double-double through the rotations (see the module), rounded to the state before a
    torque sub-flow and at the end of the ``n`` steps.
    """
    has_zero = zero[0] or zero[1] or zero[2]
    ax = int(sym[0])
    last = ops.shape[0] - 1
    # A step's last sub-flow and the next step's first are one flow when they are the same rotation (it
    # leaves its own L_i alone) or two kicks with nothing dissipative between: fused, one rounding less.
    fuse = last > 0 and (
        (ops[0] == ops[last] and ops[0] <= OP_Z)
        or (ops[0] == OP_T0 and ops[last] == OP_T1 and friction.shape[0] == 0 and drag.shape[0] == 0)
    )
    lo = np.zeros(3)
    for b in range(states.shape[0]):
        s = states[b]
        for step in range(n):
            for p in range(last + 1):
                if fuse and p == last and step < n - 1:
                    continue  # taken with the next step's first sub-flow
                frac = fracs[p] + fracs[last] if fuse and p == 0 and step > 0 else fracs[p]
                op, h = ops[p], frac * dt
                if op <= OP_Z:
                    # The angle from the high part: its rounding only shifts the sub-flow's time by 1e-16.
                    if compensated:
                        _rotate_compensated(s, lo, op, h * inv[op] * s[9 + op])
                    else:
                        _rotate(s, op, h * inv[op] * s[9 + op])
                    continue
                if compensated:
                    _fold(s, lo)
                if op == OP_T0:
                    _kick(s, h, gravity)
                    _dissipate(s, h, friction, drag, False)
                    if has_zero:
                        _hold_zero_axes(s, zero)
                elif op == OP_T1:
                    _dissipate(s, h, friction, drag, True)
                    _kick(s, h, gravity)
                    if has_zero:
                        _hold_zero_axes(s, zero)
                else:
                    a = h * sym[1]
                    _right_exp(s, a * s[9], a * s[10], a * s[11])
                    _rotate(s, ax, h * sym[2] * s[9 + ax])
            if compensated:
                _renormalise(s, lo)
        if compensated:
            _fold(s, lo)
    return states


@njit(cache=True)
def _rates(s, inv, gravity, friction, drag, out):
    """ω (out[0:3]) and dL/dt = L × ω + τ (out[3:6]) of a state."""
    l0, l1, l2 = s[9], s[10], s[11]
    w0, w1, w2 = inv[0] * l0, inv[1] * l1, inv[2] * l2
    d0, d1, d2 = l1 * w2 - l2 * w1, l2 * w0 - l0 * w2, l0 * w1 - l1 * w0
    for g in range(gravity.shape[0]):
        g0, g1, g2 = gravity[g, 0], gravity[g, 1], gravity[g, 2]
        d0 -= g1 * s[8] - g2 * s[7]
        d1 -= g2 * s[6] - g0 * s[8]
        d2 -= g0 * s[7] - g1 * s[6]
    for f in range(friction.shape[0]):
        c, a0, a1, a2 = friction[f, 0], friction[f, 2], friction[f, 3], friction[f, 4]
        wa = c * (a0 * friction[f, 5] * l0 + a1 * friction[f, 6] * l1 + a2 * friction[f, 7] * l2)
        d0 -= wa * a0
        d1 -= wa * a1
        d2 -= wa * a2
    for d in range(drag.shape[0]):
        d0 -= drag[d, 0] * drag[d, 1] * l0
        d1 -= drag[d, 0] * drag[d, 2] * l1
    out[0], out[1], out[2], out[3], out[4], out[5] = w0, w1, w2, d0, d1, d2


@njit(cache=True)
def _dexpinv(u0, u1, u2, w, k):
    """k = ω + ½ u × ω + (1/12) u × (u × ω) (dexp⁻¹ to the order RK4 needs)."""
    w0, w1, w2 = w[0], w[1], w[2]
    c0, c1, c2 = u1 * w2 - u2 * w1, u2 * w0 - u0 * w2, u0 * w1 - u1 * w0
    e0, e1, e2 = u1 * c2 - u2 * c1, u2 * c0 - u0 * c2, u0 * c1 - u1 * c0
    k[0] = w0 + 0.5 * c0 + e0 / 12.0
    k[1] = w1 + 0.5 * c1 + e1 / 12.0
    k[2] = w2 + 0.5 * c2 + e2 / 12.0


@njit(cache=True)
def run_lie_rk4(states, dt, n, inv, zero, gravity, friction, drag):
    """``n`` Runge–Kutta–Munthe-Kaas (classical tableau) steps of ``dt`` for every body, in place."""
    has_zero = zero[0] or zero[1] or zero[2]
    r = np.empty(6)
    k1, k2, k3, k4 = np.empty(3), np.empty(3), np.empty(3), np.empty(3)
    m1, m2, m3, m4 = np.empty(3), np.empty(3), np.empty(3), np.empty(3)
    st = np.empty(12)
    for b in range(states.shape[0]):
        s = states[b]
        for _ in range(n):
            h = dt
            _rates(s, inv, gravity, friction, drag, r)
            k1[:] = r[:3]
            m1[:] = r[3:]
            for stage in range(3):
                frac = 0.5 if stage < 2 else 1.0
                kp, mp = (k1, m1) if stage == 0 else ((k2, m2) if stage == 1 else (k3, m3))
                u0, u1, u2 = frac * h * kp[0], frac * h * kp[1], frac * h * kp[2]
                st[:] = s
                _right_exp(st, u0, u1, u2)
                for i in range(3):
                    st[9 + i] = s[9 + i] + frac * h * mp[i]
                _rates(st, inv, gravity, friction, drag, r)
                kn, mn = (k2, m2) if stage == 0 else ((k3, m3) if stage == 1 else (k4, m4))
                _dexpinv(u0, u1, u2, r[:3], kn)
                mn[:] = r[3:]
            h6 = h / 6.0
            u0 = h6 * (k1[0] + 2.0 * k2[0] + 2.0 * k3[0] + k4[0])
            u1 = h6 * (k1[1] + 2.0 * k2[1] + 2.0 * k3[1] + k4[1])
            u2 = h6 * (k1[2] + 2.0 * k2[2] + 2.0 * k3[2] + k4[2])
            for i in range(3):
                s[9 + i] += h6 * (m1[i] + 2.0 * m2[i] + 2.0 * m3[i] + m4[i])
            _right_exp(s, u0, u1, u2)
            if has_zero:
                _hold_zero_axes(s, zero)
    return states


@njit(cache=True)
def _component_rates(s, inv, gravity, friction, drag, r, out):
    """The twelve components' rates: Ṙ = R hat(ω) (row i: r_i × ω), then dL/dt."""
    _rates(s, inv, gravity, friction, drag, r)
    w0, w1, w2 = r[0], r[1], r[2]
    for i in range(0, 9, 3):
        a, b, c = s[i], s[i + 1], s[i + 2]
        out[i], out[i + 1], out[i + 2] = b * w2 - c * w1, c * w0 - a * w2, a * w1 - b * w0
    out[9], out[10], out[11] = r[3], r[4], r[5]


@njit(cache=True)
def run_classical_rk4(states, dt, n, inv, zero, gravity, friction, drag):
    """``n`` classical RK4 steps of ``dt`` on the twelve components of every body, in place (not geometric:
    ``R`` is integrated as any linear ODE and leaves the rotations, as :class:`ClassicalRK4` says)."""
    has_zero = zero[0] or zero[1] or zero[2]
    r = np.empty(6)
    k1, k2, k3, k4 = np.empty(12), np.empty(12), np.empty(12), np.empty(12)
    st = np.empty(12)
    for b in range(states.shape[0]):
        s = states[b]
        for _ in range(n):
            h = dt
            _component_rates(s, inv, gravity, friction, drag, r, k1)
            for i in range(12):
                st[i] = s[i] + 0.5 * h * k1[i]
            _component_rates(st, inv, gravity, friction, drag, r, k2)
            for i in range(12):
                st[i] = s[i] + 0.5 * h * k2[i]
            _component_rates(st, inv, gravity, friction, drag, r, k3)
            for i in range(12):
                st[i] = s[i] + h * k3[i]
            _component_rates(st, inv, gravity, friction, drag, r, k4)
            h6 = h / 6.0
            for i in range(12):
                s[i] = s[i] + h6 * (k1[i] + 2.0 * k2[i] + 2.0 * k3[i] + k4[i])
            if has_zero:
                _hold_zero_axes(s, zero)
    return states
