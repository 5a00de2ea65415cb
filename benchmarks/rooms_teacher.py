"""The teacher's view of a pool, measured: how soon a student's change on one process shows in the table of
a teacher on the other, and how much Redis traffic the shared table costs.

``rigid-body-lab rooms`` runs a private pool of 2 processes with a teacher PIN (127.0.0.2 and 127.0.0.3
standing in for two machines; Redis started by the command on loopback). ``sessions`` browsers join, half on
each process by the room's cookie: one driven student on process 2 (:class:`tests.rooms.panel_reader.PanelReader`),
the others read as pages read (:class:`benchmarks.rooms.Clients`, in further processes), and a teacher on
process 1 opens the teacher's view. Then:

* **traffic**: Redis's ``INFO stats`` (commands processed, bytes in and out) over ``seconds`` with the
  teacher watching, per second;
* **latency**: ``changes`` times, the student moves a slider (the pendulum's release angle, one of the
  table's main parameters) and the wall time until the teacher's page has a table showing the new value
  is taken; the student's message, process 2's look at its rows, Redis, process 1's read, the table's
  rewrite and the message to the teacher are all in it.

Run by ``python -m benchmarks.rooms`` (its last rows), or alone with ``--teacher-only``.
"""

from __future__ import annotations

import re
import statistics
import time
from collections.abc import Callable
from pathlib import Path
from typing import Any

import redis

from tests.rooms.panel_reader import PanelReader, table_numbers
from tests.rooms.running import RunningDepartment, rooms_file, running_department

PIN = "246810"
SCENE = "pendulum"
ANGLE = "release angle θ₀ (°)"
BODY = "/scene/body"
TARGET = 1.0
"""s: the issue's bound on a change reaching the teacher's table."""


def redis_stats(port: int, password: str | None = None) -> tuple[int, int, int]:
    """Redis's commands processed, bytes received and bytes sent since it started."""
    client = redis.Redis(port=port, password=password, socket_timeout=5)
    try:
        stats = client.info("stats")
    finally:
        client.close()
    return (
        int(stats["total_commands_processed"]),
        int(stats["total_net_input_bytes"]),
        int(stats["total_net_output_bytes"]),
    )


def traffic(port: int, seconds: float, password: str | None = None) -> dict[str, float]:
    """Redis's traffic per second over ``seconds`` (the INFO calls themselves taken out: 1 command each)."""
    before, t0 = redis_stats(port, password), time.monotonic()
    time.sleep(seconds)
    after, t1 = redis_stats(port, password), time.monotonic()
    span = t1 - t0
    return {
        "commands": (after[0] - before[0] - 1) / span,
        "bytes_in": (after[1] - before[1]) / span,
        "bytes_out": (after[2] - before[2]) / span,
    }


def redis_of(department: RunningDepartment) -> tuple[int, str]:
    """The port and the password of the Redis server the department started (its configuration file is in
    the department's temporary folder, readable by the user who ran it)."""
    found = re.search(r"started redis \(pid \d+\) on 127\.0\.0\.1:(\d+)", department.log())
    folder = re.search(r"nginx configuration and logs in (\S+)", department.log())
    assert found and folder, department.log()
    password = (Path(folder.group(1)) / "redis.conf").read_text().split()[1]  # "requirepass PASSWORD"
    return int(found.group(1)), password


def teacher_table(
    folder: Path, sessions: int, changes: int, seconds: float, readers: Callable[..., Any]
) -> dict[str, Any]:
    """The latency of ``changes`` changes and Redis's traffic, with ``sessions`` browsers in the pool;
    ``readers(port, plan, read_for, processes=2)`` starts the reading browsers (:class:`benchmarks.rooms.Clients`:
    each gets its cookie as a first visit does, and the student and the teacher already hold one process
    each, so least_conn spreads them evenly)."""
    path, port = rooms_file(
        folder,
        [{"name": "homework", "mode": "private", "scene": SCENE, "pin": PIN, "free_hosts": ["127.0.0.2", "127.0.0.3"]}],
    )
    with running_department(path, port, timeout=120) as department:
        redis_port, password = redis_of(department)
        student = PanelReader(port, "homework", "rbl_homework=1")
        teacher = PanelReader(port, "homework", "rbl_homework=0")
        others = sessions - 1  # the student; the teacher is not in the table
        plan = [("homework", BODY)] * others
        read_for = 3 * seconds + changes * 3.0 + 30.0
        browsers = readers(port, plan, read_for, processes=2)
        try:
            number = student.session_number()
            idle = traffic(
                redis_port, seconds, password
            )  # every session there; the processes publish, no teacher reads
            teacher.open_teachers_view(PIN)
            teacher.wait(lambda: len(table_numbers(teacher.table())) == sessions, timeout=60, what=f"{sessions} rows")
            rows = len(table_numbers(teacher.table()))
            watched = traffic(redis_port, seconds, password)
            latencies = []
            for k in range(changes):
                value = 31.0 + k
                shown = re.compile(rf'<th scope="row">{number}</th>(?:(?!</tr>).)*?= {value:.0f}(<br>|</td>)')
                sent = time.monotonic()
                student.set(ANGLE, value)
                teacher.wait(lambda shown=shown: shown.search(teacher.table()), timeout=30, what=f"angle {value:.0f}")
                latencies.append(time.monotonic() - sent)
                time.sleep(0.7)  # changes apart, at random phases of the processes' 0.1 s looks
        finally:
            student.close()
            teacher.close()
        browsers.reports(timeout=read_for + 60)
    return {
        "sessions": sessions,
        "rows": rows,
        "latencies": latencies,
        "idle": idle,
        "watched": watched,
        "seconds": seconds,
    }


def report_lines(result: dict[str, Any]) -> list[str]:
    """The rows of the teacher's table for ``benchmarks/results/rooms.md``."""
    lat = result["latencies"]
    worst, median = max(lat), statistics.median(lat)
    idle, watched = result["idle"], result["watched"]
    return [
        "",
        "## The teacher's view of the pool (through Redis)",
        "",
        f"A pool of 2 processes with a teacher PIN ({SCENE}), {result['sessions']} sessions (the teacher's "
        f"table showed {result['rows']} rows), a teacher on process 1; {len(lat)} times a student on process 2 "
        f"moved a slider shown in the table, and the teacher's page was read until its table showed the new value.",
        "",
        "| measured | value |",
        "| --- | ---: |",
        f"| change on process 2 → teacher's table on process 1: median | {median * 1e3:.0f} ms |",
        f"| same, slowest of {len(lat)} | {worst * 1e3:.0f} ms |",
        f"| Redis, no teacher watching: commands/s, bytes in/s, bytes out/s | {idle['commands']:.1f}, "
        f"{idle['bytes_in']:.0f}, {idle['bytes_out']:.0f} |",
        f"| Redis, the teacher watching: commands/s, bytes in/s, bytes out/s | {watched['commands']:.1f}, "
        f"{watched['bytes_in']:.0f}, {watched['bytes_out']:.0f} |",
        "",
        f"- a teacher's table of {result['sessions']} sessions over 2 processes refreshes within "
        f"{TARGET:g} s of a change: slowest {worst:.2f} s — {'met' if worst <= TARGET else 'NOT met'}",
        f"- Redis traffic (INFO stats over {result['seconds']:g} s each): reported above",
    ]
