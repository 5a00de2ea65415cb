"""Helpers for driving ``rigid-body-lab rooms`` as a user does: the command in a child process, its log
read as it comes, clients through the proxy (a cookie as a browser gets it, viser's websocket).

* :func:`rooms_file` — a rooms file on free loopback ports (127.0.0.2/.3 stand in for other machines);
* :func:`running_department` — the command running it; always stopped (SIGTERM, then SIGKILL) on exit;
* :func:`room_cookie` — the cookie nginx gives a browser's first visit to a private room, and who answered;
* :func:`proxied` — a websocket to ``/ROOM`` through the proxy with viser's subprotocol, as the page opens it;
* :func:`redis_server` — Debian's ``redis-server`` on a free loopback port, as ``rigid-body-lab rooms`` runs it.

Used by ``tests/rooms`` and ``benchmarks/rooms.py``; loopback only.
"""

from __future__ import annotations

import contextlib
import http.client
import os
import random
import re
import signal
import subprocess
import sys
import threading
import time
from collections.abc import Iterator
from pathlib import Path
from typing import Any

import pytest
import viser
from websockets.sync.client import ClientConnection, connect

from app.rooms.cli import READY
from app.rooms.nginx import BACKEND_HEADER, NginxMissing, find_nginx
from app.rooms.redis_server import RedisMissing, find_redis, redis_answers, redis_command
from app.rooms.supervisor import port_free
from tests.harness import CAMERA_MESSAGE

ROOT = Path(__file__).resolve().parents[2]
SUBPROTOCOL = f"viser-v{viser.__version__}"
PROBE = "/rooms-probe"  # a path every room answers with 404: cheap, and nginx still sets the cookie


def nginx_or_skip() -> str:
    """nginx's binary, or a skip saying how to install it (a skip fails CI: ``RBL_NO_SKIP=1``)."""
    try:
        return find_nginx()
    except NginxMissing as exc:
        pytest.skip(str(exc))


BLOCK_PORTS = (20_000, 32_000)
"""Where :func:`free_block` looks: below Linux's ephemeral ports (32768-60999), which every ``bind(0)`` and
outgoing connection of the other tests takes from, so a block found free stays free while the rooms start."""


def free_block(count: int) -> int:
    """The first of ``count`` consecutive ports of 127.0.0.1 free now, in :data:`BLOCK_PORTS`: a rooms file
    places its rooms on the ports after its proxy's."""
    rng = random.Random()
    for _ in range(200):
        first = rng.randrange(BLOCK_PORTS[0], BLOCK_PORTS[1] - count)
        if all(port_free("127.0.0.1", port) for port in range(first, first + count)):
            return first
    raise AssertionError(f"no {count} consecutive free ports in {BLOCK_PORTS}")


def rooms_file(folder: Path, rooms: list[dict[str, Any]], listen: int | None = None) -> tuple[Path, int]:
    """Write a rooms file into ``folder``; each room dict is its keys (``port`` and ``hosts`` given as
    written, or ``free`` = number of processes to place on free ports of 127.0.0.1, or ``free_hosts`` =
    loopback addresses to place one process each on). Returns the path and the proxy's port."""
    placed = [room for room in rooms if not {"hosts", "free_hosts", "port"} & set(room)]
    listen = listen or free_block(1 + sum(room.get("processes", 1) for room in placed))
    lines = [f'listen = "127.0.0.1:{listen}"']
    for room in rooms:
        room = dict(room)
        lines.append("[[room]]")
        if "free_hosts" in room:
            room["hosts"] = [f"{h}:{_free_on(h)}" for h in room.pop("free_hosts")]
        for key, value in room.items():
            if isinstance(value, str):
                lines.append(f'{key} = "{value}"')
            elif isinstance(value, bool):
                lines.append(f"{key} = {'true' if value else 'false'}")
            elif isinstance(value, list):
                lines.append(
                    f"{key} = [{', '.join(repr(v) if isinstance(v, int) else chr(34) + v + chr(34) for v in value)}]"
                )
            else:
                lines.append(f"{key} = {value}")
    path = folder / "rooms.toml"
    path.write_text("\n".join(lines) + "\n")
    return path, listen


def _free_on(host: str) -> int:
    """A port free now on ``host``, outside the ephemeral ports (see :data:`BLOCK_PORTS`)."""
    rng = random.Random()
    for _ in range(200):
        port = rng.randrange(*BLOCK_PORTS)
        if port_free(host, port):
            return port
    raise AssertionError(f"no free port on {host} in {BLOCK_PORTS}")


class RunningDepartment:
    """``python -m app rooms FILE`` in a child process, with its log kept line by line."""

    def __init__(self, path: Path, port: int) -> None:
        self.port = port
        self.lines: list[str] = []
        self._new_line = threading.Condition()
        env = {**os.environ, "PYTHONUNBUFFERED": "1", "PYTHONPATH": str(ROOT)}
        self.process = subprocess.Popen(
            [sys.executable, "-m", "app", "rooms", str(path)],
            cwd=ROOT,
            env=env,
            stdout=subprocess.PIPE,
            stderr=subprocess.STDOUT,
            text=True,
        )
        self._reader = threading.Thread(target=self._read, daemon=True)
        self._reader.start()

    def _read(self) -> None:
        assert self.process.stdout is not None
        for line in self.process.stdout:
            with self._new_line:
                self.lines.append(line.rstrip("\n"))
                self._new_line.notify_all()

    def log(self) -> str:
        return "\n".join(self.lines)

    def wait_line(self, pattern: str, timeout: float, start: int = 0) -> re.Match[str]:
        """The first log line (from line ``start`` on) matching ``pattern``; AssertionError after ``timeout``."""
        deadline = time.monotonic() + timeout
        regex = re.compile(pattern)
        with self._new_line:
            while True:
                for line in self.lines[start:]:
                    found = regex.search(line)
                    if found:
                        return found
                left = deadline - time.monotonic()
                if left <= 0 or (self.process.poll() is not None and not self._reader.is_alive()):
                    raise AssertionError(f"no log line matching {pattern!r} within {timeout} s:\n{self.log()}")
                self._new_line.wait(min(left, 0.2))

    def pids(self) -> dict[str, int]:
        """Each child's current pid by its label (``mech101``, ``homework 1``, ``nginx``), from the log."""
        found: dict[str, int] = {}
        for line in self.lines:
            match = re.search(r"\b(?:started|restarted) (.+?) \(pid (\d+)\)", line)
            if match:
                found[match.group(1)] = int(match.group(2))
        return found

    def url(self, path: str) -> str:
        return f"http://127.0.0.1:{self.port}{path}"

    def stop(self, signum: int = signal.SIGTERM, timeout: float = 15.0) -> int:
        """Send ``signum`` and wait for the command to end (SIGKILL after ``timeout`` s); its exit code."""
        if self.process.poll() is None:
            self.process.send_signal(signum)
            try:
                self.process.wait(timeout=timeout)
            except subprocess.TimeoutExpired:
                self.process.kill()
                self.process.wait(timeout=10)
        self._reader.join(timeout=5)
        return int(self.process.returncode)


@contextlib.contextmanager
def running_department(path: Path, port: int, timeout: float = 90.0) -> Iterator[RunningDepartment]:
    """The department of ``path`` running until the block ends (then stopped, and every child it started
    checked gone)."""
    department = RunningDepartment(path, port)
    try:
        department.wait_line(re.escape(READY), timeout)
        yield department
    finally:
        department.stop()
        left = [pid for pid in department.pids().values() if ours(pid)]
        for pid in left:  # a child left behind: killed here, and the test says so
            with contextlib.suppress(ProcessLookupError):
                os.kill(pid, signal.SIGKILL)
        if left:
            raise AssertionError(f"pids {left} outlived their department:\n{department.log()}")


def alive(pid: int) -> bool:
    """Whether ``pid`` is a running process (a zombie is not: it has exited)."""
    try:
        with open(f"/proc/{pid}/stat") as stat:
            return stat.read().rsplit(")", 1)[1].split()[0] != "Z"
    except (FileNotFoundError, ProcessLookupError):
        return False


def ours(pid: int) -> bool:
    """Whether ``pid`` is still a running room process or nginx (not a pid the system gave to another)."""
    if not alive(pid):
        return False
    try:
        command = Path(f"/proc/{pid}/cmdline").read_bytes().split(b"\0")
    except OSError:
        return False
    return (
        b"app" in command
        or any(part.endswith(b"nginx") or part.startswith(b"nginx") for part in command)
        or any(b"redis-server" in part for part in command)
    )


def room_cookie(port: int, room: str) -> tuple[str, str]:
    """A first visit to ``/room/`` without a cookie: the ``NAME=VALUE`` cookie nginx sets, and the backend
    that answered (``host:port``)."""
    connection = http.client.HTTPConnection("127.0.0.1", port, timeout=10)
    try:
        connection.request("GET", f"/{room}{PROBE}")
        response = connection.getresponse()
        response.read()
        cookie = response.getheader("Set-Cookie") or ""
        return cookie.split(";")[0], response.getheader(BACKEND_HEADER) or ""
    finally:
        connection.close()


def get(
    port: int, path: str, cookie: str | None = None, headers: dict[str, str] | None = None
) -> http.client.HTTPResponse:
    """A GET through the proxy (no redirect followed); the response, its body read into ``.body``
    (``headers``: more request headers, an Accept-Language say)."""
    connection = http.client.HTTPConnection("127.0.0.1", port, timeout=10)
    connection.request("GET", path, headers={**({"Cookie": cookie} if cookie else {}), **(headers or {})})
    response = connection.getresponse()
    response.body = response.read()  # type: ignore[attr-defined]
    connection.close()
    return response


def proxied(port: int, room: str, cookie: str | None = None, timeout: float = 30.0) -> ClientConnection:
    """viser's websocket to ``/room`` through the proxy, as the page opens it (its address without the
    trailing slash, the subprotocol ``viser-vX.Y.Z``, the room's cookie)."""
    ws = connect(
        f"ws://127.0.0.1:{port}/{room}",
        subprotocols=[SUBPROTOCOL],  # type: ignore[list-item]
        additional_headers={"Cookie": cookie} if cookie else None,
        max_size=None,
        open_timeout=timeout,
        close_timeout=1,
    )
    ws.send(CAMERA_MESSAGE)  # viser counts a client once it reports its camera, as the page does at once
    return ws


def backend_of(ws: ClientConnection) -> str:
    """The process that took this websocket (``host:port``, from the proxy's response header, which lists
    every process nginx tried: the last one answered)."""
    assert ws.response is not None
    return str(ws.response.headers.get(BACKEND_HEADER, "")).split(",")[-1].strip()


def redis_or_skip() -> str:
    """redis-server's binary, or a skip saying how to install it (a skip fails CI)."""
    try:
        return find_redis()
    except RedisMissing as exc:
        pytest.skip(str(exc))


class RedisServer:
    """``redis-server`` on 127.0.0.1:``port`` as ``rigid-body-lab rooms`` starts it; it can be killed and
    started again on the same port."""

    def __init__(self, port: int | None = None, config: Path | None = None, password: str | None = None) -> None:
        self.binary = redis_or_skip()
        self.port = port or _free_on("127.0.0.1")
        self.config, self.password = config, password  # a redis_conf file and its password, or neither
        self.process: subprocess.Popen[bytes] | None = None

    def start(self, timeout: float = 20.0) -> None:
        config = None if self.config is None else str(self.config)
        self.process = subprocess.Popen(
            redis_command(self.binary, "127.0.0.1", self.port, config),
            stdout=subprocess.DEVNULL,
            stderr=subprocess.DEVNULL,
        )
        deadline = time.monotonic() + timeout
        while not redis_answers("127.0.0.1", self.port, password=self.password):
            if self.process.poll() is not None or time.monotonic() > deadline:
                raise AssertionError(f"redis-server did not answer on 127.0.0.1:{self.port}")
            time.sleep(0.05)

    def kill(self) -> None:
        if self.process is not None and self.process.poll() is None:
            self.process.kill()
            self.process.wait(timeout=10)


@contextlib.contextmanager
def redis_server(config: Path | None = None, password: str | None = None) -> Iterator[RedisServer]:
    """A running :class:`RedisServer` (with the password ``config`` sets), killed when the block ends."""
    server = RedisServer(config=config, password=password)
    server.start()
    try:
        yield server
    finally:
        server.kill()
