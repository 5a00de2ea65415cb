"""30-digit mpmath reference for the torque-free body (helper of tests/physics/test_free_body.py; no tests here).

An independent evaluation of Landau's closed form in mpmath (its own Jacobi functions, K and Π), with
the floating-point inputs taken as exact. It was itself checked against DOP853 integrations over short
spans (tests/physics/test_free_body.py::test_matches_high_precision_integration_short_span).
"""

from __future__ import annotations

import mpmath as mp
import numpy as np

from tests.physics.mp_jacobi import mp_sn_cn_dn

DPS = 30


def _cyc(i):
    return i, (i + 1) % 3, (i + 2) % 3


def reference_motion(moments, omega0, times, attitude0=None, dps=DPS):
    """ω(t) (n, 3) and R(t) (n, 3, 3) at ``dps`` digits (30 by default) for a triaxial body off uniform rotation.

    Near the separatrix ``dps`` must exceed the digits 1 − m has zeros by about 30, or m rounds to 1 (mpmath's
    exponent range is unbounded: 1 − m = 1e-600 is an ordinary number there)."""
    with mp.workdps(dps):
        moments = [mp.mpf(float(x)) for x in moments]
        w = [mp.mpf(float(x)) for x in omega0]
        two_e = sum(i * x * x for i, x in zip(moments, w))
        l2 = sum((i * x) ** 2 for i, x in zip(moments, w))

        def excess(i_ref):
            # L² − 2 E i_ref = Σ I_k ω_k² (I_k − i_ref), summed term by term. Off a principal axis by a push
            # δ, 2 E I − L² about that axis is ~δ² of L²: formed as a difference it would need twice δ's
            # zeros in digits; each term here keeps its relative precision, so only 1 − m (which does
            # cancel, near the separatrix) sets the digits needed.
            return sum(i * x * x * (i - i_ref) for i, x in zip(moments, w))

        order = sorted(range(3), key=lambda k: -moments[k])
        mid = order[1]
        a = order[0] if l2 > two_e * moments[mid] else order[2]
        # A right-handed frame (a, mid, other): cyclic (a, a+1, a+2) when the middle axis is a+1,
        # otherwise (−e_a, e_c, e_b), which is right-handed too.
        b, c = (a + 1) % 3, (a + 2) % 3
        if mid == b:
            axes, signs = (a, b, c), (1, 1, 1)
        else:
            axes, signs = (a, c, b), (-1, 1, 1)  # (−e_a, e_c, e_b) is right-handed
        i_a, i_b, i_c = (moments[k] for k in axes)
        wa, wb, wc = (s * w[k] for s, k in zip(signs, axes))
        l2_minus_2e_ia, l2_minus_2e_ic = excess(i_a), excess(i_c)
        ga = abs(l2_minus_2e_ia)
        gc = abs(l2_minus_2e_ic)
        m = (i_b - i_c) * -l2_minus_2e_ia / ((i_a - i_b) * l2_minus_2e_ic)
        if abs(1 - m) < mp.mpf(10) ** (5 - dps):
            m = mp.mpf(1)  # exactly on the separatrix (L² = 2 E I2 holds exactly for these binary inputs)
        amp_a = mp.sqrt(gc / abs(i_a * (i_a - i_c)))
        amp_b = mp.sqrt(ga / abs(i_b * (i_a - i_b)))
        amp_c = mp.sqrt(ga / abs(i_c * (i_a - i_c)))
        pa = 1 if wa >= 0 else -1
        lam = -pa * mp.sign(i_a - i_b) * mp.sqrt((i_a - i_b) * l2_minus_2e_ic / (i_a * i_b * i_c))
        s0, c0 = wb / amp_b, wc / amp_c
        pc = 1
        if m == 1 and c0 < 0:  # separatrix: cn = sech > 0, the other branch is ω_c = −A_c sech with −λ
            pc, c0, lam = -1, -c0, -lam
        phi0 = mp.atan2(s0, c0)
        u0 = mp.ellipf(phi0, m)
        n = -i_a * (i_b - i_c) / (i_c * (i_a - i_b))
        big_l = mp.sqrt(l2)
        kk = mp.ellipk(m)
        jacobi = mp_sn_cn_dn(m)  # mp.ellipfun's sn, cn, dn, its constants computed once for this m
        pi_c = mp.ellippi(n, m) if m < 1 else mp.mpf(0)  # K = ∞ on the separatrix: never used

        known_pi: dict = {}

        def big_pi(u):
            # Π(n; am u | m), continued past |u| ≤ K by quasi-periodicity; computed once per u (t = 0 is u0,
            # whose Π is also the offset pi0: at hundreds of digits each Π takes up to a second).
            if u not in known_pi:
                known_pi[u] = new_pi(u)
            return known_pi[u]

        def new_pi(u):
            if m == 1:
                # mpmath's ellippi refuses m = 1: integrate ∫ du / (1 − n tanh² u) numerically,
                # as u/(1 − n) plus a correction that decays like e^{−2u}.
                def bump(x):
                    return 1 / (1 - n * mp.tanh(x) ** 2) - 1 / (1 - n)

                return u / (1 - n) + mp.sign(u) * mp.quad(bump, [0, 1, 4, min(abs(u), 80)])
            j = mp.nint(u / (2 * kk))
            v = u - 2 * j * kk
            sn_v, cn_v, _ = jacobi(v)
            phi = mp.atan2(sn_v, cn_v)
            return 2 * j * pi_c + mp.ellippi(n, phi, m)

        def frame(wa_, wb_, wc_):
            lv = [i_a * wa_, i_b * wb_, i_c * wc_]
            nl = mp.sqrt(sum(x * x for x in lv))
            la, lb, lc = (x / nl for x in lv)
            rho = mp.sqrt(lb * lb + lc * lc)
            return mp.matrix([[0, rho, la], [-lc / rho, -la * lb / rho, lb], [lb / rho, -la * lc / rho, lc]])

        q = mp.zeros(3, 3)
        for row, (s, k) in enumerate(zip(signs, axes)):
            q[row, k] = s
        r0 = mp.eye(3) if attitude0 is None else mp.matrix([[mp.mpf(float(x)) for x in r] for r in attitude0])
        m0 = r0 * q.T * frame(wa, wb, wc)
        pi0 = big_pi(u0)
        out_w, out_r = [], []
        for t in times:
            t = mp.mpf(float(t))
            u = lam * t + u0
            sn, cn, dn = jacobi(u)
            wcan = [pa * amp_a * dn, amp_b * sn, pc * amp_c * cn]
            wbody = q.T * mp.matrix(wcan)
            dpsi = big_l * t / i_a + big_l * (i_a - i_c) / (i_a * i_c * lam) * (big_pi(u) - pi0)
            rz = mp.matrix([[mp.cos(dpsi), -mp.sin(dpsi), 0], [mp.sin(dpsi), mp.cos(dpsi), 0], [0, 0, 1]])
            r = m0 * rz * frame(*wcan).T * q
            out_w.append([float(wbody[k]) for k in range(3)])
            out_r.append([[float(r[i, k]) for k in range(3)] for i in range(3)])
        return np.array(out_w), np.array(out_r), float(1 - m)


def one_minus_m(moments, omega0):
    """1 − m of a triaxial body for these float inputs taken as exact, as an mpf:
    ``(I_a − I_c)(L² − 2E I_b) / ((I_a − I_b)(L² − 2E I_c))`` (b the middle axis, a the one
    reference_motion takes), at 800 digits, where every sum of the inputs' products is exact (an ω component
    even of 1e-320 squared is within 2,300 bits of the others). The digits reference_motion needs are ~30 more
    than this has zeros; m itself needs none extra (it is formed without cancellation)."""
    with mp.workdps(800):
        inertia = [mp.mpf(float(x)) for x in moments]
        w = [mp.mpf(float(x)) for x in omega0]

        def excess(i_ref):  # L² − 2 E i_ref, term by term (as in reference_motion)
            return sum(i * x * x * (i - i_ref) for i, x in zip(inertia, w))

        i_max, i_mid, i_min = sorted(inertia, reverse=True)
        i_a, i_c = (i_max, i_min) if excess(i_mid) > 0 else (i_min, i_max)
        return (i_a - i_c) * excess(i_mid) / ((i_a - i_mid) * excess(i_c))


def _symmetric_reference(moments, omega0, times, attitude0):
    """The lecture's symmetric solution at 30 digits: R = exp(t hat(L)/I⊥) R0 exp(Ω t hat e_s)."""
    with mp.workdps(DPS):
        inertia = [mp.mpf(float(x)) for x in moments]
        w = [mp.mpf(float(x)) for x in omega0]
        s = next(k for k in range(3) if inertia[(k + 1) % 3] == inertia[(k + 2) % 3])
        i_perp = inertia[(s + 1) % 3]
        big_omega = w[s] * (i_perp - inertia[s]) / i_perp
        r0 = mp.matrix([[mp.mpf(float(x)) for x in r] for r in attitude0])
        l_sp = r0 * mp.matrix([i * x for i, x in zip(inertia, w)])

        def hat_(v):
            return mp.matrix([[0, -v[2], v[1]], [v[2], 0, -v[0]], [-v[1], v[0], 0]])

        e_s = [mp.mpf(1) if k == s else mp.mpf(0) for k in range(3)]
        out_w, out_r = [], []
        for t in times:
            t = mp.mpf(float(t))
            rot_b = mp.expm(hat_([big_omega * t * x for x in e_s]))
            wt = rot_b.T * mp.matrix(w)
            r = mp.expm(hat_([t * x / i_perp for x in l_sp])) * r0 * rot_b
            out_w.append([float(wt[k]) for k in range(3)])
            out_r.append([[float(r[i, k]) for k in range(3)] for i in range(3)])
        return np.array(out_w), np.array(out_r)


def accuracy_table() -> str:
    """Measured accuracy per regime over ±1,000 rotation periods (2π/|ω0|), 25 times against mpmath,
    and invariants / orthonormality at 2,001 times; printed by ``python -m tests.physics.test_free_body_reference``."""
    from physics.free_body import FreeBody
    from physics.rotations import expm_so3, orthonormality_error, rotation_angle

    sep = [1.40625, 1.15625, 1.0]
    regimes = [
        ("generic, L² > 2EI2", [2.0, 1.5, 1.2], [1.0, 0.2, 0.3]),
        ("generic, L² < 2EI2", [2.0, 1.5, 1.2], [0.1, 0.2, 1.0]),
        ("flat lamina I1 = I2 + I3", [3.0, 2.0, 1.0], [0.4, -0.9, 0.6]),
        ("near separatrix above, 1-m≈2e-6", sep, [-1.0, 0.3, 1.5 * (1 - 1e-6)]),
        ("near separatrix below, 1-m≈2e-6", sep, [-1.0, 0.3, 1.5 * (1 + 1e-6)]),
        ("near separatrix, 1-m≈1e-10", sep, [1.0, -0.3, 1.5 * (1 + 5e-11)]),
        ("near separatrix, 1-m≈2e-14", sep, [1.0, -0.3, 1.5 * (1 + 1e-14)]),
        ("on the separatrix, m = 1", sep, [1.0, -0.3, -1.5]),
        ("push 6e-21 off the intermediate axis, 1-m≈1e-40", [2.0, 1.5, 1.0], [6.1e-21, 1.0, 0.0]),
        ("push 6e-71 off the intermediate axis, 1-m≈1e-140", [2.0, 1.5, 1.0], [6.1e-71, 1.0, 0.0]),
        ("push 6e-151 off the intermediate axis, 1-m≈1e-300", [2.0, 1.5, 1.0], [6.1e-151, 1.0, 0.0]),
        ("push 1e-160 (two components), 1-m≈3e-320", [2.0, 1.5, 1.0], [1e-160, -1.0, 3e-161]),
        ("push 1e-300, 1-m≈3e-600", [2.0, 1.5, 1.0], [1e-300, 1.0, 0.0]),
        ("near-symmetric, ΔI/I = 1e-12", [2.0, 2.0 * (1 - 1e-12), 1.0], [0.3, -1.0, -0.2]),
        ("near intermediate-axis spin", [2.0, 1.5, 1.2], [1e-4, 1.0, -2e-4]),
        ("near rod I3/I1 = 1e-3, tumbling", [1.0, 0.999, 0.001], [0.3, -1.0, 0.2]),
        ("near rod, spinning about its axis", [1.0, 0.999, 0.001], [0.3, -1.0, 20.0]),
        ("symmetric (trig)", [2.0, 1.0, 2.0], [0.3, -1.0, 0.7]),
        ("rod, spin about own axis", [0.0, 1.0, 1.0], [2.5, 0.3, -1.0]),
        ("sphere", [1.0, 1.0, 1.0], [0.3, -1.0, 2.5]),
    ]
    r0 = expm_so3(np.array([0.3, -0.7, 0.5]))
    lines = [
        "| regime | 1 - m | ω rel. err | R err (rad) | |L| rel. drift | E rel. drift | |RᵀR − I| |",
        "| --- | --- | --- | --- | --- | --- | --- |",
    ]
    for name, moments, w0 in regimes:
        fb = FreeBody(moments)
        w0 = np.asarray(w0, float)
        big_t = 1000 * 2 * np.pi / np.linalg.norm(w0)
        ts = np.concatenate([np.linspace(-big_t, big_t, 21), [0.37, -1.1, 0.999 * big_t, 0.5]])
        if len(set(moments)) == 3:
            # Digits enough for 1 − m: 30 more than the push's square has zeros.
            push = np.min(np.abs(w0[w0 != 0.0])) / np.max(np.abs(w0))
            ref_w, ref_r, _ = reference_motion(moments, w0, ts, r0, dps=DPS + max(0, int(-2 * np.log10(push))))
        else:
            ref_w, ref_r = _symmetric_reference(moments, w0, ts, r0)
        om, rr = fb.motion(w0, ts, r0)
        err_w = np.max(np.linalg.norm(om - ref_w, axis=1) / np.linalg.norm(ref_w, axis=1))
        err_r = np.max(rotation_angle(rr, ref_r))
        dense = np.linspace(-big_t, big_t, 2001)
        om, rr = fb.motion(w0, dense, r0)
        l_sp = np.einsum("nij,nj->ni", rr, fb.moments * om)
        dl = np.max(np.abs(np.linalg.norm(l_sp, axis=1) / np.linalg.norm(fb.angular_momentum(w0)) - 1))
        de = np.max(np.abs(0.5 * np.sum(fb.moments * om * om, axis=1) / fb.energy(w0) - 1))
        orth = np.max(orthonormality_error(rr))
        mc = fb.elliptic_parameter(w0)[1]
        shown = f"{mc:.2g}" if mc > 0.0 or "push" not in name else name.split("≈")[-1] + " (below floats)"
        lines.append(f"| {name} | {shown} | {err_w:.1e} | {err_r:.1e} | {dl:.1e} | {de:.1e} | {orth:.1e} |")
    return "\n".join(lines)


if __name__ == "__main__":
    print(accuracy_table())
