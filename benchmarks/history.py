"""What scrubbing a stepped motion costs: memory of the history and CPU time of a seek.

The friction top as the heavy-top scene steps it (``friction_stepper`` with Blanes–Moan 6, gravity and
spin friction, four substeps of 1/240 s per frame at 60 Hz) is played for the kept span into a
:class:`physics.history.SteppedHistory` (``keep`` = 5 minutes), for several checkpoint intervals. Memory:
``nbytes`` (fixed when made) and per simulated minute kept. Seek: CPU time (``time.process_time``, best of
several runs) of a seek to the worst instant (one step before a checkpoint: ``checkpoint_every − 1`` steps
recomputed) and of seeks to random instants of the kept span. A frame of scrubbing at 30 frames/s has
33 ms; the lecture's flip and a top's nutation need the last few seconds, the issue asks for minutes.

Writes ``benchmarks/results/history.md`` and ``history.png``.
Run: ``python -m benchmarks.history`` (about a minute; ``--quick``: a 20 s span, two intervals, one run).
"""

from __future__ import annotations

import argparse
import math
import time
from pathlib import Path

import numpy as np

from physics.euler_angles import euler_attitude, omega_body_from_euler
from physics.heavy_top import HeavyTop, friction_stepper
from physics.history import SteppedHistory, stepper_step
from physics.integrators import BlanesMoan6

RATE = 60  # frames a second
SUBSTEPS = 4  # the scene's steps of at most 1/240 s
FRAME_BUDGET_MS = 1000.0 / 30.0


def measure(every: int, keep: float, repeats: int, seeks: int) -> dict[str, float]:
    """Play ``keep`` seconds of the friction top into a history checkpointed every ``every`` frames; its
    bytes and the CPU time of its seeks."""
    top = HeavyTop(1.0, 0.5, 2.0)
    step = stepper_step(friction_stepper(top, 0.05, method=BlanesMoan6), 1.0 / RATE, SUBSTEPS)
    state0 = np.concatenate(
        [euler_attitude(0.0, 0.5, 0.0).ravel(), top.moments * omega_body_from_euler(0.5, 0.0, 0.1, 0.3, 20.0)]
    )
    step(state0)  # compile the integrator's kernel outside the timings
    history = SteppedHistory(step, state0, 1.0 / RATE, keep=keep, checkpoint_every=every)
    frames = int(round(keep * RATE))
    start = time.process_time()
    history.step_forward(frames)
    play_us = (time.process_time() - start) / frames * 1e6
    # Worst instants: one frame before a checkpoint, in two intervals far apart (each seek recomputes every − 1).
    worst = [((frames // every) // 4 * every + every - 1) / RATE, ((frames // every) * 3 // 4 * every - 1) / RATE]
    rng = np.random.default_rng(0)
    random = rng.integers(0, frames + 1, seeks) / RATE
    best_worst = best_random = math.inf
    for _ in range(repeats):
        t0 = time.process_time()
        for i in range(seeks):
            history.seek(float(worst[i % 2]))
        best_worst = min(best_worst, (time.process_time() - t0) / seeks)
        t0 = time.process_time()
        for t in random:
            history.seek(float(t))
        best_random = min(best_random, (time.process_time() - t0) / seeks)
    minutes = keep / 60.0
    return {
        "every": every,
        "checkpoints": history.capacity,
        "nbytes": history.nbytes,
        "bytes_per_minute": history.nbytes / minutes,
        "worst_ms": best_worst * 1e3,
        "random_ms": best_random * 1e3,
        "play_us": play_us,
    }


def main(argv: list[str] | None = None) -> int:
    parser = argparse.ArgumentParser(description=__doc__.splitlines()[0])
    parser.add_argument("--quick", action="store_true", help="a 20 s span, two intervals, one run")
    parser.add_argument("--repeats", type=int, default=5)
    parser.add_argument("--out", type=Path, default=Path(__file__).parent / "results")
    args = parser.parse_args(argv)
    keep = 20.0 if args.quick else 300.0
    repeats = 1 if args.quick else args.repeats
    intervals = (15, 60) if args.quick else (1, 15, 60, 240)
    seeks = 6 if args.quick else 30
    rows = []
    for every in intervals:
        row = measure(every, keep, repeats, seeks)
        rows.append(row)
        print(
            f"every {every:4d} frames: {row['nbytes']:>10,} B ({row['bytes_per_minute']:,.0f} B/min), worst seek "
            f"{row['worst_ms']:.2f} ms, random {row['random_ms']:.2f} ms, a frame of play {row['play_us']:.0f} µs"
        )
    args.out.mkdir(parents=True, exist_ok=True)
    command = "python -m benchmarks.history" + (" --quick" if args.quick else f" --repeats {repeats}")
    lines = [
        "# History of a stepped motion: memory and seek time",
        "",
        f"`{command}`. The friction top (Blanes–Moan 6, gravity and spin friction, {SUBSTEPS} substeps a frame) "
        f"at {RATE} frames/s, {keep:g} s kept (`SteppedHistory(keep={keep:g})`): a state is 12 float64 (96 B). "
        f"Memory is `nbytes`, fixed when the history is made. Seek: CPU time (`time.process_time`), best of "
        f"{repeats} run(s) of {seeks} seeks; worst = one frame before a checkpoint (checkpoint_every − 1 frames "
        f"recomputed), random = instants drawn over the kept span. A frame of scrubbing at 30 frames/s has "
        f"{FRAME_BUDGET_MS:.0f} ms.",
        "",
        "| checkpoint every (frames) | checkpoints | bytes kept | bytes per simulated minute | worst seek (ms) "
        "| random seek (ms) | a frame of play (µs) |",
        "| ---: | ---: | ---: | ---: | ---: | ---: | ---: |",
        *(
            f"| {r['every']} | {r['checkpoints']:,} | {r['nbytes']:,} | {r['bytes_per_minute']:,.0f} | "
            f"{r['worst_ms']:.2f} | {r['random_ms']:.2f} | {r['play_us']:.0f} |"
            for r in rows
        ),
        "",
    ]
    (args.out / "history.md").write_text("\n".join(lines))
    import matplotlib

    matplotlib.use("Agg")
    import matplotlib.pyplot as plt

    fig, ax = plt.subplots(figsize=(7, 4.5))
    ax.plot([r["bytes_per_minute"] for r in rows], [r["worst_ms"] for r in rows], "o-", label="worst seek")
    ax.plot([r["bytes_per_minute"] for r in rows], [r["random_ms"] for r in rows], "s--", label="random seek")
    for r in rows:
        ax.annotate(f"every {r['every']}", (r["bytes_per_minute"], r["worst_ms"]), fontsize=8)
    ax.axhline(FRAME_BUDGET_MS, color="#d62728", ls=":", label="a frame at 30 frames/s")
    ax.set_xscale("log")
    ax.set_yscale("log")
    ax.set_xlabel("history memory, bytes per simulated minute (60 Hz)")
    ax.set_ylabel("seek, ms CPU")
    ax.set_title("Friction top: memory of the history against the cost of a seek")
    ax.legend()
    fig.tight_layout()
    fig.savefig(args.out / "history.png", dpi=110)
    plt.close(fig)
    print(f"written {args.out / 'history.md'}")
    return 0


if __name__ == "__main__":
    raise SystemExit(main())
