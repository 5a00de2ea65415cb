"""The shared drawing pieces of app.draw: quaternion conversion, the trace's ring buffer, cones."""

from __future__ import annotations

import math

import numpy as np
import pytest
from scipy.spatial.transform import Rotation

from app import draw
from tests.harness import matrix

SCENES = ["heavy_top", "wobble", "free_fall"]


# --------------------------------------------------------------------------------------------------
# Shared pieces
# --------------------------------------------------------------------------------------------------


def test_wxyz_from_matrix_and_scipy_quaternion_agree():
    rot = Rotation.from_rotvec([0.3, -1.2, 0.7])
    from_matrix = draw.wxyz(rot.as_matrix())
    from_quat = draw.wxyz(rot.as_quat())
    # Same rotation up to the quaternion sign; both unit norm (round-off only).
    assert min(np.abs(from_matrix - from_quat).max(), np.abs(from_matrix + from_quat).max()) < 1e-12
    np.testing.assert_allclose(draw.wxyz(np.eye(3)), [1.0, 0.0, 0.0, 0.0], atol=1e-15)
    x, y, z, w = rot.as_quat()
    np.testing.assert_allclose(draw.wxyz(rot.as_quat()), [w, x, y, z], atol=1e-15)
    # The fast single-matrix path (Shepperd) against scipy on many rotations, including half turns
    # (trace -1: the branch that divides by the largest diagonal term).
    mats = np.concatenate(
        [Rotation.random(500, random_state=3).as_matrix(), Rotation.from_rotvec(np.pi * np.eye(3)).as_matrix()]
    )
    for m in mats:
        a, b = draw.wxyz(m), draw.wxyz(m[None])[0]
        assert min(np.abs(a - b).max(), np.abs(a + b).max()) < 1e-14
    batch = draw.wxyz(np.stack([np.eye(3), rot.as_matrix()]))
    assert batch.shape == (2, 4)
    with pytest.raises(ValueError, match="rotation matrix"):
        draw.wxyz(np.zeros(5))


def test_trace_is_a_bounded_ring_buffer_in_time_order(app):
    trace = draw.Trace(app.server, "/test_trace", capacity=10)
    for i in range(25):
        trace.append([float(i), 0.0, 0.0])
    pts = trace.points()
    assert pts.shape == (10, 3)
    np.testing.assert_array_equal(pts[:, 0], np.arange(15, 25))
    # The drawn segments join consecutive points, oldest first, and include the last 9 (capacity − 1);
    # older ones drop out a chunk at a time.
    segs = trace.drawn_segments()
    np.testing.assert_array_equal(segs[:, 1, 0], segs[:, 0, 0] + 1)
    assert segs[-1, 1, 0] == 24 and 9 <= len(segs) < 9 + draw.TRACE_CHUNK
    trace.resize(4)
    assert trace.points().shape == (0, 3) and len(trace.drawn_segments()) == 0
    with pytest.raises(ValueError, match="at least 2"):
        trace.resize(1)
    trace.remove()


def test_trace_sends_one_chunk_a_point_not_the_whole_trace(app):
    """Bandwidth: a new point rewrites one chunk of TRACE_CHUNK segments, whatever the capacity."""
    trace = draw.Trace(app.server, "/test_trace_chunks", capacity=1500)
    for i in range(200):
        trace.append([0.01 * i, 0.0, 0.0])
    sent = [c for c in trace._chunks if c.visible]
    assert len(sent) == -(-199 // draw.TRACE_CHUNK)  # 199 segments so far, in 7 chunks
    assert all(np.asarray(c.points).shape == (draw.TRACE_CHUNK, 2, 3) for c in trace._chunks)
    bytes_per_point = np.asarray(trace._chunks[0].points).nbytes
    assert bytes_per_point == draw.TRACE_CHUNK * 2 * 3 * 4  # 768 bytes, against 36 kB for the whole trace
    segs = trace.drawn_segments()
    assert len(segs) == 199 and np.allclose(segs[:, 1, 0] - segs[:, 0, 0], 0.01)
    trace.remove()


def test_a_full_trace_drops_its_oldest_chunk_and_keeps_its_segments_joined(app):
    """Around the ring: the chunk that empties to become the newest drops out in the same frame, so the
    nodes always draw the last ``capacity`` points, fewer than 2 × TRACE_CHUNK more (whole chunks, the
    newest filling), joined in order."""
    trace = draw.Trace(app.server, "/test_trace_ring", capacity=300)  # 11 chunks, turned many times
    for i in range(1500):
        trace.append([0.01 * i, 0.0, 0.0])
        segs = trace.drawn_segments()
        kept = min(i, 299)
        assert kept <= len(segs) < kept + 2 * draw.TRACE_CHUNK, (i, len(segs))
        if len(segs):
            assert segs[-1, 1, 0] == pytest.approx(0.01 * i, abs=1e-5)
            np.testing.assert_allclose(segs[1:, 0], segs[:-1, 1])  # each segment starts where the last ended
    trace.remove()


@pytest.mark.parametrize("dark", [False, True])
def test_a_trace_fades_toward_the_background_with_age_and_recolours_only_what_changed(app, dark):
    """Old loops recede: the newest quarter of the chunks in the trace's own colour, each older quarter blended
    further toward the view's background (TRACE_FADE); a chunk's colours are sent only when its quarter changes."""
    trace = draw.Trace(app.server, "/test_trace_fade", capacity=300, dark=dark)
    n = len(trace._chunks)
    for i in range(40 * draw.TRACE_CHUNK):  # many turns of the ring
        trace.append([math.cos(i / 30), math.sin(i / 30), 0.0])
    own, background = np.array(draw.colour("trace", dark)), np.array(draw.VIEW_BACKGROUND[dark])
    colours = np.array(trace.chunk_colours(), dtype=float)  # newest first
    assert tuple(colours[0]) == tuple(own)
    distance = np.linalg.norm(colours - background, axis=1)
    assert np.all(np.diff(distance) <= 0) and distance[-1] < 0.5 * distance[0]  # older: nearer the background
    for age, expected in enumerate(trace.chunk_colours()):  # what each node holds is what was computed
        k = (trace._newest - age) % n
        assert np.all(np.asarray(trace._chunks[k].colors) == expected)
    # One more chunk's worth of points turns the ring once: only the chunks whose quarter changed are
    # recoloured (a colour is sent exactly when a chunk's level changes), not all of them.
    before = list(trace._fade)
    for i in range(draw.TRACE_CHUNK):
        trace.append([2.0 + 0.01 * i, 0.0, 0.0])
    changed = sum(a != b for a, b in zip(before, trace._fade, strict=True))
    assert 1 <= changed <= len(draw.TRACE_FADE) < n
    trace.remove()


def test_cone_points_along_its_axis_with_its_half_angle(app):
    cone = draw.Cone(app.server, "/test_cone", "body_cone")
    axis = np.array([0.3, -0.5, -0.8])
    cone.set(axis, math.radians(25.0), 2.0, apex=(1.0, 2.0, 3.0))
    R = matrix(cone.handle)
    # viser stores float32: agreement to ~1e-7.
    np.testing.assert_allclose(R @ [0, 0, 1], axis / np.linalg.norm(axis), atol=1e-6)
    r, _, h = cone.handle.scale
    assert math.degrees(math.atan2(r, h)) == pytest.approx(25.0, abs=1e-9)
    assert math.hypot(r, h) == pytest.approx(2.0, rel=1e-12)
    np.testing.assert_allclose(cone.handle.position, [1.0, 2.0, 3.0])
    # The rim is the rim of this cone: viser scales a mesh's geometry but not its children, so the rim
    # carries the same scale (it was the unit circle, a metre from the axis, whatever the cone's size).
    np.testing.assert_allclose(cone.rim.scale, cone.handle.scale)
    rim = np.asarray(cone.rim.points, dtype=float)[:, 0] * np.asarray(cone.rim.scale)
    np.testing.assert_allclose(np.hypot(rim[:, 0], rim[:, 1]), r, rtol=1e-6)
    np.testing.assert_allclose(rim[:, 2], h, rtol=1e-6)
    cone.set(axis, math.radians(10.0), 1.0)  # a new size: both follow
    np.testing.assert_allclose(cone.rim.scale, cone.handle.scale)
    assert cone.rim.scale[0] == pytest.approx(math.sin(math.radians(10.0)), rel=1e-6)
    cone.set(axis, 0.0, 2.0)  # degenerate: hidden
    assert not cone.handle.visible
    assert cone.rim.name.startswith(cone.handle.name + "/")  # a child: shown, hidden and moved with the cone
    cone.handle.remove()  # and removed with it


def test_lined_up_arrows_keep_their_labels_apart(app):
    """L and ω lined up (a body spinning about a principal axis): ω's label hangs below and left of its tip,
    L's above and right of its own, so the two do not print over each other; apart, both hang above and right.
    Each label stays at its arrow's tip (a label moved along the shaft sat on the heavy top's body)."""
    L = draw.Arrow(app.server, "/test_L", "L", label="L")
    omega = draw.Arrow(app.server, "/test_omega", "omega", label="ω")
    origin = np.array([0.5, -0.2, 1.0])
    L.set([0.0, 0.0, 1.0], origin)
    omega.set([0.0, 0.05, 0.98], origin, apart_from=L)  # tips 0.054 m apart: under 0.25 of 1 m
    np.testing.assert_allclose(L.label.position, origin + [0.0, 0.0, 1.0], atol=1e-6)
    np.testing.assert_allclose(omega.label.position, origin + [0.0, 0.05, 0.98], atol=1e-6)
    assert (L.label.anchor, omega.label.anchor) == ("bottom-left", "top-right")
    omega.set([0.0, 0.6, 0.6], origin, apart_from=L)  # tips 0.72 m apart: both labels in their usual place
    np.testing.assert_allclose(omega.label.position, origin + [0.0, 0.6, 0.6], atol=1e-6)
    assert omega.label.anchor == "bottom-left"
    omega.set([0.0, 0.05, 0.98], origin, apart_from=L)
    assert omega.label.anchor == "top-right"
    L.set([0.0, 0.0, 0.0], origin)  # L hidden: nothing to keep apart from
    omega.set([0.0, 0.05, 0.98], origin, apart_from=L)
    assert omega.label.anchor == "bottom-left"
    for arrow in (L, omega):
        arrow.handle.remove()


def test_arrows_whose_tips_meet_on_the_screen_share_one_label(app):
    """Composed for a screen (its right and up vectors), two tips far apart in depth but one place on that
    screen get one label naming both, at the first's tip; apart on the screen, each its own again."""
    right, up = draw.screen_axes(((0.0, -3.0, 0.0), (0.0, 0.0, 0.0)))  # looking along +y, z up
    np.testing.assert_allclose(right, [1.0, 0.0, 0.0], atol=1e-15)
    np.testing.assert_allclose(up, [0.0, 0.0, 1.0], atol=1e-15)
    L = draw.Arrow(app.server, "/test_L2", "L", label="L")
    omega = draw.Arrow(app.server, "/test_omega2", "omega", label="ω")
    origin = np.zeros(3)
    L.set([0.0, 0.0, 1.0], origin)
    omega.set([0.0, 0.8, 1.0], origin, apart_from=L, screen=(right, up))  # 0.8 m apart, along the line of sight
    assert (L.label.text, L.label.visible, omega.label.visible) == ("L, ω", True, False)
    omega.set([0.5, 0.0, 1.0], origin, apart_from=L, screen=(right, up))  # 0.5 m apart across the screen
    assert (L.label.text, L.label.visible, omega.label.visible) == ("L", True, True)
    omega.set([0.0, 0.8, 1.0], origin, apart_from=L, screen=(right, up))
    omega.set([0.0, 0.0, 0.0], origin, apart_from=L, screen=(right, up))  # ω gone: L's label names L alone
    assert (L.label.text, omega.label.visible) == ("L", False)
    for arrow in (L, omega):
        arrow.handle.remove()
        arrow.label.remove()
