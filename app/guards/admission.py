"""Caps on connections and sessions, per address and per process, sized for a lecture hall of 300.

Every websocket costs the server: a panel of its own, in private mode a whole simulation, in every mode a
share of the 60 Hz loop and of the network thread. A connection over a cap is closed as it opens, before
viser builds anything for it, with a reason the page shows ("Connection rejected: ..."; viser's page shows
the reason of a 1002 close). The address is the one :func:`app.guards.responses.connection_address` gives
(the browser's own behind the rooms' proxy). The machine itself (a direct connection from 127.0.0.1 or
::1, with no proxy's ``X-Real-IP``) is its operator's and has no per-address cap; tests and benchmarks let
127.0.0.2 and up stand in for other machines. More in docs/security.md.
"""

from __future__ import annotations

import threading
import time
from collections import Counter
from dataclasses import dataclass
from typing import Any

import viser
from viser import infra

from app.contracts import ClientId
from app.guards.gate import REFUSED_CODE, close_reason
from app.guards.responses import connection_address, hook_requests
from app.language.catalogs import SOURCE, negotiate
from app.language.words import mark, say, translate

__all__ = ["Admission", "Caps", "HOLD_SECONDS", "MOST_HELD", "QUIET_SECONDS", "install_admission"]


@dataclass(frozen=True)
class Caps:
    """How many connections and sessions a server takes.

    Attributes
    ----------
    connections : int
        Websockets open at once, all addresses together (300 seats, their presenters and a margin).
    per_address : int
        Websockets open at once from one address (a student's tabs and devices behind one address).
    sessions : int
        Simulations of their own (private sessions, or presenter mode's "Explore on my own" copies) at once.
    sessions_per_address : int
        Simulations of their own at once for the browsers of one address.
    opens_per_minute : int
        New connections one address may open a minute, sustained, after a first burst of ``per_address``
        (a page reconnects rarely; a script that reconnects for every message costs the server a panel each
        time).
    """

    connections: int = 400
    per_address: int = 4
    sessions: int = 300
    sessions_per_address: int = 4
    opens_per_minute: int = 10

    def __post_init__(self) -> None:
        for name in ("connections", "per_address", "sessions", "sessions_per_address", "opens_per_minute"):
            value = getattr(self, name)
            if isinstance(value, bool) or not isinstance(value, int) or not 1 <= value <= 100_000:
                raise ValueError(f"caps: {name} must be a whole number from 1 to 100000, got {value!r}")


QUIET_SECONDS = 2.0
"""After refusing an address (its tabs or its openings over the caps), new websockets from it are answered
429 before they open for this long: a script that reconnects in a loop costs a parsed request, not a
connection, and a page that retries gets its refusal's reason at the next full attempt."""

HOLD_SECONDS = 2.0
"""How long a websocket turned away waits for its 429: a script that reconnects the moment it is answered
(hundreds of times a second from a few clients, each a request parsed on the thread that also sends every
browser its frames) is slowed to about one attempt a second per socket it holds open."""
MOST_HELD = 1000
"""Answers held back at once, all addresses together (each holds a socket open: the rooms' units allow 8192
files); beyond it, answered at once."""

_THIS_MACHINE = frozenset({"127.0.0.1", "::1"})
"""Direct connections from the server's own machine: its operator's, no per-address cap."""


class Admission:
    """Who is connected from where, and whether one more may connect.

    Parameters
    ----------
    caps : Caps
        The limits.
    sessions_per_connection : bool
        Private mode: every connection is a session, so the session caps apply to connections too.
    """

    def __init__(self, caps: Caps, sessions_per_connection: bool = False) -> None:
        self.caps = caps
        self._private = sessions_per_connection
        self._address: dict[ClientId, str] = {}  # client id -> address, for every admitted connection
        self._count: Counter[str] = Counter()
        self.refused: Counter[str] = Counter()  # refusals by reason (tests and the benchmark read it)
        self._opens: dict[str, tuple[float, float]] = {}  # address -> (opens it may still make, when)
        self._quiet: dict[str, float] = {}  # address -> until when it is turned away before its websocket opens
        self._lock = threading.Lock()

    def admit(self, client_id: ClientId, address: str) -> str | None:
        """Count the connection in and return None, or return why it may not connect (nothing counted)."""
        caps = self.caps
        total = min(caps.connections, caps.sessions) if self._private else caps.connections
        mine = min(caps.per_address, caps.sessions_per_address) if self._private else caps.per_address
        local = address in _THIS_MACHINE
        now = time.monotonic()
        with self._lock:
            tokens = self._tokens(address, now)
            if len(self._address) >= total:
                reason, key = say("the server is full ({total} browsers); try again later", total=total), "full"
            elif not local and self._count[address] >= mine:
                reason = say("at most {mine} browser tabs from one address; close one and reload", mine=mine)
                key = "address"
            elif not local and tokens < 1.0:
                reason = mark("too many new connections from your address; wait a minute and reload")
                key = "opening"
            else:
                if not local:
                    self._opens[address] = (tokens - 1.0, now)
                    if len(self._opens) > 10_000:  # addresses come and go: forget the oldest
                        for old in list(self._opens)[:5_000]:
                            del self._opens[old]
                self._address[client_id] = address
                self._count[address] += 1
                return None
            self.refused[key] += 1
            if key != "full":  # this address's own excess: turned away cheaply for a while
                self._quiet[address] = now + QUIET_SECONDS
                if len(self._quiet) > 10_000:
                    for old in [a for a, until in self._quiet.items() if until <= now] or list(self._quiet)[:5_000]:
                        del self._quiet[old]
            return reason

    def _tokens(self, address: str, now: float) -> float:
        """New connections ``address`` may open now (a bucket of ``per_address``, refilled at
        ``opens_per_minute``); the caller holds the lock."""
        caps = self.caps
        tokens, then = self._opens.get(address, (float(caps.per_address), now))
        return min(float(caps.per_address), tokens + caps.opens_per_minute / 60.0 * (now - then))

    def turned_away(self, address: str) -> str | None:
        """Why a websocket from ``address`` is refused before it opens (within :data:`QUIET_SECONDS` of
        refusing that address, while it is still over its caps), or None: it opens, and :meth:`admit`
        decides."""
        if address in _THIS_MACHINE:
            return None
        caps = self.caps
        mine = min(caps.per_address, caps.sessions_per_address) if self._private else caps.per_address
        now = time.monotonic()
        with self._lock:
            until = self._quiet.get(address)
            if until is None or now >= until:
                return None
            if (
                self._count[address] < mine and self._tokens(address, now) >= 1.0
            ):  # a tab closed, or time passed: admit() decides
                return None
            self.refused["turned away"] += 1
        return mark("Refused: too many connections from your address; wait a moment and reload")

    def release(self, client_id: ClientId) -> None:
        """A connection closed (one never admitted: nothing to do)."""
        with self._lock:
            address = self._address.pop(client_id, None)
            if address is not None:
                self._count[address] -= 1
                if self._count[address] <= 0:
                    del self._count[address]

    def address_of(self, client_id: ClientId) -> str | None:
        """The address an admitted connection comes from."""
        with self._lock:
            return self._address.get(client_id)

    def session_refusal(self, client_id: ClientId, owners: list[ClientId]) -> str | None:
        """Why ``client_id`` may not have a simulation of its own while ``owners`` (client ids) have one, or
        None (presenter mode's copies; in private mode the connection caps already count sessions)."""
        with self._lock:
            mine = self._address.get(client_id)
            addresses = [self._address.get(owner) for owner in owners if owner != client_id]
        if len(addresses) >= self.caps.sessions:
            return say(
                "the server runs {count} copies already, its most; follow the lecture for now", count=len(addresses)
            )
        if mine is not None and mine not in _THIS_MACHINE and addresses.count(mine) >= self.caps.sessions_per_address:
            return say("at most {most} copies from one address; close one first", most=self.caps.sessions_per_address)
        return None


def install_admission(server: viser.ViserServer, admission: Admission) -> Admission:
    """Check every websocket ``server`` opens from now on against ``admission`` (call before any browser
    connects); a refused one is closed with its reason before viser builds anything for it."""
    websock = server._websock_server

    async def on_connection(client_connection: infra.WebsockClientConnection) -> None:
        client_id = client_connection.client_id
        connection = websock._live_connections.get(client_id)
        if connection is None:
            return
        reason = admission.admit(client_id, connection_address(connection))
        if reason is None:
            return
        original = connection.recv

        async def nothing(decode: bool | None = None) -> Any:
            # What the page sent before the close (its camera) is never handed to viser: viser's reader
            # sees the close, and tears the connection down before it builds anything for it.
            while True:
                await original(decode)

        connection.recv = nothing  # type: ignore[method-assign]
        # Before viser knows the browser, its language is the one its handshake asks for.
        request = getattr(connection, "request", None)
        lang = negotiate(request.headers.get("Accept-Language") if request is not None else None, SOURCE)
        await connection.close(REFUSED_CODE, close_reason(translate(say("Refused: {reason}", reason=reason), lang)))

    def on_disconnect(client_connection: infra.WebsockClientConnection) -> None:
        admission.release(client_connection.client_id)

    websock._client_connect_cb.insert(0, on_connection)
    websock._client_disconnect_cb.insert(0, on_disconnect)
    hook_requests(server, admission.turned_away, HOLD_SECONDS, MOST_HELD)
    return admission
