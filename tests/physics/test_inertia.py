"""physics.inertia against the lecture's exact examples, trimesh primitives and invariants."""

from __future__ import annotations

import warnings

import numpy as np
import pytest
import trimesh
from hypothesis import given, settings
from hypothesis import strategies as st
from hypothesis.extra.numpy import arrays

from physics.inertia import (
    MassProperties,
    box,
    from_mesh,
    parallel_axis,
    point_masses,
    rod,
    solid_cylinder,
    solid_sphere,
    validate_moments,
)
from physics.rotations import expm_so3

# Closed forms evaluate in a handful of flops: agreement to a few ulps is expected.
EXACT = 1e-14


# -- the lecture's three examples ---------------------------------------------------------------


def test_wire_is_ml2_over_12_with_zero_axial_moment():
    body = rod(mass=3.0, length=2.0)
    np.testing.assert_allclose(body.tensor, np.diag([1.0, 1.0, 0.0]), rtol=0, atol=EXACT)
    moments, axes = body.principal()
    np.testing.assert_allclose(moments, [1.0, 1.0, 0.0], atol=EXACT)
    np.testing.assert_allclose(axes[:, 2], [0, 0, 1], atol=EXACT)


def test_sphere_is_two_fifths_ma2():
    body = solid_sphere(mass=5.0, radius=0.3)
    np.testing.assert_allclose(body.moments, [0.4 * 5.0 * 0.09] * 3, rtol=EXACT)
    # All axes equivalent: the canonical choice for a fully degenerate tensor is the identity.
    np.testing.assert_allclose(body.principal_axes, np.eye(3), atol=EXACT)


def test_cylinder_matches_erratum_1():
    m, a, ell = 2.0, 0.1, 0.5
    body = solid_cylinder(m, a, ell)
    side = m * (a**2 / 4 + ell**2 / 12)
    np.testing.assert_allclose(np.diag(body.tensor), [side, side, m * a**2 / 2], rtol=EXACT)


def test_box_closed_form():
    body = box(12.0, (1.0, 2.0, 3.0))
    np.testing.assert_allclose(np.diag(body.tensor), [13.0, 10.0, 5.0], rtol=EXACT)
    moments, axes = body.principal()
    np.testing.assert_allclose(moments, [13.0, 10.0, 5.0], rtol=EXACT)
    np.testing.assert_allclose(np.abs(axes), np.eye(3), atol=EXACT)


# -- parallel-axis theorem -----------------------------------------------------------------------


def test_parallel_axis_rod_about_its_end_is_ml2_over_3():
    body = rod(mass=3.0, length=2.0)
    end = body.tensor_about([0.0, 0.0, 1.0])
    np.testing.assert_allclose(end, np.diag([1.0, 1.0, 0.0]) + 3.0 * np.diag([1.0, 1.0, 0.0]), atol=EXACT)
    assert body.moment_about([1, 0, 0], [0, 0, 1.0]) == pytest.approx(3.0 * 4.0 / 3.0, rel=EXACT)


def test_parallel_axis_equals_direct_sum_for_point_masses():
    rng = np.random.default_rng(1)
    masses = rng.uniform(0.5, 2.0, 7)
    pos = rng.normal(size=(7, 3))
    body = point_masses(masses, pos)
    a = np.array([0.3, -1.2, 2.0])
    d = pos - a
    direct = np.einsum("i,ij,ij->", masses, d, d) * np.eye(3) - np.einsum("i,ij,ik->jk", masses, d, d)
    np.testing.assert_allclose(body.tensor_about(a), direct, rtol=1e-13, atol=1e-13 * np.abs(direct).max())


def test_radius_of_gyration():
    body = solid_sphere(2.0, 1.0)
    assert body.radius_of_gyration([0, 0, 1]) == pytest.approx(np.sqrt(0.4), rel=EXACT)
    # About a tangent line: k² = 2/5 a² + a² (parallel axis).
    assert body.radius_of_gyration([0, 0, 1], [1.0, 0, 0]) == pytest.approx(np.sqrt(1.4), rel=EXACT)


def test_combining_two_spheres_matches_point_mass_limit():
    # Two tiny spheres of mass 1 at ±1 on x: I about the centre is the point-mass dumbbell plus 2·(2/5 m r²).
    r = 1e-3
    left = solid_sphere(1.0, r).transformed(np.eye(3), [-1.0, 0, 0])
    right = solid_sphere(1.0, r).transformed(np.eye(3), [1.0, 0, 0])
    both = left + right
    expected = np.diag([0.0, 2.0, 2.0]) + 2 * 0.4 * r**2 * np.eye(3)
    np.testing.assert_allclose(both.tensor, expected, atol=EXACT)
    np.testing.assert_allclose(both.center_of_mass, 0.0, atol=EXACT)


# -- trimesh primitives against closed forms ------------------------------------------------------


def test_mesh_box_is_exact():
    # A box is exactly representable by triangles: the only error is round-off.
    body = from_mesh(trimesh.creation.box((1.0, 2.0, 3.0)), mass=12.0)
    np.testing.assert_allclose(body.tensor, box(12.0, (1.0, 2.0, 3.0)).tensor, atol=1e-13)
    np.testing.assert_allclose(body.center_of_mass, 0.0, atol=1e-15)


def test_mesh_cylinder_converges_to_closed_form():
    # A prism of n sections inscribed in the circle: area and I_zz err by O((2π/n)²). With n = 512,
    # (2π/512)² ≈ 1.5e-4; mass is prescribed, so the relative error is a fraction of that.
    mesh = trimesh.creation.cylinder(radius=0.1, height=0.5, sections=512)
    body = from_mesh(mesh, mass=2.0)
    exact = solid_cylinder(2.0, 0.1, 0.5)
    np.testing.assert_allclose(np.diag(body.tensor), np.diag(exact.tensor), rtol=5e-5)


def test_mesh_sphere_converges_to_closed_form():
    # An icosphere with 5 subdivisions has edge ≈ a/40; the mass-normalised I has relative error ~1e-3.
    mesh = trimesh.creation.icosphere(subdivisions=5, radius=0.5)
    body = from_mesh(mesh, mass=3.0)
    np.testing.assert_allclose(body.moments, solid_sphere(3.0, 0.5).moments, rtol=1e-3)


def test_mesh_density_sets_the_mass():
    body = from_mesh(trimesh.creation.box((0.1, 0.2, 0.3)), density=1000.0)
    assert body.mass == pytest.approx(6.0, rel=1e-13)


def _box_of_size(size: float) -> trimesh.Trimesh:
    """A 1 × 2 × 3 box scaled to ``size`` m, off the origin by (7, −1, 0.5) sizes (the scaling made here,
    where trimesh's constructor cannot merge or drop anything)."""
    mesh = trimesh.creation.box((1.0, 2.0, 3.0))
    return trimesh.Trimesh(mesh.vertices * size + np.array([7.0, -1.0, 0.5]) * size, mesh.faces, process=False)


@pytest.mark.parametrize(
    "size, kwargs",
    [
        (1e-8, {}),
        (1e-8, {"mass": 2.0}),
        (1e-20, {"density": 1e10}),
        (1e-100, {"mass": 1.0}),  # was mass 1 with an all-zero tensor at the default density
        (1e100, {"mass": 1.0}),  # was "center_of_mass must be finite" after overflow warnings
        (1e-150, {"mass": 1e150}),
        (1e150, {"mass": 1e-150}),
    ],
)
def test_tiny_and_huge_meshes_are_exact_at_every_size(size, kwargs):
    """Audit: from_mesh computes at unit size and scales back (mass ∝ density size³,
    I ∝ mass size²), so a box of any size representable in floats gets the closed form to round-off."""
    with warnings.catch_warnings():
        warnings.simplefilter("error")  # no overflow on the way
        body = from_mesh(_box_of_size(size), **kwargs)
    mass = kwargs["mass"] if "mass" in kwargs else kwargs.get("density", 1000.0) * 6.0 * size**3
    assert body.mass == pytest.approx(mass, rel=1e-14)
    exact = box(mass, (size, 2.0 * size, 3.0 * size)).tensor
    np.testing.assert_allclose(body.tensor, exact, rtol=0, atol=1e-14 * exact.max())
    np.testing.assert_allclose(body.center_of_mass, np.array([7.0, -1.0, 0.5]) * size, rtol=1e-15)


@pytest.mark.parametrize(
    "size, kwargs, message",
    [
        (1e-100, {}, r"too small: its moments of inertia .* about 10\^-496"),
        (1e-160, {}, r"too small: its mass .* about 10\^-476"),
        (1e-300, {"mass": 1.0}, r"too small: its moments of inertia"),
        (1e100, {}, r"too large: its moments of inertia .* about 10\^504"),
        (1e200, {"mass": 1.0}, r"too large: its moments of inertia"),
    ],
)
def test_meshes_whose_mass_properties_leave_the_float_range_are_refused_with_the_range(size, kwargs, message):
    with warnings.catch_warnings():
        warnings.simplefilter("error")
        with pytest.raises(ValueError, match=message + r".*between 1e-308 and 1e308"):
            from_mesh(_box_of_size(size), **kwargs)


def test_inverted_mesh_is_fixed_not_refused():
    mesh = trimesh.creation.box((1.0, 2.0, 3.0))
    mesh.invert()
    body = from_mesh(mesh, mass=12.0)
    np.testing.assert_allclose(body.tensor, box(12.0, (1.0, 2.0, 3.0)).tensor, atol=1e-13)


# -- hypothesis: invariants on random point clouds --------------------------------------------------

clouds = st.integers(min_value=1, max_value=12).flatmap(
    lambda n: st.tuples(
        arrays(np.float64, (n,), elements=st.floats(0.1, 10.0)),
        arrays(np.float64, (n, 3), elements=st.floats(-5.0, 5.0)),
    )
)


@settings(max_examples=60, deadline=None)
@given(clouds, arrays(np.float64, (3,), elements=st.floats(-3, 3)))
def test_random_clouds_obey_the_invariants(cloud, rotvec):
    masses, pos = cloud
    body = point_masses(masses, pos)
    t = body.tensor
    scale = max(np.abs(t).max(), 1.0)
    np.testing.assert_allclose(t, t.T, atol=1e-14 * scale)
    moments, axes = body.principal()
    assert np.all(moments >= 0.0)
    assert moments[0] >= moments[1] >= moments[2]
    # Triangle inequality I1 <= I2 + I3 (equality for a planar cloud), to round-off.
    assert moments[0] <= moments[1] + moments[2] + 1e-12 * scale
    assert np.linalg.det(axes) == pytest.approx(1.0, abs=1e-12)
    np.testing.assert_allclose(axes @ np.diag(moments) @ axes.T, t, atol=1e-12 * scale)
    # Rotating the body rotates the tensor: I' = R I Rᵀ.
    rot = expm_so3(rotvec)
    turned = point_masses(masses, pos @ rot.T)
    np.testing.assert_allclose(turned.tensor, rot @ t @ rot.T, atol=1e-12 * scale)
    # Parallel-axis consistency: going to a point and back is the identity.
    a = np.array([1.0, -2.0, 0.5])
    moved = body.tensor_about(body.center_of_mass + a)
    np.testing.assert_allclose(moved - parallel_axis(body.mass, a), t, atol=1e-12 * scale * (1 + a @ a))


def test_principal_axes_of_a_symmetric_body_are_well_defined():
    # Two equal moments: a cylinder tilted by a rotation keeps its symmetry axis as axis 3 (smallest).
    rot = expm_so3([0.3, -0.2, 0.9])
    body = solid_cylinder(1.0, 0.5, 0.2).transformed(rot)  # oblate: I3 = Ma²/2 is the largest
    moments, axes = body.principal()
    assert moments[1] == moments[2]  # the degenerate pair is reported exactly equal
    np.testing.assert_allclose(np.abs(axes[:, 0] @ rot[:, 2]), 1.0, atol=1e-12)
    # Same input, same axes: deterministic.
    np.testing.assert_array_equal(axes, body.principal()[1])


# -- bad input -----------------------------------------------------------------------------------


@pytest.mark.parametrize(
    "call, message",
    [
        (lambda: rod(float("nan"), 1.0), "mass must be finite"),
        (lambda: rod(-1.0, 1.0), "mass must be positive"),
        (lambda: rod(0.0, 1.0), "mass must be positive"),
        (lambda: solid_sphere(1.0, float("inf")), "radius must be finite"),
        (lambda: solid_cylinder(1.0, -0.1, 1.0), "radius must be positive"),
        (lambda: box(1.0, (1.0, 0.0, 0.0)), "at most one of them zero"),
        (lambda: point_masses([1.0, -1.0], [[0, 0, 0], [1, 0, 0]]), "every point mass must be positive"),
        (lambda: point_masses([1.0], [[0, 0]]), "shape"),
        (lambda: validate_moments([1.0, 1.0, 2.5]), "no rigid body has these moments"),
        (lambda: validate_moments([1.0, -1.0, 1.0]), "must not be negative"),
        (lambda: validate_moments([1.0, float("nan"), 1.0]), "must be finite"),
        (lambda: validate_moments([0.0, 0.0, 0.0]), "all zero"),
        (lambda: MassProperties(1.0, np.zeros(3), np.diag([1.0, 1.0, 3.0])), "no rigid body has these moments"),
        (lambda: MassProperties(1.0, np.zeros(3), [[1, 0.5, 0], [0, 1, 0], [0, 0, 1]]), "symmetric"),
        (lambda: solid_sphere(1.0, 1.0).transformed(np.diag([1.0, 1.0, -1.0])), "proper rotation"),
    ],
)
def test_bad_input_raises_a_clear_message(call, message):
    with pytest.raises(ValueError, match=message):
        call()


def test_triangle_inequality_allows_a_flat_plate_and_round_off():
    validate_moments([2.0, 1.0, 1.0])  # a flat lamina: equality
    validate_moments([2.0 + 1e-13, 1.0, 1.0])  # within the 1e-12 relative slack
    with pytest.raises(ValueError, match="no rigid body"):
        validate_moments([2.0 + 1e-10, 1.0, 1.0])


def test_bad_meshes_are_refused_with_a_reason():
    with pytest.raises(ValueError, match="empty"):
        from_mesh(trimesh.Trimesh(), mass=1.0)
    open_box = trimesh.creation.box((1, 1, 1))
    open_box.update_faces(np.arange(len(open_box.faces) - 2))
    with pytest.raises(ValueError, match="not watertight"):
        from_mesh(open_box, mass=1.0)
    flat = trimesh.Trimesh(
        vertices=[[0, 0, 0], [1, 0, 0], [0, 1, 0], [1, 1, 0]],
        faces=[[0, 1, 2], [2, 1, 3], [2, 1, 0], [3, 1, 2]],
        process=False,
    )
    with pytest.raises(ValueError, match="zero volume|not watertight"):
        from_mesh(flat, mass=1.0)
    with pytest.raises(ValueError, match="not both"):
        from_mesh(trimesh.creation.box((1, 1, 1)), mass=1.0, density=1.0)
    with pytest.raises(ValueError, match="trimesh.Trimesh"):
        from_mesh("not a mesh", mass=1.0)


# ---------------------------------------------------------------------------------------------------
# Winding: never a wrong mass from a mesh wound inconsistently.
# ---------------------------------------------------------------------------------------------------
def _box_faces():
    box = trimesh.creation.box((1.0, 2.0, 3.0))  # 6 m³: 6000 kg at 1000 kg/m³
    return box.vertices, box.faces


def test_one_flipped_triangle_is_refused_naming_the_winding():
    vertices, faces = _box_faces()
    for flipped in ([0], list(range(0, 12, 2)), list(range(6))):
        wound = faces.copy()
        wound[flipped] = wound[flipped, ::-1]
        with pytest.raises(ValueError, match="wound inconsistently"):
            from_mesh(trimesh.Trimesh(vertices, wound, process=False))


def test_a_separate_part_inside_out_is_refused_a_cavity_is_subtracted():
    vertices, faces = _box_faces()
    both = np.vstack([vertices, vertices + [2.0, 0.0, 0.0]])
    outward = np.vstack([faces, faces + 8])
    assert from_mesh(trimesh.Trimesh(both, outward, process=False)).mass == pytest.approx(12000.0, rel=1e-12)
    inside_out = np.vstack([faces, (faces + 8)[:, ::-1]])  # the repro: was "zero volume" (or 24000 kg)
    with pytest.raises(ValueError, match="inside out"):
        from_mesh(trimesh.Trimesh(both, inside_out, process=False))
    # A hollow box: the inner surface faces inward on purpose; 6 − 0.75 m³ of material.
    inner = trimesh.creation.box((0.5, 1.0, 1.5))
    hollow = trimesh.Trimesh(np.vstack([vertices, inner.vertices]), np.vstack([faces, (inner.faces + 8)[:, ::-1]]))
    props = from_mesh(hollow)
    assert props.mass == pytest.approx(5250.0, rel=1e-12)
    # Its inertia is the outer box's minus the cavity's (both centred): an independent closed form.
    origin = np.zeros(3)
    expected = box(6000.0, (1.0, 2.0, 3.0)).tensor_about(origin) - box(750.0, (0.5, 1.0, 1.5)).tensor_about(origin)
    np.testing.assert_allclose(props.tensor_about(origin), expected, rtol=1e-12, atol=1e-9)
