"""The teacher's view of a private pool of two processes behind real nginx, through the real redis-server
``rigid-body-lab rooms`` starts: a teacher on process 1 lists and spotlights a student on process 2; a
killed process's sessions leave the table within 5 s; Redis stopped, then killed and restarted: the rooms
keep serving and the table comes back.

Raw websockets through the proxy stand in for browsers (``tests/rooms/panel_reader.py``); the room's
cookie names the process (``rbl_homework=0`` process 1, ``=1`` process 2). Loopback only; the department
and every process it started are stopped at the end.
"""

from __future__ import annotations

import contextlib
import os
import re
import signal
import time
from collections.abc import Iterator

import pytest
import redis

from tests.rooms.panel_reader import PanelReader, table_numbers
from tests.rooms.running import (
    RunningDepartment,
    alive,
    nginx_or_skip,
    redis_or_skip,
    rooms_file,
    running_department,
)

PIN = "246810"
ANGLE = "release angle θ₀ (°)"  # the pendulum's third control: in the table's main parameters
ON_1, ON_2 = "rbl_homework=0", "rbl_homework=1"


@pytest.fixture(scope="module")
def department(tmp_path_factory: pytest.TempPathFactory) -> Iterator[RunningDepartment]:
    nginx_or_skip()
    redis_or_skip()
    path, port = rooms_file(
        tmp_path_factory.mktemp("pool"),
        [{"name": "homework", "mode": "private", "processes": 2, "pin": PIN, "scene": "pendulum"}],
    )
    with running_department(path, port) as running:
        running.wait_line(r"started redis \(pid \d+\)", 5)
        yield running


@contextlib.contextmanager
def browser(department: RunningDepartment, cookie: str) -> Iterator[PanelReader]:
    reader = PanelReader(department.port, "homework", cookie)
    try:
        yield reader
    finally:
        reader.close()


@contextlib.contextmanager
def student_on_process_2(department: RunningDepartment) -> Iterator[PanelReader]:
    """A browser on process 2 by its cookie, once nginx sends it there again (after a test that killed it,
    nginx sends the cookie's browsers to the living process for a while: ``error_page 502``)."""
    _, two = _backends(department)
    deadline = time.monotonic() + 60
    while True:
        reader = PanelReader(department.port, "homework", ON_2)
        if reader.backend == two:
            break
        reader.close()
        assert time.monotonic() < deadline, "process 2 never took its cookie's browser again"
        time.sleep(0.5)
    try:
        yield reader
    finally:
        reader.close()


def _backends(department: RunningDepartment) -> tuple[str, str]:
    found = dict(re.findall(r"started (homework \d) \(pid \d+\) on (\S+)", department.log()))
    return found["homework 1"], found["homework 2"]


def test_a_teacher_on_process_1_lists_and_spotlights_a_student_on_process_2(department: RunningDepartment) -> None:
    one, two = _backends(department)
    # The department's own Redis takes no client without its password (which only its processes are given).
    port = int(department.wait_line(r"started redis \(pid \d+\) on 127\.0\.0\.1:(\d+)", 5).group(1))
    with pytest.raises(redis.AuthenticationError):
        redis.Redis(port=port, socket_timeout=5).keys("rbl:*")
    with browser(department, ON_2) as student, browser(department, ON_1) as teacher:
        assert (student.backend, teacher.backend) == (two, one)
        number = student.session_number()
        assert number % 2 == 0  # process 2 of 2 numbers its sessions 2, 4, 6, ...
        student.set("Your name", "Ann <b>Lee</b>")
        student.wait(lambda: student.value(ANGLE) is not None, what="the pendulum's controls")
        student.set(ANGLE, 45.0)
        student.set("Pause", True)
        teacher.open_teachers_view(PIN)
        # The student's row comes from the other process: its number, its cleaned (and escaped) name, its angle.
        teacher.wait(
            lambda: number in table_numbers(teacher.table()) and "= 45" in teacher.table(),
            what="process 2's student in the teacher's table",
        )
        table = teacher.table()
        assert f"{number} · Ann b Lee b" in table and "<b>" not in table
        own = teacher.session_number()
        assert own % 2 == 1 and own not in table_numbers(table)  # a teacher is not in the table
        teacher.set("Session", str(number))
        teacher.wait(lambda: teacher.value("Session") == str(number), what="the choice")
        teacher.press("Spotlight")
        teacher.wait(lambda: teacher.value(ANGLE) == 45.0, what="the student's angle in the teacher's view")
        titles = teacher.wait(
            lambda: [b for t, b in teacher.notifications if t == "Spotlight"], what="the Spotlight notice"
        )
        assert f"Session {number} (Ann b Lee b)" in titles[-1]
        # The student is untouched: same angle, still its own session, not told anything.
        assert student.value(ANGLE) == 45.0 and not student.closed
        assert not [t for t, _ in student.notifications if t == "Spotlight"]


def test_a_killed_process_sessions_leave_the_table_within_5_s(department: RunningDepartment) -> None:
    with browser(department, ON_1) as teacher, student_on_process_2(department) as student:
        number = student.session_number()
        teacher.open_teachers_view(PIN)
        teacher.wait(lambda: number in table_numbers(teacher.table()), what="the student in the table")
        pid = department.pids()["homework 2"]
        start = len(department.lines)
        os.kill(pid, signal.SIGKILL)
        killed = time.monotonic()
        teacher.wait(
            lambda: number not in table_numbers(teacher.table()), timeout=30, what="the dead process's row to go"
        )
        gone = time.monotonic() - killed
        assert gone < 5.0, f"the killed process's session stayed {gone:.1f} s in the table"
        department.wait_line(r"restarted homework 2", 30, start)  # the supervisor's part: it comes back
        assert not alive(pid)


def test_redis_stopped_killed_and_restarted_the_rooms_serve_and_the_table_comes_back(
    department: RunningDepartment,
) -> None:
    with browser(department, ON_1) as teacher, student_on_process_2(department) as student:
        number = student.session_number()
        teacher.open_teachers_view(PIN)
        teacher.wait(lambda: number in table_numbers(teacher.table()), what="the student in the table")
        pid = department.pids()["redis"]
        os.kill(pid, signal.SIGSTOP)  # unreachable: every call times out, as a server gone off the network
        try:
            teacher.wait(
                lambda: "cannot be reached" in teacher.table() and number not in table_numbers(teacher.table()),
                timeout=30,
                what="the notice that only this process's sessions are shown",
            )
            # The rooms keep serving: a new browser gets its panel on each process, the student its frames.
            for cookie in (ON_1, ON_2):
                with browser(department, cookie) as late:
                    late.session_number()
            before = student.value("Time (s)")
            student.set("Pause", False)
            student.wait(lambda: student.value("Time (s)") != before, what="the student's clock to run")
        finally:
            start = len(department.lines)
            os.kill(pid, signal.SIGKILL)  # and gone: the supervisor starts it again, empty
            with contextlib.suppress(ProcessLookupError):
                os.kill(pid, signal.SIGCONT)
        department.wait_line(r"restarted redis", 30, start)
        teacher.wait(
            lambda: number in table_numbers(teacher.table()) and "cannot be reached" not in teacher.table(),
            timeout=30,
            what="the whole table back",
        )
