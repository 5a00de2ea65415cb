"""The teacher's table shared by the processes of a private pool, through Redis.

Each process of a pool (``rigid-body-lab rooms`` runs ``processes`` of them, perhaps on several machines)
knows only its own sessions. A :class:`PoolTable` shares them: a thread of its own (``rbl-pool``) does all
of the Redis I/O, never the event loop nor a frame:

* **publish**: this process's rows as one small JSON value under ``rbl:POOL:r:I`` (I: its place in the
  pool) with a time to live of :data:`TTL` s, written again when a row changes (looked at every
  :data:`PERIOD` s; a running clock's time alone is not a change) and at least every :data:`KEEPALIVE` s; a process that dies stops writing, and its
  rows are gone from every table within :data:`TTL` + :data:`PERIOD` s;
* **read**: while this process has a teacher (``watching``), the other processes' versions
  (``rbl:POOL:v:I``, a few bytes) every :data:`PERIOD` s, and their rows when a version moved; every value is untrusted text, checked field by field (:func:`decode_rows`);
* **answer**: a Spotlight asked of this process (a request pushed on ``rbl:POOL:q:I``) with the state text
  the process already makes (:meth:`app.serving.simulation.Simulation.state_text`), pushed on the asker's
  reply key; :meth:`PoolTable.ask` is the asking side, with a timeout.

Redis down or unreachable: the table is this process's rows alone (``available`` False, the teacher is told),
and the thread tries again after 0.5, 1, 2, 4 s (at most :data:`MAX_BACKOFF`): the rooms keep serving, and
the table comes back by itself. The footprint is bounded: at most :data:`MAX_ROWS` rows a process, values
at most :data:`MAX_VALUE` bytes, every key with a time to live, a request queue of :data:`MAX_REQUESTS`.

A process learns its pool from its environment (:func:`place_from_environment`): ``RBL_REDIS`` (the
server, ``host:port``), ``RBL_POOL`` (``NAME INDEX SIZE``) and ``RBL_REDIS_PASSWORD`` (the server's
password, if it has one), which ``rigid-body-lab rooms`` sets.
"""

from __future__ import annotations

import json
import math
import os
import re
import secrets
import threading
import time
import traceback
from collections.abc import Callable, Mapping, Sequence
from dataclasses import dataclass, field, replace
from typing import Any

import redis
from redis.backoff import NoBackoff
from redis.retry import Retry

__all__ = [
    "KEEPALIVE",
    "MAX_BACKOFF",
    "MAX_REQUESTS",
    "MAX_ROWS",
    "MAX_VALUE",
    "PERIOD",
    "PASSWORD_VARIABLE",
    "POOL_VARIABLE",
    "REDIS_VARIABLE",
    "TTL",
    "PoolPlace",
    "PoolRow",
    "PoolTable",
    "SessionFields",
    "decode_rows",
    "encode_rows",
    "place_from_environment",
]

REDIS_VARIABLE = "RBL_REDIS"
"""The environment variable naming the pool's Redis server, ``host:port``."""

PASSWORD_VARIABLE = "RBL_REDIS_PASSWORD"
"""The environment variable holding the Redis server's password (never on a command line)."""

POOL_VARIABLE = "RBL_POOL"
"""The environment variable naming the pool and this process's place in it: ``NAME INDEX SIZE``."""

PERIOD = 0.1
"""Seconds between two looks at this process's rows (and, with a teacher here, two reads of the others')."""

KEEPALIVE = 1.0
"""Seconds after which the rows are written again even if none changed (their time moves on)."""

TTL = 2.5
"""Seconds a process's rows live in Redis after its last write: a dead process's rows leave every table
within TTL + PERIOD (+ the table's own refresh)."""

MAX_BACKOFF = 4.0
"""The longest wait, s, before trying an unreachable Redis again."""

MAX_ROWS = 300
"""Rows a process publishes at most (the app's default cap on sessions), and reads at most from another."""

MAX_VALUE = 256 * 1024
"""Bytes a process's published rows may take; a longer value read is refused whole."""

MAX_REQUESTS = 16
"""Spotlight requests waiting for one process at most (older ones are dropped)."""

ANSWER_TTL = 10
"""Seconds a request queue or an answer lives in Redis if nobody takes it."""

_NAME = re.compile(r"[a-z0-9][a-z0-9_-]{0,39}")
_TEXT = 64  # longest name, scene, label or value kept from another process's row, characters


@dataclass(frozen=True)
class PoolPlace:
    """Where a process is: the Redis server, its pool's name and its place (1-based) among ``size``."""

    host: str
    port: int
    pool: str
    index: int
    size: int
    password: str | None = field(default=None, repr=False)

    def owner(self, number: int) -> int:
        """The place of the process that numbers its sessions ``index, index + size, ...`` and so gave ``number``."""
        return (number - 1) % self.size + 1

    def key(self, kind: str, which: int | str) -> str:
        """A short key of this pool: ``rbl:POOL:KIND:WHICH``."""
        return f"rbl:{self.pool}:{kind}:{which}"


def place_from_environment(environ: Mapping[str, str] | None = None) -> PoolPlace | None:
    """The place :data:`REDIS_VARIABLE` and :data:`POOL_VARIABLE` give; None if either is unset.

    Raises
    ------
    ValueError
        A variable that is set but malformed (what was expected and what came).
    """
    environ = os.environ if environ is None else environ
    address, pool = environ.get(REDIS_VARIABLE), environ.get(POOL_VARIABLE)
    if not address or not pool:
        return None
    host, sep, port = address.rpartition(":")
    host = host[1:-1] if host.startswith("[") and host.endswith("]") else host
    if not sep or not host or not port.isdigit() or not 1 <= int(port) <= 65535:
        raise ValueError(f'{REDIS_VARIABLE} must be "host:port", got {address!r}')
    parts = pool.split()
    if len(parts) != 3 or not _NAME.fullmatch(parts[0]) or not parts[1].isdigit() or not parts[2].isdigit():
        raise ValueError(f'{POOL_VARIABLE} must be "NAME INDEX SIZE" (e.g. "homework 1 2"), got {pool!r}')
    index, size = int(parts[1]), int(parts[2])
    if not 1 <= index <= size <= 1000:
        raise ValueError(f"{POOL_VARIABLE}: the place must be 1 to SIZE (at most 1000), got {index} of {size}")
    return PoolPlace(host, int(port), parts[0], index, size, environ.get(PASSWORD_VARIABLE) or None)


@dataclass(frozen=True)
class SessionFields:
    """What the teacher's table says of one session, wherever it runs (see :class:`app.teaching.teacher.Row`)."""

    number: int
    name: str
    scene: str
    parameters: tuple[tuple[str, str], ...]
    time: float
    playing: bool


@dataclass(frozen=True)
class PoolRow(SessionFields):
    """One session as the pool shares it; ``active_at`` is the wall clock, s, of its student's last action
    (not the seconds since: an unchanged row is an unchanged value)."""

    active_at: float


def encode_rows(rows: Sequence[PoolRow]) -> bytes:
    """Rows as the compact JSON a process publishes (at most :data:`MAX_ROWS`)."""
    return json.dumps(
        [
            [r.number, r.name, r.scene, [list(p) for p in r.parameters], round(r.time, 1), int(r.playing), r.active_at]
            for r in rows[:MAX_ROWS]
        ],
        separators=(",", ":"),
        ensure_ascii=False,
    ).encode()


def _text(value: Any) -> str:
    if not isinstance(value, str):
        raise ValueError(f"expected text, got {type(value).__name__}")
    return value[:_TEXT]


def _finite(value: Any) -> float:
    if isinstance(value, bool) or not isinstance(value, (int, float)) or not math.isfinite(value):
        raise ValueError(f"expected a finite number, got {value!r}")
    return float(value)


def decode_rows(value: bytes | str | None, place: PoolPlace, index: int) -> list[PoolRow]:
    """The rows process ``index`` published, checked: a value too long or not JSON gives none; a row with a
    field of the wrong type, or a number that process does not give (:meth:`PoolPlace.owner`), is left
    out; texts are cut to 64 characters (the table escapes them where it shows them)."""
    if value is None or len(value) > MAX_VALUE:
        return []
    try:
        data = json.loads(value)
    except ValueError:
        return []
    if not isinstance(data, list):
        return []
    rows = []
    for item in data[:MAX_ROWS]:
        try:
            number, name, scene, params, t, playing, active_at = item
            if isinstance(number, bool) or not isinstance(number, int) or not 1 <= number < 10**9:
                raise ValueError(f"a session number from 1 to 10**9, got {number!r}")
            if place.owner(number) != index:
                raise ValueError(f"session {number} is not one process {index} gives")
            if not isinstance(params, list) or len(params) > 3:
                raise ValueError("at most three parameters")
            pairs = tuple((_text(p[0]), _text(p[1])) for p in params if isinstance(p, list) and len(p) == 2)
            rows.append(
                PoolRow(number, _text(name), _text(scene), pairs, _finite(t), bool(playing), _finite(active_at))
            )
        except (ValueError, TypeError):
            continue  # one bad row: the others still show
    return rows


class PoolTable:
    """This process's part of a pool's shared table (see the module's docstring).

    Parameters
    ----------
    place : PoolPlace
        The Redis server and this process's place in its pool.
    local_rows : callable() -> list of PoolRow
        This process's rows now (called on the pool's thread every :data:`PERIOD` s).
    answer : callable(number) -> str
        The state text of this process's session ``number``, for a Spotlight asked from another process;
        raises ValueError with what to tell the teacher (a session that left, a teacher's, no scene).
    watching : callable() -> bool
        Whether a teacher is here (only then are the other processes' rows read).
    changed : callable(), optional
        Called on the pool's thread when the other processes' rows (or ``available``) changed.
    """

    def __init__(
        self,
        place: PoolPlace,
        local_rows: Callable[[], list[PoolRow]],
        answer: Callable[[int], str],
        watching: Callable[[], bool],
        changed: Callable[[], None] | None = None,
    ) -> None:
        self.place = place
        self._local_rows = local_rows
        self._answer = answer
        self._watching = watching
        self._changed = changed or (lambda: None)
        self._redis = redis.Redis(
            host=place.host,
            port=place.port,
            password=place.password,
            socket_timeout=5.0,  # longer than any blocking pop below
            socket_connect_timeout=1.0,
            retry=Retry(NoBackoff(), 0),  # the thread's own back-off retries; a Spotlight fails at once
            max_connections=8,  # the pool's thread and a few Spotlights at once
        )
        self.available = False
        self.writes = 0  # rows written, for tests and the benchmark
        self.failures = 0  # cycles Redis did not answer
        self._remote: dict[int, list[PoolRow]] = {}
        self._lock = threading.Lock()
        self._stop = threading.Event()
        self._thread: threading.Thread | None = None
        self._last: bytes | None = None
        self._last_write = 0.0
        self._instance = secrets.token_hex(4)  # a restarted process's versions never repeat its predecessor's
        self._seen: dict[int, Any] = {}  # the version of each other process's rows read last

    @property
    def address(self) -> str:
        """The Redis server, ``host:port``."""
        return f"{self.place.host}:{self.place.port}"

    def remote_rows(self) -> list[PoolRow]:
        """The other processes' rows as last read (none while Redis is unreachable or no teacher is here)."""
        with self._lock:
            return [row for rows in self._remote.values() for row in rows]

    # ------------------------------------------------------------------ the thread
    def start(self) -> None:
        """Start the pool's thread (daemon); a second call does nothing."""
        if self._thread is not None:
            return
        self._stop.clear()
        self._thread = threading.Thread(target=self._run, name="rbl-pool", daemon=True)
        self._thread.start()

    def stop(self) -> None:
        """Stop the thread and take this process's rows out of the table at once (if Redis answers)."""
        self._stop.set()
        if self._thread is not None:
            self._thread.join(timeout=7.0)
            self._thread = None
        try:
            self._redis.delete(self.place.key("r", self.place.index))
        except (redis.RedisError, OSError):
            pass
        self._redis.close()

    def _run(self) -> None:
        backoff = 0.5
        while not self._stop.is_set():
            began = time.monotonic()
            try:
                self.cycle()
                backoff = 0.5
                # A fixed pace of our own (a blocking pop's timeout would follow Redis's 10 Hz clock).
                self._stop.wait(max(0.0, PERIOD - (time.monotonic() - began)))
            except (redis.RedisError, OSError) as exc:
                if self.available:
                    print(f"the pool's table: Redis at {self.address} unreachable ({exc}); retrying", flush=True)
                self.failures += 1
                self._lost()
                self._stop.wait(backoff)
                backoff = min(MAX_BACKOFF, backoff * 2.0)
            except Exception:  # noqa: BLE001 - a bug in one cycle must not end the table
                traceback.print_exc()
                self._stop.wait(PERIOD)

    def _lost(self) -> None:
        with self._lock:
            was = self.available or bool(self._remote)
            self.available = False
            self._remote = {}
            self._seen = {}
            self._last = None  # written again whole once Redis is back
        if was:
            self._changed()

    def cycle(self) -> None:
        """One turn of the thread: publish (if changed or due), read (if watched), answer the requests
        waiting. Raises redis.RedisError or OSError when Redis does not answer."""
        place = self.place
        rows = self._local_rows()
        # What a change is: anything but a running clock's time, which the keep-alive carries once a second.
        signature = encode_rows([replace(r, time=0.0) if r.playing else r for r in rows])
        now = time.monotonic()
        if signature != self._last or now - self._last_write >= KEEPALIVE:
            pipe = self._redis.pipeline(transaction=False)
            pipe.set(place.key("r", place.index), encode_rows(rows), px=int(TTL * 1000))
            # A short version beside it: a reader fetches the rows only when it moved.
            pipe.set(place.key("v", place.index), f"{self._instance}.{self.writes + 1}", px=int(TTL * 1000))
            pipe.execute()
            self.writes += 1
            self._last, self._last_write = signature, now
        came_back = not self.available
        remote: dict[int, list[PoolRow]] = {}
        if self._watching():
            remote = self._read_others()
        else:
            self._seen = {}
        with self._lock:
            moved = remote != self._remote or came_back
            self._remote, self.available = remote, True
        if moved:
            self._changed()
        for _ in range(MAX_REQUESTS):
            request = self._redis.lpop(place.key("q", place.index))
            if not isinstance(request, (bytes, str)):  # None: the queue is empty (a count was not asked)
                break
            self._serve(request)

    def _read_others(self) -> dict[int, list[PoolRow]]:
        """The other processes' rows: their versions read every cycle (a few bytes each), their rows only
        when a version moved; a process whose version expired is gone."""
        place = self.place
        others = [i for i in range(1, place.size + 1) if i != place.index]
        if not others:
            return {}
        versions = self._redis.mget([place.key("v", i) for i in others])
        with self._lock:
            remote = {i: rows for i, rows in self._remote.items() if i in others}
        moved = [i for i, v in zip(others, versions, strict=True) if v is not None and self._seen.get(i) != v]
        for i, v in zip(others, versions, strict=True):
            if v is None:
                remote.pop(i, None)
                self._seen.pop(i, None)
        if moved:
            values = self._redis.mget([place.key("r", i) for i in moved])
            for i, value in zip(moved, values, strict=True):
                remote[i] = decode_rows(value, place, i)
                self._seen[i] = versions[others.index(i)]
        return {i: rows for i, rows in remote.items() if rows}

    def _serve(self, raw: bytes | str) -> None:
        """Answer one Spotlight request (untrusted: a malformed one is dropped)."""
        try:
            request = json.loads(raw)
            number, reply = request["n"], request["r"]
        except (ValueError, TypeError, KeyError):
            return
        if not (isinstance(reply, str) and re.fullmatch(r"[0-9a-f]{16}", reply)):
            return
        if isinstance(number, bool) or not isinstance(number, int) or not 1 <= number < 10**9:
            answer = {"e": "not a session number"}
        else:
            try:
                answer = {"s": self._answer(number)}
            except ValueError as exc:
                answer = {"e": str(exc)[:200]}
        key = self.place.key("a", reply)
        pipe = self._redis.pipeline()
        pipe.rpush(key, json.dumps(answer))
        pipe.expire(key, ANSWER_TTL)
        pipe.execute()

    # ------------------------------------------------------------------ asking another process
    def ask(self, number: int, timeout: float = 3.0) -> str:
        """The state text of session ``number`` from the process that has it (on the caller's thread, which
        waits up to ``timeout`` s: call it from a browser's callback, never from the event loop).

        Raises
        ------
        ValueError
            What to tell the teacher: Redis unreachable, no answer in time, or the owner's refusal.
        """
        place = self.place
        owner = place.owner(number)
        reply = secrets.token_hex(8)
        queue = place.key("q", owner)
        try:
            pipe = self._redis.pipeline()
            pipe.rpush(queue, json.dumps({"n": number, "r": reply}))
            pipe.ltrim(queue, -MAX_REQUESTS, -1)
            pipe.expire(queue, ANSWER_TTL)
            pipe.execute()
            popped = self._redis.blpop([place.key("a", reply)], timeout=timeout)
        except (redis.RedisError, OSError) as exc:
            raise ValueError(f"the pool's shared table (Redis at {self.address}) is unreachable: {exc}") from exc
        if popped is None:
            raise ValueError(f"process {owner} of the pool did not answer within {timeout:g} s")
        try:
            answer = json.loads(popped[1])
        except ValueError as exc:
            raise ValueError(f"process {owner} answered something that is not an answer") from exc
        if isinstance(answer, dict) and isinstance(answer.get("s"), str):
            return str(answer["s"])
        if isinstance(answer, dict) and isinstance(answer.get("e"), str):
            raise ValueError(str(answer["e"])[:200])
        raise ValueError(f"process {owner} answered something that is not an answer")
