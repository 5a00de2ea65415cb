"""Soak: browsers join and leave for a long time; the server's memory must stay flat.

One server in this process (presenter or private mode) plays the heavy top while websocket clients on
127.0.0.1 join, read for a moment and leave, a few at a time, for ``--minutes``. In presenter mode half
of them explore on their own (a copy of the lecture each); in private mode each has a session of its
own and half of them switch it to another scene. Every ``--every`` seconds (and once at the end), after
everyone has left: the server's resident memory (``/proc/self/statm``), the sessions and connected clients
left, the :class:`app.serving.app.Simulation` objects still alive after a full garbage collection (a session
dropped but still referred to stays alive), and the size of viser's broadcast buffer. The results file
(``benchmarks/results/soak.md``, or ``--out``) is rewritten after every sample, so a run cut short keeps
what it measured; private mode writes ``benchmarks/results/soak_private.md``. Bounded by ``--minutes``;
traffic to 127.0.0.1 only.

Run: python -m benchmarks.soak [--minutes 60] [--mode presenter|private] [--every 60] [--out PATH]
"""

from __future__ import annotations

import argparse
import contextlib
import gc
import os
import random
import time
from collections.abc import Callable
from pathlib import Path
from typing import Any

from tests.harness import drain, raw_client, running_app, send_value, wait_for

RESULTS = Path(__file__).resolve().parent / "results" / "soak.md"
RESULTS_PRIVATE = RESULTS.with_name("soak_private.md")  # private mode's own file: both soaks stay in the repo
SEED = 20261124


def resident_mb() -> float:
    """This process's resident memory now, MB (Linux)."""
    pages = int(Path("/proc/self/statm").read_text().split()[1])
    return pages * os.sysconf("SC_PAGE_SIZE") / 1e6


def settled(count: Callable[[], int], settle: float = 5.0, pause: float = 0.5) -> int:
    """``count()`` once it has fallen to 0, or its last value after ``settle`` seconds: a browser's departure
    is handled on viser's threads a moment after its socket closed, so a sample taken right after everyone
    left gives it that long."""
    deadline = time.monotonic() + settle
    while True:
        n = count()
        if n == 0 or time.monotonic() >= deadline:
            return n
        time.sleep(pause)


def simulations_alive(settle: float = 5.0) -> int:
    """How many :class:`app.serving.app.Simulation` objects (sessions and explorers' copies, not the App) are
    alive after a full collection. A copy can still be in the making for a browser that pressed "Explore"
    just before it left (a worker thread builds it, then drops it): up to ``settle`` seconds are given for
    the count to fall to 0, and the last count is returned."""
    from app.serving.simulation import Simulation

    def alive() -> int:
        gc.collect()
        return sum(1 for o in gc.get_objects() if type(o) is Simulation)

    return settled(alive, settle)


def _join(app: Any, stack: contextlib.ExitStack) -> tuple[Any, Any]:
    """A client that joins (closed when ``stack`` closes); returns its socket and its client id."""
    before = set(app.server.get_clients())
    ws = stack.enter_context(raw_client(app))
    return ws, next(iter(set(app.server.get_clients()) - before))


def _explore(app: Any, ws: Any, client_id: Any) -> None:
    """Presenter mode: the client presses "Explore on my own" in its own panel."""
    wait_for(lambda: client_id in app.classroom._panels, what="the client's panel")
    send_value(ws, app.classroom._panels[client_id].explore._impl.uuid, True)


def _switch(app: Any, ws: Any, client_id: Any, rng: random.Random) -> None:
    """Private mode: the client picks another scene in its own session's panel. A function of its own: no
    reference to the session outlives it (the samples count the sessions still alive)."""
    wait_for(lambda: client_id in app.sessions, what="the client's session")
    picker = app.sessions[client_id].scene_picker
    others = [title for title in picker._impl.props.options if title != picker.value]
    send_value(ws, picker._impl.uuid, rng.choice(others))


def main(argv: list[str] | None = None) -> None:
    parser = argparse.ArgumentParser(description=__doc__.splitlines()[0])
    parser.add_argument("--minutes", type=float, default=60.0)
    parser.add_argument("--mode", choices=["presenter", "private"], default="presenter")
    parser.add_argument("--every", type=float, default=60.0, help="seconds between samples")
    parser.add_argument("--out", type=Path, default=None, help="default: results/soak.md, soak_private.md")
    args = parser.parse_args(argv)
    if args.out is None:
        args.out = RESULTS if args.mode == "presenter" else RESULTS_PRIVATE
    rng = random.Random(SEED)
    rows: list[str] = []
    joins = 0
    with running_app("heavy_top", presenter=args.mode == "presenter", private=args.mode == "private") as app:
        start = time.monotonic()
        next_sample = start

        def sample() -> None:
            rss = resident_mb()  # before the collection below: what the server holds as it runs
            buffer = len(app.server._websock_server._broadcast_buffer.message_from_id)
            clients = settled(lambda: len(app.server.get_clients()), pause=0.05)
            sessions = settled(lambda: len(app.sessions), pause=0.05)  # freed as its browser's departure is handled
            row = (
                f"| {(time.monotonic() - start) / 60:.1f} | {joins} | {rss:.1f} | {sessions} | "
                f"{clients} | {simulations_alive()} | {buffer} |"
            )
            print(row, flush=True)
            rows.append(row)
            _write(args, rows, (time.monotonic() - start) / 60.0)  # kept after every sample

        while time.monotonic() - start < args.minutes * 60.0:
            with contextlib.ExitStack() as stack:
                joined = [_join(app, stack) for _ in range(rng.randint(1, 4))]
                joins += len(joined)
                for ws, client_id in joined[: len(joined) // 2 + 1]:
                    if args.mode == "presenter":
                        _explore(app, ws, client_id)
                    else:
                        _switch(app, ws, client_id, rng)
                t_end = time.monotonic() + rng.uniform(0.5, 2.0)
                while time.monotonic() < t_end:
                    for ws, _ in joined:
                        drain(ws)
                    time.sleep(0.05)
            wait_for(lambda: not app.server.get_clients(), timeout=30, what="every client to leave")
            if time.monotonic() >= next_sample:
                next_sample += args.every
                sample()
        wait_for(lambda: not app.sessions, timeout=30, what="the last sessions to be dropped")
        if not rows or int(rows[-1].split("|")[2]) != joins:
            sample()  # the end, after everyone left (unless the last sample was taken after the last leave)


def _write(args: argparse.Namespace, rows: list[str], minutes: float) -> None:
    args.out.parent.mkdir(parents=True, exist_ok=True)
    rss = [float(row.split("|")[3]) for row in rows]
    what = (
        ", half of them explore on their own (a copy of the lecture each)"
        if args.mode == "presenter"
        else ", each in a session of its own, half of which switch to another scene"
    )
    command = f"python -m benchmarks.soak --minutes {args.minutes:g} --mode {args.mode}"
    if args.every != 60.0:
        command += f" --every {args.every:g}"
    args.out.write_text(
        "\n".join(
            [
                f"# Soak: {minutes:.1f} of {args.minutes:g} minutes of joins and leaves ({args.mode} mode)",
                "",
                f"`{command}`: 1 to 4 websocket clients at a time join, read for 0.5 to 2 s{what}, and leave; "
                f"the heavy top plays throughout. Sampled every {args.every:g} s and at the end, after everyone "
                "left. Simulations alive: Simulation objects (sessions, explorers' copies) still alive after a "
                "full garbage collection, given up to 5 s for one still being built for a browser that just left "
                "(0 when every departed browser's simulation was freed).",
                "",
                f"Resident memory: {rss[0]:.1f} MB at the first sample, {rss[-1]:.1f} MB at the last, "
                f"{max(rss):.1f} MB at most.",
                "",
                "| minute | joins so far | server RSS (MB) | sessions left | clients left | simulations alive | "
                "broadcast buffer (messages) |",
                "| ---: | ---: | ---: | ---: | ---: | ---: | ---: |",
                *rows,
            ]
        )
        + "\n"
    )
    print(f"written {args.out}")


if __name__ == "__main__":
    main()
