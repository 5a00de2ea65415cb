"""systemd units for a deployment: one service per app process, one for the proxy, and a target for all.

Each room's process is ``rigid-body-lab-NAME.service`` (a pool's are ``rigid-body-lab-NAME-1.service``,
``-2``, ...), restarted by systemd when it dies. A backend on another machine (the room's ``hosts``)
gets its unit too: it is copied to that machine (:func:`machines` says which unit goes where). The
proxy's unit runs nginx with the written configuration; ``rigid-body-lab.target`` starts and stops
everything that runs on one machine.

An app's unit runs it as a user of its own made for it (``DynamicUser=``), with the file system read-only
(``ProtectSystem=strict``), homes hidden, a private /tmp, no new privileges and a memory ceiling; the mesh
worker it starts is in the same cgroup, under the same limits. A presenter room's PIN is never on a command
line: systemd reads it from an ``EnvironmentFile=`` only root can read (``--write`` writes it 0600), and the
app takes it from the environment (:data:`app.rooms.config.PIN_VARIABLE`).
"""

from __future__ import annotations

import shlex
from collections.abc import Mapping, Sequence
from pathlib import Path, PurePath

from app.rooms.config import Backend, Department, Room, app_arguments

__all__ = [
    "HARDENING",
    "MEMORY_MAX",
    "PROXY_UNIT",
    "TARGET",
    "app_unit",
    "is_loopback_host",
    "machines",
    "proxy_unit",
    "target_unit",
    "unit_name",
]

TARGET = "rigid-body-lab.target"
PROXY_UNIT = "rigid-body-lab-proxy.service"


MEMORY_MAX = "2G"
"""The memory ceiling of one app process and its mesh worker (which alone may take 1 GiB: app.uploads.limits)."""

HARDENING = (
    "DynamicUser=yes",
    "NoNewPrivileges=yes",
    "ProtectSystem=strict",
    "PrivateTmp=yes",
    "ProtectKernelTunables=yes",
    "ProtectKernelModules=yes",
    "ProtectControlGroups=yes",
    "RestrictSUIDSGID=yes",
    "LockPersonality=yes",
    "UMask=0077",
    "RestrictAddressFamilies=AF_INET AF_INET6 AF_UNIX",
    "CapabilityBoundingSet=",
    f"MemoryMax={MEMORY_MAX}",
    "TasksMax=512",
    # 400 websockets, up to 1000 refusals held back (app.guards.admission.MOST_HELD), the files: over 1024.
    "LimitNOFILE=8192",
    # numba's compiled kernels are cached here (the installed tree is read-only to the service).
    "CacheDirectory=rigid-body-lab",
    "Environment=NUMBA_CACHE_DIR=/var/cache/rigid-body-lab",
)
"""The sandbox of every app unit (``ProtectHome=`` is added by :func:`app_unit`: it depends on where
Python is installed)."""

_HOMES = ("/home", "/root", "/run/user")


def _under_a_home(path: str) -> bool:
    return any(PurePath(path).is_relative_to(home) for home in _HOMES)


def unit_name(room: Room, backend: Backend) -> str:
    """``rigid-body-lab-NAME.service``, or ``rigid-body-lab-NAME-I.service`` for process I of a pool."""
    suffix = f"-{backend.index}" if len(room.backends) > 1 else ""
    return f"rigid-body-lab-{room.name}{suffix}.service"


def _exec(command: Sequence[str]) -> str:
    return " ".join(shlex.quote(part) for part in command)


def app_unit(
    room: Room,
    backend: Backend,
    python: str,
    *,
    workdir: str | None = None,
    environment_file: str | None = None,
    readable: Sequence[str] = (),
    environment: Mapping[str, str] | None = None,
) -> str:
    """The unit of one app process: ``python -m app`` with the room's mode on the backend's address.

    Parameters
    ----------
    room, backend : Room, Backend
        The room and which of its processes.
    python : str
        The interpreter to run.
    workdir : str, optional
        The directory the app runs in (the installed tree).
    environment_file : str, optional
        A presenter room's file of ``RBL_PIN=...`` (mode 0600, read by systemd before it drops privileges).
    readable : sequence of str
        Directories the service must read (Python's prefix, the installed tree). Homes are hidden
        (``ProtectHome=yes``); when one of these is in a home, homes are an empty ``tmpfs`` instead, with
        these directories bound read-only into it.
    environment : mapping of str to str, optional
        Variables that are no secret (where a pool shares its teacher's table:
        :func:`app.rooms.config.pool_environment`).
    """
    command = [python, "-m", "app", *app_arguments(room, backend)]
    lines = [
        "[Unit]",
        f"Description=Rigid Body Lab room {room.name} ({room.mode}), process {backend.index} on {backend.address}",
        "After=network-online.target",
        "Wants=network-online.target",
        f"PartOf={TARGET}",
        "",
        "[Service]",
        f"ExecStart={_exec(command)}",
        "Environment=PYTHONUNBUFFERED=1",
        *(f'Environment="{key}={value}"' for key, value in (environment or {}).items()),
    ]
    if environment_file is not None:
        lines.append(f"EnvironmentFile={environment_file}")
    if workdir is not None:
        lines.append(f"WorkingDirectory={workdir}")
    homes = sorted({path for path in readable if _under_a_home(path)})
    lines += [
        "Restart=always",
        "RestartSec=2",
        "KillSignal=SIGTERM",
        "TimeoutStopSec=10",
        *HARDENING,
        "ProtectHome=tmpfs" if homes else "ProtectHome=yes",
    ]
    if homes:
        lines.append("BindReadOnlyPaths=" + " ".join(homes))
    lines += ["", "[Install]", f"WantedBy={TARGET}"]
    return "\n".join(lines) + "\n"


def proxy_unit(nginx: str, folder: Path, local_units: Sequence[str]) -> str:
    """The proxy's unit: nginx in the foreground with the written configuration (``folder`` is its prefix)."""
    folder = folder.resolve()
    after = " ".join(local_units)
    command = [nginx, "-p", f"{folder}/", "-c", str(folder / "nginx.conf"), "-g", "daemon off;"]
    lines = [
        "[Unit]",
        "Description=Rigid Body Lab rooms: nginx in front of the rooms",
        "After=network-online.target" + (f" {after}" if after else ""),
        "Wants=network-online.target",
        f"PartOf={TARGET}",
        "",
        "[Service]",
        f"ExecStartPre={_exec([nginx, '-t', '-q', '-p', f'{folder}/', '-c', str(folder / 'nginx.conf')])}",
        f"ExecStart={_exec(command)}",
        "ExecReload=/bin/kill -HUP $MAINPID",
        "KillSignal=SIGTERM",
        "Restart=always",
        "RestartSec=2",
        "",
        "[Install]",
        f"WantedBy={TARGET}",
    ]
    return "\n".join(lines) + "\n"


def target_unit(units: Sequence[str]) -> str:
    """The target that starts every unit of one machine (``systemctl start rigid-body-lab.target``)."""
    wants = f"Wants={' '.join(units)}\n" if units else ""
    return (
        "[Unit]\nDescription=Rigid Body Lab rooms (every process on this machine)\n"
        f"{wants}\n[Install]\nWantedBy=multi-user.target\n"
    )


def is_loopback_host(host: str) -> bool:
    """127.0.0.0/8, ::1 or localhost: a backend on the proxy's own machine."""
    return host == "localhost" or host == "::1" or host.startswith("127.")


def machines(department: Department) -> dict[str, list[str]]:
    """Which app units run on which machine: ``"this machine"`` (the proxy's) for loopback backends,
    otherwise the backend's host."""
    where: dict[str, list[str]] = {}
    for room in department.rooms:
        for backend in room.backends:
            here = is_loopback_host(backend.host)
            where.setdefault("this machine" if here else backend.host, []).append(unit_name(room, backend))
    return where
