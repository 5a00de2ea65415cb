"""physics.rotations: the hat map and the SO(3) exponential against exact identities."""

from __future__ import annotations

import numpy as np
import pytest
from scipy.linalg import expm
from scipy.spatial.transform import Rotation

from physics.rotations import (
    as_quaternion,
    expm_so3,
    frame_from_axis,
    from_quaternion,
    hat,
    orthonormality_error,
    rotation_about,
    rotation_angle,
    vee,
)


def test_hat_is_the_cross_product_and_vee_inverts_it():
    rng = np.random.default_rng(0)
    v, x = rng.normal(size=(2, 5, 3))
    np.testing.assert_allclose(np.einsum("nij,nj->ni", hat(v), x), np.cross(v, x), atol=1e-15)
    np.testing.assert_array_equal(vee(hat(v)), v)


@pytest.mark.parametrize("angle", [0.0, 1e-12, 1e-6, 9.9e-5, 1.01e-4, 0.3, 2.0, np.pi - 1e-9])
def test_exponential_matches_scipy_expm_across_the_taylor_switch(angle):
    axis = np.array([0.48, -0.6, 0.64])
    r = expm_so3(angle * axis)
    # Both sides are correctly rounded up to a few ulps of entries of size 1.
    np.testing.assert_allclose(r, expm(hat(angle * axis)), atol=4e-16)
    assert orthonormality_error(r) < 5e-16


def test_small_rotation_keeps_relative_precision():
    # The skew part of exp(hat(v)) is v to first order: its relative error must stay at round-off.
    v = np.array([1e-10, -2e-10, 3e-10])
    np.testing.assert_allclose(vee(expm_so3(v)), v, rtol=1e-15)


def test_rotation_angle_is_accurate_for_tiny_angles():
    r = rotation_about([0, 0, 1], [0.0, 1e-12, 0.5, 3.0])
    np.testing.assert_allclose(rotation_angle(np.eye(3), r), [0.0, 1e-12, 0.5, 3.0], rtol=1e-14, atol=0)


def test_quaternions_follow_scipy_scalar_last():
    r = rotation_about([1, 2, 3], 0.7)
    np.testing.assert_allclose(as_quaternion(r), Rotation.from_matrix(r).as_quat(), atol=1e-16)
    np.testing.assert_allclose(from_quaternion(as_quaternion(r)), r, atol=1e-15)


def test_frame_from_axis_is_right_handed_with_the_axis_third():
    for axis in ([0, 0, 1], [1, 1, 1], [0.0, -1.0, 1e-9]):
        f = frame_from_axis(axis)
        assert orthonormality_error(f) < 1e-15
        assert np.linalg.det(f) == pytest.approx(1.0, abs=1e-15)
        np.testing.assert_allclose(f[:, 2], np.asarray(axis) / np.linalg.norm(axis), atol=1e-16)
