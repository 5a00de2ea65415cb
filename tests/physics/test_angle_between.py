"""physics.rotations.angle_between: atan2(|a × b|, a · b), right at 0, π and 1e-12 rad, at any scale,
against the exact angle between the float vectors (mpmath, 50 digits)."""

from __future__ import annotations

import math

import mpmath
import numpy as np
import pytest

from physics.rotations import angle_between


def exact_angle(a, b) -> float:
    """The angle between the float vectors as given, in 50-digit arithmetic."""
    with mpmath.workdps(50):
        va, vb = [mpmath.mpf(float(x)) for x in a], [mpmath.mpf(float(x)) for x in b]
        cross = [va[1] * vb[2] - va[2] * vb[1], va[2] * vb[0] - va[0] * vb[2], va[0] * vb[1] - va[1] * vb[0]]
        return float(mpmath.atan2(mpmath.sqrt(sum(c * c for c in cross)), sum(x * y for x, y in zip(va, vb))))


def test_parallel_antiparallel_and_perpendicular_exactly():
    assert angle_between([1.0, 2.0, 3.0], [2.0, 4.0, 6.0]) == 0.0
    assert angle_between([1.0, 2.0, 3.0], [-2.0, -4.0, -6.0]) == math.pi
    assert angle_between([0.0, 0.0, 1.0], [0.3, -0.4, 0.0]) == math.pi / 2


def test_a_tiny_angle_keeps_its_digits_where_arccos_loses_them():
    a, b = [1.0, 0.0, 0.0], [1.0, 1e-12, 0.0]
    assert angle_between(a, b) == pytest.approx(1e-12, rel=1e-15)
    assert np.arccos(np.dot(a, b) / np.linalg.norm(b)) == 0.0  # why not arccos
    # Near π the angle is π − 1e-12 to one ulp of π.
    assert angle_between(a, [-1.0, 1e-12, 0.0]) == pytest.approx(math.pi - 1e-12, abs=4.5e-16)


@pytest.mark.parametrize("seed", range(5))
def test_generic_and_tiny_angles_against_fifty_digits(seed):
    """Absolute error a few 1e-16 rad at any angle (the cross product of two nearly parallel vectors carries
    rounding of order eps |a||b|), so relative 1e-3 at 1e-12 rad, where arccos gives 0 or 1.5e-8."""
    rng = np.random.default_rng(seed)
    a = rng.normal(size=3)
    for size in (1.0, 1e-3, 1e-8, 1e-12, 1e-15):
        b = a + size * np.cross(a, rng.normal(size=3))
        expected = exact_angle(a, b)
        assert angle_between(a, b) == pytest.approx(expected, abs=1e-15)
        assert angle_between(a, -b) == pytest.approx(math.pi - expected, abs=1e-15)


def test_any_scale_without_overflow_or_underflow():
    assert angle_between([1e300, 1e300, 0.0], [1e300, 0.0, 0.0]) == pytest.approx(math.pi / 4, abs=1e-16)
    assert angle_between([1e-320, 0.0, 0.0], [0.0, 5e-324, 0.0]) == math.pi / 2
    assert angle_between([1e200, 0.0, 0.0], [1e-200, 1e-212, 0.0]) == pytest.approx(1e-12, rel=1e-15)


def test_batched_and_broadcast():
    out = angle_between([[1.0, 0.0, 0.0], [0.0, 1.0, 0.0], [0.0, 0.0, 2.0]], [1.0, 1.0, 0.0])
    np.testing.assert_allclose(out, [math.pi / 4, math.pi / 4, math.pi / 2], rtol=0, atol=1e-16)
    assert out.shape == (3,)


def test_a_zero_vector_has_no_direction_nan_not_an_error():
    """ω of a body at rest is a state, not a mistake: the readout shows no angle."""
    assert math.isnan(angle_between([0.0, 0.0, 0.0], [1.0, 0.0, 0.0]))
    assert math.isnan(angle_between([1.0, 0.0, 0.0], [0.0, -0.0, 0.0]))
    out = angle_between([[0.0, 0.0, 0.0], [1.0, 0.0, 0.0]], [0.0, 1.0, 0.0])
    assert math.isnan(out[0]) and out[1] == math.pi / 2


@pytest.mark.parametrize(
    ("a", "b", "message"),
    [
        ([math.nan, 0.0, 1.0], [1.0, 0.0, 0.0], "a must be finite"),
        ([1.0, 0.0, 0.0], [math.inf, 0.0, 0.0], "b must be finite"),
        ([1.0, 0.0], [1.0, 0.0, 0.0], r"a must have shape \(3,\) or \(n, 3\)"),
        ("<script>", [1.0, 0.0, 0.0], "a must be numeric"),
        ([[1.0, 0.0, 0.0]] * 2, [[1.0, 0.0, 0.0]] * 3, "a and b must have shapes that broadcast"),
    ],
)
def test_bad_vectors_are_refused_by_name(a, b, message):
    with pytest.raises(ValueError, match=message):
        angle_between(a, b)
