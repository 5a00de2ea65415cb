"""30-digit mpmath reference for the torque-free body (helper of tests/test_free_body.py; no tests here).

An independent evaluation of Landau's closed form in mpmath (its own Jacobi functions, K and Π), with
the floating-point inputs taken as exact. It was itself checked against DOP853 integrations over short
spans (tests/test_free_body.py::test_matches_high_precision_integration_short_span).
"""

from __future__ import annotations

import mpmath as mp
import numpy as np

DPS = 30


def _cyc(i):
    return i, (i + 1) % 3, (i + 2) % 3


def reference_motion(moments, omega0, times, attitude0=None):
    """ω(t) (n, 3) and R(t) (n, 3, 3) at 30 digits for a triaxial body off uniform rotation."""
    with mp.workdps(DPS):
        moments = [mp.mpf(float(x)) for x in moments]
        w = [mp.mpf(float(x)) for x in omega0]
        two_e = sum(i * x * x for i, x in zip(moments, w))
        l2 = sum((i * x) ** 2 for i, x in zip(moments, w))
        order = sorted(range(3), key=lambda k: -moments[k])
        mid = order[1]
        a = order[0] if l2 > two_e * moments[mid] else order[2]
        # Canonical cyclic frame starting at a (a, a+1, a+2); the middle axis may be a+1 or a+2.
        ia = moments[a]
        b, c = (a + 1) % 3, (a + 2) % 3
        # If the middle axis is c, reverse orientation: use axes (a, c, b) with ω_b -> -ω_b... instead
        # pick the proper frame (a, mid, other) with a sign flip on a.
        if mid == b:
            axes, signs = (a, b, c), (1, 1, 1)
        else:
            axes, signs = (a, c, b), (-1, 1, 1)  # (−e_a, e_c, e_b) is right-handed
        i_a, i_b, i_c = (moments[k] for k in axes)
        wa, wb, wc = (s * w[k] for s, k in zip(signs, axes))
        ga = abs(two_e * i_a - l2)
        gb = abs(l2 - two_e * i_b)
        gc = abs(l2 - two_e * i_c)
        m = (i_b - i_c) * (two_e * i_a - l2) / ((i_a - i_b) * (l2 - two_e * i_c))
        amp_a = mp.sqrt(gc / abs(i_a * (i_a - i_c)))
        amp_b = mp.sqrt(ga / abs(i_b * (i_a - i_b)))
        amp_c = mp.sqrt(ga / abs(i_c * (i_a - i_c)))
        pa = 1 if wa >= 0 else -1
        lam = -pa * mp.sign(i_a - i_b) * mp.sqrt((i_a - i_b) * (l2 - two_e * i_c) / (i_a * i_b * i_c))
        s0, c0 = wb / amp_b, wc / amp_c
        phi0 = mp.atan2(s0, c0)
        u0 = mp.ellipf(phi0, m)
        n = -i_a * (i_b - i_c) / (i_c * (i_a - i_b))
        big_l = mp.sqrt(l2)
        kk = mp.ellipk(m)
        pi_c = mp.ellippi(n, m)

        def big_pi(u):
            # Π(n; am u | m), continued past |u| ≤ K by quasi-periodicity.
            j = mp.nint(u / (2 * kk))
            v = u - 2 * j * kk
            phi = mp.atan2(mp.ellipfun("sn", v, m=m), mp.ellipfun("cn", v, m=m))
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
            sn, cn, dn = (mp.ellipfun(k, u, m=m) for k in ("sn", "cn", "dn"))
            wcan = [pa * amp_a * dn, amp_b * sn, amp_c * cn]
            wbody = q.T * mp.matrix(wcan)
            dpsi = big_l * t / i_a + big_l * (i_a - i_c) / (i_a * i_c * lam) * (big_pi(u) - pi0)
            rz = mp.matrix([[mp.cos(dpsi), -mp.sin(dpsi), 0], [mp.sin(dpsi), mp.cos(dpsi), 0], [0, 0, 1]])
            r = m0 * rz * frame(*wcan).T * q
            out_w.append([float(wbody[k]) for k in range(3)])
            out_r.append([[float(r[i, k]) for k in range(3)] for i in range(3)])
        return np.array(out_w), np.array(out_r), float(1 - m)
