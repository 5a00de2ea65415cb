"""The inertia explorer headless: bodies and their moments, pivot, uploads (good, bad, convex hull),
"Spin it" hands the body to the racket scene, uploads parsed outside the lock.
"""

from __future__ import annotations

import math
from types import SimpleNamespace

import numpy as np
import pytest
import trimesh
from scipy.spatial.transform import Rotation
from viser import UploadedFile

import app.scenes.inertia_explorer as explorer_module
from app.scenes.tennis_racket import AXES, snap_symmetric
from app.uploads.limits import MAX_BYTES
from app.uploads.reading import body_from_upload
from assets import mass_properties
from physics.inertia import box, parallel_axis
from tests.harness import FRAME, open_scene
from tests.uploading import lock_is_free


def _box_stl(extents=(0.3, 0.2, 0.1)) -> bytes:
    return trimesh.creation.box(extents=extents).export(file_type="stl")


def _open_stl() -> bytes:
    m = trimesh.creation.box(extents=(0.3, 0.2, 0.1))
    return trimesh.Trimesh(m.vertices, m.faces[1:], process=False).export(file_type="stl")


BAD_UPLOADS = [
    ("notes.txt", b"not a mesh at all", "is not a mesh file"),
    ("empty.stl", b"", "is empty"),
    ("garbage.stl", b"this is not an STL file, only words\n" * 20, "contains no triangles"),
    ("huge.stl", b"\0" * (MAX_BYTES + 1), "the limit is 20.0 MB"),
    ("open.stl", _open_stl(), "is not watertight"),
]


def test_explorer_box_moments_pivot_and_ellipsoid(app):
    sc = open_scene(app, "inertia_explorer")
    assert sc.choice.value.startswith("Box")
    a, length = sc.params.values["a"], sc.params.values["length"]
    exact = box(1.0, [length, 2 * a, a])
    np.testing.assert_allclose(sc.moments, exact.moments, rtol=1e-14)  # same formula, round-off only
    offset = np.array([sc.params.values[k] for k in ("px", "py", "pz")])
    # Parallel-axis theorem: the tensor about the pivot is I_CM + M (a² δ − a aᵀ), to round-off.
    np.testing.assert_allclose(sc.tensor_pivot, exact.tensor + parallel_axis(1.0, offset), rtol=0, atol=1e-15)
    np.testing.assert_allclose(sorted(sc.pivot_moments), np.linalg.eigvalsh(sc.tensor_pivot), rtol=1e-12)
    # The ellipsoid's semi-axes go as 1/√I_i.
    semi = np.asarray(sc.ellipsoid.handle.scale)
    np.testing.assert_allclose(semi * np.sqrt(sc.moments), semi[0] * math.sqrt(sc.moments[0]), rtol=1e-6)
    # The pivot marker is drawn at the centre plus the scaled offset.
    np.testing.assert_allclose(sc.pivot_marker.position, sc.centre + sc.display_scale * offset, atol=1e-6)


def test_explorer_sliders_change_the_body_and_pivot(app):
    sc = open_scene(app, "inertia_explorer")
    before = sc.moments.copy()
    assert sc.params.offer({"a": 0.3, "pz": -0.5})
    assert not np.allclose(sc.moments, before)
    np.testing.assert_allclose(sc.pivot - sc.props.center_of_mass, [0.4, 0.0, -0.5], atol=1e-15)
    np.testing.assert_allclose(sc.moments, box(1.0, [0.8, 0.6, 0.3]).moments, rtol=1e-14)


def test_explorer_every_choice_builds_with_physics_moments(app):
    sc = open_scene(app, "inertia_explorer")
    for choice in sc.choice.options:
        sc.choice.value = choice
        assert sc.label == choice
        assert sc.moments[0] >= sc.moments[1] >= sc.moments[2] >= 0.0
    sc.choice.value = "Tennis racket"
    np.testing.assert_allclose(sc.moments, mass_properties("tennis_racket").moments, rtol=1e-14)
    sc.choice.value = "Rod"
    assert sc.moments[2] == 0.0  # the ellipsoid still has finite axes (capped)
    semi = sc.ellipsoid.semi_axes(sc.moments, 1.0)
    # The rod's infinite axis is capped at 4x the shortest; the two equal ones stay equal.
    np.testing.assert_allclose(sorted(semi), [0.25, 0.25, 1.0], rtol=1e-14)


def test_explorer_point_mass_sets_match_hand_sums(app):
    sc = open_scene(app, "inertia_explorer")
    length = sc.params.values["length"]
    sc.choice.value = "Point masses: dumbbell (2 × 0.5 kg)"
    # Two 0.5 kg masses at ±L/2: I⊥ = 2 · 0.5 (L/2)² = L²/4, zero along the bar (exact sums).
    np.testing.assert_allclose(sc.moments, [length**2 / 4, length**2 / 4, 0.0], rtol=1e-14, atol=1e-16)
    sc.choice.value = "Point masses: square (4 × 0.25 kg)"
    # Four 0.25 kg masses at (±L/2, ±L/2, 0): I_z = L²/2, I_x = I_y = L²/4 (perpendicular-axis theorem).
    np.testing.assert_allclose(sc.moments, [length**2 / 2, length**2 / 4, length**2 / 4], rtol=1e-14)


@pytest.mark.parametrize(("filename", "content", "reason"), BAD_UPLOADS, ids=[b[0] for b in BAD_UPLOADS])
def test_explorer_bad_upload_is_refused_and_previous_body_stays(app, filename, content, reason):
    sc = open_scene(app, "inertia_explorer")
    assert sc.load_upload("brick.stl", _box_stl())  # a good upload first: that is the body to keep
    label, moments, refusals = sc.label, sc.moments.copy(), sc.upload_refusals
    assert not sc.load_upload(filename, content)
    assert sc.upload_refusals == refusals + 1
    assert reason in sc.last_upload_message and reason in app.messages[-1][1]
    assert app.messages[-1][0].startswith("Upload refused")
    assert sc.label == label and sc.choice.value == "Uploaded: brick.stl"
    np.testing.assert_array_equal(sc.moments, moments)


def test_explorer_open_mesh_offers_its_convex_hull(app):
    sc = open_scene(app, "inertia_explorer")
    assert not sc.load_upload("open.stl", _open_stl())
    assert sc.hull_button.visible and "convex hull" in sc.last_upload_message
    sc._use_hull(None)
    assert sc.label == "open.stl (convex hull)" and not sc.hull_button.visible
    np.testing.assert_allclose(sc.moments, box(1.0, [0.3, 0.2, 0.1]).moments, rtol=1e-6)  # float32 STL


def test_explorer_good_upload_then_spin_it_hands_the_body_over(app):
    sc = open_scene(app, "inertia_explorer")
    assert sc.load_upload("brick.stl", _box_stl())
    moments = sc.moments.copy()
    sc._spin_it(None)
    tr = app.scene
    assert tr.name == "tennis_racket" and tr.description == "brick.stl (from the explorer)"
    np.testing.assert_allclose(tr.moments, moments, rtol=1e-12)
    app.frame(FRAME)


@pytest.mark.parametrize("choice", ["Solid cylinder", "Point masses: square (4 × 0.25 kg)", "Rod"])
def test_explorer_spin_it_takes_a_symmetric_body_which_precesses(app, choice):
    sc = open_scene(app, "inertia_explorer")
    sc.choice.value = choice
    sc._spin_it(None)
    tr = app.scene
    assert tr.name == "tennis_racket" and tr.description == f"{choice} (from the explorer)"
    m, spin, eps = tr.moments, tr.params.values["spin"], tr.eps
    s = tr.precession.symmetry_axis  # the axis whose moment differs from the two equal ones
    i_perp, i_s = m[(s + 1) % 3], m[s]
    assert m[(s + 1) % 3] == m[(s + 2) % 3]
    # Spun about one of the equal axes: neutral; ω turns about the symmetry axis at the lecture's
    # Ω = ω_s (I⊥ − I_s)/I⊥, here with ω_s = ε Ω_spin (round-off only: 1e-12).
    assert tr.axis_index != s and tr.stability.kind == "neutral"
    omega_body = eps * spin * (i_perp - i_s) / i_perp
    assert tr.precession.body == pytest.approx(omega_body, rel=1e-12)
    assert float(tr.rate_readout.text) == pytest.approx(omega_body, rel=1e-3)  # shown to 4 digits
    assert "precesses" in tr.stability_readout.text and "precession" in tr.period_readout.handle.label
    # Measured from sign changes of the exact ω(t) on a 4,000-point grid: 1e-5.
    assert tr.flip_period == pytest.approx(2 * math.pi / abs(omega_body), rel=1e-5)
    # Exactly a precession: ω_s and |ω⊥| constant (closed form: round-off only).
    w = tr.model.omega(tr.omega0, np.linspace(0.0, 3.0 * tr.flip_period, 50))
    np.testing.assert_allclose(w[:, s], tr.omega0[s], rtol=1e-12)
    np.testing.assert_allclose(np.hypot(w[:, (s + 1) % 3], w[:, (s + 2) % 3]), spin * math.hypot(1.0, eps), rtol=1e-12)
    assert app.frame(FRAME)
    L0 = np.array(tr.L_arrow.handle.points)
    for _ in range(5):
        assert app.frame(FRAME)
    np.testing.assert_allclose(tr.L_arrow.handle.points, L0, atol=1e-6)  # L fixed in space (float32 handle)
    # About the symmetry axis itself (not a rod's own axis, which carries no L): stable, and the
    # lecture's wobble frequency is the precession rate Ω = Ω_spin (I⊥ − I_s)/I⊥.
    if i_s > 0.0:
        tr.axis.value = next(label for label, i in AXES.items() if i == s)
        assert tr.stability.kind == "stable"
        assert tr.stability.rate == pytest.approx(abs(spin * (i_perp - i_s) / i_perp), rel=1e-12)
        assert tr.precession.body == pytest.approx(spin * (i_perp - i_s) / i_perp, rel=1e-12)


def test_explorer_spin_it_takes_a_sphere_which_turns_uniformly(app):
    sc = open_scene(app, "inertia_explorer")
    sc.choice.value = "Solid sphere"
    sc._spin_it(None)
    tr = app.scene
    assert tr.name == "tennis_racket" and tr.stability.kind == "neutral" and tr.precession.body == 0.0
    assert tr.flip_period == math.inf and not tr.separatrix.visible
    # ω stays what it was (every axis is principal): exact.
    np.testing.assert_array_equal(tr.model.omega(tr.omega0, [0.0, 7.3])[1], tr.omega0)
    assert app.frame(FRAME)


def test_uploaded_float32_cylinder_is_taken_as_symmetric(app):
    sc = open_scene(app, "inertia_explorer")
    can = trimesh.creation.cylinder(radius=0.1, height=0.3, sections=64)
    can.vertices = can.vertices @ Rotation.from_rotvec([0.3, 0.5, 0.7]).as_matrix().T  # tilted: a full tensor
    assert sc.load_upload("can.stl", can.export(file_type="stl"))
    assert sc.moments[0] != sc.moments[1]  # float32 vertices: equal only to about 1e-7
    np.testing.assert_allclose(sc.moments[0], sc.moments[1], rtol=1e-6)
    sc._spin_it(None)
    tr = app.scene
    assert tr.moments[0] == tr.moments[1] and tr.precession is not None and tr.stability.kind == "neutral"
    assert snap_symmetric(np.array([3.0, 2.0, 1.0])).tolist() == [3.0, 2.0, 1.0]  # distinct moments untouched


def test_upload_is_parsed_outside_the_lock_and_swapped_in_under_it(app, monkeypatch):
    sc = open_scene(app, "inertia_explorer")
    free = {}

    def parse(filename, content, **kw):
        free["parse"] = lock_is_free(app.simulation.lock)
        return body_from_upload(filename, content, **kw)

    adopt = sc._adopt

    def swap(body, client):
        free["swap"] = lock_is_free(app.simulation.lock)
        return adopt(body, client)

    monkeypatch.setattr(explorer_module, "body_in_worker", parse)
    monkeypatch.setattr(sc, "_adopt", swap)
    sc.upload._impl.value = UploadedFile("brick.stl", _box_stl())  # what viser stores when a file arrives
    for callback in sc.upload._impl.update_cb:  # the callback viser runs for the real upload button
        callback(SimpleNamespace(client=None, target=sc.upload))
    assert free == {"parse": True, "swap": False}
    assert sc.label == "brick.stl" and app.messages[-1][0] == "Mesh loaded"


def test_upload_parsed_after_the_user_left_the_scene_is_dropped(app, monkeypatch):
    sc = open_scene(app, "inertia_explorer")
    n_messages = len(app.messages)

    def parse_while_someone_switches(filename, content, **kw):
        app.switch_scene("pendulum")  # possible now: the parse no longer holds the lock
        return body_from_upload(filename, content, **kw)

    monkeypatch.setattr(explorer_module, "body_in_worker", parse_while_someone_switches)
    assert not sc.load_upload("brick.stl", _box_stl())
    assert app.scene.name == "pendulum" and len(app.messages) == n_messages  # nothing adopted, nothing said
    assert app.frame(FRAME)
