"""Headless tests of the inertia explorer, pendulum and tennis-racket scenes: each builds and steps, its
handles move, sliders change the model, bad uploads and impossible bodies are refused with the previous
state kept, and the numbers shown are the physics modules' numbers.

One App (real viser server on a free port, no loop thread) serves the module; frames are driven by
calling ``App.frame(dt)`` directly.
"""

from __future__ import annotations

import math

import numpy as np
import pytest
import trimesh

from app.scenes import REGISTRY, load_all
from app.scenes.tennis_racket import AXES, SLIDERS, box_for_moments, separatrix_circles
from app.upload import MAX_BYTES
from assets import mass_properties
from browser import FRAME, matrix, open_scene
from physics.inertia import box, parallel_axis
from physics.pendulum import PhysicalPendulum





def test_scenes_are_registered_with_legends():
    load_all()
    for name in ("inertia_explorer", "pendulum", "tennis_racket"):
        cls = REGISTRY[name]
        assert cls.title and cls.caption and cls.quantities


# --------------------------------------------------------------------------------------------------
# Inertia explorer
# --------------------------------------------------------------------------------------------------


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


def test_explorer_spin_it_refuses_a_symmetric_body(app):
    sc = open_scene(app, "inertia_explorer")
    sc.choice.value = "Solid sphere"
    with pytest.raises(ValueError, match="two equal moments"):
        sc._spin_it(None)
    assert app.scene is sc


# --------------------------------------------------------------------------------------------------
# Tennis racket
# --------------------------------------------------------------------------------------------------


def test_racket_builds_steps_and_moves_with_L_fixed(app):
    sc = open_scene(app, "tennis_racket")
    q0 = np.array(sc.body.handle.wxyz)
    L0 = np.array(sc.L_arrow.handle.points)
    for _ in range(30):
        app.frame(FRAME)
    assert app.time == pytest.approx(31 * FRAME, rel=1e-12)
    assert np.abs(np.array(sc.body.handle.wxyz) - q0).max() > 1e-3
    np.testing.assert_allclose(sc.L_arrow.handle.points, L0, atol=1e-6)  # L fixed in space
    # L in space is R I ω at any time (exact solution: only round-off).
    st = sc.compute(0.7, 0.0)
    np.testing.assert_allclose(st["R"] @ (sc.moments * st["omega_body"]), sc.L_space, rtol=0,
                               atol=1e-12 * np.linalg.norm(sc.L_space))
    assert sc.plot.data[0].size >= 2


def test_racket_intermediate_axis_growth_rate_and_flip(app):
    sc = open_scene(app, "tennis_racket")
    i1, i2, i3 = sc.moments
    spin = sc.params.values["spin"]
    assert sc.stability.kind == "unstable"
    # Lecture: λ = Ω √((I1 − I2)(I2 − I3)/(I1 I3)).
    assert sc.stability.rate == pytest.approx(spin * math.sqrt((i1 - i2) * (i2 - i3) / (i1 * i3)), rel=1e-12)
    period = sc.model.period(sc.omega0)
    # Measured from sign changes on a grid of 4,000 points with linear interpolation: 1e-5.
    assert sc.flip_period == pytest.approx(period, rel=1e-5)
    # Half a period later the body has flipped: ω along axis 2 has reversed.
    assert sc.compute(period / 2, 0.0)["omega_body"][1] < -0.9 * spin


@pytest.mark.parametrize("label", ["1 — largest moment", "3 — smallest moment"])
def test_racket_stable_axes_wobble_at_the_lecture_frequency(app, label):
    sc = open_scene(app, "tennis_racket")
    sc.axis.value = label
    i = AXES[label]
    m = sc.moments
    j, k = (i + 1) % 3, (i + 2) % 3
    spin = sc.params.values["spin"]
    expected = spin * math.sqrt((m[i] - m[j]) * (m[i] - m[k]) / (m[j] * m[k]))
    assert sc.stability.kind == "stable" and sc.stability.rate == pytest.approx(expected, rel=1e-12)
    # For ε = 1e-3 the exact wobble period is the linear one to O(ε²): 1e-5.
    assert sc.flip_period == pytest.approx(2 * math.pi / expected, rel=1e-5)
    # It stays near the axis: the spin component never drops below 99 %.
    w = sc.model.omega(sc.omega0, np.linspace(0, 20, 400))
    assert np.all(np.abs(w[:, i]) > 0.99 * spin)


def test_racket_sliders_refuse_impossible_or_unordered_moments(app):
    sc = open_scene(app, "tennis_racket")
    sc.source.value = SLIDERS
    np.testing.assert_allclose(sc.moments, [3.0, 2.0, 1.0])
    refusals = sc.params.refusals
    assert not sc.params.offer({"I1": 4.0, "I2": 1.0, "I3": 1.0})  # > I2 + I3: impossible
    assert "no rigid body" in app.messages[-1][1]
    assert not sc.params.offer({"I2": 3.5})  # I2 > I1: numbering broken
    assert sc.params.refusals == refusals + 2
    np.testing.assert_allclose(sc.moments, [3.0, 2.0, 1.0])  # the last valid body stays
    assert sc.params.offer({"I2": 2.5})
    np.testing.assert_allclose(sc.moments, [3.0, 2.5, 1.0])
    # The drawn box has exactly these moments (M = 1 kg).
    ext = np.ptp(box_for_moments(sc.moments).vertices, axis=0)
    np.testing.assert_allclose(box(1.0, ext).moments, sc.moments, rtol=1e-12)


def test_racket_perturbation_slider_is_logarithmic(app):
    sc = open_scene(app, "tennis_racket")
    assert sc.params.offer({"log_eps": -6.0})
    spin = sc.params.values["spin"]
    np.testing.assert_allclose(sc.omega0, [1e-6 * spin, spin, 1e-6 * spin], rtol=1e-15)
    assert float(sc.first_flip_readout.text) == pytest.approx(math.log(1e6) / sc.stability.rate, rel=1e-3)


def test_racket_polhode_and_separatrix_lie_where_the_invariants_say(app):
    sc = open_scene(app, "tennis_racket")
    inv = 1.0 / sc.moments
    rel = lambda p: (np.asarray(p, dtype=float).reshape(-1, 3) - sc.sphere_centre)  # noqa: E731
    sep = rel(sc.separatrix.points)
    sep /= np.linalg.norm(sep, axis=1, keepdims=True)
    # On the separatrix 2E/L² = 1/I2 (float32 points: 1e-6).
    np.testing.assert_allclose(sep**2 @ inv, inv[1], rtol=1e-5)
    pol = rel(sc.polhode.points)
    pol /= np.linalg.norm(pol, axis=1, keepdims=True)
    energy = pol**2 @ inv  # 2E/L², constant along the polhode
    assert np.ptp(energy) < 1e-5 * energy.mean()
    circles = separatrix_circles(sc.moments)
    np.testing.assert_allclose(np.linalg.norm(circles, axis=2), 1.0, rtol=1e-14)


def test_racket_t_handle_and_book_flip_too(app):
    sc = open_scene(app, "tennis_racket")
    for source in ("T-handle, Dzhanibekov (mesh)", "Book (mesh)"):
        sc.source.value = source
        assert sc.stability.kind == "unstable" and math.isfinite(sc.flip_period)
        app.frame(FRAME)


# --------------------------------------------------------------------------------------------------
# Pendulum
# --------------------------------------------------------------------------------------------------


def test_pendulum_swings_exactly_about_the_fixed_pivot(app):
    sc = open_scene(app, "pendulum")
    for _ in range(40):
        app.frame(FRAME)
    R = matrix(sc.body.handle)
    # The pivot does not move: R pivot + position = pivot (float32 handle values: 1e-6).
    np.testing.assert_allclose(R @ sc.pivot + np.asarray(sc.body.handle.position), sc.pivot, atol=1e-6)
    theta, _ = sc.model.solve(math.radians(sc.params.values["amplitude"]), 0.0, [app.time])
    np.testing.assert_allclose(R, sc.model.attitude(float(theta[0])), atol=1e-6)
    m = sc.model
    assert float(sc.k_readout.text) == pytest.approx(m.radius_of_gyration, rel=1e-3)
    assert float(sc.l_readout.text) == pytest.approx(m.radius_of_gyration**2 / m.a_perp, rel=1e-3)
    assert float(sc.a_readout.text) == pytest.approx(m.a_perp, rel=1e-3)
    np.testing.assert_allclose(sc.cop_marker.position, m.center_of_percussion(float(theta[0])), atol=1e-6)


def test_pendulum_pivot_slider_changes_a_perp(app):
    sc = open_scene(app, "pendulum")
    a0 = sc.model.a_perp
    assert sc.params.offer({"pivot": sc.params.values["pivot"] + 0.1})
    assert sc.model.a_perp == pytest.approx(a0 - 0.1, abs=1e-12)  # the bat hangs straight: a⊥ shrinks by 0.1 m


def test_pendulum_strike_at_centre_of_percussion_needs_no_pivot_impulse(app):
    sc = open_scene(app, "pendulum")
    l = sc.model.effective_length
    assert sc.params.offer({"strike": l})
    result = sc.strike()
    # J = 1 N s at the centre of percussion: the reaction vanishes to round-off.
    assert np.linalg.norm(result.reaction_impulse) < 1e-12
    app.frame(FRAME)
    assert sc.impulse_arrow.handle.visible and not sc.reaction_arrow.handle.visible  # zero arrow hidden
    assert sc.params.offer({"strike": 0.2})
    t0 = app.time
    _, thetadot_before = sc.state_at(t0)
    result = sc.strike()
    assert np.linalg.norm(result.reaction_impulse) > 0.1
    # The reaction is M Δv_cm − J, and the swing continues from the struck state.
    _, thetadot_after = sc.state_at(t0)
    assert thetadot_after == pytest.approx(thetadot_before + result.delta_omega, rel=1e-12)
    app.frame(FRAME)
    assert sc.reaction_arrow.handle.visible
    for _ in range(int(2.0 / FRAME)):
        app.frame(FRAME)
    assert not sc.impulse_arrow.handle.visible  # arrows go after ARROW_SHOW seconds


def test_pendulum_strike_point_slider_does_not_restart_the_swing(app):
    sc = open_scene(app, "pendulum")
    for _ in range(20):
        app.frame(FRAME)
    t, model = app.time, sc.model
    assert sc.params.offer({"strike": 0.3, "impulse": 2.0})
    assert app.time == t and sc.model is model
    assert sc.params.offer({"amplitude": 45.0})  # a new release angle does restart
    assert app.time == 0.0 and sc.model is not model


def test_pendulum_refuses_pivot_off_or_at_the_centre_of_mass(app):
    sc = open_scene(app, "pendulum")
    sc.choice.value = "Uniform rod 0.84 m, 0.9 kg"
    pend = sc.model
    assert isinstance(pend, PhysicalPendulum)
    assert not sc.params.offer({"pivot": 0.42})  # the rod's centre of mass
    assert "balanced" in app.messages[-1][1]
    assert sc.model is pend
    assert not sc.params.offer({"strike": 0.84})  # beyond the end of the rod below the pivot
    assert "on the body" in app.messages[-1][1]
    # A uniform rod hung from its end: ℓ = 2/3 of its length (lecture).
    assert sc.params.offer({"pivot": 0.0, "strike": 0.3})
    assert sc.model.effective_length == pytest.approx(2 * 0.84 / 3, rel=1e-12)
