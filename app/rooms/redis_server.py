"""The Redis server a private pool with a teacher PIN shares its teacher's table through.

``rigid-body-lab rooms`` starts Debian's ``redis-server`` on loopback when a pool of several processes has
a teacher PIN and the rooms file names no ``redis`` address (:func:`redis_command`: its own port, nothing
written to disk, a memory ceiling, keys with the shortest time to live dropped first if it is ever full:
every key the pool writes has one); with ``redis = "host:port"`` it uses that server (one for a pool on
several machines). ``--write`` writes its systemd unit (:func:`redis_unit`). What the processes keep in it
is :mod:`app.teaching.pool_table`.
"""

from __future__ import annotations

import shlex
import shutil
from collections.abc import Sequence

import redis

__all__ = [
    "MAXMEMORY",
    "REDIS_UNIT",
    "RedisMissing",
    "find_redis",
    "redis_answers",
    "redis_command",
    "redis_conf",
    "redis_unit",
]

REDIS_UNIT = "rigid-body-lab-redis.service"

MAXMEMORY = "64mb"
"""The server's memory ceiling: a pool of 300 sessions a process keeps well under 1 MB in it."""

DEBIAN = "/usr/bin/redis-server"


class RedisMissing(RuntimeError):
    """No ``redis-server`` binary: the message says how to install it."""


def find_redis(given: str | None = None) -> str:
    """The ``redis-server`` binary (``given``, else on PATH, else Debian's); :class:`RedisMissing` saying
    ``apt-get install redis-server`` if there is none."""
    for candidate in (given, shutil.which("redis-server"), DEBIAN):
        if candidate and shutil.which(candidate):
            return candidate
    raise RedisMissing(
        "a private pool with a teacher PIN shares its table through Redis, and redis-server is not installed: "
        'sudo apt-get install redis-server (or name a running server in the rooms file: redis = "host:port")'
    )


def redis_conf(password: str) -> str:
    """The server's configuration file: its password (a file readable by its owner alone, never a command
    line, where ``ps`` shows it to every user of the machine)."""
    return f"requirepass {password}\n"


def redis_command(binary: str, host: str, port: int, config: str | None = None) -> list[str]:
    """``redis-server`` in the foreground on ``host:port``: no snapshot, no append-only file, at most
    :data:`MAXMEMORY`, the keys closest to expiry evicted first; ``config``: the file of :func:`redis_conf`."""
    loopback = host.startswith("127.") or host in ("::1", "localhost")
    return [
        binary,
        *([config] if config is not None else []),
        "--bind",
        host,
        "--port",
        str(port),
        "--save",
        "",
        "--appendonly",
        "no",
        "--maxmemory",
        MAXMEMORY,
        "--maxmemory-policy",
        "volatile-ttl",
        # Off the loopback, the pool's other machines must reach it: the firewall keeps everyone else out.
        "--protected-mode",
        "yes" if loopback else "no",
        "--daemonize",
        "no",
        "--loglevel",
        "warning",
    ]


def redis_answers(host: str, port: int, timeout: float = 1.0, password: str | None = None) -> bool:
    """Whether a Redis server answers PING at ``host:port`` (with ``password``, if it has one)."""
    client = redis.Redis(
        host=host, port=port, password=password, socket_timeout=timeout, socket_connect_timeout=timeout
    )
    try:
        return bool(client.ping())
    except (redis.RedisError, OSError):
        return False
    finally:
        client.close()


def redis_unit(
    binary: str, host: str, port: int, target: str, app_units: Sequence[str], config: str | None = None
) -> str:
    """The Redis server's systemd unit (for the machine at ``host``), before the app units there; ``config``:
    the path of its :func:`redis_conf` (0600, root's), handed to the service as a credential."""
    given = "${CREDENTIALS_DIRECTORY}/redis.conf" if config is not None else None
    # systemd expands ${CREDENTIALS_DIRECTORY} in a word of its own: that one unquoted.
    command = " ".join(
        part if part == given else shlex.quote(part) for part in redis_command(binary, host, port, given)
    )
    lines = [
        "[Unit]",
        f"Description=Rigid Body Lab rooms: Redis for the teacher's table of private pools, on {host}:{port}",
        "After=network-online.target",
        "Wants=network-online.target",
        *([f"Before={' '.join(app_units)}"] if app_units else []),
        f"PartOf={target}",
        "",
        "[Service]",
        *([f"LoadCredential=redis.conf:{config}"] if config is not None else []),
        f"ExecStart={command}",
        "Restart=always",
        "RestartSec=1",
        "DynamicUser=yes",
        "NoNewPrivileges=yes",
        "ProtectSystem=strict",
        "ProtectHome=yes",
        "PrivateTmp=yes",
        "MemoryMax=256M",
        "",
        "[Install]",
        f"WantedBy={target}",
    ]
    return "\n".join(lines) + "\n"
