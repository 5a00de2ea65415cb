"""Rooms behind nginx: frames/s per simulated browser through the proxy, isolation, and
a pool process killed with SIGKILL.

``rigid-body-lab rooms`` runs in a child process exactly as a department runs it (nginx in front, one
process per room, 127.0.0.2 and 127.0.0.3 standing in for two machines of a private pool). The simulated
browsers are websocket clients speaking viser's protocol (as :mod:`benchmarks.serve`: no browser), in
further processes (two for the pool, one per presenter room: browsers read on their own machines, not
under one GIL), each reading all of its connections on one asyncio event loop (no thread per connection:
they stand in for browsers on other machines, so they take as little of the measured cores as a reader
can); each first gets its room's cookie from nginx as a page load does, then opens ``/ROOM`` with viser's
subprotocol and reads and decodes every message from then on. A frame is
a websocket message that sets the pose of the room's body (:func:`benchmarks.serve_clients.posed_nodes`).

Rows:

1. **pool**: a private room of 2 processes (heavy top), ``--sessions`` (60) browsers: frames/s of the
   slowest and the median browser, and how nginx spread them (sticky by cookie, all from one address).
2. **presenter**: 3 presenter rooms (heavy top, pendulum, tennis racket) with ``--followers`` (30) each:
   frames/s per follower, and isolation — every follower's Scene picker shows its own room's scene and it
   receives no node that only another room draws.
3. **kill**: in the pool of row 1, one process is killed with SIGKILL while every browser reads: the
   longest gap between two frames of the browsers on the other process (before and after the kill),
   where browsers joining during the 5 s after the kill land, and when the killed process answers again.
4. **teacher**: a pool of 2 processes with a teacher PIN, ``--sessions`` browsers: how soon a change on one
   process shows in the table of a teacher on the other, and Redis's traffic (:mod:`benchmarks.rooms_teacher`).

Loopback only, bounded (about three minutes). Writes ``benchmarks/results/rooms.md`` (or ``--out``);
``--teacher-only`` runs row 4 alone and writes ``benchmarks/results/rooms_teacher.md``.

Run: python -m benchmarks.rooms [--sessions 60] [--followers 30] [--seconds 5] [--changes 10] [--teacher-only]
"""

from __future__ import annotations

import argparse
import asyncio
import contextlib
import multiprocessing as mp
import os
import re
import resource
import signal
import statistics
import tempfile
import time
from concurrent.futures import ThreadPoolExecutor
from pathlib import Path
from typing import Any

import msgspec
import zstandard
from websockets.asyncio.client import connect

from app.rooms.supervisor import answers
from app.scenes import REGISTRY, load_all
from benchmarks.rooms_teacher import report_lines, teacher_table
from benchmarks.serve_clients import WARMUP, posed_nodes
from tests.harness import CAMERA_MESSAGE
from tests.rooms.running import SUBPROTOCOL, backend_of, proxied, room_cookie, rooms_file, running_department

RESULTS = Path(__file__).resolve().parent / "results" / "rooms.md"
BODY = {"heavy_top": "/scene/top", "pendulum": "/scene/body", "tennis_racket": "/scene/body"}
"""The node each scene's body is drawn as (``app/scenes/*.py``): its pose messages are the frames."""
PRESENTER_ROOMS = (("mech101", "heavy_top"), ("phys202", "pendulum"), ("sport", "tennis_racket"))
POOL_SCENE = "heavy_top"
GAP_LIMIT = 0.25
"""s: a survivor's longest wait between two frames around the kill that still counts as "no gap" (15
frames at 60 frames/s; the loop itself never pauses that long on an idle machine)."""


# ------------------------------------------------------------------------------------------ the clients
def picker_and_nodes(raw: bytes, state: dict[str, Any]) -> None:
    """Fold one websocket message into ``state``: the Scene picker's value and every node named."""
    inner_size = int.from_bytes(raw[:8], "little")
    compressed = int.from_bytes(raw[8:16], "little")
    inner = zstandard.ZstdDecompressor().decompress(raw[16 : 16 + compressed], max_output_size=inner_size)
    for m in msgspec.msgpack.decode(inner)["messages"]:
        name = m.get("name")
        if isinstance(name, str):
            state["nodes"].add(name)
        if m["type"] == "GuiDropdownMessage" and m.get("props", {}).get("label") == "Scene":
            state["picker"], state["scene"] = m["uuid"], m["value"]
        elif m["type"] == "GuiUpdateMessage" and m.get("uuid") == state.get("picker"):
            state["scene"] = m["updates"].get("value", state.get("scene"))


async def browse(port: int, room: str, body: str, report: dict[str, Any], zstd: Any) -> Any:
    """One browser: its room's cookie from nginx (a page load), the websocket through the proxy, then a
    task reading every message from then on (each decoded; a frame: a message setting ``body``'s pose)."""
    cookie, _ = await asyncio.to_thread(room_cookie, port, room)
    ws = await connect(
        f"ws://127.0.0.1:{port}/{room}",
        subprotocols=[SUBPROTOCOL],  # type: ignore[list-item]
        additional_headers={"Cookie": cookie} if cookie else None,
        max_size=None,
        open_timeout=60,
        close_timeout=1,
    )
    await ws.send(CAMERA_MESSAGE)  # viser counts a client once it reports its camera, as the page does
    report["backend"] = backend_of(ws)  # type: ignore[arg-type]  # the asyncio connection has the same .response
    connected = time.monotonic()

    async def read() -> None:
        try:
            async for message in ws:
                now = time.monotonic()
                assert isinstance(message, bytes)
                if now - connected < WARMUP:  # the room's GUI and meshes arrive first: read them fully
                    picker_and_nodes(message, report)
                nodes = posed_nodes(message, zstd)
                report["nodes"] |= nodes
                if body in nodes:
                    report["frames"].append(now)
            report["lost"] = "the server closed the connection"
        except Exception as exc:  # noqa: BLE001 - a lost connection: the report says so
            report["lost"] = f"{type(exc).__name__}: {exc}"

    return ws, asyncio.get_running_loop().create_task(read())


async def browsers(
    port: int, rooms: list[tuple[str, str]], read_for: float, out: Any, go: Any, start: Any
) -> list[dict[str, Any]]:
    zstd = zstandard.ZstdDecompressor()  # one for every message of this process
    reports: list[dict[str, Any]] = []
    opened = []
    for room, body in rooms:
        report: dict[str, Any] = {"room": room, "backend": "", "frames": [], "nodes": set(), "scene": None, "lost": ""}
        opened.append(await browse(port, room, body, report, zstd))
        reports.append(report)
    out.put(("connected", len(opened)))
    await asyncio.to_thread(go.wait, 600)
    await asyncio.sleep(max(0.0, start.value + read_for - time.monotonic()))
    for ws, reader in opened:
        reader.cancel()
        with contextlib.suppress(BaseException):
            await reader
        with contextlib.suppress(Exception):
            await ws.close()
    return reports


def clients(port: int, rooms: list[tuple[str, str]], read_for: float, out: Any, go: Any, start: Any) -> None:
    """In a child process: one browser per (room, body node) of ``rooms``, all read by one asyncio event
    loop (as cheap as a reader can be: no thread per connection), each reading from its connection on as a
    page does. Puts ("connected", n) once all are in, waits for ``go``, reads until ``start.value`` +
    ``read_for`` (monotonic s, one clock for every process), then puts the list of reports: per browser its
    process, its frames' times, the nodes and the Scene picker it was shown, why it lost its connection."""
    reports = asyncio.run(browsers(port, rooms, read_for, out, go, start))
    out.put([{**r, "nodes": sorted(r["nodes"])} for r in reports])


class Clients:
    """Simulated browsers in ``processes`` spawned processes (``plan`` cut into that many consecutive
    parts), each process one GIL of readers, as browsers on their own machines read on their own."""

    def __init__(self, port: int, plan: list[tuple[str, str]], read_for: float, processes: int) -> None:
        ctx = mp.get_context("spawn")
        self.out = ctx.Queue()
        go, start = ctx.Event(), ctx.Value("d", 0.0)
        size = -(-len(plan) // processes)
        parts = [plan[i : i + size] for i in range(0, len(plan), size)]
        self.children = [
            ctx.Process(target=clients, args=(port, part, read_for, self.out, go, start), daemon=True) for part in parts
        ]
        for child in self.children:
            child.start()
        for _ in self.children:
            tag, _n = self.out.get(timeout=300)
            assert tag == "connected"
        self.t0 = time.monotonic()  # every browser is in: the clock of the rows starts
        start.value = self.t0
        go.set()

    def reports(self, timeout: float) -> list[dict[str, Any]]:
        found: list[dict[str, Any]] = []
        for _ in self.children:
            found += self.out.get(timeout=timeout)
        for child in self.children:
            child.join(timeout=10)
        return found


# ------------------------------------------------------------------------------------------ the figures
def rate(frames: list[float], start: float, end: float) -> float:
    """Frames per second between ``start`` and ``end`` (monotonic s)."""
    return sum(1 for t in frames if start <= t < end) / (end - start)


def longest_gap(frames: list[float], start: float, end: float) -> float:
    """The longest time between two consecutive frames (or a window edge and a frame) in [start, end), s."""
    inside = [start, *(t for t in frames if start <= t < end), end]
    return max(b - a for a, b in zip(inside, inside[1:], strict=False))


def scene_titles() -> dict[str, str]:
    load_all()
    return {name: cls.title for name, cls in REGISTRY.items()}


def isolation_problems(reports: list[dict[str, Any]], scenes: dict[str, str]) -> list[str]:
    """Why some follower saw another room: its picker shows another scene, or it received a node that every
    follower of another room receives and its own room's followers do not all receive. ``scenes``: room ->
    the title its picker must show."""
    own: dict[str, set[str]] = {}
    for r in reports:
        own[r["room"]] = own[r["room"]] & set(r["nodes"]) if r["room"] in own else set(r["nodes"])
    problems = []
    for r in reports:
        if r["scene"] != scenes[r["room"]]:
            problems.append(f"a follower of {r['room']} was shown the scene {r['scene']!r}")
        others = set().union(*(nodes for room, nodes in own.items() if room != r["room"]))
        foreign = set(r["nodes"]) & (others - own[r["room"]])
        if foreign:
            problems.append(f"a follower of {r['room']} received {sorted(foreign)}")
    return sorted(set(problems))


def cpu_seconds(pid: int) -> float:
    """CPU time (user + system) a process has used so far, s (Linux ``/proc``)."""
    fields = Path(f"/proc/{pid}/stat").read_text().rsplit(")", 1)[1].split()
    return (int(fields[11]) + int(fields[12])) / os.sysconf("SC_CLK_TCK")


def window_cpu(department: Any, labels: list[str], window: tuple[float, float]) -> dict[str, float]:
    """Each room process's CPU time per second of wall time over ``window`` (waits until it ends)."""
    pids = department.pids()
    time.sleep(max(0.0, window[0] - time.monotonic()))
    before = {label: cpu_seconds(pids[label]) for label in labels}
    time.sleep(max(0.0, window[1] - time.monotonic()))
    return {label: (cpu_seconds(pids[label]) - before[label]) / (window[1] - window[0]) for label in labels}


def answering_again(address: str, since: float, limit: float = 20.0) -> float:
    """Seconds from ``since`` until the process at ``address`` (host:port) answers HTTP (inf after ``limit``)."""
    host, port = address.rsplit(":", 1)
    while time.monotonic() - since < limit:
        if answers(host, int(port), timeout=0.5):
            return time.monotonic() - since
        time.sleep(0.05)
    return float("inf")


def pool_and_kill(folder: Path, sessions: int, seconds: float) -> dict[str, Any]:
    """Rows 1 and 3: a pool of 2 processes, ``sessions`` browsers; then one process killed."""
    path, port = rooms_file(
        folder, [{"name": "homework", "mode": "private", "scene": POOL_SCENE, "free_hosts": ["127.0.0.2", "127.0.0.3"]}]
    )
    with running_department(path, port, timeout=120) as department:
        started = dict(re.findall(r"started (homework \d) \(pid \d+\) on (\S+)", department.log()))
        first, second = started["homework 1"], started["homework 2"]
        read_for = WARMUP + seconds + 0.5 + 6.0
        browsers = Clients(port, [("homework", BODY[POOL_SCENE])] * sessions, read_for, processes=2)
        t0 = browsers.t0
        window = (t0 + WARMUP, t0 + WARMUP + seconds)
        cpu = window_cpu(department, ["homework 1", "homework 2"], window)
        time.sleep(max(0.0, window[1] + 0.5 - time.monotonic()))
        lines_before = len(department.lines)
        victim = department.pids()["homework 1"]
        killed = time.monotonic()
        os.kill(victim, signal.SIGKILL)
        back = ThreadPoolExecutor(1).submit(answering_again, first, killed)
        joins: list[tuple[float, str, bool]] = []  # (s after the kill, process that took it, received a frame)
        while time.monotonic() - killed < 5.0:
            cookie, _ = room_cookie(port, "homework")
            try:
                with proxied(port, "homework", cookie, timeout=10) as ws:
                    took = backend_of(ws)
                    got = bool(ws.recv(timeout=10))
            except Exception:  # noqa: BLE001 - a join that failed: counted as landing nowhere
                took, got = "failed", False
            back_line = any("homework 1 is back" in line for line in department.lines[lines_before:])
            joins.append((time.monotonic() - killed, took if not back_line else f"{took} (after the restart)", got))
            time.sleep(0.5)
        back_after = back.result(timeout=20.0)
        department.wait_line(r"homework 1 is back", 20.0, lines_before)  # and the log says so
        reports = browsers.reports(timeout=read_for + 60)
    on_first = [r for r in reports if r["backend"] == first]
    on_second = [r for r in reports if r["backend"] == second]
    rates = [rate(r["frames"], *window) for r in reports]
    return {
        "sessions": sessions,
        "spread": (len(on_first), len(on_second)),
        "frames_min": min(rates),
        "frames_median": statistics.median(rates),
        "lost_before_kill": sum(1 for r in reports if r["lost"] and r["backend"] == second),
        "gap_before": max(longest_gap(r["frames"], killed - 2.0, killed) for r in on_second),
        "gap_after": max(longest_gap(r["frames"], killed, killed + 4.0) for r in on_second),
        "survivor_rate_after": statistics.median(rate(r["frames"], killed, killed + 4.0) for r in on_second),
        "survivors_lost": sum(1 for r in on_second if r["lost"]),
        "victims_lost": sum(1 for r in on_first if r["lost"]),
        "joins": joins,
        "living": second,
        "back_after": back_after,
        "cpu": cpu,
    }


def presenter_rooms(folder: Path, followers: int, seconds: float) -> dict[str, Any]:
    """Row 2: three presenter rooms, ``followers`` browsers each."""
    rooms = [{"name": name, "mode": "presenter", "pin": "246810", "scene": scene} for name, scene in PRESENTER_ROOMS]
    path, port = rooms_file(folder, rooms)
    titles = scene_titles()
    with running_department(path, port, timeout=120) as department:
        plan = [(name, BODY[scene]) for name, scene in PRESENTER_ROOMS for _ in range(followers)]
        browsers = Clients(port, plan, WARMUP + seconds + 0.2, processes=len(PRESENTER_ROOMS))
        window = (browsers.t0 + WARMUP, browsers.t0 + WARMUP + seconds)
        cpu = window_cpu(department, [name for name, _ in PRESENTER_ROOMS], window)
        reports = browsers.reports(timeout=WARMUP + seconds + 60)
    per_room = {}
    for name, _ in PRESENTER_ROOMS:
        rates = [rate(r["frames"], *window) for r in reports if r["room"] == name]
        per_room[name] = (min(rates), statistics.median(rates))
    scenes = {name: titles[scene] for name, scene in PRESENTER_ROOMS}
    return {
        "followers": followers,
        "per_room": per_room,
        "frames_min": min(low for low, _ in per_room.values()),
        "isolation": isolation_problems(reports, scenes),
        "lost": sum(1 for r in reports if r["lost"]),
        "cpu": cpu,
    }


# ------------------------------------------------------------------------------------------ the report
def verdict(ok: bool) -> str:
    return "met" if ok else "NOT met"


def report(
    pool: dict[str, Any], lecture: dict[str, Any], command: str, machine: str, took: float, used: str = ""
) -> list[str]:
    joins_down = [(t, b) for t, b, _ in pool["joins"] if "after the restart" not in b]
    joins_ok = all(got for _, _, got in pool["joins"])
    lines = [
        "# Rooms benchmark: a department behind nginx",
        "",
        f"`{command}`. `rigid-body-lab rooms` in a child process (nginx in front on 127.0.0.1; the pool's two "
        "processes on 127.0.0.2 and 127.0.0.3 standing in for two machines). Simulated browsers: websocket "
        "clients speaking viser's protocol in further processes on the same cores (two for the pool, one per "
        "presenter room; each process reads all its connections on one asyncio event loop and decodes every "
        "message), each getting its room's cookie from nginx first as a page load does; a frame is a "
        "message that sets the pose of the room's body.",
        "",
        machine,
        "",
        "| row | browsers | frames/s: slowest | frames/s: median | room process CPU (s/s) | notes |",
        "| --- | ---: | ---: | ---: | ---: | --- |",
        f"| private pool, 2 processes ({POOL_SCENE}) | {pool['sessions']} | {pool['frames_min']:.1f} | "
        f"{pool['frames_median']:.1f} | {' + '.join(f'{c:.2f}' for c in pool['cpu'].values())} | "
        f"nginx spread them {pool['spread'][0]} + {pool['spread'][1]} (by cookie) |",
    ]
    for name, scene in PRESENTER_ROOMS:
        low, mid = lecture["per_room"][name]
        lines.append(
            f"| presenter room {name} ({scene}) | {lecture['followers']} | {low:.1f} | {mid:.1f} | "
            f"{lecture['cpu'][name]:.2f} | |"
        )
    lines += [
        "",
        "Targets:",
        "",
        f"- a private pool of 2 processes holds {pool['sessions']} sessions at ≥ 30 frames/s each: slowest "
        f"{pool['frames_min']:.1f} — {verdict(pool['frames_min'] >= 30.0)}",
        f"- 3 presenter rooms with {lecture['followers']} followers each keep ≥ 55 frames/s: slowest "
        f"{lecture['frames_min']:.1f} — {verdict(lecture['frames_min'] >= 55.0)}",
        "- a follower of one room never receives another room's scene: "
        + ("no follower did — met" if not lecture["isolation"] else "NOT met: " + "; ".join(lecture["isolation"])),
        f"- SIGKILL of one pool process: the {pool['spread'][1]} sessions on the other "
        f"kept moving — longest gap between two frames {pool['gap_after'] * 1e3:.0f} ms in the 4 s after the kill "
        f"({pool['gap_before'] * 1e3:.0f} ms in the 2 s before), median {pool['survivor_rate_after']:.1f} "
        f"frames/s after it, {pool['survivors_lost']} connections lost — "
        f"{verdict(pool['gap_after'] <= GAP_LIMIT and pool['survivors_lost'] == 0)} (no gap over "
        f"{GAP_LIMIT * 1e3:.0f} ms)",
        f"- a browser that joins within 5 s lands on the living process: {len(joins_down)} joins while the killed "
        f"process was down, on {sorted({b for _, b in joins_down})} (living: {pool['living']})"
        + (
            f", {len(pool['joins']) - len(joins_down)} after it was back"
            if len(joins_down) < len(pool["joins"])
            else ""
        )
        + f", every join received frames: {joins_ok} — "
        + verdict(bool(joins_down) and {b for _, b in joins_down} == {pool["living"]} and joins_ok),
        f"- the killed process is back within 10 s: it answered {pool['back_after']:.1f} s after the kill "
        f"(restarted by the supervisor, which polls every 0.25 s) — {verdict(pool['back_after'] < 10.0)}",
    ]
    problems = []
    if lecture["lost"]:
        problems.append(f"{lecture['lost']} followers lost their connection")
    if pool["lost_before_kill"]:
        problems.append(f"{pool['lost_before_kill']} sessions on the living process lost their connection")
    if problems:
        lines += ["", "Problems:", "", *(f"- {p}" for p in problems)]
    lines += [
        "",
        "Room process CPU: CPU seconds per second of wall time of each room's process during the measured "
        "seconds (1.00 = a whole core; the pool's two processes together could use both cores of an idle "
        f"machine). This run and everything it started used {used}, start-up and waits included.",
        "",
        f"Run time: {took:.0f} s.",
    ]
    return lines


def main(argv: list[str] | None = None) -> None:
    parser = argparse.ArgumentParser(description=__doc__.splitlines()[0])
    parser.add_argument("--sessions", type=int, default=60, help="browsers in the private pool")
    parser.add_argument("--followers", type=int, default=30, help="followers in each presenter room")
    parser.add_argument("--seconds", type=float, default=5.0, help="measured seconds per row")
    parser.add_argument("--changes", type=int, default=10, help="changes timed into the teacher's table")
    parser.add_argument("--teacher-only", action="store_true", help="only row 4, into results/rooms_teacher.md")
    parser.add_argument("--out", type=Path, default=None)
    args = parser.parse_args(argv)
    if args.teacher_only:
        load = os.getloadavg()
        with tempfile.TemporaryDirectory() as tmp:
            result = teacher_table(Path(tmp), args.sessions, args.changes, args.seconds, Clients)
        out = args.out or RESULTS.with_name("rooms_teacher.md")
        command = f"python -m benchmarks.rooms --teacher-only --sessions {args.sessions} --changes {args.changes}"
        machine = (
            f"Machine: {os.cpu_count()} cores, shared with other work while this ran (load average 1, 5, 15 min: "
            f"{' '.join(f'{x:.2f}' for x in load)} at the start, "
            f"{' '.join(f'{x:.2f}' for x in os.getloadavg())} at the end)."
        )
        lines = ["# Rooms benchmark: the teacher's view of a pool", "", f"`{command}`.", "", machine]
        lines += report_lines(result)
        out.write_text("\n".join(lines) + "\n")
        print("\n".join(lines))
        print(f"written {out}")
        return
    command = (
        f"python -m benchmarks.rooms --sessions {args.sessions} --followers {args.followers} --seconds {args.seconds:g} "
        f"--changes {args.changes}"
    )
    started = time.monotonic()
    start_load = os.getloadavg()
    cpu_start = sum(r.ru_utime + r.ru_stime for r in (resource.getrusage(resource.RUSAGE_SELF),))
    with tempfile.TemporaryDirectory() as tmp:
        for sub in ("pool", "lecture"):
            (Path(tmp) / sub).mkdir()
        pool = pool_and_kill(Path(tmp) / "pool", args.sessions, args.seconds)
        print(
            f"pool: {pool['frames_min']:.1f} / {pool['frames_median']:.1f} frames/s, spread {pool['spread']}",
            flush=True,
        )
        lecture = presenter_rooms(Path(tmp) / "lecture", args.followers, args.seconds)
        print(f"presenter: {lecture['per_room']}", flush=True)
        (Path(tmp) / "teacher").mkdir()
        teacher = teacher_table(Path(tmp) / "teacher", args.sessions, args.changes, args.seconds, Clients)
    end_load = os.getloadavg()
    machine = (
        f"Machine: {os.cpu_count()} cores, shared with other work while this ran (load average 1, 5, 15 min: "
        f"{' '.join(f'{x:.2f}' for x in start_load)} at the start, {' '.join(f'{x:.2f}' for x in end_load)} at the "
        "end); the servers, nginx and the clients all run on these cores."
    )
    took = time.monotonic() - started
    rusage = [resource.getrusage(who) for who in (resource.RUSAGE_SELF, resource.RUSAGE_CHILDREN)]
    cpu_total = sum(r.ru_utime + r.ru_stime for r in rusage) - cpu_start
    used = f"{cpu_total:.0f} CPU seconds in {took:.0f} s ({cpu_total / took:.2f} cores on average)"
    lines = report(pool, lecture, command, machine, took, used) + report_lines(teacher)
    out = args.out or RESULTS
    out.parent.mkdir(parents=True, exist_ok=True)
    out.write_text("\n".join(lines) + "\n")
    print("\n".join(lines))
    print(f"written {out}")


if __name__ == "__main__":
    main()
