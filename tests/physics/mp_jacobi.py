"""mpmath's Jacobi functions with the parts that depend on m alone computed once (a helper of the tests'
references; no tests here).

``mp.ellipfun(kind, u, m)`` recomputes the nome q and the theta constants θ2(0), θ3(0), θ4(0) at every call,
and computes θ4(z) again for each of sn, cn and dn; a reference evaluating the three at many u with one m
repeats all of that. These closures do the same operations at the same precision (mp.ellipfun's: 10 extra
bits, the same order of products and quotients), so they give the same digits (tests/physics/test_elliptic.py::
test_mp_sn_cn_dn_is_mp_ellipfun checks this bit for bit).
"""

from __future__ import annotations

from collections.abc import Callable

import mpmath as mp


def mp_sn_cn_dn(m) -> Callable:
    """``u ↦ (sn, cn, dn)(u | m)``, as ``mp.ellipfun`` gives them, at the working precision."""
    with mp.extraprec(10):
        q = mp.qfrom(m=m)
    if q == 0 or q == 1:  # mp's own limits (sin, cos, 1; tanh, sech, sech), also where q rounds to them
        return lambda u: tuple(mp.ellipfun(kind, u, m) for kind in ("sn", "cn", "dn"))
    with mp.extraprec(10):
        theta2, theta3, theta4 = (mp.jtheta(k, 0, q) for k in (2, 3, 4))
        one = mp.mpf(1)
        sn_c, cn_c, dn_c = one * theta3 / theta2, one * theta4 / theta2, one * theta4 / theta3
        theta3_squared = theta3**2

    def jacobi(u):
        with mp.extraprec(10):
            t = mp.convert(u) / theta3_squared
            t1, t2, t3, t4 = (mp.jtheta(k, t, q) for k in (1, 2, 3, 4))
            values = (sn_c * t1 / t4, cn_c * t2 / t4, dn_c * t3 / t4)
        return tuple(+v for v in values)

    return jacobi


def mp_sn(m) -> Callable:
    """``u ↦ sn(u | m)`` as ``mp.ellipfun("sn", u, m)`` gives it (two theta functions a call)."""
    with mp.extraprec(10):
        q = mp.qfrom(m=m)
    if q == 0 or q == 1:  # mp's own limits (sin, tanh), also where q rounds to them
        return lambda u: mp.ellipfun("sn", u, m)
    with mp.extraprec(10):
        theta3 = mp.jtheta(3, 0, q)
        ratio = mp.mpf(1) * theta3 / mp.jtheta(2, 0, q)
        theta3_squared = theta3**2

    def sn(u):
        with mp.extraprec(10):
            t = mp.convert(u) / theta3_squared
            v = ratio * mp.jtheta(1, t, q) / mp.jtheta(4, t, q)
        return +v

    return sn
