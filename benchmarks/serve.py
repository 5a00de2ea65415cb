"""What the server sends each browser: bytes per second and frames per second, per scene and client count.

Connects N websocket clients on 127.0.0.1 (viser's protocol, as the page's script; no browser), lets
each scene run at 1× for a few seconds while every client reads continuously, and writes a table to
``benchmarks/results/serve.md``: bytes/s per client, frames/s the loop drew, the server's CPU time per
second and its peak resident memory. Bounded: a few seconds per row, traffic to 127.0.0.1 only.

Only the shared mode exists today (presenter and private sessions are not built yet).

Run: python -m benchmarks.serve [--clients 1 10 30] [--seconds 4]
"""

from __future__ import annotations

import argparse
import contextlib
import resource
import threading
import time
from pathlib import Path

from app.scenes import scene_names
from tests.harness import raw_client, running_app

RESULTS = Path(__file__).resolve().parent / "results" / "serve.md"


def measure(scene: str, n_clients: int, seconds: float) -> dict[str, float]:
    """One row: ``n_clients`` read for ``seconds`` while ``scene`` plays at 1×."""
    with running_app(scene) as app, contextlib.ExitStack() as stack:
        clients = [stack.enter_context(raw_client(app)) for _ in range(n_clients)]
        received = [0] * n_clients
        stop = threading.Event()

        def read(i: int) -> None:
            while not stop.is_set():
                try:
                    received[i] += len(clients[i].recv(timeout=0.1))
                except TimeoutError:
                    continue

        time.sleep(1.0)  # the first scene messages (meshes, GUI) are not a frame's cost
        readers = [threading.Thread(target=read, args=(i,), daemon=True) for i in range(n_clients)]
        for r in readers:
            r.start()
        time.sleep(0.5)
        base_bytes, frames0, cpu0, t0 = list(received), app.frames, time.process_time(), time.monotonic()
        time.sleep(seconds)
        elapsed = time.monotonic() - t0
        sent = [received[i] - base_bytes[i] for i in range(n_clients)]
        frames, cpu = app.frames - frames0, time.process_time() - cpu0
        stop.set()
        for r in readers:
            r.join(timeout=2.0)
    return {
        "bytes_per_s": sum(sent) / n_clients / elapsed,
        "frames_per_s": frames / elapsed,
        "cpu": cpu / elapsed,
        "rss_mb": resource.getrusage(resource.RUSAGE_SELF).ru_maxrss / 1024,
    }


def main(argv: list[str] | None = None) -> None:
    parser = argparse.ArgumentParser(description=__doc__.splitlines()[0])
    parser.add_argument("--clients", type=int, nargs="+", default=[1, 10])
    parser.add_argument("--seconds", type=float, default=4.0)
    args = parser.parse_args(argv)
    lines = [
        "# Serve benchmark: what each browser receives (shared mode)",
        "",
        f"`python -m benchmarks.serve --clients {' '.join(map(str, args.clients))} --seconds {args.seconds:g}`; "
        "websocket clients on 127.0.0.1 reading continuously; the scene plays at 1×. CPU is the whole "
        "process (server, loop and the test clients) per second of wall time; RSS is the process's peak.",
        "",
        "| scene | clients | kB/s per client | frames/s | CPU s/s | peak RSS (MB) |",
        "| --- | ---: | ---: | ---: | ---: | ---: |",
    ]
    for n in args.clients:
        for scene in scene_names():
            row = measure(scene, n, args.seconds)
            line = (
                f"| {scene} | {n} | {row['bytes_per_s'] / 1e3:.1f} | {row['frames_per_s']:.1f} | "
                f"{row['cpu']:.2f} | {row['rss_mb']:.0f} |"
            )
            print(line, flush=True)
            lines.append(line)
    RESULTS.parent.mkdir(parents=True, exist_ok=True)
    RESULTS.write_text("\n".join(lines) + "\n")
    print(f"written {RESULTS}")


if __name__ == "__main__":
    main()
