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


def test_the_cases_without_a_closed_form_have_a_checked_reference():
    import re

    from benchmarks.cases import all_cases

    open_cases = [case for case in all_cases(quick=True) if not case.closed_form]
    assert {case.name for case in open_cases} == {"asym_top_slow", "asym_top_fast"}
    for case in open_cases:
        case.reference()
        # DOP853 at rtol 1e-14 and Yoshida 8 at fine steps, two independent methods, agree far below the
        # benchmark's finest level (1e-10).
        gap = float(re.search(r"agrees to ([0-9.e+-]+) rad", case.reference_note).group(1))
        assert gap < 1e-11, case.reference_note
