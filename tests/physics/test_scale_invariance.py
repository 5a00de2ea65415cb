"""Huge and tiny magnitudes where the physics is scale-invariant: the motion depends
on the moments' ratios only, and on rates and times only through their product. Moments from 1e-300
to 1e300 kg m², and rates scaled against times by 1e±90, give the same motion to a few roundings; the
conserved quantities scale as they should."""

from __future__ import annotations

import warnings

import numpy as np
import pytest

from physics.free_body import FreeBody
from physics.heavy_top import HeavyTop

TIMES = np.array([0.0, 1.3, 7.0])
SCALES = [1e-300, 1e-150, 1e150, 1e300]
EPS = np.finfo(float).eps
# Scaled data round differently (a product k x rounds, x/k rounds): the attitude agrees to a few roundings
# of the largest phase turned, here ψ ≈ 140 rad, i.e. 4 eps × 140 ≈ 1.2e-13.
PHASE_ROUNDING = 4 * EPS * 20.0 * TIMES[-1]


@pytest.mark.parametrize("scale", SCALES)
def test_heavy_top_moments_at_any_scale(scale):
    reference = HeavyTop(1.0, 0.5, 2.0).solve(0.5, 0.1, 0.3, 20.0, TIMES)
    with warnings.catch_warnings():
        warnings.simplefilter("error")
        scaled = HeavyTop(scale, 0.5 * scale, 2.0 * scale).solve(0.5, 0.1, 0.3, 20.0, TIMES)
    np.testing.assert_allclose(scaled.attitude, reference.attitude, rtol=0, atol=PHASE_ROUNDING)
    np.testing.assert_allclose(scaled.psi, reference.psi, rtol=4 * EPS, atol=0)
    for name in ("L3", "Lz", "energy"):
        assert getattr(scaled, name) == pytest.approx(scale * getattr(reference, name), rel=4e-16)


@pytest.mark.parametrize("factor", [1e-90, 1e-30, 1e30, 1e90])
def test_heavy_top_rates_against_times(factor):
    # ω → k ω, t → t / k, M g ℓ → k² M g ℓ: the same path, traversed k times faster.
    reference = HeavyTop(1.0, 0.5, 2.0).solve(0.5, 0.1, 0.3, 20.0, TIMES)
    s = HeavyTop(1.0, 0.5, 2.0 * factor**2).solve(0.5, 0.1 * factor, 0.3 * factor, 20.0 * factor, TIMES / factor)
    np.testing.assert_allclose(s.attitude, reference.attitude, rtol=0, atol=PHASE_ROUNDING)


@pytest.mark.parametrize("scale", SCALES)
def test_free_body_moments_at_any_scale(scale):
    moments = np.array([1.0, 2.0, 3.0])
    reference = FreeBody(moments).motion([0.1, 1.0, 0.2], TIMES)[1]
    with warnings.catch_warnings():
        warnings.simplefilter("error")
        scaled = FreeBody(moments * scale).motion([0.1, 1.0, 0.2], TIMES)[1]
    np.testing.assert_allclose(scaled, reference, rtol=0, atol=4e-15)


@pytest.mark.parametrize("factor", [1e-100, 1e100])
def test_free_body_rates_against_times(factor):
    reference = FreeBody([1.0, 2.0, 3.0]).motion([0.1, 1.0, 0.2], TIMES)[1]
    scaled = FreeBody([1.0, 2.0, 3.0]).motion(np.array([0.1, 1.0, 0.2]) * factor, TIMES / factor)[1]
    np.testing.assert_allclose(scaled, reference, rtol=0, atol=4e-15)
