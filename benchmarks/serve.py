"""What the server sends each browser, in each way of serving: bytes/s, frames/s, server CPU and memory.

The server runs in this process; N websocket clients (viser's protocol, as the page's script; no
browser) run in a second process so that reading does not compete with the server for this process's
GIL. Each row lets a case play at 1× for a few seconds while every client reads continuously, and
reports per client the bytes/s it received and its frames/s: the websocket messages that carry the pose
of the case's body (``SetOrientationMessage`` / ``SetPositionMessage`` for its node, which the loop
sends once per drawn frame when the body moved, :mod:`app.guards.wire`). A message without it (a 10 Hz
readout, a plot, a notification) is not a frame. Per row: the median and the largest bytes/s, the
slowest client's and the median client's frames/s, the websocket messages/s, the server's CPU time per
second of wall time and its resident memory.

Cases: every scene as it opens, and the two heaviest: the friction top (the heavy top stepped with spin
friction, its preset "sleeping top with friction: falls") and the heavy top with its integrator ghost on
("Compare with integrator": classical RK4 at the smallest step, h = 0.002 s). Modes: ``shared`` (one
simulation everyone drives), ``presenter`` (one lecture, every client follows read-only), ``private``
(one simulation per client). Every case gets a row with one client and rows with ``--crowd`` (30)
clients in presenter and private mode (the heavy cases in shared mode too); ``--scene`` gets every
client count in every mode. Bounded: a few seconds per row, traffic to 127.0.0.1 only. Writes
``benchmarks/results/serve.md`` (or ``--out``).

Run: python -m benchmarks.serve [--clients 1 10 30 60] [--crowd 30] [--seconds 4] [--cases ...] [--out PATH]
"""

from __future__ import annotations

import argparse
import multiprocessing as mp
import os
import statistics
import time
from collections import Counter
from collections.abc import Callable
from dataclasses import dataclass, field
from pathlib import Path
from typing import Any

from app.scenes import load_all, scene_names
from app.teaching.questions import Ask
from benchmarks.serve_clients import WARMUP, read_clients
from benchmarks.soak import resident_mb
from physics.integrators.warm import warm
from tests.harness import running_app

RESULTS = Path(__file__).resolve().parent / "results" / "serve.md"
MODES = ("shared", "presenter", "private")


# ------------------------------------------------------------------------------------------ the cases
@dataclass(frozen=True)
class Case:
    """What a row plays: a scene, optionally a preset chosen and controls set (then every simulation of the
    row starts from the state text this makes: ``App(state=...)``, in private mode each session)."""

    name: str  # on the command line and in the table
    scene: str
    preset: str | None = None
    controls: dict[str, Any] = field(default_factory=dict)  # label -> value, set after the preset
    restart: bool = False  # restart the clock once every client is connected (see FRICTION)
    heavy: bool = False  # rows in shared mode with a crowd too
    check: Callable[[Any], str | None] | None = None  # why a simulation's scene is not this case, or None
    question: bool = False  # presenter mode: a class question open on every follower's panel during the row


def _friction_check(scene: Any) -> str | None:
    if scene.values["friction"] <= 0.0:
        return "no spin friction"
    return "the top landed during the row (no frames once it lies on the table)" if scene.landed else None


def _ghost_check(scene: Any) -> str | None:
    return None if scene.ghost.method is not None else "the ghost is off"


GHOST_METHOD = "classical RK4 (not geometric)"
GHOST_STEP = 0.002
FRICTION_PRESET = "sleeping top with friction: falls"

FRICTION = Case(
    "friction_top",
    "heavy_top",
    preset=FRICTION_PRESET,
    # It sleeps, then falls and lies still at t ≈ 16 s: the shared clock restarts when everyone is connected,
    # so the row measures 0 < t < WARMUP + seconds (a private session starts when its browser connects).
    restart=True,
    heavy=True,
    check=_friction_check,
)
GHOST = Case(
    "ghost_top",
    "heavy_top",
    controls={"Compare with integrator": GHOST_METHOD, "integrator step h (s)": GHOST_STEP},
    heavy=True,
    check=_ghost_check,
)
QUESTION = Case("question_top", "heavy_top", question=True)
"""The heavy top in presenter mode while the class answers: a question with three choices is put to
the class once every client is connected, and each client's answer is cast, as a lecture step does."""
HEAVY = (FRICTION, GHOST)


def cases() -> list[Case]:
    """Every scene as it opens, then the heavy cases."""
    load_all()
    return [Case(name, name) for name in scene_names()] + list(HEAVY) + [QUESTION]


def case_state(case: Case) -> str | None:
    """The state text a case starts from (None: the scene as it opens), made on a headless app."""
    if case.preset is None and not case.controls:
        return None
    with running_app(case.scene, start_loop=False) as app:
        scene = app.scene
        with app.simulation.lock:
            if case.preset is not None and not scene.presets.choose(case.preset):
                raise RuntimeError(f"{case.name}: preset {case.preset!r} refused: {scene.presets.panel.last_refusal}")
            inputs = {str(h.label): h for h in app.simulation.scene_inputs}
            for label, value in case.controls.items():
                inputs[label].value = value  # runs the control's callback, as a browser's change does
                if inputs[label].value != value:
                    raise RuntimeError(f"{case.name}: {label} = {value!r} refused: {app.messages[-1:]}")
        problem = case.check(scene) if case.check is not None else None
        if problem is not None:
            raise RuntimeError(f"{case.name}: {problem}")
        return app.state_text()


def _body_node(app: Any) -> str:
    """The scene-node name of the body the simulations draw (the same in every session: under /scene)."""
    for simulation in app.simulations():
        body = getattr(simulation.scene, "body", None)
        if body is not None:
            return str(body.handle._impl.name)
    raise RuntimeError("no simulation draws a body")


def _ask_the_class(app: Any) -> None:
    """Put a three-choice question to the class and cast every connected follower's answer."""
    app.questions.ask(Ask("After a few seconds the racket...", ("keeps spinning", "wobbles", "flips")), "benchmark")
    for k, client in enumerate(app.server.get_clients().values()):
        app.questions.vote(client, "ABC"[k % 3])


def _problems(case: Case, app: Any) -> list[str]:
    if case.check is None:
        return []
    found = (case.check(s.scene) for s in app.simulations() if s.scene is not None)
    return sorted({p for p in found if p is not None})


def measure(case: Case, mode: str, n_clients: int, seconds: float, state: str | None = None) -> dict[str, Any]:
    """One row: ``n_clients`` read for ``seconds`` while ``case`` plays at 1× in ``mode``."""
    with running_app(case.scene, private=mode == "private", presenter=mode == "presenter", state=state) as app:
        ctx = mp.get_context("spawn")
        out = ctx.Queue()
        child = ctx.Process(target=read_clients, args=(app.port, n_clients, seconds, out), daemon=True)
        child.start()
        deadline = time.monotonic() + 60
        while len(app.server.get_clients()) < n_clients and time.monotonic() < deadline:
            time.sleep(0.05)
        if mode == "private":  # a session is built as its browser connects
            while len(app.sessions) < n_clients and time.monotonic() < deadline:
                time.sleep(0.05)
        connected = len(app.sessions) if mode == "private" else len(app.server.get_clients())
        if case.restart and mode != "private":
            app.restart()
        if case.question and app.questions is not None:
            _ask_the_class(app)
        problems = _problems(case, app)
        if connected < n_clients:
            problems.append(f"only {connected} of {n_clients} clients connected within 60 s")
        body = _body_node(app)  # now: once the clients leave, a private server has no simulation to ask
        time.sleep(WARMUP)
        cpu0, t0 = time.process_time(), time.monotonic()
        rss = [resident_mb()]
        while time.monotonic() - t0 < seconds:
            time.sleep(min(0.25, max(0.0, seconds - (time.monotonic() - t0))))
            rss.append(resident_mb())
        cpu = (time.process_time() - cpu0) / (time.monotonic() - t0)
        problems += _problems(case, app)
        per_client = out.get(timeout=60 + seconds)
        child.join(timeout=10)
    frames = [nodes.get(body, 0.0) for _, _, nodes, _ in per_client]
    data = [b for b, _, _, _ in per_client]
    for why, count in Counter(why for _, _, _, why in per_client if why).items():
        problems.append(f"{count} of {n_clients} clients lost their connection ({why})")
    silent = sum(1 for b, _, _, why in per_client if b == 0.0 and not why)
    if silent:
        problems.append(f"{silent} of {n_clients} clients received nothing while measured")
    return {
        "bytes_median": statistics.median(data),
        "bytes_max": max(data),
        "frames_min": min(frames),
        "frames_median": statistics.median(frames),
        "messages_median": statistics.median(m for _, m, _, _ in per_client),
        "cpu": cpu,
        "rss_mb": max(rss),
        "body": body,
        "problems": sorted(set(problems)),
    }


# ------------------------------------------------------------------------------------------ the table
HEADER = (
    "| case | mode | clients | kB/s per client (median) | kB/s (largest) | frames/s: slowest client | "
    "frames/s: median client | messages/s (median) | server CPU (s/s) | server RSS (MB) |"
)


def table_line(case: str, mode: str, n: int, row: dict[str, Any]) -> str:
    return (
        f"| {case} | {mode} | {n} | {row['bytes_median'] / 1e3:.1f} | {row['bytes_max'] / 1e3:.1f} | "
        f"{row['frames_min']:.1f} | {row['frames_median']:.1f} | {row['messages_median']:.1f} | "
        f"{row['cpu']:.2f} | {row['rss_mb']:.0f} |"
    )


def targets(measured: list[tuple[str, str, int, dict[str, Any]]], cores: int | None = None) -> list[str]:
    """The issue's targets against the rows measured: one line each, with the worst row."""
    out = ["Targets:", ""]
    # A case whose body never moves (the inertia explorer) sends only its 10 Hz readouts: no frames to count.
    # (A row that received nothing at all is not that: it is listed among the problems below.)
    still = {
        case
        for case, mode, n, row in measured
        if (mode, n) == ("shared", 1) and row["frames_median"] < 1.0 and row["messages_median"] > 0.0
    }
    one = [(case, row) for case, mode, n, row in measured if n == 1]
    if one:
        # "at 60 frames/s": a row that ran slower is scaled up to 60 frames/s (bytes per frame × 60).
        def at_60(row: dict[str, Any]) -> float:
            frames = row["frames_median"]
            return row["bytes_max"] * (60.0 / frames if 1.0 <= frames < 60.0 else 1.0)

        case, row = max(one, key=lambda r: at_60(r[1]))
        value = at_60(row)
        out.append(
            f"- at most 150 kB/s per browser at 60 frames/s (rows with one client): worst "
            f"{row['bytes_max'] / 1e3:.1f} kB/s at {row['frames_median']:.1f} frames/s ({case}), "
            f"{value / 1e3:.1f} kB/s at 60 frames/s — {'met' if value <= 150e3 else 'NOT met'}"
        )
    on = f" on {cores} cores" if cores else ""
    for what, mode, limit in (
        ("30 followers: every browser at least 55 frames/s", "presenter", 55.0),
        (f"30 private sessions{on}: each at least 30 frames/s", "private", 30.0),
    ):
        rows = [(case, row["frames_min"]) for case, m, n, row in measured if (m, n) == (mode, 30) and case not in still]
        if rows:
            case, value = min(rows, key=lambda r: r[1])
            out.append(f"- {what}: slowest {value:.1f} frames/s ({case}) — {'met' if value >= limit else 'NOT met'}")
    if still:
        out.append(f"- no body motion, left out of the frame rates: {', '.join(sorted(still))} (10 Hz readouts only)")
    problems = [f"{case} {mode} {n}: {p}" for case, mode, n, row in measured for p in row.get("problems", [])]
    if problems:
        out += ["", "Rows that did not measure their case as intended:", "", *(f"- {p}" for p in problems)]
    return out


def plan(
    chosen: list[Case], modes: list[str], clients: list[int], crowd: int, scene: str
) -> list[tuple[Case, str, int]]:
    """The rows, in order: each case with one client (shared) and with ``crowd`` clients (presenter and
    private; shared too for a heavy case); the ``scene``'s own case with every client count in every mode."""
    rows: list[tuple[Case, str, int]] = []
    for case in chosen:
        wanted = [("shared", 1)]
        if case.name == scene:
            wanted += [(mode, n) for mode in modes for n in clients]
        elif crowd > 0:
            wanted += [(mode, crowd) for mode in modes if mode != "shared" or case.heavy]
        for mode, n in wanted:
            if (case, mode, n) not in rows:
                rows.append((case, mode, n))
    return rows


def _load(load: tuple[float, float, float]) -> str:
    return " ".join(f"{x:.2f}" for x in load)


def main(argv: list[str] | None = None) -> None:
    every = cases()
    by_name = {c.name: c for c in every}
    parser = argparse.ArgumentParser(description=__doc__.splitlines()[0])
    parser.add_argument("--clients", type=int, nargs="+", default=[1, 10, 30, 60], help="the --scene's client counts")
    parser.add_argument("--crowd", type=int, default=30, help="clients in every other case's crowd rows (0: none)")
    parser.add_argument("--modes", nargs="+", choices=MODES, default=list(MODES))
    parser.add_argument("--scene", default="heavy_top", help="the case with every client count in every mode")
    parser.add_argument("--cases", nargs="+", choices=list(by_name), default=list(by_name))
    parser.add_argument("--seconds", type=float, default=4.0)
    parser.add_argument("--out", type=Path, default=RESULTS)
    args = parser.parse_args(argv)
    chosen = [by_name[name] for name in args.cases]
    command = (
        f"python -m benchmarks.serve --clients {' '.join(map(str, args.clients))} --crowd {args.crowd} "
        f"--modes {' '.join(args.modes)} --scene {args.scene} --seconds {args.seconds:g}"
        + ("" if args.cases == list(by_name) else f" --cases {' '.join(args.cases)}")
    )
    cores = os.cpu_count()
    start_load = os.getloadavg()
    lines = [
        "# Serve benchmark: what each browser receives",
        "",
        f"`{command}`. Websocket clients on 127.0.0.1 in a second process, reading continuously; the case "
        "plays at 1×. Frames/s: the websocket messages a client received per second that carry the pose of "
        "the case's body (viser sends at most one message per 1/60 s window, and the loop draws a frame "
        "inside one window: the frame rate a page can show); messages/s counts every message, frames or "
        "not. kB = 1000 bytes. CPU: the server process's CPU seconds per second of wall time. RSS: the "
        "server process's resident memory, the largest of samples every 0.25 s during the row (one process "
        "runs every row, so it includes what earlier rows left).",
        "",
        f"Cases: a scene's name is the scene as it opens; `{FRICTION.name}`: the heavy top with spin friction "
        f"(preset “{FRICTION_PRESET}”; the shared clock is restarted once every client is connected, so the "
        f"row runs before the top lands at t ≈ 16 s); `{GHOST.name}`: the heavy top with its integrator ghost "
        f"(“Compare with integrator”: {GHOST_METHOD}, h = {GHOST_STEP:g} s); `{QUESTION.name}`: the heavy top "
        "with a class question (three choices) put to the class once every client is connected and every "
        "follower's answer cast (presenter mode; in the other modes there is no class to ask).",
        "",
        "MACHINE",
        "",
        HEADER,
        "| --- | --- | ---: | ---: | ---: | ---: | ---: | ---: | ---: | ---: |",
    ]
    measured: list[tuple[str, str, int, dict[str, Any]]] = []
    states = {case.name: case_state(case) for case in chosen}
    started = time.monotonic()
    warm()  # numba's kernels compiled or loaded now, not in the first row's frames
    for case, mode, n in plan(chosen, args.modes, args.clients, args.crowd, args.scene):
        row = measure(case, mode, n, args.seconds, states[case.name])
        measured.append((case.name, mode, n, row))
        line = table_line(case.name, mode, n, row)
        print(line + "".join(f" ({p})" for p in row["problems"]), flush=True)
        lines.append(line)
    end_load = os.getloadavg()
    lines[lines.index("MACHINE")] = (
        f"Machine: {cores} cores; load average (1, 5, 15 min) {_load(start_load)} at the start, "
        f"{_load(end_load)} at the end (other work on the machine takes cores from the server)."
    )
    lines += ["", *targets(measured, cores), "", f"Run time: {time.monotonic() - started:.0f} s."]
    args.out.parent.mkdir(parents=True, exist_ok=True)
    args.out.write_text("\n".join(lines) + "\n")
    print(f"written {args.out}")


if __name__ == "__main__":
    main()
