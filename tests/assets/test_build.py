"""The asset meshes: closed, small, reproducible, and with the mass distribution their shape implies."""

from __future__ import annotations

import numpy as np
import pytest
import trimesh

import assets
from assets import ASSETS, asset_path, load_mesh, mass_properties
from assets.build import BUILDERS
from assets.build import main as build_main
from physics.inertia import box

NAMES = sorted(ASSETS)


def test_catalogue_and_builders_agree():
    assert set(ASSETS) == set(BUILDERS) == {"tennis_racket", "t_handle", "spinning_top", "baseball_bat", "book"}


@pytest.mark.parametrize("name", NAMES)
def test_asset_is_a_small_closed_outward_solid(name):
    path = asset_path(name)
    assert path.suffix == ".ply"
    assert path.stat().st_size < 300_000  # the brief's size budget per committed mesh
    mesh = load_mesh(name)
    assert mesh.is_watertight
    assert mesh.is_winding_consistent
    assert mesh.volume > 0.0  # outward normals
    assert 0 < len(mesh.faces) < 20_000


def test_rebuild_is_byte_identical(tmp_path):
    # The committed files are exactly what the generator makes: no hand edits, no randomness.
    build_main(["--out", str(tmp_path)])
    for name in NAMES:
        assert (tmp_path / f"{name}.ply").read_bytes() == asset_path(name).read_bytes(), name


@pytest.mark.parametrize("name", NAMES)
def test_catalogue_mass_is_used(name):
    props = mass_properties(name)
    # from_mesh scales the density to the requested mass; only round-off separates them.
    assert props.mass == pytest.approx(ASSETS[name].mass, rel=1e-12)


def test_unknown_asset_is_refused():
    with pytest.raises(ValueError, match="unknown asset 'racket'"):
        asset_path("racket")


@pytest.mark.parametrize(("name", "thickness_axis", "thickness"), [
    ("tennis_racket", 1, 0.022),
    ("t_handle", 1, 0.012),
    ("book", 1, 0.240),
])  # fmt: skip
def test_prism_obeys_perpendicular_axis_theorem_with_thickness(name, thickness_axis, thickness):
    # For a uniform prism of thickness t along axis n, with a, b the in-plane axes:
    # I_aa + I_bb - I_nn = 2 ∫ρ n² dV = 2 M t²/12, exactly, whatever the cross-section.
    props = mass_properties(name)
    t = props.tensor
    a, b = [k for k in range(3) if k != thickness_axis]
    lhs = t[a, a] + t[b, b] - t[thickness_axis, thickness_axis]
    rhs = 2.0 * props.mass * thickness**2 / 12.0
    # The mesh integrates a polyhedron exactly; the PLY stores vertices as float32 (relative rounding
    # 6e-8 per coordinate, doubled in a quadratic moment, and the difference cancels ~10x): 1e-6.
    assert lhs == pytest.approx(rhs, rel=1e-6)


def test_t_handle_equals_two_boxes():
    # The T is exactly a crossbar box 70 x 12 x 12 mm on top of a stem box 12 x 12 x 60 mm.
    crossbar_vol, stem_vol = 0.070 * 0.012 * 0.012, 0.012 * 0.012 * 0.060
    m = ASSETS["t_handle"].mass
    crossbar = box(m * crossbar_vol / (crossbar_vol + stem_vol), [0.070, 0.012, 0.012])
    stem = box(m * stem_vol / (crossbar_vol + stem_vol), [0.012, 0.012, 0.060])
    exact = crossbar.transformed(np.eye(3), [0, 0, 0.006]) + stem.transformed(np.eye(3), [0, 0, -0.030])
    props = mass_properties("t_handle")
    # float32 vertices in the PLY (relative rounding 6e-8, here 1e-10 m on a 70 mm bar) bound the error.
    np.testing.assert_allclose(props.center_of_mass, exact.center_of_mass, atol=1e-9)
    np.testing.assert_allclose(props.tensor, exact.tensor, rtol=0, atol=1e-6 * exact.tensor.max())
    moments = props.moments
    # Three well separated moments (the point of the Dzhanibekov demonstration).
    assert moments[0] > 1.3 * moments[1] > 1.3 * 1.3 * moments[2]


@pytest.mark.parametrize("name", ["spinning_top", "baseball_bat"])
def test_revolved_bodies_are_axisymmetric(name):
    # A 48- or 64-fold symmetric solid has an isotropic tensor across its axis (any n >= 3).
    props = mass_properties(name)
    t = props.tensor
    # Exact symmetry up to the float32 rounding of the stored vertices (relative 6e-8): 1e-6.
    np.testing.assert_allclose(props.center_of_mass[:2], 0.0, atol=1e-9)
    assert t[0, 0] == pytest.approx(t[1, 1], rel=1e-6)
    np.testing.assert_allclose([t[0, 1], t[0, 2], t[1, 2]], 0.0, atol=1e-6 * t.max())
    if name == "baseball_bat":
        assert t[2, 2] < 0.05 * t[0, 0]  # a long thin body: tiny moment about its axis
    else:
        assert t[2, 2] > t[0, 0]  # a top is oblate about its centre of mass: spins stably


def test_racket_shape_and_moment_order():
    mesh = load_mesh("tennis_racket")
    np.testing.assert_allclose(mesh.bounds, [[-0.135, -0.011, 0.0], [0.135, 0.011, 0.685]], atol=1e-7)  # float32
    props = mass_properties("tennis_racket")
    t = props.tensor
    # Normal to the face (y) > across the face (x) > along the handle (z): the lecture's tennis racket.
    assert t[1, 1] > t[0, 0] > t[2, 2]
    # Mirror symmetric in x and y: the principal axes are the coordinate axes.
    np.testing.assert_allclose([t[0, 1], t[0, 2], t[1, 2]], 0.0, atol=1e-6 * t.max())  # float32 vertices


def test_bat_and_top_dimensions():
    np.testing.assert_allclose(load_mesh("baseball_bat").bounds[:, 2], [0.0, 0.84], atol=1e-7)  # float32
    np.testing.assert_allclose(load_mesh("spinning_top").bounds[:, 2], [0.0, 0.092], atol=1e-7)
    # The bat's centre of mass is in the thick half, as in a real bat.
    assert 0.5 < mass_properties("baseball_bat").center_of_mass[2] < 0.65


def test_load_mesh_returns_a_copy():
    a = load_mesh("book")
    a.apply_translation([1.0, 0.0, 0.0])
    assert load_mesh("book").bounds[0, 0] == pytest.approx(-0.091, abs=1e-3)
    assert isinstance(a, trimesh.Trimesh) and assets.ASSET_DIR.is_dir()
