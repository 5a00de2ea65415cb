"""Frames per second each scene draws in headless Chromium at 1280×800: what a software-rendering page
(SwiftShader, no GPU: the tests' Chromium, a slow phone) can show.

For each scene an app is started on 127.0.0.1 (no loop thread: this script drives its frames at 60 per
second of wall time, after first playing ``--prefill`` frames headless so that traces are full, as after a
minute of watching), one page is opened in Debian's Chromium (Playwright) at one pixel per CSS pixel
(``?fixedDpr=1``), and the page counts its WebGL renders for ``--seconds`` (viser's page renders on demand:
after a message that changed the scene, and once a second). Chromium's CPU a render (all its processes, from
/proc) is the steadier figure on a shared machine. Best of ``--runs`` runs per scene. Results are kept by ``--label`` in ``benchmarks/results/browser_frames.json``, so a run "before" a
change and one "after" it land side by side in ``browser_frames.md`` and ``browser_frames.png``.

Run: python -m benchmarks.browser_frames [--label after] [--seconds 8] [--runs 3] [--scenes heavy_top ...]
"""

from __future__ import annotations

import argparse
import contextlib
import json
import os
import platform
import socket
import threading
import time
from collections.abc import Callable, Iterator
from pathlib import Path
from typing import Any

RESULTS = Path(__file__).resolve().parent / "results"
CHROMIUM = "/usr/bin/chromium"
CHROMIUM_ARGS = ["--headless", "--no-sandbox", "--disable-gpu", "--no-first-run", "--disable-background-networking"]
SCENES = ["heavy_top", "wobble", "free_fall", "pendulum", "tennis_racket", "inertia_explorer"]
VIEWPORT = {"width": 1280, "height": 800}

COUNT_RENDERS = """(() => {
  // viser's page renders on demand (a message that changes the scene, a 1 s heartbeat): a render is counted
  // where three.js begins it, at its clear of the canvas.
  window.rblRenders = 0;
  for (const gl of [WebGLRenderingContext, WebGL2RenderingContext]) {
    const clear = gl.prototype.clear;
    gl.prototype.clear = function (mask) { window.rblRenders += 1; return clear.call(this, mask); };
  }
})();"""
"""An init script counting the page's WebGL renders in ``window.rblRenders``."""

RENDERS_IN = """(ms) => new Promise((resolve) => {
  const start = window.rblRenders, t0 = performance.now();
  setTimeout(() => resolve([window.rblRenders - start, performance.now() - t0]), ms);
})"""
"""Renders the page draws in ``ms`` milliseconds, and the milliseconds that took."""


def _free_port() -> int:
    with socket.socket(socket.AF_INET, socket.SOCK_STREAM) as s:
        s.bind(("127.0.0.1", 0))
        return int(s.getsockname()[1])


def chromium_seconds() -> float:
    """CPU seconds (user + system) used so far by this process's descendants that are Chromium's (read from
    /proc): the browser, its renderers and its GPU process, where SwiftShader draws."""
    tick = os.sysconf("SC_CLK_TCK")
    parent, cpu, name = {}, {}, {}
    for stat in Path("/proc").glob("[0-9]*/stat"):
        with contextlib.suppress(OSError, ValueError, IndexError):
            text = stat.read_text()
            fields = text[text.rindex(")") + 2 :].split()
            pid = int(stat.parent.name)
            parent[pid], cpu[pid] = int(fields[1]), (int(fields[11]) + int(fields[12])) / tick
            name[pid] = text[text.index("(") + 1 : text.rindex(")")]
    me, total = os.getpid(), 0.0
    for pid in cpu:
        ancestor = parent.get(pid)
        while ancestor not in (None, 0, 1, me):
            ancestor = parent.get(ancestor)
        if ancestor == me and "chrom" in name[pid].lower():
            total += cpu[pid]
    return total


@contextlib.contextmanager
def watched(
    browser: Any,
    scene: str,
    prefill: int,
    after_frame: Callable[[Any], None] | None = None,
    viewport: dict[str, int] = VIEWPORT,
) -> Iterator[Any]:
    """An app on 127.0.0.1 showing ``scene`` after ``prefill`` frames played headless, then playing at 60 frames
    a second of wall time (``after_frame(app)`` after each, under the app's lock), and a page showing it at
    ``viewport`` (1280×800) that counts its renders; yields ``(app, page)``, everything stopped afterwards."""
    from app.serving.app import App

    app = App(host="127.0.0.1", port=_free_port(), scene=scene, start_loop=False)
    shared = app.shared  # the one simulation every page follows: its lock is the frame loop's
    assert shared is not None
    stop = threading.Event()

    def play() -> None:
        while not stop.is_set():
            with shared.lock:
                app.frame(1.0 / 60.0)
                if after_frame is not None:
                    after_frame(app)
            time.sleep(1.0 / 60.0)

    player = threading.Thread(target=play, daemon=True)
    context = None
    try:
        app.set_playing(True)
        for _ in range(prefill):
            app.frame(1.0 / 60.0)
        context = browser.new_context(viewport=viewport)
        context.add_init_script(COUNT_RENDERS)
        page = context.new_page()
        # One pixel per CSS pixel throughout: viser's adaptive resolution would otherwise change what a render
        # costs while it is measured.
        page.goto(f"{app.url}/?fixedDpr=1", wait_until="domcontentloaded")
        page.wait_for_selector("canvas", timeout=120_000)
        player.start()
        yield app, page
    finally:
        stop.set()
        if player.is_alive():
            player.join()
        if context is not None:
            context.close()
        app.stop()


def rate_and_cost(page: Any, seconds: float, settle: float) -> tuple[float, float]:
    """After ``settle`` s, the page's renders a second over ``seconds`` s and Chromium's CPU ms a render."""
    page.evaluate(RENDERS_IN, settle * 1000)
    cpu = chromium_seconds()
    frames, ms = page.evaluate(RENDERS_IN, seconds * 1000)
    frames = max(frames, 1)
    return 1000.0 * frames / ms, 1000.0 * (chromium_seconds() - cpu) / frames


def frames_per_second(browser: Any, scene: str, seconds: float, prefill: int) -> tuple[float, float]:
    """One run: renders per second a fresh page draws of ``scene`` while the app plays at 60 frames/s, and
    Chromium's CPU milliseconds a render (all its processes: on a shared machine the frame rate depends on the
    load, the CPU a render costs much less)."""
    with watched(browser, scene, prefill) as (_, page):
        return rate_and_cost(page, seconds, settle=3.0)  # the scene's nodes arrive and compile first


def _hide_by_name(app: object, name: str) -> None:
    """Hide the scene node ``name`` by adding an empty, hidden node in its place (public API only)."""
    app.server.scene.add_frame(name, show_axes=False, visible=False)  # type: ignore[attr-defined]


def _hide_arrows(scene: object) -> None:
    """Hide the heavy top's arrows and their labels (an arrow resends its visibility only when it changes)."""
    for arrow in (scene.L_arrow, scene.omega_arrow, scene.torque_arrow):  # type: ignore[attr-defined]
        arrow.handle.visible = False
        if arrow.label is not None:
            arrow.label.visible = False


BREAKDOWN = [
    ("the trace", lambda app: app.shared.scene.trace.clear()),
    ("the faint sphere", lambda app: _hide_by_name(app, "/scene/sphere")),
    ("its equator", lambda app: _hide_by_name(app, "/scene/sphere_equator")),
    ("the grid", lambda app: _hide_by_name(app, "/grid")),
    ("L, ω, τ and labels", lambda app: _hide_arrows(app.shared.scene)),
    ("the top", lambda app: setattr(app.shared.scene.body.handle, "visible", False)),
]
"""What the heavy top's page draws, in the order :func:`breakdown` takes it away (the trace, cleared, is cleared
again after every frame: the top goes on moving)."""


def breakdown(browser: Any, seconds: float, prefill: int) -> list[tuple[str, float, float]]:
    """The heavy top's page at 1280×800 while playing: renders/s and Chromium CPU ms a render with everything,
    then with each of :data:`BREAKDOWN` taken away in turn (cumulatively)."""
    hidden: list[str] = []

    def keep_the_trace_empty(app: Any) -> None:
        if "the trace" in hidden:
            app.shared.scene.trace.clear()  # it would fill again as the top moves on

    rows = []
    with watched(browser, "heavy_top", prefill, keep_the_trace_empty) as (app, page):
        for label, take_away in [("nothing (all drawn)", None), *BREAKDOWN]:
            if take_away is not None:
                with app.shared.lock:
                    take_away(app)
                hidden.append(label)
            rows.append((label, *rate_and_cost(page, seconds, settle=1.5)))
            print(f"without {label:<22} {rows[-1][1]:6.2f} renders/s {rows[-1][2]:6.0f} CPU ms a render", flush=True)
    return rows


def write(results: dict[str, dict[str, dict[str, float]]], note: str) -> str:
    """The markdown table of every label's renders/s and Chromium CPU ms a render by scene, and a bar chart of
    the CPU a render beside it."""
    labels = list(results)
    scenes = [s for s in SCENES if any(s in results[label] for label in labels)]
    lines = [
        "# Frames per second in headless Chromium (software rendering), 1280×800",
        "",
        note,
        "",
        "| scene | " + " | ".join(f"{label}: renders/s | {label}: CPU ms a render" for label in labels) + " |",
        "|---|" + "---:|---:|" * len(labels),
    ]
    for scene in scenes:
        cells = []
        for label in labels:
            row = results[label].get(scene)
            cells += [f"{row['fps']:.2f}", f"{row['cpu_ms']:.0f}"] if row else ["", ""]
        lines.append(f"| {scene} | " + " | ".join(cells) + " |")
    text = "\n".join(lines) + "\n"
    (RESULTS / "browser_frames.md").write_text(text, encoding="utf-8")
    import matplotlib

    matplotlib.use("Agg")
    import matplotlib.pyplot as plt

    fig, ax = plt.subplots(figsize=(9, 4.5))
    width = 0.8 / max(1, len(labels))
    for i, label in enumerate(labels):
        shown = [s for s in scenes if s in results[label]]
        xs = [scenes.index(s) + i * width for s in shown]
        ax.bar(xs, [results[label][s]["cpu_ms"] for s in shown], width, label=label)
    ax.set_xticks([k + 0.4 - width / 2 for k in range(len(scenes))], scenes, rotation=20)
    ax.set_ylabel("Chromium CPU ms a render (least of runs)")
    ax.set_title("Headless Chromium, SwiftShader, 1280×800: the CPU a render costs")
    ax.legend()
    fig.tight_layout()
    fig.savefig(RESULTS / "browser_frames.png", dpi=100)
    plt.close(fig)
    return text


def main(argv: list[str] | None = None) -> str:
    parser = argparse.ArgumentParser(description=__doc__.splitlines()[0])
    parser.add_argument("--label", default="now")
    parser.add_argument("--seconds", type=float, default=8.0)
    parser.add_argument("--runs", type=int, default=3)
    parser.add_argument("--prefill", type=int, default=1800, help="frames played headless before the page opens")
    parser.add_argument("--scenes", nargs="*", default=SCENES)
    parser.add_argument("--breakdown", action="store_true", help="the heavy top's nodes taken away one by one")
    args = parser.parse_args(argv)
    from playwright.sync_api import sync_playwright

    if args.breakdown:
        with sync_playwright() as pw:
            browser = pw.chromium.launch(executable_path=CHROMIUM, args=CHROMIUM_ARGS, headless=True)
            try:
                rows = breakdown(browser, args.seconds, args.prefill)
            finally:
                with contextlib.suppress(Exception):
                    browser.close()
        text = "\n".join(
            [
                "# What a render of the heavy top costs in headless Chromium (software rendering), 1280×800",
                "",
                "Playing, `?fixedDpr=1`; each row takes one more thing away (cumulative). "
                "`python -m benchmarks.browser_frames --breakdown`.",
                "",
                "| without | renders/s | Chromium CPU ms a render |",
                "|---|---:|---:|",
                *(f"| {label} | {fps:.2f} | {cpu:.0f} |" for label, fps, cpu in rows),
            ]
        )
        (RESULTS / "browser_frames_breakdown.md").write_text(text + "\n", encoding="utf-8")
        return text

    store = RESULTS / "browser_frames.json"
    results = json.loads(store.read_text(encoding="utf-8")) if store.is_file() else {}
    measured: dict[str, dict[str, float]] = {}
    with sync_playwright() as pw:
        browser = pw.chromium.launch(executable_path=CHROMIUM, args=CHROMIUM_ARGS, headless=True)
        try:
            for scene in args.scenes:
                runs = [frames_per_second(browser, scene, args.seconds, args.prefill) for _ in range(args.runs)]
                measured[scene] = {"fps": max(r[0] for r in runs), "cpu_ms": min(r[1] for r in runs)}
                print(
                    f"{args.label:>16} {scene:<18} {measured[scene]['fps']:6.2f} renders/s "
                    f"{measured[scene]['cpu_ms']:7.0f} CPU ms a render",
                    flush=True,
                )
        finally:
            with contextlib.suppress(Exception):
                browser.close()
    results[args.label] = {**results.get(args.label, {}), **measured}
    store.write_text(json.dumps(results, indent=1) + "\n", encoding="utf-8")
    note = (
        f"Best of {args.runs} runs of {args.seconds:g} s per scene (most renders/s, least CPU a render: the CPU of "
        f"every Chromium process, read from /proc), after {args.prefill} frames played headless; "
        f"{platform.processor() or platform.machine()}, {os.cpu_count()} cores shared with other work "
        "(renders/s depends on that load, CPU a render much less); `python -m benchmarks.browser_frames --label LABEL`."
    )
    return write(results, note)


if __name__ == "__main__":
    print(main())
