"""The history benchmark's quick mode runs, measures the friction top's history and writes its table and plot."""

from __future__ import annotations

import os

from benchmarks.history import main, measure


def test_history_benchmark_quick_mode_writes_table_and_plot(tmp_path):
    assert main(["--quick", "--out", str(tmp_path)]) == 0
    md = (tmp_path / "history.md").read_text()
    assert "| 15 | 81 | 7,968 | 23,904 |" in md  # 81 checkpoints of 96 B and two states, for 20 s
    assert "bytes per simulated minute" in md
    assert os.path.getsize(tmp_path / "history.png") > 10_000


def test_memory_per_minute_falls_with_the_checkpoint_interval():
    dense, sparse = measure(1, 10.0, 1, 2), measure(60, 10.0, 1, 2)
    assert dense["nbytes"] == (601 + 2) * 96 and sparse["nbytes"] == (11 + 2) * 96
    assert sparse["bytes_per_minute"] < dense["bytes_per_minute"] / 40
