"""The trajectory benchmark runs and writes its table and plot (one repeat: seconds)."""

from __future__ import annotations

import os

from benchmarks.trajectories import cases, main


def test_trajectory_benchmark_writes_table_and_plot(tmp_path):
    assert main(["--repeats", "1", "--out", str(tmp_path)]) == 0
    md = (tmp_path / "trajectories.md").read_text()
    for model, regime, _ in cases():
        assert f"| {model} | {regime} |" in md
    assert "Worst one time" in md
    assert os.path.getsize(tmp_path / "trajectories.png") > 10_000
