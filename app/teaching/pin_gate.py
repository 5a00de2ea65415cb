"""A PIN checked with limits on guessing: per browser, and for the whole room.

The presenter PIN (:mod:`app.teaching.presenter`) and the teacher's view of private sessions
(:mod:`app.teaching.teacher`) are asked for through this gate, with the same limits and messages.
"""

from __future__ import annotations

import secrets
import string
import threading
import time
from typing import Any

__all__ = ["ATTEMPTS", "CLASS_ATTEMPTS", "LOCKOUT", "PinGate", "check_pin", "new_pin"]

ATTEMPTS = 5
"""Wrong PINs one browser may try before it must wait :data:`LOCKOUT` seconds."""

LOCKOUT = 60.0
"""Seconds a browser waits after :data:`ATTEMPTS` wrong PINs (and the room after :data:`CLASS_ATTEMPTS`)."""

CLASS_ATTEMPTS = 30
"""Wrong PINs the whole room may try in a minute (a student reconnecting does not reset this one)."""


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
    """

    def __init__(self, pin: str, where: str) -> None:
        self.pin = check_pin(pin)
        self.where = where
        self._wrong: dict[Any, tuple[int, float]] = {}  # client id -> (wrong PINs, locked until, monotonic s)
        self._room: list[float] = []  # when each wrong PIN was tried, the last minute
        self._lock = threading.Lock()

    def refusal(self, client_id: Any, typed: Any, now: float | None = None) -> tuple[str, str] | None:
        """None if ``typed`` is the PIN and this browser may try; otherwise (title, body) for that browser.

        A wrong PIN counts against the browser (:data:`ATTEMPTS`, then :data:`LOCKOUT` s) and against the
        room (:data:`CLASS_ATTEMPTS` a minute); while either is exhausted, even the right PIN is refused.
        ``now`` is the monotonic clock (s), for tests.
        """
        now = time.monotonic() if now is None else now
        with self._lock:
            count, until = self._wrong.get(client_id, (0, 0.0))
            self._room = [t for t in self._room if now - t < 60.0]
            if until > now or len(self._room) >= CLASS_ATTEMPTS:
                wait = max(until - now, 60.0 - (now - self._room[0]) if self._room else 0.0)
                return "Too many wrong PINs", f"Try again in {wait:.0f} s."
            if not (isinstance(typed, str) and secrets.compare_digest(typed.strip().encode(), self.pin.encode())):
                count += 1
                self._room.append(now)
                self._wrong[client_id] = (0, now + LOCKOUT) if count >= ATTEMPTS else (count, 0.0)
                return "Wrong PIN", self.where
            self._wrong.pop(client_id, None)
            return None

    def forget(self, client_id: Any) -> None:
        """A browser left: its own count goes (the room's stays, so reconnecting does not reset it)."""
        with self._lock:
            self._wrong.pop(client_id, None)
