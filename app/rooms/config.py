"""A department's rooms file (``ROOMS.toml``): read it, check it, and say exactly what is wrong.

The file names where the proxy listens and the rooms behind it::

    listen = "127.0.0.1:8000"       # where the proxy listens ("0.0.0.0:80" on a server)
    redis = "10.0.0.5:6379"         # optional: the Redis a pool's teacher's table goes through (default:
                                    # started on loopback, on the port after the rooms', when one is needed)
    [[room]]
    name = "mech101"                # served at /mech101/
    mode = "presenter"              # presenter | private | shared
    pin = "111111"                  # presenter rooms only; 4 to 12 digits (default: six random digits)
    scene = "heavy_top"             # the scene shown first (default: the app's first scene)
    [[room]]
    name = "homework"
    mode = "private"
    processes = 2                   # private rooms only: a pool of processes, browsers spread over it
    pin = "246810"                  # a private room's teacher PIN: the table of every session of the pool
    port = 8201                     # optional: first backend port (default: after the proxy's port)
    hosts = ["10.0.0.5:8101", "10.0.0.6:8101"]   # optional: backends on other machines, one process each

Every refusal is a :class:`RoomsError` naming the room and the key, raised before anything starts.
A backend is one app process: ``sys.executable -m app --host H --port P`` with the room's mode
(:func:`app_arguments`); a presenter or shared room has exactly one, a private pool ``processes``.
A private pool of several processes with a teacher PIN shares its teacher's table through Redis
(:func:`pool_environment`, :mod:`app.teaching.pool_table`).
"""

from __future__ import annotations

import re
import secrets
import tomllib
from dataclasses import dataclass, field
from pathlib import Path
from typing import Any

from app.scenes import scene_names
from app.teaching.pool_table import POOL_VARIABLE, REDIS_VARIABLE

__all__ = [
    "MODES",
    "Backend",
    "Department",
    "Room",
    "RoomsError",
    "PIN_VARIABLE",
    "app_arguments",
    "pin_environment",
    "parse_address",
    "parse_rooms",
    "pool_environment",
    "read_rooms",
]

MODES = ("presenter", "private", "shared")
"""A room's modes: one lecture followed read-only; one simulation per browser; one simulation for all."""

NAME = re.compile(r"[a-z0-9][a-z0-9_-]{0,39}")
"""A room's name: its URL path (/NAME/), so lower-case letters, digits, '-' and '_' only."""

PIN = re.compile(r"[0-9]{4,12}")
TOP_KEYS = frozenset({"listen", "redis", "room", "title"})
ROOM_KEYS = frozenset({"name", "mode", "pin", "scene", "processes", "port", "hosts", "dark"})
DEFAULT_LISTEN = "127.0.0.1:8000"
DEFAULT_TITLE = "Rigid Body Lab"


class RoomsError(ValueError):
    """A rooms file the department cannot run: the message names the room and the key."""


@dataclass(frozen=True)
class Backend:
    """One app process of a room: where it listens (``host``, ``port``) and its place in the pool."""

    host: str
    port: int
    index: int = 1  # 1-based place in the room's pool (1 for a presenter or shared room)

    @property
    def address(self) -> str:
        """``host:port`` as nginx and a URL write it (an IPv6 host in brackets)."""
        return f"[{self.host}]:{self.port}" if ":" in self.host else f"{self.host}:{self.port}"


@dataclass(frozen=True)
class Room:
    """One room: served at ``/name/`` by its backends (one process, or a private pool)."""

    name: str
    mode: str
    backends: tuple[Backend, ...]
    scene: str | None = None
    pin: str | None = None  # presenter rooms: always set once read (given, or drawn at random); private: teacher PIN
    pin_given: bool = True  # False: the PIN was drawn at random when the file was read
    dark: bool = False

    @property
    def shares_table(self) -> bool:
        """A private pool of several processes with a teacher PIN: its table goes through Redis."""
        return self.mode == "private" and self.pin is not None and len(self.backends) > 1

    @property
    def ident(self) -> str:
        """The room's name as an nginx variable or cookie name accepts it (letters, digits, '_')."""
        return "rbl_" + self.name.replace("-", "_")


@dataclass(frozen=True)
class Department:
    """The whole file: where the proxy listens and the rooms, in the file's order."""

    listen_host: str
    listen_port: int
    rooms: tuple[Room, ...]
    title: str = DEFAULT_TITLE
    source: str = "ROOMS.toml"  # where it was read from, for messages
    redis: tuple[str, int] | None = None  # the Redis server (host, port), when a pool shares its table
    redis_given: bool = False  # named in the file (used, not started); False: started here on loopback

    @property
    def redis_address(self) -> str | None:
        """The Redis server as ``host:port`` (an IPv6 host in brackets), or None."""
        return None if self.redis is None else Backend(*self.redis).address

    @property
    def listen(self) -> str:
        """``host:port`` where the proxy listens, as nginx writes it (an IPv6 host in brackets)."""
        return Backend(self.listen_host, self.listen_port).address

    def room(self, name: str) -> Room:
        for room in self.rooms:
            if room.name == name:
                return room
        raise KeyError(name)


@dataclass
class _Where:
    """Who is speaking in a message: the file, and the room (by name and place) when there is one."""

    source: str
    room: str | None = None
    index: int | None = None
    used: dict[tuple[str, int], str] = field(default_factory=dict)  # address -> "room NAME" using it

    def error(self, key: str, problem: str) -> RoomsError:
        where = f"{self.source}: "
        if self.index is not None:
            where += f"room {self.index}, " if self.room is None else f"room {self.room!r} (room {self.index}), "
        return RoomsError(f"{where}key {key!r}: {problem}")


def parse_address(text: Any, default_host: str = "127.0.0.1") -> tuple[str, int]:
    """``"host:port"`` (or ``"[v6]:port"``, or ``"port"`` alone) as (host, port); ValueError if it is not."""
    if not isinstance(text, str) or not text:
        raise ValueError(f'expected "host:port" as a string, got {text!r}')
    host, sep, port_text = text.rpartition(":")
    if not sep:
        host, port_text = default_host, text
    if host.startswith("[") and host.endswith("]"):
        host = host[1:-1]
    if not host or not re.fullmatch(r"[A-Za-z0-9.:_-]+", host):
        raise ValueError(f'expected "host:port", got {text!r}')
    if not port_text.isdigit() or not 1 <= int(port_text) <= 65535:
        raise ValueError(f"the port of {text!r} must be a number from 1 to 65535")
    return host, int(port_text)


def read_rooms(path: str | Path, *, pin_source: Any = None) -> Department:
    """Read and check a rooms file; :class:`RoomsError` naming the room and the key if it is wrong."""
    path = Path(path)
    try:
        text = path.read_text(encoding="utf-8")
    except OSError as exc:
        raise RoomsError(f"{path}: cannot read it ({exc.strerror or exc})") from exc
    try:
        data = tomllib.loads(text)
    except tomllib.TOMLDecodeError as exc:
        raise RoomsError(f"{path}: not valid TOML ({exc})") from exc
    return parse_rooms(data, source=str(path), pin_source=pin_source)


def parse_rooms(data: dict[str, Any], *, source: str = "ROOMS.toml", pin_source: Any = None) -> Department:
    """Check a rooms file's parsed TOML and build the department (``pin_source``: draws a missing PIN,
    default six random digits)."""
    top = _Where(source)
    for key in data:
        if key not in TOP_KEYS:
            raise top.error(key, f"unknown key; the file's keys are {', '.join(sorted(TOP_KEYS))}")
    try:
        listen_host, listen_port = parse_address(data.get("listen", DEFAULT_LISTEN))
    except ValueError as exc:
        raise top.error("listen", str(exc)) from exc
    title = data.get("title", DEFAULT_TITLE)
    if not isinstance(title, str) or not title.strip():
        raise top.error("title", f"expected a non-empty string, got {title!r}")
    tables = data.get("room")
    if not isinstance(tables, list) or not tables or not all(isinstance(t, dict) for t in tables):
        raise top.error("room", "expected at least one [[room]] table")
    top.used[(listen_host, listen_port)] = "the proxy (key 'listen')"
    names: dict[str, int] = {}
    idents: dict[str, str] = {}
    drafts = [_room_draft(table, i, top, names, idents) for i, table in enumerate(tables, start=1)]
    # Rooms that name their ports first, so that a room placed automatically never takes a port a later
    # room names; then the others, each after the last port placed.
    placed: dict[int, tuple[Backend, ...]] = {}
    next_port = listen_port + 1
    for draft in sorted(drafts, key=lambda d: d["port"] is None and d["hosts"] is None):
        placed[draft["index"]], next_port = _backends(draft, top, next_port)
    redis = None
    sharing = any(d["mode"] == "private" and d["pin"] is not None and len(placed[d["index"]]) > 1 for d in drafts)
    if "redis" in data:
        try:
            redis = parse_address(data["redis"])
        except ValueError as exc:
            raise top.error("redis", str(exc)) from exc
        if redis in top.used:
            raise top.error("redis", f"{data['redis']} is already used by {top.used[redis]}")
    elif sharing:  # started here, on loopback, on the first port free after the rooms'
        while ("127.0.0.1", next_port) in top.used:
            next_port += 1
        if next_port > 65535:
            raise top.error("redis", "no port is left after the rooms' for the Redis server: name one")
        redis = ("127.0.0.1", next_port)
    far = [
        d["name"]
        for d in drafts
        if d["mode"] == "private" and d["pin"] is not None and len(placed[d["index"]]) > 1
        for b in placed[d["index"]]
        if not _loopback(b.host)
    ]
    if far and redis is not None and _loopback(redis[0]):
        raise top.error(
            "redis",
            f"room {far[0]!r} has processes on other machines, which cannot reach a Redis on loopback: "
            'name one they all reach (redis = "10.0.0.5:6379")',
        )
    rooms = []
    for draft in drafts:
        backends = placed[draft["index"]]
        pin = draft["pin"]
        pin_given = pin is not None
        if draft["mode"] == "presenter" and pin is None:
            pin = (pin_source or _random_pin)()
        rooms.append(
            Room(
                name=draft["name"],
                mode=draft["mode"],
                backends=backends,
                scene=draft["scene"],
                pin=pin,
                pin_given=pin_given,
                dark=draft["dark"],
            )
        )
    return Department(
        listen_host,
        listen_port,
        tuple(rooms),
        title=title.strip(),
        source=source,
        redis=redis if sharing or "redis" in data else None,
        redis_given="redis" in data,
    )


def _loopback(host: str) -> bool:
    return host == "localhost" or host == "::1" or host.startswith("127.")


def _random_pin() -> str:
    return f"{secrets.randbelow(10**6):06d}"


def _room_draft(
    table: dict[str, Any], index: int, top: _Where, names: dict[str, int], idents: dict[str, str]
) -> dict[str, Any]:
    """One [[room]] table checked key by key (its ports are placed later, once every room is read)."""
    name = table.get("name")
    where = _Where(top.source, name if isinstance(name, str) else None, index)
    for key in table:
        if key not in ROOM_KEYS:
            raise where.error(key, f"unknown key; a room's keys are {', '.join(sorted(ROOM_KEYS))}")
    if name is None:
        raise where.error("name", "missing: every room needs a name (its address is /NAME/)")
    if not isinstance(name, str) or not NAME.fullmatch(name):
        raise where.error(
            "name", "expected 1 to 40 lower-case letters, digits, '-' or '_', starting with a letter or digit"
        )
    if name in names:
        raise where.error("name", f"duplicate: room {names[name]} is also called {name!r}")
    names[name] = index
    ident = "rbl_" + name.replace("-", "_")
    if ident in idents:
        raise where.error("name", f"too close to room {idents[ident]!r}: '-' and '_' would name the same cookie")
    idents[ident] = name
    mode = table.get("mode")
    if mode is None:
        raise where.error("mode", f"missing; choose one of {', '.join(MODES)}")
    if mode not in MODES:
        raise where.error("mode", f"unknown mode {mode!r}; choose one of {', '.join(MODES)}")
    pin = table.get("pin")
    if pin is not None:
        if mode == "shared":
            raise where.error(
                "pin", "a PIN drives a presenter room or opens a private room's teacher's view; this room is shared"
            )
        if not isinstance(pin, str) or not PIN.fullmatch(pin):
            raise where.error("pin", f'expected 4 to 12 digits as a string (pin = "123456"), got {pin!r}')
    scene = table.get("scene")
    if scene is not None:
        known = scene_names()
        if scene not in known:
            raise where.error("scene", f"unknown scene {scene!r}; choose one of {', '.join(known)}")
    processes = table.get("processes", 1)
    if not isinstance(processes, int) or isinstance(processes, bool):
        raise where.error("processes", f"expected a whole number, got {processes!r}")
    if processes < 1:
        raise where.error("processes", f"must be at least 1, got {processes}")
    if processes > 1 and mode != "private":
        raise where.error(
            "processes",
            f"only a private room is a pool; a {mode} room is one process (its class shares one simulation)",
        )
    dark = table.get("dark", False)
    if not isinstance(dark, bool):
        raise where.error("dark", f"expected true or false, got {dark!r}")
    return {
        "name": name,
        "mode": mode,
        "pin": pin,
        "scene": scene,
        "processes": processes,
        "processes_given": "processes" in table,
        "port": table.get("port"),
        "hosts": table.get("hosts"),
        "dark": dark,
        "index": index,
    }


def _backends(draft: dict[str, Any], top: _Where, next_port: int) -> tuple[tuple[Backend, ...], int]:
    """The room's backends, each address checked against every address used so far."""
    where = _Where(top.source, draft["name"], draft["index"])
    hosts, port = draft["hosts"], draft["port"]
    addresses: list[tuple[str, int]] = []
    if hosts is not None and port is not None:
        raise where.error("port", "give 'port' or 'hosts' (each with its own port), not both")
    if hosts is not None:
        if not isinstance(hosts, list) or not hosts:
            raise where.error("hosts", 'expected a list of "host:port" strings, one per process')
        for text in hosts:
            try:
                addresses.append(parse_address(text))
            except ValueError as exc:
                raise where.error("hosts", str(exc)) from exc
        if draft["processes_given"] and draft["processes"] != len(hosts):
            raise where.error(
                "processes", f"{draft['processes']} processes but {len(hosts)} hosts: each host entry is one process"
            )
        if len(hosts) > 1 and draft["mode"] != "private":
            raise where.error("hosts", f"only a private room is a pool; a {draft['mode']} room has one host")
        key = "hosts"
    else:
        if port is not None and (not isinstance(port, int) or isinstance(port, bool) or not 1 <= port <= 65535):
            raise where.error("port", f"expected a port number from 1 to 65535, got {port!r}")
        first = next_port if port is None else port
        if port is None:  # placed after the ports already taken, skipping any a later room names
            while any(("127.0.0.1", p) in top.used for p in range(first, first + draft["processes"])):
                first += 1
        if first + draft["processes"] - 1 > 65535:
            raise where.error("port", f"{draft['processes']} processes from port {first} run past 65535")
        addresses = [("127.0.0.1", p) for p in range(first, first + draft["processes"])]
        next_port = max(next_port, first + draft["processes"]) if port is None else next_port
        key = "port"
    for address in addresses:
        if address in top.used:
            shown = f"{address[0]}:{address[1]}"
            raise where.error(key, f"duplicate port: {shown} is already used by {top.used[address]}")
        top.used[address] = f"room {draft['name']!r}"
    backends = tuple(Backend(host, p, i) for i, (host, p) in enumerate(addresses, start=1))
    return backends, next_port


PIN_VARIABLE = "RBL_PIN"
"""The environment variable the app takes its PIN from when no ``--pin`` is given: a presenter room's PIN
is never on a command line, where ``ps`` shows it to every user of the machine."""


def pin_environment(room: Room) -> dict[str, str]:
    """What a room's process needs in its environment: the presenter PIN or a private room's teacher PIN
    (:data:`PIN_VARIABLE`), or nothing."""
    return {PIN_VARIABLE: str(room.pin)} if room.mode in ("presenter", "private") and room.pin is not None else {}


def pool_environment(department: Department, room: Room, backend: Backend) -> dict[str, str]:
    """Where a pool's process shares its teacher's table (:mod:`app.teaching.pool_table`): the Redis server
    and ``NAME INDEX SIZE``; nothing for a room that does not share one (:attr:`Room.shares_table`)."""
    if not room.shares_table or department.redis_address is None:
        return {}
    return {
        REDIS_VARIABLE: department.redis_address,
        POOL_VARIABLE: f"{room.name} {backend.index} {len(room.backends)}",
    }


def app_arguments(room: Room, backend: Backend, *, host: str | None = None) -> list[str]:
    """The app's command-line arguments for one backend (after ``python -m app``); ``host``: the address
    it binds (default the backend's own)."""
    args = ["--host", host or backend.host, "--port", str(backend.port)]
    if room.scene is not None:
        args += ["--scene", room.scene]
    if room.mode == "presenter":
        args += ["--presenter"]  # the PIN goes in the environment (pin_environment)
    elif room.mode == "private":
        args += ["--private"]
    else:
        args += ["--shared"]
    if room.dark:
        args += ["--dark"]
    return args
