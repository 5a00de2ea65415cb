"""The real-toss benchmark end to end, on a folder laid out like the shared recordings but holding a recording
the project makes with its own model (two hand-marked tosses); and its stop when the folder is absent."""

from __future__ import annotations

from pathlib import Path

import numpy as np

from benchmarks.gyro_fit import main
from physics.gyro import Toss, synthetic_recording


def write_phyphox(folder: Path) -> None:
    rec, windows = synthetic_recording(
        [0.8, 0.21, 1.0],
        [Toss(1.0, 0.8, (18.0, 1.0, 0.6)), Toss(3.0, 0.9, (22.0, 0.5, -0.8))],
        misalignment=(0.02, -0.01, 0.015),
        drag=(0.1, 0.02, 0.05),
    )
    (folder / "meta").mkdir(parents=True)
    rows = ['"Time (s)","Gyroscope x (rad/s)","Gyroscope y (rad/s)","Gyroscope z (rad/s)","Absolute (rad/s)"']
    rows += [f"{t:.9E},{w[0]:.9E},{w[1]:.9E},{w[2]:.9E},{np.linalg.norm(w):.9E}" for t, w in zip(rec.times, rec.omega)]
    (folder / "Raw Data.csv").write_text("\n".join(rows) + "\n")
    (folder / "meta" / "device.csv").write_text('"property","value"\n"deviceModel","Synthetic1,1"\n')
    marks = ["segment,start,end,keep,comment"]
    marks += [f"{i},{a + 0.03:.2f},{b - 0.03:.2f},,Intermediate axis rotation" for i, (a, b) in enumerate(windows)]
    marks.append("9,5.0,5.5,false,Not a trial")
    (folder / "meta" / "segments.csv").write_text("\n".join(marks) + "\n")


def test_the_benchmark_reports_windows_ratios_residuals_and_baselines(tmp_path: Path) -> None:
    write_phyphox(tmp_path / "data" / "synthetic-phone" / "Gyroscope rotation rate 2026-01-01 10-00-00")
    out = tmp_path / "results"
    assert main(["--data", str(tmp_path / "data"), "--out", str(out), "--baseline-every", "2"]) == 0
    text = (out / "gyro_fit.md").read_text()
    assert (out / "gyro_fit.png").stat().st_size > 10_000
    assert "2 tosses (2 hand-marked" in text and "2 fitted" in text
    assert "Both ends within 50 ms: **100%** of 2 hand-marked tosses" in text
    # The phone's ratios: the true 0.8 and 0.21, both tosses within ±0.02 of their median.
    assert "| Synthetic1,1 | 2 | 0.80" in text and "| 100% | zxy |" in text
    for row in ("| ours: exact free body", "| student method", "| solve_ivp RK45"):
        assert row in text
    assert (
        "Ours below the student method's residual on 100%" in text
        and "below solve_ivp's on 100% of those it ran on" in text
    )
    assert "## Refused\n\nNone." in text


def test_without_the_shared_folder_it_says_so_and_stops(tmp_path: Path, capsys) -> None:
    assert main(["--data", str(tmp_path / "absent"), "--out", str(tmp_path / "results")]) == 2
    assert "no recordings at" in capsys.readouterr().err
    assert not (tmp_path / "results").exists()
