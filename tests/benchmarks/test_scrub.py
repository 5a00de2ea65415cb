"""The scrub benchmark runs in a small mode, writes its table and reports the friction top's history memory."""

from __future__ import annotations

from benchmarks.scrub import main


def test_scrub_benchmark_writes_its_table(tmp_path):
    out = tmp_path / "scrub.md"
    table = main(["--scrubs", "5", "--repeats", "1", "--played", "5", "--out", str(out)])
    assert out.read_text() == table
    rows = [line for line in table.splitlines() if line.startswith("| heavy top with friction")]
    # The friction top keeps 300 s at a checkpoint every 60 steps of 1/240 s: 1,201 checkpoints of 13
    # float64, and two states, whatever was played.
    assert len(rows) == 1 and rows[0].endswith(f"| {(1201 + 2) * 13 * 8:,} |")
    assert table.count("\n| ") == 7  # the header, its rule and five scenes
