"""benchmarks/browser_frames.py: its table and chart from measured rows (the measuring itself drives Chromium)."""

from __future__ import annotations

import benchmarks.browser_frames as browser_frames


def test_the_table_puts_each_label_beside_the_others_by_scene(tmp_path, monkeypatch):
    monkeypatch.setattr(browser_frames, "RESULTS", tmp_path)
    results = {
        "before": {"heavy_top": {"fps": 6.09, "cpu_ms": 175.4}, "wobble": {"fps": 8.0, "cpu_ms": 120.0}},
        "after": {"heavy_top": {"fps": 5.53, "cpu_ms": 186.2}},
    }
    text = browser_frames.write(results, "a note")
    rows = [line for line in text.splitlines() if line.startswith("| ")]
    assert (
        rows[0] == "| scene | before: renders/s | before: CPU ms a render | after: renders/s | after: CPU ms a render |"
    )
    # In the order of SCENES; a scene one label did not measure has empty cells there.
    assert rows[1:] == ["| heavy_top | 6.09 | 175 | 5.53 | 186 |", "| wobble | 8.00 | 120 |  |  |"]
    assert (tmp_path / "browser_frames.md").read_text(encoding="utf-8") == text
    assert (tmp_path / "browser_frames.png").stat().st_size > 1000
