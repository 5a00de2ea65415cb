"""A PIN checked with limits on guessing: per browser, per address, and for the whole room.

The presenter PIN (:mod:`app.teaching.presenter`) and the teacher's view of private sessions
(:mod:`app.teaching.teacher`) are asked for through this gate, with the same limits and messages.

Wrong PINs are counted against the browser (its voter cookie, :mod:`app.teaching.voters`, so reconnecting
does not reset them; a script without the cookie counts per connection) and against its address (a script
that reconnects without a cookie is still one address). The room's budget slows a guesser spread over many
addresses, but it never stops the right PIN from an address that has not been guessing: a script that
keeps reconnecting with wrong PINs cannot lock the lecturer out.
"""

from __future__ import annotations

import secrets
import string
import threading
import time
from collections.abc import Callable
from typing import Any

from app.contracts import ClientId
from app.language.words import mark, say

__all__ = [
    "ADDRESS_ATTEMPTS",
    "ATTEMPTS",
    "CLASS_ATTEMPTS",
    "GUESSER",
    "LOCKOUT",
    "PinGate",
    "check_pin",
    "new_pin",
]

ATTEMPTS = 5
"""Wrong PINs one browser may try before it must wait :data:`LOCKOUT` seconds."""

ADDRESS_ATTEMPTS = 10
"""Wrong PINs one address may try in a minute (however many browsers or connections it uses) before it
must wait :data:`LOCKOUT` seconds."""

LOCKOUT = 60.0
"""Seconds a browser or an address waits after its limit (and a guessing address after the room's)."""

CLASS_ATTEMPTS = 30
"""Wrong PINs the whole room may try in a minute; past it, every address that tried :data:`GUESSER` or more
wrong PINs in the last minute waits until the room's minute has room again."""

GUESSER = 3
"""Wrong PINs in a minute that make an address a guesser once the room's budget is spent (one typo does
not: the lecturer's right PIN on a second try still works)."""

_FORGET_AFTER = 1_000
"""Browsers and addresses kept in the tables before those with nothing pending are forgotten."""


def new_pin() -> str:
    """A random six-digit PIN."""
    return f"{secrets.randbelow(10**6):06d}"


def check_pin(pin: str) -> str:
    """The PIN if it is 4 to 32 letters or digits; otherwise ValueError saying what is expected."""
    allowed = set(string.ascii_letters + string.digits)
    if not isinstance(pin, str) or not 4 <= len(pin) <= 32 or not set(pin) <= allowed:
        raise ValueError(f"a presenter PIN is 4 to 32 letters or digits, got {pin!r}")
    return pin


class PinGate:
    """Checks PINs typed by browsers against one PIN, refusing guessers for a while.

    Parameters
    ----------
    pin : str
        The PIN (4 to 32 letters or digits, :func:`check_pin`).
    where : str
        The body of the "Wrong PIN" message: where the right one is to be found.
    identify : callable(client_id) -> (browser, address), optional
        Who a client is: its browser (the voter identity, kept across reconnects) and its network address.
        Default: every connection is its own browser at its own address (no limit survives a reconnect:
        for tests of one connection; the app always says who).
    """

    def __init__(self, pin: str, where: str, identify: Callable[[Any], tuple[str, str]] | None = None) -> None:
        self.pin = check_pin(pin)
        self.where = where
        self._identify = identify
        self._wrong: dict[Any, tuple[int, float]] = {}  # browser -> (wrong PINs, locked until, monotonic s)
        self._address: dict[str, tuple[list[float], float]] = {}  # address -> (wrong PINs' times, locked until)
        self._room: list[float] = []  # when each wrong PIN was tried, the last minute
        self._lock = threading.Lock()

    def wrong_last_minute(self, now: float | None = None) -> int:
        """Wrong PINs the room tried in the last minute (``now``: the monotonic clock, s)."""
        now = time.monotonic() if now is None else now
        with self._lock:
            return sum(1 for t in self._room if now - t < 60.0)

    def _who(self, client_id: ClientId) -> tuple[Any, str]:
        if self._identify is None:
            return client_id, f"connection {client_id}"
        return self._identify(client_id)

    def refusal(self, client_id: ClientId, typed: Any, now: float | None = None) -> tuple[str, str] | None:
        """None if ``typed`` is the PIN and this browser may try; otherwise (title, body) for that browser.

        A wrong PIN counts against the browser (:data:`ATTEMPTS`, then :data:`LOCKOUT` s), its address
        (:data:`ADDRESS_ATTEMPTS` a minute, then :data:`LOCKOUT` s) and the room (:data:`CLASS_ATTEMPTS` a
        minute, which then stops addresses with :data:`GUESSER` wrong PINs in the minute); while one of these
        holds, even the right PIN is refused to that browser. ``now`` is the monotonic clock (s), for tests.
        """
        now = time.monotonic() if now is None else now
        browser, address = self._who(client_id)
        with self._lock:
            self._room = [t for t in self._room if now - t < 60.0]
            count, until = self._wrong.get(browser, (0, 0.0))
            tries, address_until = self._address.get(address, ([], 0.0))
            tries = [t for t in tries if now - t < 60.0]
            wait = max(until - now, address_until - now, 0.0)
            if len(self._room) >= CLASS_ATTEMPTS and len(tries) >= GUESSER:
                wait = max(wait, 60.0 - (now - self._room[0]))
            if wait > 0.0:
                return mark("Too many wrong PINs"), say("Try again in {wait:.0f} s.", wait=wait)
            if not (isinstance(typed, str) and secrets.compare_digest(typed.strip().encode(), self.pin.encode())):
                count += 1
                tries.append(now)
                self._room.append(now)
                self._wrong[browser] = (0, now + LOCKOUT) if count >= ATTEMPTS else (count, 0.0)
                self._address[address] = ([], now + LOCKOUT) if len(tries) >= ADDRESS_ATTEMPTS else (tries, 0.0)
                self._tidy(now)
                return mark("Wrong PIN"), self.where
            self._wrong.pop(browser, None)
            return None

    def _tidy(self, now: float) -> None:
        """Forget browsers and addresses with nothing pending once the tables grow (called under the lock)."""
        if len(self._wrong) > _FORGET_AFTER:
            self._wrong = {k: v for k, v in self._wrong.items() if v[1] > now or v[0] > 0}
            if len(self._wrong) > _FORGET_AFTER:  # a flood of identities: keep the locked ones
                self._wrong = {k: v for k, v in self._wrong.items() if v[1] > now}
        if len(self._address) > _FORGET_AFTER:
            self._address = {k: v for k, v in self._address.items() if v[1] > now or any(now - t < 60.0 for t in v[0])}

    def forget(self, client_id: ClientId) -> None:
        """A browser left. A connection without a cookie was its own browser: its count goes (its address's
        and the room's stay, so reconnecting resets nothing); a browser with a cookie keeps its count."""
        if self._identify is not None:
            return
        with self._lock:
            self._wrong.pop(client_id, None)
