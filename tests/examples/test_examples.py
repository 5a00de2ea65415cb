"""Every script in examples/ runs headless, and the numbers it prints are the physics' numbers.

Each example runs in its own process from the repository root, as a user would run it; its printed
output is parsed and checked against the physics package or the lecture's formula.
"""

from __future__ import annotations

import math
import os
import re
import subprocess
import sys
from pathlib import Path

import numpy as np
import pytest

from assets import mass_properties

ROOT = Path(__file__).resolve().parents[2]
EXAMPLES = ROOT / "examples"


def run_example(name: str, *args: str, timeout: float = 120.0) -> str:
    env = {**os.environ, "PYTHONPATH": str(ROOT), "MPLBACKEND": "Agg"}
    result = subprocess.run(
        [sys.executable, str(EXAMPLES / name), *args],
        cwd=ROOT,
        env=env,
        capture_output=True,
        text=True,
        timeout=timeout,
    )
    assert result.returncode == 0, f"{name} failed:\n{result.stdout}\n{result.stderr}"
    return result.stdout


def numbers(line: str) -> list[float]:
    # Numbers standing alone: not the 2 of "omega_2" or "m^2", nor the 1 of "I1".
    return [float(x) for x in re.findall(r"(?<![\w^.])[-+]?\d+\.?\d*(?:e[-+]?\d+)?", line)]


def line_with(out: str, text: str) -> str:
    found = [line for line in out.splitlines() if text in line]
    assert found, f"no line with {text!r} in:\n{out}"
    return found[0]


def test_every_example_is_tested():
    scripts = sorted(p.name for p in EXAMPLES.glob("[0-9][0-9]_*.py"))
    tested = re.findall(r'run_example\("(\d\d_\w+\.py)"', Path(__file__).read_text())
    assert scripts and set(scripts) == set(tested)


def test_01_mesh_inertia_prints_the_assets_principal_moments():
    out = run_example("01_mesh_inertia.py", "--asset", "tennis_racket")
    printed = np.array(numbers(line_with(out, "moments I1 >= I2 >= I3"))[-3:])
    moments, axes = mass_properties("tennis_racket").principal()
    np.testing.assert_allclose(printed, moments, rtol=1e-9)  # printed with 10 significant digits
    assert numbers(line_with(out, "det(axes)"))[-1] == pytest.approx(1.0, abs=1e-14)


def test_02_racket_flip_grows_like_the_lectures_cosh():
    out = run_example("02_tennis_racket_flip.py", "--push", "1e-3")
    kinds = [line.split(":")[1].split(",")[0].strip() for line in out.splitlines() if line.startswith("spin about")]
    assert kinds == ["stable", "unstable", "stable"]  # lecture: the intermediate axis is unstable
    rows = [numbers(line) for line in out.splitlines() if "cosh(sigma t)" in line]
    assert len(rows) == 3
    for row in rows:
        exact, linear = row[-2], row[-1]  # ω3(t)/ω3(0) from the exact motion; the lecture's cosh σt
        # The linearisation drops terms of order push² × growth² ≈ 1e-6 × 10² = 1e-4 at σt = 3.
        assert exact == pytest.approx(linear, rel=1e-4)
    w2 = numbers(line_with(out, "flip period"))
    assert w2[2] == pytest.approx(-3.0, abs=1e-3)  # ω2 reverses: the racket flipped


def test_03_heavy_top_trace_has_cusps_and_writes_its_plot(tmp_path):
    png = tmp_path / "trace.png"
    out = run_example("03_heavy_top_trace.py", "--out", str(png))
    theta_min, theta_max = numbers(line_with(out, "theta between"))
    assert theta_min == pytest.approx(math.degrees(0.5), abs=1e-4)  # released at θ0 = 0.5 rad
    assert theta_max > theta_min  # erratum 5: the top first falls
    assert numbers(line_with(out, "min phi-dot"))[0] >= -1e-12  # cusps: φ̇ touches 0, never reverses
    assert numbers(line_with(out, "energy drift"))[0] < 1e-13
    assert png.stat().st_size > 10_000


def test_04_asymmetric_top_converges_at_fourth_order():
    out = run_example("04_asymmetric_top.py")
    rows = [numbers(line) for line in out.splitlines() if re.match(r"\d\.?\d*e-0\d", line)]
    assert len(rows) == 3
    energy, lz, diff = (np.array([r[i] for r in rows]) for i in (1, 2, 3))
    order = np.log2(diff[:-1] / diff[1:])
    assert np.all((order > 3.5) & (order < 4.5)), order  # Yoshida 4: halving the step gains 2⁴
    assert np.all(np.diff(energy) < 0) and energy[-1] < 1e-8
    assert np.all(lz < 1e-12)  # gravity has no torque about z: L_z is conserved to round-off


def test_05_custom_scene_serves_and_shows_the_lectures_rate():
    out = run_example("05_custom_scene.py", "--port", "0", "--seconds", "1.5")
    assert numbers(line_with(out, "frames drawn"))[0] > 10
    shown = numbers(line_with(out, "precession rate shown"))[0]
    lecture = numbers(line_with(out, "lecture: L/I1"))[-1]
    assert shown == pytest.approx(lecture, rel=1e-3)
