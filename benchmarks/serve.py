"""What the server sends each browser, in each way of serving: bytes/s, updates/s, server CPU and memory.

The server runs in this process; N websocket clients (viser's protocol, as the page's script; no
browser) run in a second process so that reading does not compete with the server for this process's
GIL. Each row lets a scene play at 1× for a few seconds while every client reads continuously, and
reports per client the bytes/s and the updates/s it received (websocket messages: viser sends one per
window of at most 1/60 s, so this is the frame rate a page can show), the slowest client's updates/s,
the server's CPU time per second of wall time and its peak resident memory.

Modes: ``shared`` (one simulation everyone drives), ``presenter`` (one lecture, every client follows
read-only), ``private`` (one simulation per client). Every scene gets a row with one client and rows with
30 followers and 30 private sessions; the ``--scene`` gets every client count in every mode. Bounded: a few seconds per row, traffic to
127.0.0.1 only. Writes ``benchmarks/results/serve.md``.

Run: python -m benchmarks.serve [--clients 1 10 30 60] [--seconds 4]
"""

from __future__ import annotations

import argparse
import multiprocessing as mp
import resource
import threading
import time
from pathlib import Path
from typing import Any

from app.scenes import scene_names
from tests.harness import running_app

RESULTS = Path(__file__).resolve().parent / "results" / "serve.md"
WARMUP = 1.5  # s: the first messages (meshes, the panel) are not a frame's cost


def _clients(port: int, n: int, seconds: float, out: Any) -> None:
    """In a child process: connect ``n`` clients, read for WARMUP + ``seconds``, report per-client totals."""
    import contextlib

    from tests.harness import raw_client

    class _Port:  # raw_client needs .port and a server to ask for its clients: skip that wait here
        def __init__(self) -> None:
            self.port = port

    counts = [[0, 0] for _ in range(n)]  # bytes, messages after the warm-up
    stop = threading.Event()
    measuring = threading.Event()

    def read(ws: Any, i: int) -> None:
        while not stop.is_set():
            try:
                message = ws.recv(timeout=0.1)
            except TimeoutError:
                continue
            except Exception:  # noqa: BLE001 - a closed connection is reported as no traffic
                return
            if measuring.is_set():
                counts[i][0] += len(message)
                counts[i][1] += 1

    with contextlib.ExitStack() as stack:
        sockets = [stack.enter_context(raw_client(_Port(), wait=False)) for _ in range(n)]
        readers = [threading.Thread(target=read, args=(ws, i), daemon=True) for i, ws in enumerate(sockets)]
        for r in readers:
            r.start()
        time.sleep(WARMUP)
        measuring.set()
        t0 = time.monotonic()
        time.sleep(seconds)
        measuring.clear()
        elapsed = time.monotonic() - t0
        stop.set()
        for r in readers:
            r.join(timeout=2.0)
    out.put([(b / elapsed, m / elapsed) for b, m in counts])


def measure(scene: str, mode: str, n_clients: int, seconds: float) -> dict[str, float]:
    """One row: ``n_clients`` read for ``seconds`` while ``scene`` plays at 1× in ``mode``."""
    with running_app(scene, private=mode == "private", presenter=mode == "presenter") as app:
        ctx = mp.get_context("spawn")
        out = ctx.Queue()
        child = ctx.Process(target=_clients, args=(app.port, n_clients, seconds, out), daemon=True)
        child.start()
        deadline = time.monotonic() + 60
        while len(app.server.get_clients()) < n_clients and time.monotonic() < deadline:
            time.sleep(0.05)
        time.sleep(WARMUP)
        cpu0, t0 = time.process_time(), time.monotonic()
        time.sleep(seconds)
        cpu = (time.process_time() - cpu0) / (time.monotonic() - t0)
        per_client = out.get(timeout=60 + seconds)
        child.join(timeout=10)
    rates = [u for _, u in per_client]
    return {
        "bytes_per_s": sum(b for b, _ in per_client) / n_clients,
        "updates_per_s": sum(rates) / n_clients,
        "slowest_updates_per_s": min(rates),
        "cpu": cpu,
        "rss_mb": resource.getrusage(resource.RUSAGE_SELF).ru_maxrss / 1024,
    }


def _line(scene: str, mode: str, n: int, row: dict[str, float]) -> str:
    return (
        f"| {scene} | {mode} | {n} | {row['bytes_per_s'] / 1e3:.1f} | {row['updates_per_s']:.1f} | "
        f"{row['slowest_updates_per_s']:.1f} | {row['cpu']:.2f} | {row['rss_mb']:.0f} |"
    )


def targets(measured: list[tuple[str, str, int, dict[str, float]]]) -> list[str]:
    """The issue's targets against the rows measured: one line each, with the worst row."""
    out = ["Targets (issue 10):", ""]
    # A scene with nothing moving (the inertia explorer) sends only its 10 Hz readouts: no frame rate to hold.
    still = {scene for scene, mode, n, row in measured if (mode, n) == ("shared", 1) and row["updates_per_s"] < 30}
    checks = [
        ("at most 150 kB/s per browser (one client, every scene)", lambda m, n: n == 1, "bytes_per_s", max, 150e3),
        (
            "30 followers: every browser at least 55 updates/s",
            lambda m, n: m == "presenter" and n == 30,
            "slowest_updates_per_s",
            min,
            55.0,
        ),
        (
            "30 private sessions: each at least 30 updates/s",
            lambda m, n: m == "private" and n == 30,
            "slowest_updates_per_s",
            min,
            30.0,
        ),
    ]
    for what, pick, key, worst, limit in checks:
        rows = [
            (scene, row[key])
            for scene, mode, n, row in measured
            if pick(mode, n) and (key == "bytes_per_s" or scene not in still)
        ]
        if not rows:
            continue
        scene, value = worst(rows, key=lambda r: r[1])
        ok = value <= limit if worst is max else value >= limit
        shown = f"{value / 1e3:.1f} kB/s" if key == "bytes_per_s" else f"{value:.1f}/s"
        out.append(f"- {what}: worst {shown} ({scene}) — {'met' if ok else 'NOT met'}")
    if still:
        out.append(f"- not animated, left out of the frame rates: {', '.join(sorted(still))} (10 Hz readouts only)")
    return out


def main(argv: list[str] | None = None) -> None:
    parser = argparse.ArgumentParser(description=__doc__.splitlines()[0])
    parser.add_argument("--clients", type=int, nargs="+", default=[1, 10, 30, 60])
    parser.add_argument("--modes", nargs="+", default=["shared", "presenter", "private"])
    parser.add_argument("--scene", default="heavy_top", help="the scene of the client-count rows")
    parser.add_argument("--seconds", type=float, default=4.0)
    args = parser.parse_args(argv)
    command = (
        f"python -m benchmarks.serve --clients {' '.join(map(str, args.clients))} "
        f"--modes {' '.join(args.modes)} --scene {args.scene} --seconds {args.seconds:g}"
    )
    lines = [
        "# Serve benchmark: what each browser receives",
        "",
        f"`{command}`. Websocket clients on 127.0.0.1 in a second process, reading continuously; the "
        "scene plays at 1×. Updates/s: websocket messages a client received per second (viser sends at "
        "most one per 1/60 s window: the frame rate a page can show). CPU: the server process's CPU "
        "seconds per second of wall time (2 cores on the machine of record). RSS: the server process's peak.",
        "",
        "| scene | mode | clients | kB/s per client | updates/s per client | slowest client | CPU s/s | peak RSS (MB) |",
        "| --- | --- | ---: | ---: | ---: | ---: | ---: | ---: |",
    ]

    measured: list[tuple[str, str, int, dict[str, float]]] = []

    def run(scene: str, mode: str, n: int) -> None:
        row = measure(scene, mode, n, args.seconds)
        measured.append((scene, mode, n, row))
        line = _line(scene, mode, n, row)
        print(line, flush=True)
        lines.append(line)

    for scene in scene_names():  # every scene: bandwidth to one browser, 30 followers, 30 private sessions
        run(scene, "shared", 1)
        for mode in ("presenter", "private"):
            if mode in args.modes and 30 in args.clients and scene != args.scene:
                run(scene, mode, 30)
    for mode in args.modes:
        for n in args.clients:
            if (mode, n) != ("shared", 1) or args.scene not in scene_names():
                run(args.scene, mode, n)
    lines += ["", *targets(measured)]
    RESULTS.parent.mkdir(parents=True, exist_ok=True)
    RESULTS.write_text("\n".join(lines) + "\n")
    print(f"written {RESULTS}")


if __name__ == "__main__":
    main()
