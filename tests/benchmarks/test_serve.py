"""The serve benchmark: what counts as a frame, its heavy cases, its rows and its targets (a few seconds)."""

from __future__ import annotations

import msgspec
import pytest
import zstandard

from benchmarks.serve import FRICTION, GHOST, Case, case_state, cases, measure, plan, targets
from benchmarks.serve_clients import posed_nodes
from tests.harness import running_app


def _wire(messages: list[dict]) -> bytes:
    """One websocket message as viser 1.1.1 sends it: both sizes, zstd msgpack, then (none here) buffers."""
    inner = msgspec.msgpack.encode({"messages": messages, "timestampSec": 1.0, "binaryBufferLengths": ()})
    compressed = zstandard.ZstdCompressor(level=1).compress(inner)
    return len(inner).to_bytes(8, "little") + len(compressed).to_bytes(8, "little") + compressed


def test_only_a_pose_message_makes_a_node_posed():
    readout = {"type": "GuiUpdateMessage", "uuid": "abc", "updates": {"value": "1.00"}}
    plot = {"type": "SceneNodeUpdateMessage", "name": "/scene/trace/3", "updates": {"points": {"index": 0}}}
    assert posed_nodes(_wire([readout, plot])) == set()
    window = [
        readout,
        {"type": "SetOrientationMessage", "name": "/scene/top", "wxyz": (1.0, 0.0, 0.0, 0.0)},
        {"type": "SetPositionMessage", "name": "/scene/L", "position": (0.0, 0.0, 1.0)},
    ]
    assert posed_nodes(_wire(window)) == {"/scene/top", "/scene/L"}


@pytest.mark.parametrize("case", [FRICTION, GHOST], ids=lambda c: c.name)
def test_the_heavy_cases_open_as_described_in_every_simulation_that_starts_from_their_state(case):
    state = case_state(case)
    assert state is not None
    with running_app(case.scene, start_loop=False, state=state) as app:
        assert case.check is not None and case.check(app.scene) is None
        if case is FRICTION:
            assert app.scene.values["friction"] > 0.0 and not app.scene.landed
        else:
            assert type(app.scene.ghost.method).__name__ == "ClassicalRK4"
            assert app.scene.ghost.step_slider.value == pytest.approx(0.002)


def test_a_message_without_the_bodys_pose_is_no_frame():
    # The explorer's body stands still and its clock does not run (a static scene): whatever it sends, no frame.
    still = measure(Case("inertia_explorer", "inertia_explorer"), "shared", 1, 1.0)
    assert still["frames_median"] == still["frames_min"] == 0.0
    moving = measure(Case("heavy_top", "heavy_top"), "private", 2, 1.0)
    assert moving["body"] == "/scene/top"
    assert 0.0 < moving["frames_min"] <= moving["frames_median"] <= moving["messages_median"]
    assert moving["bytes_max"] >= moving["bytes_median"] > 0.0 and moving["rss_mb"] > 0.0
    assert not moving["problems"]


def test_rows_cover_every_case_and_the_heavy_ones_in_every_mode_with_a_crowd():
    every = cases()
    rows = [(c.name, mode, n) for c, mode, n in plan(every, ["shared", "presenter", "private"], [1, 10], 30, "wobble")]
    assert len(rows) == len(set(rows))
    for case in every:
        assert (case.name, "shared", 1) in rows
        assert (case.name, "presenter", 30) in rows or case.name == "wobble"
    for mode in ("shared", "presenter", "private"):
        assert (FRICTION.name, mode, 30) in rows and (GHOST.name, mode, 30) in rows
        assert ("wobble", mode, 10) in rows
    assert ("pendulum", "shared", 30) not in rows


def _row(kb: float, frames_min: float, frames: float | None = None) -> dict:
    frames = frames_min if frames is None else frames
    return {
        "bytes_median": kb * 1e3,
        "bytes_max": kb * 1e3,
        "frames_min": frames_min,
        "frames_median": frames,
        "messages_median": frames or 10.0,  # a still body: its 10 Hz readouts
    }


def test_targets_name_the_worst_row_against_each_limit():
    measured = [
        ("heavy_top", "shared", 1, _row(100.0, 50.0)),  # 120 kB/s at 60 frames/s
        ("wobble", "shared", 1, _row(140.0, 59.0, 60.0)),
        ("inertia_explorer", "shared", 1, _row(1.6, 0.0)),
        ("inertia_explorer", "presenter", 30, _row(1.6, 0.0)),
        ("heavy_top", "presenter", 30, _row(100.0, 56.0, 59.0)),
        ("friction_top", "presenter", 30, _row(100.0, 54.0, 58.0)),
        ("friction_top", "private", 30, {**_row(90.0, 31.0, 40.0), "problems": ["the top landed"]}),
    ]
    text = "\n".join(targets(measured, cores=2))
    assert "worst 140.0 kB/s at 60.0 frames/s (wobble), 140.0 kB/s at 60 frames/s — met" in text
    assert "30 followers: every browser at least 55 frames/s: slowest 54.0 frames/s (friction_top) — NOT met" in text
    assert (
        "30 private sessions on 2 cores: each at least 30 frames/s: slowest 31.0 frames/s (friction_top) — met" in text
    )
    assert "left out of the frame rates: inertia_explorer" in text
    assert "- friction_top private 30: the top landed" in text
    silent = targets([("free_fall", "shared", 1, {**_row(0.0, 0.0), "messages_median": 0.0})])
    assert not any("left out" in line for line in silent)  # nothing received is no still body
    slow = targets([("heavy_top", "shared", 1, _row(100.0, 40.0))])
    assert "150.0 kB/s at 60 frames/s — met" in slow[2]  # scaled from 40 to 60 frames/s: at the limit
