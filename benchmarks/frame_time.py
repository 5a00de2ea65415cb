"""Frame time of the app, headless: median and p99 milliseconds per frame over 1,000 frames per scene.

A frame is what the real-time loop does 60 times a second: advance the clock, ask the scene's model for
the state (exact closed form, or integrator steps with friction), check it for NaN, and update the kept
viser handles inside ``server.atomic()``. No browser is connected (messages are still serialised and
queued), so this measures the server's Python work, the budget the issue sets (median <= 2 ms).

Run: ``python -m benchmarks.frame_time`` (``--frames N``, ``--out PATH`` for the markdown table).
"""

from __future__ import annotations

import argparse
import os
import platform
import time
from pathlib import Path

import numpy as np

CASES = [
    ("heavy_top", None, "heavy top, exact (cusps)"),
    ("heavy_top", "loops (φ̇0 = −1 × steady)", "heavy top, exact (loops)"),
    ("heavy_top", "sleeping top with friction: falls", "heavy top, friction (Blanes–Moan 6 steps)"),
    ("wobble", None, "torque-free wobble"),
    ("free_fall", None, "body in free fall"),
    ("pendulum", None, "physical pendulum"),
    ("tennis_racket", None, "tennis racket"),
    ("tennis_racket", "ghost", "tennis racket + Yoshida 6 ghost (h = 5 ms)"),
    ("tennis_racket", "ghost:Sofroniou", "tennis racket + Sofroniou–Spaletta 10 ghost (h = 5 ms)"),
    ("inertia_explorer", None, "inertia explorer (static: a frame redraws only after a change)"),
]

STATIC = {"inertia_explorer"}  # a frame there draws nothing unless a control changed


def measure(app, scene: str, preset: str | None, frames: int, warmup: int = 60) -> np.ndarray:
    app.switch_scene(scene)
    app.set_playing(True)
    app.set_speed(1.0)
    if preset is not None and preset.startswith("ghost"):  # "ghost" (Yoshida 6) or "ghost:<word of its label>"
        ghost = app.scene.ghost
        ghost.step_slider.value = 0.005
        word = preset.partition(":")[2] or "Yoshida"
        ghost.choice.value = next(label for label in ghost.choice.options if word in label)
    elif preset:
        assert app.scene.presets.choose(preset), preset
    for _ in range(warmup):
        app.frame(1.0 / 60.0)
    wall, cpu = np.empty(frames), np.empty(frames)
    for i in range(frames):
        t0, c0 = time.perf_counter(), time.thread_time()
        drawn = app.frame(1.0 / 60.0)
        wall[i], cpu[i] = time.perf_counter() - t0, time.thread_time() - c0
        if not drawn and scene not in STATIC:
            raise RuntimeError(f"{scene}: frame {i} was not drawn ({app.messages[-1:]})")
    return wall * 1e3, cpu * 1e3


def main(argv: list[str] | None = None) -> str:
    parser = argparse.ArgumentParser(description=__doc__.splitlines()[0])
    parser.add_argument("--frames", type=int, default=1000)
    parser.add_argument("--out", type=Path, default=Path(__file__).parent / "results" / "frame_time.md")
    args = parser.parse_args(argv)

    from app.serving.app import App

    app = App(port=0, start_loop=False)
    rows = []
    try:
        for scene, preset, label in CASES:
            ms, cpu = measure(app, scene, preset, args.frames)
            rows.append(
                (
                    label,
                    float(np.median(ms)),
                    float(np.percentile(ms, 99)),
                    float(ms.max()),
                    float(np.median(cpu)),
                    float(np.percentile(cpu, 99)),
                )
            )
    finally:
        app.stop()
    lines = [
        f"Frame time, headless, {args.frames} frames per scene at 60 fps simulation steps "
        f"(`python -m benchmarks.frame_time`; {platform.python_implementation()} {platform.python_version()}, "
        f"{platform.machine()}).",
        "",
        f"Load average when measured: {os.getloadavg()[0]:.1f} on {os.cpu_count()} CPUs. Wall time includes waiting "
        "for a CPU; the loop thread's own CPU time (`time.thread_time`) does not.",
        "",
        "| scene | median (ms) | p99 (ms) | max (ms) | CPU median (ms) | CPU p99 (ms) |",
        "| --- | ---: | ---: | ---: | ---: | ---: |",
    ]
    lines += [
        f"| {label} | {med:.2f} | {p99:.2f} | {mx:.2f} | {cm:.2f} | {c99:.2f} |"
        for label, med, p99, mx, cm, c99 in rows
    ]
    table = "\n".join(lines) + "\n"
    print(table)
    args.out.parent.mkdir(parents=True, exist_ok=True)
    args.out.write_text(table)
    return table


if __name__ == "__main__":
    main()
