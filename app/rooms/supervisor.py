"""Keep a set of child processes running: start them, forward their output, restart one that dies, stop all.

Each child is a command (an app process of a room, or nginx) in its own session, so that a Ctrl-C in the
terminal reaches only the supervisor, which then stops the children in order: the proxy first (no new
browser reaches a stopping room), then the rooms, each with SIGTERM and, after :data:`STOP_GRACE`
seconds, SIGKILL to its whole process group. On Linux each child also gets SIGTERM if the supervisor
itself dies without stopping it (``PR_SET_PDEATHSIG``), so no room outlives its department.

:meth:`Supervisor.check` (called every :data:`POLL` seconds from the thread that started the children)
restarts a child that exited at once, and says so in the log; a child that keeps dying within
:data:`STEADY` seconds of its start waits 1, 2, 4 s (at most :data:`MAX_BACKOFF`) between attempts.
"""

from __future__ import annotations

import contextlib
import ctypes
import http.client
import os
import re
import signal
import socket
import subprocess
import sys
import threading
import time
from collections.abc import Callable, Sequence
from dataclasses import dataclass, field

__all__ = [
    "MAX_BACKOFF",
    "POLL",
    "STEADY",
    "STOP_GRACE",
    "Child",
    "ChildSpec",
    "Supervisor",
    "answers",
    "describe_exit",
    "is_local_address",
    "port_free",
]

POLL = 0.25
"""Seconds between two looks at the children."""

STEADY = 10.0
"""A child that ran this long before it died is restarted at once (otherwise after a back-off)."""

MAX_BACKOFF = 4.0
"""The longest wait, s, before restarting a child that keeps dying at start-up."""

STOP_GRACE = 5.0
"""Seconds a child has to leave after SIGTERM before it gets SIGKILL."""

BANNER = ("╭", "│", "╰")
"""viser's start-up box: noise in a department's log."""


@dataclass(frozen=True)
class ChildSpec:
    """What to run: a label for the log, the command, where it must answer (``host``, ``port``)."""

    label: str
    command: tuple[str, ...]
    host: str
    port: int
    env: dict[str, str] = field(default_factory=dict)  # added to this process's environment
    port_said: str | None = None  # a regex whose group 1 is the port the child says it serves on
    probe: Callable[[str, int], bool] | None = None  # whether it answers at (host, port); default HTTP (answers)


PROBE = "/rooms-probe"
"""The path asked for to see whether a child answers (a room's app and nginx both answer 404)."""


def answers(host: str, port: int, timeout: float = 1.0) -> bool:
    """Whether an HTTP server answers at ``host:port`` (any status: a bare TCP connection would make a
    websocket server log a failed handshake)."""
    connection = http.client.HTTPConnection(host, port, timeout=timeout)
    try:
        connection.request("GET", PROBE)
        connection.getresponse().read()
        return True
    except (OSError, http.client.HTTPException):
        return False
    finally:
        connection.close()


def port_free(host: str, port: int) -> bool:
    """Whether this machine can listen at ``host:port`` now."""
    family = socket.AF_INET6 if ":" in host else socket.AF_INET
    with socket.socket(family, socket.SOCK_STREAM) as s:
        s.setsockopt(socket.SOL_SOCKET, socket.SO_REUSEADDR, 1)
        try:
            s.bind((host, port))
        except OSError:
            return False
    return True


def is_local_address(host: str) -> bool:
    """Whether ``host`` is an address of this machine (a backend there is started here, not proxied to)."""
    family = socket.AF_INET6 if ":" in host else socket.AF_INET
    with socket.socket(family, socket.SOCK_STREAM) as s:
        try:
            s.bind((host, 0))
        except OSError:
            return False
    return True


def _die_with_parent() -> None:
    """In the child, before exec: SIGTERM when the supervisor's thread that started it dies (Linux)."""
    with contextlib.suppress(Exception):
        ctypes.CDLL("libc.so.6", use_errno=True).prctl(1, signal.SIGTERM)  # PR_SET_PDEATHSIG = 1


class Child:
    """One running (or restarting) child process and its history."""

    def __init__(self, spec: ChildSpec, log: Callable[[str], None]) -> None:
        self.spec = spec
        self.log = log
        self.process: subprocess.Popen[bytes] | None = None
        self.started = 0.0  # time.monotonic() of the last start
        self.restarts = 0
        self.quick_deaths = 0  # deaths within STEADY s of a start, in a row
        self.next_start = 0.0  # time.monotonic() before which a dead child is not restarted
        self.ready_announced = False
        self._reader: threading.Thread | None = None

    @property
    def pid(self) -> int | None:
        return None if self.process is None else self.process.pid

    def start(self) -> None:
        env = {**os.environ, "PYTHONUNBUFFERED": "1", **self.spec.env}
        preexec = _die_with_parent if sys.platform.startswith("linux") else None
        self.process = subprocess.Popen(  # noqa: S603 - our own command line, no shell
            list(self.spec.command),
            stdin=subprocess.DEVNULL,
            stdout=subprocess.PIPE,
            stderr=subprocess.STDOUT,
            env=env,
            start_new_session=True,
            preexec_fn=preexec,  # noqa: PLW1509 - only prctl, safe before exec
        )
        self.started = time.monotonic()
        self.ready_announced = False
        self._reader = threading.Thread(target=self._forward, args=(self.process,), daemon=True)
        self._reader.start()

    def _forward(self, process: subprocess.Popen[bytes]) -> None:
        """Copy the child's output into the log, one line at a time, labelled."""
        assert process.stdout is not None
        for raw in process.stdout:
            line = raw.decode("utf-8", "replace").rstrip()
            if line and not line.lstrip().startswith(BANNER):
                self.log(f"[{self.spec.label}] {line}")
            said = re.search(self.spec.port_said, line) if self.spec.port_said else None
            if said and int(said.group(1)) != self.spec.port:
                # viser moves to the next free port when its own is taken: nginx would never reach it.
                self.log(
                    f"{self.spec.label} serves on port {said.group(1)}, not {self.spec.port} (taken?): stopping it"
                )
                with contextlib.suppress(ProcessLookupError, PermissionError):
                    os.killpg(process.pid, signal.SIGTERM)

    def ready(self) -> bool:
        """Running, and answering at its address."""
        return self.alive() and (self.spec.probe or answers)(self.spec.host, self.spec.port)

    def alive(self) -> bool:
        return self.process is not None and self.process.poll() is None

    def signal(self, signum: int) -> None:
        """Send ``signum`` to the child's process group (itself and anything it started)."""
        if self.process is None or self.process.poll() is not None:
            return
        with contextlib.suppress(ProcessLookupError, PermissionError):
            os.killpg(self.process.pid, signum)

    def clear_group(self) -> None:
        """SIGKILL whatever is left of a dead child's process group (nginx's workers outlive a killed master
        and keep its port)."""
        if self.process is not None:
            with contextlib.suppress(ProcessLookupError, PermissionError):
                os.killpg(self.process.pid, signal.SIGKILL)

    def stop(self, grace: float = STOP_GRACE) -> None:
        """SIGTERM (unless already sent), then SIGKILL after ``grace`` s; waits until it is gone."""
        if self.process is None:
            return
        self.signal(signal.SIGTERM)
        try:
            self.process.wait(timeout=grace)
        except subprocess.TimeoutExpired:
            self.log(f"{self.spec.label} (pid {self.process.pid}) did not stop within {grace:g} s: killed")
            self.signal(signal.SIGKILL)
            self.process.wait(timeout=grace)
        with contextlib.suppress(ProcessLookupError, PermissionError):
            os.killpg(self.process.pid, signal.SIGKILL)  # anything it left behind in its group
            deadline = time.monotonic() + grace
            while time.monotonic() < deadline:  # until the group is empty (a zombie counts until reaped)
                os.killpg(self.process.pid, 0)
                time.sleep(0.02)
        if self._reader is not None:
            self._reader.join(timeout=1.0)


def describe_exit(code: int) -> str:
    """A child's exit for the log: "exited with code N" or "killed by SIGNAME"."""
    if code < 0:
        try:
            return f"killed by {signal.Signals(-code).name}"
        except ValueError:
            return f"killed by signal {-code}"
    return f"exited with code {code}"


class Supervisor:
    """Children started in order, watched, restarted when they die, and stopped in reverse order."""

    def __init__(self, log: Callable[[str], None]) -> None:
        self.log = log
        self.children: list[Child] = []
        self.stopping = threading.Event()

    def add(self, spec: ChildSpec) -> Child:
        child = Child(spec, self.log)
        self.children.append(child)
        return child

    def start(self, children: Sequence[Child], timeout: float = 60.0) -> None:
        """Start ``children`` and wait until each answers; RuntimeError naming the ones that did not."""
        for child in children:
            child.start()
            self.log(f"started {child.spec.label} (pid {child.pid}) on {child.spec.host}:{child.spec.port}")
        deadline = time.monotonic() + timeout
        waiting = list(children)
        while waiting and time.monotonic() < deadline and not self.stopping.is_set():
            dead = [c for c in waiting if not c.alive()]
            if dead:
                codes = ", ".join(f"{c.spec.label} {describe_exit(c.process.returncode)}" for c in dead if c.process)
                raise RuntimeError(f"stopped at start-up: {codes}")
            waiting = [c for c in waiting if not c.ready()]
            time.sleep(0.05)
        for child in children:
            child.ready_announced = True
        if waiting and not self.stopping.is_set():
            raise RuntimeError(
                "no answer within {:g} s from {}".format(timeout, ", ".join(c.spec.label for c in waiting))
            )

    def check(self) -> None:
        """One look at every child: restart the dead (after a back-off if they die at start-up) and say when a
        restarted child answers again."""
        now = time.monotonic()
        for child in self.children:
            process = child.process
            if process is None or self.stopping.is_set():
                continue
            code = process.poll()
            if code is None:
                if not child.ready_announced and child.ready():
                    child.ready_announced = True
                    took = time.monotonic() - child.started
                    self.log(f"{child.spec.label} is back (pid {child.pid}), answering {took:.1f} s after its restart")
                continue
            if child.next_start == 0.0:  # first look since it died
                child.clear_group()
                ran = now - child.started
                child.quick_deaths = child.quick_deaths + 1 if ran < STEADY else 0
                wait = 0.0 if child.quick_deaths <= 1 else min(MAX_BACKOFF, 2.0 ** (child.quick_deaths - 2))
                child.next_start = now + wait
                self.log(
                    f"{child.spec.label} (pid {process.pid}) {describe_exit(code)} after {ran:.1f} s; "
                    + ("restarting" if wait == 0.0 else f"restarting in {wait:g} s (it keeps dying at start-up)")
                )
            if now >= child.next_start:
                child.next_start = 0.0
                child.restarts += 1
                child.start()
                self.log(f"restarted {child.spec.label} (pid {child.pid}), restart {child.restarts}")

    def run(self, poll: float = POLL) -> None:
        """Watch the children until :attr:`stopping` is set (by a signal handler), then stop them all."""
        try:
            while not self.stopping.wait(poll):
                self.check()
        finally:
            self.stop()

    def stop(self) -> None:
        """Stop every child, the last started first."""
        self.stopping.set()
        for child in reversed(self.children):  # the proxy first, then every room at once
            if child.alive():
                self.log(f"stopping {child.spec.label} (pid {child.pid})")
                child.signal(signal.SIGTERM)
        for child in reversed(self.children):
            child.stop()
