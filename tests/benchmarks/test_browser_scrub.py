"""benchmarks/browser_scrub.py: its table from measured runs (the measuring itself drives Chromium)."""

from __future__ import annotations

import pytest

import benchmarks.browser_scrub as browser_scrub


def _run(scrubbing: float, instants: float) -> dict[str, float]:
    return {"playing": 10.0, "playing_cpu": 150.0, "scrubbing": scrubbing, "instants": instants, "scrub_cpu": 110.0}


def test_the_table_takes_the_best_run_and_judges_the_servers_instants() -> None:
    measured = {"1280×800": [_run(13.0, 47.0), _run(14.0, 29.0)], "640×400": [_run(30.0, 20.0), _run(33.0, 25.0)]}
    text = browser_scrub.write(measured, 8.0, 2, 1800)
    rows = [line for line in text.splitlines() if line.startswith("| ")]
    assert rows[1:] == [
        "| 1280×800 | playing | 10.0 | 150 | (60 frames/s played) |",
        "| 1280×800 | scrubbing | 14.0 | 110 | 47.0 (≥ 30: met) |",
        "| 640×400 | playing | 10.0 | 150 | (60 frames/s played) |",
        "| 640×400 | scrubbing | 33.0 | 110 | 25.0 (≥ 30: NOT met) |",
    ]
    assert "each run: 13.0 renders/s, 47.0 instants/s; 14.0 renders/s, 29.0 instants/s." in text


def test_the_command_is_bounded() -> None:
    with pytest.raises(SystemExit):
        browser_scrub.main(["--seconds", "1000"])
