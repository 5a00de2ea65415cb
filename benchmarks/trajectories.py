"""Solve once, evaluate often: CPU time of ``trajectory(...).at(t)`` for one time and for 1,000 times.

For each model (heavy top, free body, physical pendulum) and each of its regimes, the trajectory is
built once; then ``at`` is called with one time (what a frame of the app asks) and with an array of
1,000 times (a plot, an export). CPU time by ``time.process_time``, best of several runs of many calls,
all in one process. Targets: one time ≤ 20 µs, 1,000 times ≤ 2 ms. The time to build the
trajectory (once per initial condition) is shown beside them.

Writes ``benchmarks/results/trajectories.md`` and ``trajectories.png``.
Run: ``python -m benchmarks.trajectories`` (``--repeats N``, ``--out DIR``).
"""

from __future__ import annotations

import argparse
import math
import time
from collections.abc import Callable
from pathlib import Path
from typing import Any

import numpy as np

from physics.free_body import FreeBody
from physics.heavy_top import HeavyTop
from physics.inertia import box
from physics.pendulum import PhysicalPendulum

ONE_TARGET_US = 20.0
MANY_TARGET_MS = 2.0


def cases() -> list[tuple[str, str, Callable[[], Any]]]:
    """(model, regime, build) for every regime the closed forms distinguish."""
    top = HeavyTop(1.0, 0.5, 2.0)
    slow = top.steady_precession_rates(0.5, 10.0)[0]
    pendulum = PhysicalPendulum(box(1.0, [0.1, 0.2, 0.3]), [0.0, 0.0, 0.15], [1.0, 0.0, 0.0])
    w0 = pendulum.omega0
    sep = [1.40625, 1.15625, 1.0]
    return [
        ("heavy top", "nutating (cusps-like)", lambda: top.trajectory(0.5, 0.1, 0.3, 20.0)),
        ("heavy top", "steady precession", lambda: top.trajectory(0.5, 0.0, slow, 20.0 - slow * math.cos(0.5))),
        ("heavy top", "through the pole", lambda: top.trajectory(0.0, 0.8, 0.0, 5.0)),
        ("heavy top", "near the bottom pole", lambda: top.trajectory(3.1, 0.2, 1.0, 3.0)),
        ("heavy top", "sleeping (vertical)", lambda: top.trajectory(0.0, 0.0, 0.0, 5.0)),
        ("free body", "triaxial", lambda: FreeBody([2.0, 1.5, 1.2]).trajectory([1.0, 0.2, 0.3])),
        ("free body", "separatrix 1-m = 1e-14", lambda: FreeBody(sep).trajectory([1.0, -0.3, 1.5 * (1 + 1e-14)])),
        ("free body", "symmetric", lambda: FreeBody([2.0, 1.0, 2.0]).trajectory([0.3, -1.0, 0.7])),
        ("free body", "uniform spin", lambda: FreeBody([2.0, 1.5, 1.2]).trajectory([0.0, -3.0, 0.0])),
        ("pendulum", "libration", lambda: pendulum.trajectory(3.0, 0.0)),
        ("pendulum", "rotation", lambda: pendulum.trajectory(0.0, 5.0 * w0)),
        ("pendulum", "separatrix", lambda: pendulum.trajectory(0.0, 2.0 * w0)),
    ]


def best_cpu(call: Callable[[], Any], number: int, repeats: int) -> float:
    """Least CPU seconds per call over ``repeats`` runs of ``number`` calls."""
    best = math.inf
    for _ in range(repeats):
        start = time.process_time()
        for _ in range(number):
            call()
        best = min(best, (time.process_time() - start) / number)
    return best


def main(argv: list[str] | None = None) -> int:
    parser = argparse.ArgumentParser(description=__doc__.splitlines()[0])
    parser.add_argument("--repeats", type=int, default=7)
    parser.add_argument("--out", type=Path, default=Path(__file__).parent / "results")
    args = parser.parse_args(argv)
    times = np.linspace(-50.0, 50.0, 1000)
    rows = []
    for model, regime, build in cases():
        motion = build()
        build_us = best_cpu(build, 50, args.repeats) * 1e6
        one_us = best_cpu(lambda m=motion: m.at(1.2345), 2000, args.repeats) * 1e6
        many_ms = best_cpu(lambda m=motion: m.at(times), 20, args.repeats) * 1e3
        rows.append((model, regime, build_us, one_us, many_ms))
        print(f"{model:10s} {regime:28s} build {build_us:8.1f} µs  one {one_us:6.1f} µs  1000 {many_ms:6.3f} ms")
    args.out.mkdir(parents=True, exist_ok=True)
    worst_one, worst_many = max(r[3] for r in rows), max(r[4] for r in rows)
    lines = [
        "# Trajectories: solve once, evaluate often",
        "",
        f"`python -m benchmarks.trajectories --repeats {args.repeats}`. CPU time (`time.process_time`), best of "
        f"{args.repeats} runs; one time = `motion.at(1.2345)`, 1,000 times = `motion.at(np.linspace(-50, 50, 1000))`. "
        f"Targets: one time ≤ {ONE_TARGET_US:g} µs, 1,000 times ≤ {MANY_TARGET_MS:g} ms.",
        "",
        f"Worst one time: **{worst_one:.1f} µs** ({'meets' if worst_one <= ONE_TARGET_US else 'misses'} the target); "
        f"worst 1,000 times: **{worst_many:.2f} ms** ({'meets' if worst_many <= MANY_TARGET_MS else 'misses'} it).",
        "",
        "| model | regime | build (µs, once) | one time (µs) | 1,000 times (ms) |",
        "| --- | --- | ---: | ---: | ---: |",
        *(f"| {m} | {r} | {b:.0f} | {o:.1f} | {n:.3f} |" for m, r, b, o, n in rows),
        "",
    ]
    (args.out / "trajectories.md").write_text("\n".join(lines))
    import matplotlib

    matplotlib.use("Agg")
    import matplotlib.pyplot as plt

    fig, (left, right) = plt.subplots(1, 2, figsize=(11, 4.8), sharey=True)
    labels = [f"{m}: {r}" for m, r, *_ in rows]
    y = np.arange(len(rows))
    left.barh(y, [r[3] for r in rows], color="#1f77b4")
    left.axvline(ONE_TARGET_US, color="#d62728", ls="--", label="target")
    left.set_xlabel("one time (µs CPU)")
    left.set_yticks(y, labels)
    left.invert_yaxis()
    left.legend()
    right.barh(y, [r[4] for r in rows], color="#2ca02c")
    right.axvline(MANY_TARGET_MS, color="#d62728", ls="--", label="target")
    right.set_xlabel("1,000 times (ms CPU)")
    right.legend()
    fig.suptitle("trajectory(...).at(t): cost per call")
    fig.tight_layout()
    fig.savefig(args.out / "trajectories.png", dpi=110)
    plt.close(fig)
    print(f"written {args.out / 'trajectories.md'}")
    return 0


if __name__ == "__main__":
    raise SystemExit(main())
