"""The rooms benchmark's arithmetic: frames/s in a window, the longest gap, isolation, the targets' verdicts."""

from __future__ import annotations

import msgspec
import pytest
import zstandard

from benchmarks.rooms import BODY, isolation_problems, longest_gap, picker_and_nodes, rate, report, scene_titles
from benchmarks.rooms_teacher import report_lines


def _wire(messages: list[dict]) -> bytes:
    inner = msgspec.msgpack.encode({"messages": messages, "timestampSec": 1.0, "binaryBufferLengths": ()})
    compressed = zstandard.ZstdCompressor(level=1).compress(inner)
    return len(inner).to_bytes(8, "little") + len(compressed).to_bytes(8, "little") + compressed


def test_rate_counts_frames_inside_the_window_only() -> None:
    frames = [0.5, 1.0, 1.5, 2.0, 2.5, 3.0]
    assert rate(frames, 1.0, 3.0) == 2.0  # 1.0, 1.5, 2.0, 2.5 in [1, 3): 4 frames in 2 s


def test_the_longest_gap_includes_the_window_edges() -> None:
    assert longest_gap([1.1, 1.2, 1.9], 1.0, 2.0) == pytest.approx(0.7)
    assert longest_gap([], 1.0, 2.0) == 1.0  # nothing at all: the whole window is a gap
    assert longest_gap([1.0, 1.95], 1.0, 2.0) == pytest.approx(0.95)


def test_the_picker_and_the_nodes_a_follower_was_shown() -> None:
    state: dict = {"nodes": set(), "scene": None}
    picker = {"type": "GuiDropdownMessage", "uuid": "u1", "value": "Heavy top", "props": {"label": "Scene"}}
    picker_and_nodes(
        _wire([picker, {"type": "SetPositionMessage", "name": "/scene/top", "position": (0, 0, 1)}]), state
    )
    picker_and_nodes(
        _wire([{"type": "GuiUpdateMessage", "uuid": "u1", "updates": {"value": "Physical pendulum"}}]), state
    )
    assert state["scene"] == "Physical pendulum" and state["nodes"] == {"/scene/top"}


def test_a_node_only_another_room_draws_is_a_breach_of_isolation() -> None:
    clean = [
        {"room": "a", "scene": "Heavy top", "nodes": ["/grid", "/scene/top"]},
        {"room": "b", "scene": "Pendulum", "nodes": ["/grid", "/scene/body"]},
    ]
    assert isolation_problems(clean, {"a": "Heavy top", "b": "Pendulum"}) == []
    leaked = [*clean, {"room": "b", "scene": "Heavy top", "nodes": ["/grid", "/scene/body", "/scene/top"]}]
    assert isolation_problems(leaked, {"a": "Heavy top", "b": "Pendulum"}) == [
        "a follower of b received ['/scene/top']",
        "a follower of b was shown the scene 'Heavy top'",
    ]


def test_the_body_nodes_are_the_scenes_titles_own() -> None:
    assert set(BODY) <= set(scene_titles())


def test_the_report_judges_each_target() -> None:
    pool = {
        "sessions": 60,
        "spread": (31, 29),
        "frames_min": 31.0,
        "frames_median": 40.0,
        "lost_before_kill": 0,
        "gap_before": 0.05,
        "gap_after": 0.3,
        "survivor_rate_after": 50.0,
        "survivors_lost": 0,
        "victims_lost": 31,
        "joins": [(0.1, "127.0.0.3:1", True), (4.8, "127.0.0.2:1 (after the restart)", True)],
        "living": "127.0.0.3:1",
        "back_after": 4.5,
        "cpu": {"homework 1": 0.9, "homework 2": 0.85},
    }
    lecture = {"followers": 30, "per_room": {n: (56.0, 58.0) for n in ("mech101", "phys202", "sport")}}
    lecture |= {"frames_min": 56.0, "isolation": [], "lost": 0, "cpu": {"mech101": 0.5, "phys202": 0.4, "sport": 0.4}}
    text = "\n".join(report(pool, lecture, "cmd", "machine", 1.0, "9 CPU seconds"))
    assert "| 60 | 31.0 | 40.0 | 0.90 + 0.85 |" in text and "| 30 | 56.0 | 58.0 | 0.50 |" in text
    assert "60 sessions at ≥ 30 frames/s each: slowest 31.0 — met" in text
    assert "slowest 56.0 — met" in text
    assert "longest gap between two frames 300 ms" in text and "— NOT met (no gap over 250 ms)" in text
    assert "1 joins while the killed process was down, on ['127.0.0.3:1']" in text and "1 after it was back" in text
    assert "answered 4.5 s after the kill" in text


def test_the_teachers_table_rows_judge_the_one_second_bound() -> None:
    result = {
        "sessions": 60,
        "rows": 60,
        "latencies": [0.2, 0.4, 0.3],
        "idle": {"commands": 12.0, "bytes_in": 9000.0, "bytes_out": 350.0},
        "watched": {"commands": 20.0, "bytes_in": 9100.0, "bytes_out": 27000.0},
        "seconds": 5.0,
    }
    text = "\n".join(report_lines(result))
    assert "| change on process 2 → teacher's table on process 1: median | 300 ms |" in text
    assert "| same, slowest of 3 | 400 ms |" in text
    assert "| 12.0, 9000, 350 |" in text and "| 20.0, 9100, 27000 |" in text
    assert "within 1 s of a change: slowest 0.40 s — met" in text
    slow = "\n".join(report_lines(result | {"latencies": [0.2, 1.5]}))
    assert "slowest 1.50 s — NOT met" in slow
