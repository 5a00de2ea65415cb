"""Soak: browsers join and leave for a long time; the server's memory must stay flat.

One server in this process (presenter or private mode) plays the heavy top while websocket clients on
127.0.0.1 join, read for a moment, (in presenter mode) explore on their own and come back, and leave,
a few at a time, for ``--minutes``. Every minute the server's resident memory (``/proc/self/statm``),
the number of sessions and connected clients, and the size of viser's broadcast buffer are written to
``benchmarks/results/soak.md``. Bounded by ``--minutes``; traffic to 127.0.0.1 only.

Run: python -m benchmarks.soak [--minutes 60] [--mode presenter]
"""

from __future__ import annotations

import argparse
import contextlib
import os
import random
import time
from pathlib import Path

from tests.harness import drain, raw_client, running_app, send_value, wait_for

RESULTS = Path(__file__).resolve().parent / "results" / "soak.md"
SEED = 20261124


def resident_mb() -> float:
    """This process's resident memory now, MB (Linux)."""
    pages = int(Path("/proc/self/statm").read_text().split()[1])
    return pages * os.sysconf("SC_PAGE_SIZE") / 1e6


def main(argv: list[str] | None = None) -> None:
    parser = argparse.ArgumentParser(description=__doc__.splitlines()[0])
    parser.add_argument("--minutes", type=float, default=60.0)
    parser.add_argument("--mode", choices=["presenter", "private"], default="presenter")
    args = parser.parse_args(argv)
    rng = random.Random(SEED)
    rows: list[str] = []
    joins = 0
    with running_app("heavy_top", presenter=args.mode == "presenter", private=args.mode == "private") as app:
        start = time.monotonic()
        next_sample = start
        while time.monotonic() - start < args.minutes * 60.0:
            with contextlib.ExitStack() as stack:
                sockets = [stack.enter_context(raw_client(app)) for _ in range(rng.randint(1, 4))]
                joins += len(sockets)
                if args.mode == "presenter":
                    wait_for(lambda: len(app.classroom._panels) >= len(sockets), what="the panels")  # noqa: B023
                    for panel in list(app.classroom._panels.values())[: len(sockets) // 2 + 1]:
                        send_value(sockets[0], panel.explore._impl.uuid, True)
                t_end = time.monotonic() + rng.uniform(0.5, 2.0)
                while time.monotonic() < t_end:
                    for ws in sockets:
                        drain(ws)
                    time.sleep(0.05)
            wait_for(lambda: not app.server.get_clients(), timeout=30, what="every client to leave")
            if time.monotonic() >= next_sample:
                next_sample += 60.0
                buffer = len(app.server._websock_server._broadcast_buffer.message_from_id)
                row = (
                    f"| {(time.monotonic() - start) / 60:.0f} | {joins} | {resident_mb():.1f} | "
                    f"{len(app.sessions)} | {len(app.server.get_clients())} | {buffer} |"
                )
                print(row, flush=True)
                rows.append(row)
                _write(args, rows, (time.monotonic() - start) / 60.0)  # kept after every sample


def _write(args: argparse.Namespace, rows: list[str], minutes: float) -> None:
    RESULTS.parent.mkdir(parents=True, exist_ok=True)
    first, last = rows[0].split("|")[3], rows[-1].split("|")[3]
    RESULTS.write_text(
        "\n".join(
            [
                f"# Soak: {minutes:.0f} of {args.minutes:g} minutes of joins and leaves ({args.mode} mode)",
                "",
                f"`python -m benchmarks.soak --minutes {args.minutes:g} --mode {args.mode}`: 1 to 4 websocket "
                "clients at a time join, read for 0.5 to 2 s"
                + (", half of them explore on their own" if args.mode == "presenter" else "")
                + ", and leave; the heavy top plays throughout. Sampled once a minute, after everyone left.",
                "",
                f"Resident memory: {first.strip()} MB at the first sample, {last.strip()} MB at the last.",
                "",
                "| minute | joins so far | server RSS (MB) | sessions left | clients left | broadcast buffer (messages) |",
                "| ---: | ---: | ---: | ---: | ---: | ---: |",
                *rows,
            ]
        )
        + "\n"
    )
    print(f"written {RESULTS}")


if __name__ == "__main__":
    main()
