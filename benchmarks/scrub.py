"""What a frame of scrubbing costs the server: a drag of the timeline to a random instant, then the frame
drawn there, headless (no browser; messages are still serialised and queued).

Per scene: the CPU time (``time.process_time``, best of several runs) of ``Timeline.seek`` plus the frame
at that instant, over scrubs to instants drawn uniformly over the span played (the friction top: until it
comes to rest on the table, since at rest a step is free; its history recomputes up to 59 steps from a
checkpoint; an exact scene evaluates its closed form), and the
friction top's history memory (``SteppedHistory.nbytes``). A scrub at 30 frames/s has 33 ms.

Writes ``benchmarks/results/scrub.md``.
Run: ``python -m benchmarks.scrub`` (``--scrubs N``, ``--repeats N``, ``--played S``).
"""

from __future__ import annotations

import argparse
import time
from pathlib import Path

import numpy as np

CASES = [
    ("heavy_top", None, "heavy top, exact"),
    ("heavy_top", "sleeping top with friction: falls", "heavy top with friction (stepped history)"),
    ("tennis_racket", None, "tennis racket"),
    ("pendulum", None, "physical pendulum"),
    ("wobble", None, "torque-free wobble"),
]
BUDGET_MS = 1000.0 / 30.0


def measure(app, scene: str, preset: str | None, played: float, scrubs: int, repeats: int) -> tuple[float, int, float]:
    """Best-of-``repeats`` mean CPU ms of one scrub (seek + frame), the history's bytes (0: none) and the
    span scrubbed over (s: what was played, or until the friction top came to rest)."""
    app.switch_scene(scene)
    if preset:
        assert app.scene.presets.choose(preset), preset
    app.set_speed(10.0)
    app.set_playing(True)
    moving = played  # the friction top lies still once landed: scrubbing there steps nothing
    for _ in range(round(played / 1.0)):  # 1 s of simulated time a frame at 10x
        app.frame(0.1)
        if getattr(app.scene, "landed", False) and moving == played:
            moving = app.time
    sim = app.simulation
    rng = np.random.default_rng(7)
    best = np.inf
    for _ in range(repeats):
        targets = rng.uniform(0.0, moving, scrubs)
        c0 = time.process_time()
        for t in targets:
            sim.timeline.seek(float(t))
            if not app.frame(1.0 / 60.0):
                raise RuntimeError(f"{scene}: the scrub to {t} s was not drawn")
        best = min(best, (time.process_time() - c0) / scrubs * 1e3)
    history = getattr(app.scene, "history", None)
    return float(best), int(history.nbytes) if history is not None and preset else 0, moving


def main(argv: list[str] | None = None) -> str:
    parser = argparse.ArgumentParser(description=__doc__.splitlines()[0])
    parser.add_argument("--scrubs", type=int, default=200)
    parser.add_argument("--repeats", type=int, default=5)
    parser.add_argument("--played", type=float, default=60.0, help="simulated seconds played before scrubbing")
    parser.add_argument("--out", type=Path, default=Path(__file__).parent / "results" / "scrub.md")
    args = parser.parse_args(argv)

    from app.serving.app import App

    app = App(port=0, start_loop=False)
    rows = []
    try:
        for scene, preset, label in CASES:
            rows.append((label, *measure(app, scene, preset, args.played, args.scrubs, args.repeats)))
    finally:
        app.stop()
    lines = [
        f"# A frame of scrubbing, headless\n\n`python -m benchmarks.scrub --scrubs {args.scrubs} --repeats "
        f"{args.repeats} --played {args.played:g}`: {args.played:g} s played at 10×, then {args.scrubs} scrubs to "
        "uniformly drawn instants of it, each `Timeline.seek` and the frame drawn there; CPU time "
        f"(`time.process_time`), best of {args.repeats}. A scrub at 30 frames/s has {BUDGET_MS:.1f} ms.",
        "",
        "| scene | span scrubbed (s) | CPU per scrub (ms) | frames/s it allows | history bytes |",
        "| --- | ---: | ---: | ---: | ---: |",
    ]
    lines += [f"| {label} | {span:.0f} | {ms:.2f} | {1e3 / ms:,.0f} | {nbytes:,} |" for label, ms, nbytes, span in rows]
    table = "\n".join(lines) + "\n"
    print(table)
    args.out.parent.mkdir(parents=True, exist_ok=True)
    args.out.write_text(table)
    return table


if __name__ == "__main__":
    main()
