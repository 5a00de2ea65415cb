"""physics.elliptic against mpmath at 40 digits: the Jacobi functions (both forms, down to the separatrix),
Carlson's R_J down to the smallest normal arguments, the integrals of the first and third kinds and the
Jacobi amplitude. The float forms (``*_one``) give the same numbers as the array forms."""

from __future__ import annotations

import math

import mpmath
import numpy as np
import pytest
from scipy.special import ellipkm1

from physics.elliptic import (
    carlson_rj,
    carlson_rj_one,
    complete_q,
    complete_third_kind,
    incomplete_first_kind,
    incomplete_first_kind_one,
    incomplete_third_kind,
    incomplete_third_kind_one,
    jacobi_amplitude,
    jacobi_amplitude_one,
    jacobi_half_period,
    jacobi_half_period_one,
    jacobi_sn_cn_dn,
    ladder_of,
    landen_ladder,
    q_integral,
    q_integral_one,
    reduce_half_period,
    reduced_jacobi,
    reduced_jacobi_one,
)
from tests.physics.mp_jacobi import mp_sn, mp_sn_cn_dn

mpmath.mp.dps = 40

# Complements 1 − m from the middle of the range to below the float range of m itself.
COMPLEMENTS = [0.9, 0.5, 0.1, 1e-3, 1e-6, 1e-12, 1e-16, 1e-40, 1e-200]


def mp_jacobi(u: float, mc: float) -> tuple[float, float, float]:
    """sn, cn, dn (u | 1 − mc) with 40 digits beyond those 1 − mc has zeros."""
    with mpmath.workdps(40 + max(0, -math.floor(math.log10(mc)))):
        m = 1 - mpmath.mpf(mc)
        sn, cn, dn = (float(mpmath.ellipfun(kind, mpmath.mpf(u), m=m)) for kind in ("sn", "cn", "dn"))
    return sn, cn, dn


def relative(a: float, b: float) -> float:
    return abs(a - b) / abs(b) if b != 0.0 else abs(a)


@pytest.mark.parametrize("mc", COMPLEMENTS)
def test_jacobi_sn_cn_dn_match_mpmath_over_a_period(mc):
    m = 1.0 - mc
    K = float(ellipkm1(mc))
    u = np.linspace(-4.0 * K, 4.0 * K, 41)[1:-1] + 0.1234
    sn, cn, dn = jacobi_sn_cn_dn(u, m, mc)
    for k, x in enumerate(u):
        ref = mp_jacobi(float(x), mc)
        # To 2e-15, plus the reduction by the float period: u − 2Kj is off by j ulp(2K) ~ 4.4e-16 |u|, and
        # the derivatives of sn, cn, dn are at most 1 in size.
        for got, want in zip((sn[k], cn[k], dn[k]), ref):
            assert abs(got - want) <= 2e-15 + 4.4e-16 * abs(x), (x, mc, got, want)


@pytest.mark.parametrize("mc", COMPLEMENTS)
def test_cn_and_dn_keep_their_relative_digits_at_the_quarter_period(mc):
    """Near u = K, cn(K − x) = √mc sd x is small and keeps its relative digits: up to the float K's own
    rounding, ulp(K) / x, relative (the distance K − u is all cn knows)."""
    m = 1.0 - mc
    K = float(ellipkm1(mc))
    for x in (1e-3, 0.1, 0.5):
        u = np.array([K - x])
        _, cn, dn = jacobi_sn_cn_dn(u, m, mc)
        _, cn_ref, dn_ref = mp_jacobi(K - x, mc)
        bound = 1e-14 + 2.0 * math.ulp(K) / x
        assert relative(cn[0], cn_ref) < bound and relative(dn[0], dn_ref) < bound, (x, cn[0], cn_ref)


@pytest.mark.parametrize("mc", COMPLEMENTS)
def test_the_float_form_of_the_reduced_jacobi_functions_is_the_array_form(mc):
    m = 1.0 - mc
    K = float(ellipkm1(mc))
    u = np.linspace(-3.0 * K, 3.0 * K, 25) + 0.01
    roots, scale = landen_ladder(np.array(m), np.array(mc))
    kp = math.sqrt(mc)
    arrays = reduced_jacobi(u, np.array(m), np.array(mc), K, (roots, scale), kp)
    float_roots = [float(q) for q in roots]
    for k, x in enumerate(u.tolist()):
        one = reduced_jacobi_one(x, m, mc, K, float_roots, float(scale), kp)
        for a, b in zip(one, arrays):
            assert a == pytest.approx(float(b[k]), rel=1e-15, abs=1e-300)


def test_the_separatrix_is_tanh_and_sech():
    u = np.array([-30.0, -1.0, 0.0, 0.5, 2.0, 700.0])
    sn, cn, dn = jacobi_sn_cn_dn(u, 1.0, 0.0)
    np.testing.assert_allclose(sn, np.tanh(u), rtol=1e-15)
    np.testing.assert_allclose(cn, 1.0 / np.cosh(u), rtol=1e-15)
    np.testing.assert_allclose(dn, 1.0 / np.cosh(u), rtol=1e-15)


@pytest.mark.parametrize("one_m", [0.5, 1e-3, 1e-4 * 1.01, 1e-4 * 0.99, 1e-8, 7e-16])
def test_the_half_period_form_matches_mpmath_on_both_sides_of_the_switch(one_m):
    """jacobi_half_period (the heavy top's) uses scipy above 1 − m = 1e-4 and the Landen ladder below."""
    m = 1.0 - one_m
    K = float(ellipkm1(one_m))
    r = np.linspace(-K, K, 33)[:-1]
    sn, cn, dn = jacobi_half_period(r, m, one_m, K)
    for k, x in enumerate(r.tolist()):
        ref = mp_jacobi(x, one_m)
        assert abs(sn[k] - ref[0]) <= 2e-15 * max(abs(ref[0]), 1.0) + 4e-16 * abs(x)
        assert relative(cn[k], ref[1]) <= 1e-13 or abs(cn[k] - ref[1]) <= 4e-16 * abs(x)
        assert relative(dn[k], ref[2]) <= 1e-13
        assert jacobi_half_period_one(x, m, one_m, K) == (sn[k], cn[k], dn[k])


def test_reduce_half_period_puts_tau_in_minus_k_to_k():
    K = 1.75
    tau = np.array([-5.0 * K, -K, 0.0, K, 3.2 * K])
    k, r = reduce_half_period(tau, K)
    assert np.all((r >= -K) & (r < K))
    np.testing.assert_allclose(2.0 * K * k + r, tau, rtol=0, atol=1e-15)
    assert r[3] == -K  # the top turning point is counted as passed


def test_the_cached_ladder_is_the_landen_ladder_on_floats():
    roots, scale = ladder_of(1.0 - 1e-9, 1e-9)
    arr_roots, arr_scale = landen_ladder(np.array(1.0 - 1e-9), np.array(1e-9))
    assert roots == [float(q) for q in arr_roots] and scale == float(arr_scale)


@pytest.mark.parametrize(
    "x, y, p",
    [
        (0.3, 0.7, 0.9),
        (0.0, 0.5, 0.25),
        (1e-20, 1e-30, 0.5),
        (1e-120, 1e-130, 1.0),
        (0.0, 1e-200, 1e-190),
        (1e-300, 1e-301, 1e-250),
        (0.0, 2.2e-308, 0.5),
    ],
)
def test_carlson_rj_matches_mpmath_down_to_the_smallest_normal_arguments(x, y, p):
    want = float(mpmath.elliprj(mpmath.mpf(x), mpmath.mpf(y), 1, mpmath.mpf(p)))
    got = float(carlson_rj(x, y, p))
    assert relative(got, want) < 1e-14
    assert relative(carlson_rj_one(x, y, p), want) < 1e-14


@pytest.mark.parametrize("n, one_m", [(-0.5, 0.3), (0.3, 0.5), (-3.0, 1e-3), (0.9, 0.2), (-1e-8, 0.7)])
def test_third_kind_integrals_match_mpmath(n, one_m):
    m = 1.0 - one_m
    K = float(ellipkm1(one_m))
    one_n = 1.0 - n
    pi_ref = mpmath.ellippi(n, 1 - mpmath.mpf(one_m))
    assert relative(complete_third_kind(n, one_n, m, one_m, K), float(pi_ref)) < 1e-14
    k_ref = mpmath.ellipk(1 - mpmath.mpf(one_m))
    assert relative(complete_q(one_n, one_m), float((pi_ref - k_ref) / n)) < 1e-12 * max(1.0, 1e-8 / abs(n))
    r = np.linspace(-K, K, 9)[1:-1]
    sn, cn, dn = jacobi_half_period(r, m, one_m, K)
    third = incomplete_third_kind(r, sn, cn * cn, dn * dn, n, one_n)
    qc = complete_q(one_n, one_m)
    k = np.array([0.0] * r.size)
    q = q_integral(k, sn, cn * cn, dn * dn, n, one_n, qc)
    for i, x in enumerate(r.tolist()):
        phi = mpmath.asin(mpmath.ellipfun("sn", mpmath.mpf(x), m=1 - mpmath.mpf(one_m)))
        want = float(mpmath.ellippi(n, phi, 1 - mpmath.mpf(one_m)))
        assert abs(third[i] - want) <= 1e-14 * abs(want) + 1e-40  # mpmath's own 0 is ~1e-47
        assert third[i] == incomplete_third_kind_one(x, sn[i], cn[i] ** 2, dn[i] ** 2, n, one_n)
        q_want = float((mpmath.ellippi(n, phi, 1 - mpmath.mpf(one_m)) - mpmath.ellipf(phi, 1 - mpmath.mpf(one_m))) / n)
        assert abs(q[i] - q_want) <= 1e-13 * max(abs(q_want), 1e-3)
        assert q[i] == q_integral_one(0.0, sn[i], cn[i] ** 2, dn[i] ** 2, n, one_n, qc)


@pytest.mark.parametrize("one_m", [0.5, 1e-6, 1e-14])
def test_first_kind_and_the_amplitude_invert_each_other_and_match_mpmath(one_m):
    m = 1.0 - one_m
    K = float(ellipkm1(one_m))
    phis = np.array([-1.5, -0.4, 0.0, 0.2, 1.0, 1.5707])
    f = incomplete_first_kind(np.sin(phis), np.cos(phis), np.full(phis.shape, one_m))
    for i, phi in enumerate(phis.tolist()):
        want = float(mpmath.ellipf(mpmath.mpf(phi), 1 - mpmath.mpf(one_m)))
        assert abs(f[i] - want) <= 1e-14 * max(abs(want), 1e-300)
        one = incomplete_first_kind_one(math.sin(phi) ** 2, math.cos(phi) ** 2, m, one_m)
        assert abs(math.copysign(one, phi) - want) <= 1e-14 * max(abs(want), 1e-300)
    u = np.linspace(-1.9 * K, 1.9 * K, 15)
    am = jacobi_amplitude(u, np.full(u.shape, m), np.full(u.shape, one_m))
    for i, x in enumerate(u.tolist()):
        # am = atan2(sn, cn) for |u| < 2K, continuous there; sn and cn from mpmath.
        sn, cn, _ = mp_jacobi(x, one_m)
        assert abs(am[i] - math.atan2(sn, cn)) <= 1e-14 * max(abs(am[i]), 1.0)
        assert jacobi_amplitude_one(x, m, one_m) == pytest.approx(float(am[i]), rel=1e-15, abs=1e-300)


def test_mp_sn_cn_dn_is_mp_ellipfun():
    """The references' Jacobi functions (tests/physics/mp_jacobi.py: mp.ellipfun's formula with its constants
    computed once per m) give mp.ellipfun's digits, bit for bit, from m = 0 to 1 and 30 to 360 digits."""
    for dps in (30, 60, 360):
        with mpmath.workdps(dps):
            for m in (
                mpmath.mpf(0),
                mpmath.mpf("0.3"),
                1 - mpmath.mpf(10) ** -15,
                1 - mpmath.mpf(10) ** (40 - dps),
                mpmath.mpf(1),
            ):
                jacobi, sn = mp_sn_cn_dn(m), mp_sn(m)
                for u in (mpmath.mpf("1e-30"), mpmath.mpf("0.1"), mpmath.mpf("-3.7"), mpmath.mpf(41) / 7):
                    exact = tuple(mpmath.ellipfun(kind, u, m) for kind in ("sn", "cn", "dn"))
                    assert jacobi(u) == exact and sn(u) == exact[0], (dps, m, u)
