"""Which uploads may start, and which of those in flight have stalled: the rules for a transfer, beside the
limits they apply.

A browser declares a file's name, size and number of parts when its transfer starts; this module decides on
those declarations alone, before a byte is kept (:func:`start_refusal`), keeps when each accepted transfer
started and last sent a part (:class:`Transfers`), and words the refusal of a transfer whose parts outgrow
what it declared (:func:`overrun_refusal`). The door to viser's transfers, which applies these rules to
every upload a browser starts, is :mod:`app.guards.uploads`.
"""

from __future__ import annotations

import threading
from dataclasses import dataclass
from pathlib import PurePath

from app.language.words import say
from app.uploads import limits

__all__ = ["Declared", "InFlight", "Transfers", "well_formed_count", "start_refusal", "overrun_refusal"]


@dataclass(frozen=True)
class Declared:
    """What a browser declares when it starts a transfer: values from the wire, of any type until checked."""

    filename: object
    transfer: object
    size: object
    parts: object


@dataclass(frozen=True)
class InFlight:
    """Transfers in flight when another starts: this browser's, everyone's, and this address's."""

    mine: int
    everyone: int
    here: int


def well_formed_count(value: object) -> bool:
    """Whether a declared size or number of parts is a count: an int (not a bool) from 0 to 2**53."""
    return isinstance(value, int) and not isinstance(value, bool) and 0 <= value <= 2**53


def _name(filename: object) -> str:
    """The file's own name, without any folder a browser put in front of it."""
    return PurePath(str(filename) or "upload").name


def start_refusal(declared: Declared, in_flight: InFlight) -> str | None:
    """Why a transfer may not start, in the reader's words (:func:`app.language.words.say`), or None.

    Refused: a name that is not text or is longer than :data:`~app.uploads.limits.MAX_NAME`; a size or part
    count that is not a count, more than :data:`~app.uploads.limits.MAX_PARTS` parts, or parts without bytes;
    a file over :data:`~app.uploads.limits.MAX_BYTES`; and a start while this browser
    (:data:`~app.uploads.limits.PER_CLIENT`), its address (:data:`~app.uploads.limits.PER_ADDRESS`) or the
    server (:data:`~app.uploads.limits.MAX_TRANSFERS`) already has as many transfers in flight as it may.
    """
    size, count, filename = declared.size, declared.parts, declared.filename
    if not isinstance(filename, str) or not isinstance(declared.transfer, str) or len(filename) > limits.MAX_NAME:
        return say("Upload refused: a file name is at most {most} characters of text.", most=limits.MAX_NAME)
    name = _name(filename)
    if not well_formed_count(size) or not well_formed_count(count):
        return _form_refusal(name, size, count)
    assert isinstance(size, int) and isinstance(count, int)
    if count > limits.MAX_PARTS or (count == 0) != (size == 0):
        return _form_refusal(name, size, count)
    too_large = limits.size_refusal(name, size)
    if too_large is not None:
        return say("Upload refused: {reason}", reason=too_large)
    if in_flight.mine >= limits.PER_CLIENT:
        return say(
            "Upload refused: {name!s} was sent while your previous file is still arriving; wait for it.", name=name
        )
    if in_flight.here >= limits.PER_ADDRESS:
        return say(
            "Upload refused: {name!s} was sent while another file from your address is arriving; wait for it.",
            name=name,
        )
    if in_flight.everyone >= limits.MAX_TRANSFERS:
        return say(
            "Upload refused: the server is receiving {everyone} other files; upload {name!s} again in a moment.",
            everyone=in_flight.everyone,
            name=name,
        )
    return None


def _form_refusal(name: str, size: object, count: object) -> str:
    return say(
        "Upload refused: {name!s} was sent in a form this server does not take (size {size!r}, {count!r} parts).",
        name=name,
        size=size,
        count=count,
    )


def overrun_refusal(filename: object, declared_size: int) -> str:
    """The refusal of a transfer whose parts came to more bytes than the ``declared_size`` it started with."""
    return say(
        "Upload refused: {name!s} sent more bytes than it declared ({declared:,}).",
        name=_name(filename),
        declared=declared_size,
    )


class Transfers:
    """When each accepted transfer started and last sent a part, and the address it comes from, so that one
    stalled (over :data:`~app.uploads.limits.STALL_SECONDS` since it started, or
    :data:`~app.uploads.limits.IDLE_SECONDS` since its last part) can be dropped and no longer counted.

    Times are ``time.monotonic()`` seconds, passed in; safe from any thread. A transfer met first in
    :meth:`stalled` (one the guard did not see start) counts from then.
    """

    def __init__(self) -> None:
        self._lock = threading.Lock()
        self._started: dict[str, float] = {}
        self._active: dict[str, tuple[float, str]] = {}  # transfer -> (when it last sent a part, its address)

    def accepted(self, transfer: str, address: str, now: float) -> None:
        """A transfer from ``address`` was let start at ``now``."""
        with self._lock:
            self._started[transfer] = now
            self._active[transfer] = (now, address)

    def sent_part(self, transfer: str, now: float) -> None:
        """A transfer sent a part at ``now`` (nothing if it is not kept)."""
        with self._lock:
            seen = self._active.get(transfer)
            if seen is not None:
                self._active[transfer] = (now, seen[1])

    def stalled(self, transfer: str, now: float) -> bool:
        """Whether a transfer has stalled at ``now``."""
        with self._lock:
            started = self._started.setdefault(transfer, now)
            last, _ = self._active.setdefault(transfer, (now, ""))
        return now - started > limits.STALL_SECONDS or now - last > limits.IDLE_SECONDS

    def address(self, transfer: str) -> str:
        """The address a transfer comes from ("" if it is not known)."""
        with self._lock:
            return self._active.get(transfer, (0.0, ""))[1]

    def forget(self, transfer: str) -> None:
        """A transfer ended (complete, refused or dropped)."""
        with self._lock:
            self._started.pop(transfer, None)
            self._active.pop(transfer, None)

    def keep_only(self, live: set[str]) -> None:
        """Forget every transfer not in ``live`` (finished, or dropped with a browser that left)."""
        with self._lock:
            for transfer in [t for t in self._started if t not in live]:
                del self._started[transfer]
                self._active.pop(transfer, None)
