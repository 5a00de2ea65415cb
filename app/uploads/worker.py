"""Reading an uploaded file (a mesh, a gyroscope recording) in a worker process with its own memory and time
limits.

The file is checked first (:func:`app.uploads.limits.check_upload`, in this process: a refused file costs
no worker), then read by :func:`app.uploads.reading.body_from_parsed_upload` (a mesh) or fitted by
:func:`app.uploads.gyro.fit_toss_upload` (a recording) in a process capped at
:data:`~app.uploads.limits.MEMORY_LIMIT` and killed after :data:`~app.uploads.limits.TIME_LIMIT`; at most
:data:`~app.uploads.limits.READERS` run at once, and an upload finding them busy is refused at once.
"""

from __future__ import annotations

import errno
import multiprocessing
import threading
from collections.abc import Callable
from multiprocessing.connection import Connection
from pathlib import PurePath
from typing import Any

from app.language.words import carried, said_again, say
from app.uploads.gyro import TossFit, fit_toss_upload
from app.uploads.limits import MAX_MESSAGE, MEMORY_LIMIT, READERS, TIME_LIMIT, check_upload
from app.uploads.reading import NotWatertightError, UploadedBody, body_from_parsed_upload

__all__ = ["ReadersBusy", "body_in_worker", "toss_fit_in_worker"]

_readers = threading.BoundedSemaphore(READERS)


class ReadersBusy(ValueError):
    """Every reader is busy with another upload: this one is refused, to be sent again shortly."""


def _refusal(text: str) -> tuple[str, str, Any]:
    """A refusal as the worker sends it back: the text, and how it was said (so the app translates it)."""
    # A reader may quote the file (a header cell): the message stays short, whatever the file holds.
    if len(text) <= MAX_MESSAGE:
        return ("refused", text, carried(text))
    return ("refused", text[: MAX_MESSAGE - 1] + "…", None)


def _again(text: str, said: Any) -> str:
    """A text from the worker, said again here if the worker said how (then it translates), else as it came."""
    return said_again(said) if said is not None else text


def _read(conn: Connection, filename: str, content: bytes, use_convex_hull: bool, memory: int) -> None:
    """The mesh worker: limits first, then the ordinary checks; the outcome goes back as plain data."""

    def read() -> tuple[Any, ...]:
        try:
            return ("done", body_from_parsed_upload(filename, content, use_convex_hull=use_convex_hull))
        except NotWatertightError as exc:
            return ("open", str(exc), exc.hull, carried(str(exc)))

    _run(conn, filename, memory, read)


def _fit(conn: Connection, filename: str, content: bytes, chosen: int | None, memory: int) -> None:
    """The recording worker: read, find the tosses, fit; the outcome goes back as plain data."""
    _run(conn, filename, memory, lambda: ("done", fit_toss_upload(filename, content, chosen)))


def _memory_text(n_bytes: int) -> str:
    return (
        say("{size:.0f} GB", size=n_bytes / 2**30) if n_bytes >= 2**30 else say("{size:.0f} MB", size=n_bytes / 2**20)
    )


def _too_big(name: str, memory: int) -> str:
    return say(
        "{name} needs more than {memory} of memory to read; simplify it.", name=name, memory=_memory_text(memory)
    )


def _run(conn: Connection, filename: str, memory: int, work: Callable[[], tuple[Any, ...]]) -> None:
    import resource

    resource.setrlimit(resource.RLIMIT_AS, (memory, memory))
    name = PurePath(filename or "upload").name
    outcome: tuple[Any, ...]
    too_big = _too_big(name, memory)
    try:
        outcome = work()
    except MemoryError:
        outcome = _refusal(too_big)
    except OSError as exc:  # the memory limit met by the operating system (a temporary file, a thread)
        outcome = _refusal(
            too_big
            if exc.errno == errno.ENOMEM
            else say("{name} could not be read ({reason}).", name=name, reason=str(exc))
        )
    except ValueError as exc:
        outcome = _refusal(str(exc))
    except Exception as exc:  # noqa: BLE001 - any parser failure means "not a readable file"
        outcome = _refusal(
            say("{name} could not be read ({kind}: {reason}).", name=name, kind=type(exc).__name__, reason=str(exc))
        )
    try:
        conn.send(outcome)
    except MemoryError:
        conn.send(_refusal(say("{name} is too large to send back from the reader; simplify it.", name=name)))
    finally:
        conn.close()


def body_in_worker(
    filename: str,
    content: bytes,
    *,
    use_convex_hull: bool = False,
    memory_limit: int = MEMORY_LIMIT,
    time_limit: float = TIME_LIMIT,
) -> UploadedBody:
    """:func:`app.uploads.reading.body_from_upload` in a worker process with memory and time limits.

    Raises
    ------
    NotWatertightError
        As :func:`~app.uploads.reading.body_from_upload` (with the convex hull to offer).
    ReadersBusy
        :data:`READERS` workers are reading other uploads (a ValueError: the message says to try again).
    ValueError
        Every other refusal, including a file over the declared-size limits, a worker that ran out of
        memory or time; the message names the file and the limit.
    """
    outcome = _in_worker(_read, filename, content, use_convex_hull, memory_limit, time_limit)
    if outcome[0] == "open":
        raise NotWatertightError(_again(outcome[1], outcome[3]), outcome[2])
    body: UploadedBody = outcome[1]
    return body


def toss_fit_in_worker(
    filename: str,
    content: bytes,
    chosen: int | None = None,
    *,
    memory_limit: int = MEMORY_LIMIT,
    time_limit: float = TIME_LIMIT,
) -> TossFit:
    """:func:`app.uploads.gyro.fit_toss_upload` in a worker process with memory and time limits.

    Raises
    ------
    ReadersBusy
        :data:`READERS` workers are reading other uploads (a ValueError: the message says to try again).
    ValueError
        Every refusal: over the size limits (a zip's declared contents too), not gyroscope data, no toss, a
        toss too short, too slow or clipped, a worker out of memory or time; the message names the file.
    """
    result: TossFit = _in_worker(_fit, filename, content, chosen, memory_limit, time_limit)[1]
    return result


def _in_worker(
    target: Callable[..., None], filename: str, content: bytes, option: Any, memory_limit: int, time_limit: float
) -> tuple[Any, ...]:
    """Check the file, take a reader's place and run ``target`` in a worker: its outcome, or a ValueError."""
    name = PurePath(filename or "upload").name
    check_upload(filename, content)
    if not _readers.acquire(blocking=False):
        raise ReadersBusy(
            say(
                "{name} was not read: the server is reading {readers} other uploads just now. "
                "Upload it again in a few seconds.",
                name=name,
                readers=READERS,
            )
        )
    try:
        outcome = _read_in_worker(target, name, filename, content, option, memory_limit, time_limit)
    finally:
        _readers.release()
    if outcome[0] == "refused":
        raise ValueError(_again(outcome[1], outcome[2]))
    return outcome


def _read_in_worker(
    target: Callable[..., None],
    name: str,
    filename: str,
    content: bytes,
    option: Any,
    memory_limit: int,
    time_limit: float,
) -> tuple[Any, ...]:
    """One worker process reads the file (the caller holds a reader's place)."""
    context = multiprocessing.get_context("forkserver")
    # The fork server imports this module (trimesh, numpy, scipy) once; each worker forks from it ready to
    # read in about 15 ms instead of importing them anew (0.7 s an upload). Only the first start of the fork
    # server reads the list; "__main__" is its default, kept so that a worker does not run the main script again.
    context.set_forkserver_preload(["__main__", __name__])
    receiver, sender = context.Pipe(duplex=False)
    worker = context.Process(target=target, args=(sender, filename, content, option, memory_limit), daemon=True)
    worker.start()
    sender.close()
    try:
        if not receiver.poll(time_limit):
            raise ValueError(
                say(
                    "{name} took more than {seconds:.0f} s to read; simplify it and upload it again.",
                    name=name,
                    seconds=time_limit,
                )
            )
        try:
            outcome: tuple[Any, ...] = receiver.recv()
        except EOFError:
            raise ValueError(_too_big(name, memory_limit)) from None
    finally:
        receiver.close()
        if worker.is_alive():
            worker.kill()
        worker.join(timeout=5.0)
    return outcome
