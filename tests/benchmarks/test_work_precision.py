"""The benchmark command runs and writes its table (smoke mode: two cases, tiny budget, seconds)."""

from __future__ import annotations

import os

from benchmarks.work_precision import main


def test_benchmark_smoke_writes_table_and_plots(tmp_path):
    assert main(["--smoke", "--out", str(tmp_path)]) == 0
    md = (tmp_path / "work_precision.md").read_text()
    # The summary table has a row per case with a ratio for every error level, and each case its section.
    for name in ("free_generic", "top_cusps"):
        assert f"| {name} |" in md and f"### {name}" in md
        assert os.path.getsize(tmp_path / f"{name}.png") > 10_000
    assert "| 1e-04 |" in md and "Lie-Poisson Strang" in md and "DOP853" in md and "MuJoCo RK4" in md
    assert (tmp_path / "long_run_energy.png").exists()
