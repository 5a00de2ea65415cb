"""The suite-time benchmark: its table, pytest's closing line, and the CPU burners start and stop."""

from __future__ import annotations

import os
import time
from pathlib import Path

from benchmarks.suite_time import Run, burning, closing_line, failure_report, failures, write_table


def test_the_closing_line_is_pytests_counts():
    out = "....\n=== short test summary info ===\nFAILED x\n===== 1 failed, 2003 passed in 301.2s (0:05:01) =====\n"
    assert closing_line(out) == "1 failed, 2003 passed in 301.2s (0:05:01)"
    assert closing_line("no tests ran\n") == "no tests ran"


def test_the_failed_tests_are_named():
    out = "..F\n=== short test summary info ===\nFAILED tests/a.py::t - AssertionError: 6.4\nERROR tests/b.py::u\n=== 1 failed ===\n"
    assert failures(out) == ("FAILED tests/a.py::t - AssertionError: 6.4", "ERROR tests/b.py::u")
    assert failures("2005 passed in 300.1s\n") == ()


def test_a_failed_runs_report_is_pytests_failure_section():
    out = (
        "..F\n=== FAILURES ===\n___ t ___\n    assert 1 == 2\nE   AssertionError\n"
        "=== short test summary info ===\nFAILED tests/a.py::t\n=== 1 failed in 3s ===\n"
    )
    assert failure_report(out) == "=== FAILURES ===\n___ t ___\n    assert 1 == 2\nE   AssertionError"
    assert failure_report("...\n=== 3 passed in 1s ===\n") == ""


def test_the_table_counts_passes_and_names_the_load(tmp_path):
    runs = [Run(300.4, 0, "2005 passed in 300.1s"), Run(350.0, 1, "1 failed, 2004 passed in 349.9s", ("FAILED t::x",))]
    text = write_table(runs, quick=False, burn=2, path=tmp_path / "suite_time.md")
    assert "| 1 | 300 | passed | 2005 passed in 300.1s |" in text
    assert "| 2 | 350 | **failed** (1) |" in text
    assert "1 of 2 runs passed; slowest 350 s." in text and "2 processes spinning" in text
    assert "- run 2: FAILED t::x" in text
    assert (tmp_path / "suite_time.png").stat().st_size > 1000


def _cpu_seconds(pid: int) -> float:
    fields = Path(f"/proc/{pid}/stat").read_text().rsplit(")", 1)[1].split()
    return (int(fields[11]) + int(fields[12])) / os.sysconf("SC_CLK_TCK")  # utime + stime


def test_burners_use_the_cpu_and_stop():
    with burning(2) as burners:
        time.sleep(1.0)
        assert all(p.is_alive() for p in burners)
        # Each spins: it gathers CPU time. On loaded cores a spawned process may take seconds to start
        # (CI's run gave one under 0.1 s of CPU in its first second), so it is waited for, up to a minute.
        deadline = time.monotonic() + 60.0
        while not all(_cpu_seconds(p.pid) > 0.1 for p in burners) and time.monotonic() < deadline:
            time.sleep(0.2)
        assert all(_cpu_seconds(p.pid) > 0.1 for p in burners)
    assert not any(p.is_alive() for p in burners)
