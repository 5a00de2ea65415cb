"""``rigid-body-lab rooms ROOMS.toml [--write DIR]``: run a department here, or write its deployment.

Run (the default), in the foreground: the file is checked (every refusal names the room and the key),
nginx is found (or the ``apt-get install`` line printed), every port is checked free, nginx's
configuration is written into a temporary folder and tested with ``nginx -t``; only then the rooms'
processes start (after ``redis-server`` on loopback, when a private pool with a teacher PIN shares its
table and the file names no ``redis``: :mod:`app.rooms.redis_server`) (``sys.executable -m app ...``, one per presenter or shared room, ``processes`` per
private pool), and nginx once they answer. The supervisor restarts a process that dies and says so;
SIGTERM or Ctrl-C stops nginx and every process and removes the folder. A backend on an address that is
not this machine's (a room's ``hosts``) is not started here, only proxied to.

``--write DIR`` writes instead: ``rooms.conf`` (nginx's ``http`` part, for ``/etc/nginx/conf.d/``),
``nginx.conf`` (a whole configuration around it, run with ``-p DIR``), ``systemd/`` (a unit per process,
the proxy's unit, Redis's unit when a pool shares its teacher's table, a target) and ``README.txt`` saying which unit goes onto which machine.
"""

from __future__ import annotations

import argparse
import os
import signal
import subprocess
import sys
import tempfile
import time
from functools import partial
from pathlib import Path
from secrets import token_urlsafe
from types import FrameType

from app.rooms.config import (
    Backend,
    Department,
    Room,
    RoomsError,
    app_arguments,
    pin_environment,
    pool_environment,
    read_rooms,
)
from app.rooms.nginx import NginxMissing, find_nginx, nginx_command, nginx_conf, rooms_conf
from app.rooms.redis_server import (
    REDIS_UNIT,
    RedisMissing,
    find_redis,
    redis_answers,
    redis_command,
    redis_conf,
    redis_unit,
)
from app.rooms.supervisor import ChildSpec, Supervisor, is_local_address, port_free
from app.rooms.units import (
    PROXY_UNIT,
    TARGET,
    app_unit,
    is_loopback_host,
    machines,
    proxy_unit,
    target_unit,
    unit_name,
)
from app.teaching.pool_table import PASSWORD_VARIABLE

__all__ = ["READY", "check_ports", "main", "run", "write", "write_nginx", "write_private"]

READY = "Rooms ready on"
"""The start of the line printed once nginx and every room answer (tests wait for it)."""

SERVING = r"Rigid Body Lab serving on http://\S+:(\d+)"
"""The app's first line (``app/__main__.py``): the port it really listens on."""

APP_ROOT = str(Path(__file__).resolve().parents[2])
"""The folder holding the ``app`` package: the rooms' processes run this same code."""


def log(message: str) -> None:
    """One line of the department's log, timestamped, on stdout."""
    print(f"{time.strftime('%H:%M:%S')} {message}", flush=True)


def write_nginx(department: Department, folder: Path, *, backend_header: bool = False) -> None:
    """nginx.conf, rooms.conf and the logs/ and temp/ folders nginx needs, in ``folder``."""
    (folder / "logs").mkdir(parents=True, exist_ok=True)
    (folder / "temp").mkdir(exist_ok=True)
    (folder / "nginx.conf").write_text(nginx_conf())
    (folder / "rooms.conf").write_text(rooms_conf(department, backend_header=backend_header))


def check_ports(department: Department) -> list[tuple[Room, Backend]]:
    """The backends to start here (those on this machine's addresses), after checking that the proxy's
    port and each of their ports are free; RoomsError naming the room and the key if not."""
    if not port_free(department.listen_host, department.listen_port):
        raise RoomsError(f"{department.source}: key 'listen': {department.listen} is in use (or not this machine's)")
    local = []
    for i, room in enumerate(department.rooms, start=1):
        for backend in room.backends:
            if not is_local_address(backend.host):
                continue
            if not port_free(backend.host, backend.port):
                key = "port" if backend.host == "127.0.0.1" else "hosts"
                raise RoomsError(
                    f"{department.source}: room {room.name!r} (room {i}), key {key!r}: {backend.address} is in use"
                )
            local.append((room, backend))
    if department.redis is not None and not department.redis_given and not port_free(*department.redis):
        raise RoomsError(
            f"{department.source}: key 'redis': {department.redis_address} (the port after the rooms') is in use; "
            'name a free one for the Redis server (redis = "127.0.0.1:PORT")'
        )
    return local


def _pins(department: Department) -> list[str]:
    return [
        f"  /{room.name}/ {'presenter' if room.mode == 'presenter' else 'teacher'} PIN: {room.pin}"
        + ("" if room.pin_given else " (drawn at random)")
        for room in department.rooms
        if room.pin is not None
    ]


def run(department: Department, nginx: str) -> int:
    """Run the department in the foreground until SIGTERM or Ctrl-C; 0 when stopped cleanly."""
    local = check_ports(department)
    redis_binary = find_redis() if department.redis is not None and not department.redis_given else None
    supervisor = Supervisor(log)

    def stop(signum: int, frame: FrameType | None) -> None:
        supervisor.stopping.set()

    for signum in (signal.SIGTERM, signal.SIGINT, signal.SIGHUP):  # systemd, Ctrl-C, a closed terminal
        signal.signal(signum, stop)
    with tempfile.TemporaryDirectory(prefix="rigid-body-lab-rooms-") as tmp:
        folder = Path(tmp)
        folder.chmod(0o755)  # nginx's workers (user nobody when started as root) write its temp/ files
        write_nginx(department, folder, backend_header=True)
        test = subprocess.run(nginx_command(nginx, folder, test=True), capture_output=True, text=True, check=False)
        if test.returncode != 0:
            log(f"nginx refused the configuration written in {folder}:\n{test.stderr.strip()}")
            return 2
        log(f"nginx configuration and logs in {folder}")
        env = {"PYTHONPATH": os.pathsep.join(filter(None, [APP_ROOT, os.environ.get("PYTHONPATH")]))}
        rooms = []
        password = os.environ.get(PASSWORD_VARIABLE)  # a Redis named in the file: its password, if any
        if redis_binary is not None and department.redis is not None:  # first: the pools' processes use it
            host, port = department.redis
            password = token_urlsafe(24)  # this run's own server: a password of its own, in a 0600 file
            write_private(folder / "redis.conf", redis_conf(password))
            command = tuple(redis_command(redis_binary, host, port, str(folder / "redis.conf")))
            probe = partial(redis_answers, password=password)
            rooms.append(supervisor.add(ChildSpec("redis", command, host, port, probe=probe)))
        elif department.redis is not None:
            log(f"the teacher's table of private pools goes through the Redis at {department.redis_address}")
        for room, backend in local:
            label = room.name if len(room.backends) == 1 else f"{room.name} {backend.index}"
            command = (sys.executable, "-m", "app", *app_arguments(room, backend))
            # The PIN in its environment: never on a command line; and where its pool shares its table.
            own = {**env, **pin_environment(room), **pool_environment(department, room, backend)}
            if room.shares_table and password:
                own[PASSWORD_VARIABLE] = password
            spec = ChildSpec(label, command, backend.host, backend.port, own, port_said=SERVING)
            rooms.append(supervisor.add(spec))
        for room in department.rooms:
            for backend in room.backends:
                if not is_local_address(backend.host):
                    log(f"{room.name}: {backend.address} is another machine's: proxied to, not started here")
        proxy = supervisor.add(
            ChildSpec("nginx", tuple(nginx_command(nginx, folder)), department.listen_host, department.listen_port)
        )
        try:
            supervisor.start(rooms, timeout=60.0 + 5.0 * len(rooms))  # they start at once, sharing the cores
            supervisor.start([proxy], timeout=20.0)
        except RuntimeError as exc:
            log(f"the department did not start: {exc}")
            supervisor.stop()
            return 1
        if supervisor.stopping.is_set():
            supervisor.stop()
            return 0
        host = "127.0.0.1" if department.listen_host in ("0.0.0.0", "::") else department.listen_host
        url = f"http://{host}:{department.listen_port}/"
        log(f"{READY} {url} ({len(rooms)} room processes; Ctrl-C stops them all)")
        for room in department.rooms:
            log(f"  {url}{room.name}/  {room.mode}, {len(room.backends)} process(es), scene {room.scene or 'default'}")
        for line in _pins(department):
            log(line)
        supervisor.run()
        log("stopped: nginx and every room process")
    return 0


def write(department: Department, folder: Path, nginx: str | None) -> None:
    """Write the deployment into ``folder`` (see the module's docstring)."""
    folder = folder.resolve()
    write_nginx(department, folder)
    units = folder / "systemd"
    units.mkdir(exist_ok=True)
    where = machines(department)
    secrets = folder / "secrets"  # the PINs, for systemd (root) alone
    readable = [sys.base_prefix, sys.prefix, APP_ROOT]
    password = token_urlsafe(24) if department.redis is not None else None  # the Redis unit's
    for room in department.rooms:
        pins = pin_environment(room)
        if room.shares_table and password is not None:
            pins[PASSWORD_VARIABLE] = password
        for backend in room.backends:
            name = unit_name(room, backend)
            environment_file = None
            if pins:
                secrets.mkdir(mode=0o700, exist_ok=True)
                secrets.chmod(0o700)
                environment_file = secrets / name.replace(".service", ".env")
                write_private(environment_file, "".join(f"{k}={v}\n" for k, v in pins.items()))
            path = units / name
            text = app_unit(
                room,
                backend,
                sys.executable,
                workdir=APP_ROOT,
                environment_file=None if environment_file is None else str(environment_file),
                readable=readable,
                environment=pool_environment(department, room, backend),
            )
            path.write_text(text)
            path.chmod(0o644)  # no secret in it
    redis_lines = _write_redis(department, units, where, secrets, password)
    here = where.get("this machine", [])
    nginx_path = nginx or "/usr/sbin/nginx"
    (units / PROXY_UNIT).write_text(proxy_unit(nginx_path, folder, here))
    (units / TARGET).write_text(target_unit([*here, PROXY_UNIT]))
    lines = [
        f"Rigid Body Lab rooms from {department.source}, served on {department.listen}.",
        "",
        "Either run nginx with this folder as its prefix (the proxy's unit does):",
        f"  nginx -p {folder}/ -c {folder}/nginx.conf -g 'daemon off;'",
        "or copy rooms.conf into /etc/nginx/conf.d/ and reload the system's nginx.",
        "",
        "systemd units (copy to /etc/systemd/system/, then: systemctl daemon-reload;",
        f"systemctl enable --now {TARGET}):",
    ]
    for machine, names in where.items():
        lines.append(
            f"  {machine}: {' '.join(names)}" + (f" {PROXY_UNIT} {TARGET}" if machine == "this machine" else "")
        )
    others = [m for m in where if m != "this machine"]
    if others:
        lines += [
            "",
            "On each other machine: install Rigid Body Lab the same way (the units run",
            f"{sys.executable} -m app), copy its units and a target that wants them.",
        ]
    lines += redis_lines
    if _pins(department):
        lines += [
            "",
            f"The PINs are in {secrets}/ (mode 0600, for systemd), and here (this file is 0600):",
            *_pins(department),
        ]
    write_private(folder / "README.txt", "\n".join(lines) + "\n")


def _write_redis(
    department: Department, units: Path, where: dict[str, list[str]], secrets: Path, password: str | None
) -> list[str]:
    """Redis's unit, when a pool shares its teacher's table, added to the machine it runs on in ``where``,
    and its password in ``secrets/redis.conf`` (0600); the README's lines about it."""
    if department.redis is None or password is None:
        return []
    secrets.mkdir(mode=0o700, exist_ok=True)
    secrets.chmod(0o700)
    write_private(secrets / "redis.conf", redis_conf(password))
    host, port = department.redis
    machine = "this machine" if is_loopback_host(host) else host
    try:
        binary = find_redis()
    except RedisMissing:
        binary = "/usr/bin/redis-server"  # Debian's, on the machine the unit is for
    config = str(secrets / "redis.conf")
    (units / REDIS_UNIT).write_text(redis_unit(binary, host, port, TARGET, where.get(machine, []), config))
    where.setdefault(machine, []).insert(0, REDIS_UNIT)
    lines = [
        "",
        f"The teacher's table of a private pool goes through Redis at {department.redis_address}:",
        f"{REDIS_UNIT} runs it on {machine} (sudo apt-get install redis-server there; Debian's own",
        "redis-server.service can stay disabled). Every process of the pool connects to it with the",
        f"password in {secrets}/redis.conf (copy it with the unit; the pool's secrets/*.env hold it too).",
    ]
    if machine != "this machine":
        lines.append("Let only the pool's machines reach its port as well (a firewall rule).")
    return lines


def write_private(path: Path, text: str) -> None:
    """Write ``text`` to ``path`` readable by its owner alone (0600 from the moment it exists, and made 0600
    if it existed before)."""
    descriptor = os.open(path, os.O_WRONLY | os.O_CREAT | os.O_TRUNC, 0o600)
    with os.fdopen(descriptor, "w", encoding="utf-8") as handle:
        os.fchmod(handle.fileno(), 0o600)
        handle.write(text)


def main(argv: list[str]) -> int:
    """``rigid-body-lab rooms``: the exit status (2 for a refused file or missing nginx, as argparse)."""
    parser = argparse.ArgumentParser(
        prog="rigid-body-lab rooms",
        description="Serve a department: rooms behind nginx on one port, /NAME/ for each room of ROOMS.toml "
        "(presenter: one process; shared: one process; private: a pool of processes). In the foreground "
        "until Ctrl-C; with --write DIR, write nginx's configuration and systemd units instead.",
    )
    parser.add_argument("file", metavar="ROOMS.toml", help="the rooms file (see examples/rooms.toml)")
    parser.add_argument("--write", metavar="DIR", type=Path, default=None, help="write the deployment into DIR")
    parser.add_argument("--nginx", metavar="PATH", default=None, help="the nginx binary (default: found on PATH)")
    args = parser.parse_args(argv)
    try:
        department = read_rooms(args.file)
    except RoomsError as exc:
        print(f"rigid-body-lab rooms: refused: {exc}", file=sys.stderr, flush=True)
        return 2
    if args.write is not None:
        try:
            nginx: str | None = find_nginx(args.nginx)
        except NginxMissing:
            nginx = None  # the configuration is for another machine: written all the same
        write(department, args.write, nginx)
        print(f"written {args.write.resolve()} (README.txt there says what goes where)", flush=True)
        return 0
    try:
        nginx_binary = find_nginx(args.nginx)
        return run(department, nginx_binary)
    except (RoomsError, NginxMissing, RedisMissing) as exc:
        print(f"rigid-body-lab rooms: refused: {exc}", file=sys.stderr, flush=True)
        return 2
