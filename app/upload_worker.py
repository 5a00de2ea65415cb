"""Reading an uploaded mesh in a worker process with its own memory and time limits.

trimesh can expand a small file into a very large mesh (instancing, subdivision, a lying header), and a
pathological file can make a parser loop for a long time. Whatever an upload does, it must not take the
server's memory or the simulation's frames with it: the file is first checked against its declared
sizes (:mod:`app.upload_limits`, microseconds), then :func:`app.upload.body_from_upload` runs in a
separate process whose address space is capped at :data:`MEMORY_LIMIT` and which is killed after
:data:`TIME_LIMIT`. The server process only receives the finished body (or the reason for a refusal).
At most :data:`READERS` workers run at once (a semaphore): 32 browsers uploading together cannot start
32 workers of 1 GiB each; an upload that finds them all busy is refused at once (:class:`ReadersBusy`)
and its browser is told to try again.
"""

from __future__ import annotations

import multiprocessing
import threading
from multiprocessing.connection import Connection
from pathlib import PurePath
from typing import Any

from app import upload
from app.upload import NotWatertightError, UploadedBody
from app.upload_limits import check_declared_size

__all__ = ["MEMORY_LIMIT", "TIME_LIMIT", "READERS", "ReadersBusy", "body_in_worker"]

MEMORY_LIMIT = 1024 * 1024 * 1024
"""Address space a worker may use, bytes (1 GiB)."""
TIME_LIMIT = 30.0
"""Seconds a worker may take to read one file."""
READERS = 2
"""Workers that may read files at once (one per core of a small server)."""

_readers = threading.BoundedSemaphore(READERS)


class ReadersBusy(ValueError):
    """Every reader is busy with another upload: this one is refused, to be sent again shortly."""


def _read(conn: Connection, filename: str, content: bytes, use_convex_hull: bool, memory: int) -> None:
    """The worker: limits first, then the ordinary checks; the outcome goes back as plain data."""
    import resource

    resource.setrlimit(resource.RLIMIT_AS, (memory, memory))
    name = PurePath(filename or "upload").name
    outcome: tuple[Any, ...]
    try:
        outcome = ("body", upload.body_from_upload(filename, content, use_convex_hull=use_convex_hull))
    except NotWatertightError as exc:
        outcome = ("open", str(exc), exc.hull)
    except MemoryError:
        outcome = ("refused", f"{name} needs more than {memory / 2**30:.0f} GB of memory to read; simplify it.")
    except ValueError as exc:
        outcome = ("refused", str(exc))
    except Exception as exc:  # noqa: BLE001 - any parser failure means "not a readable mesh"
        outcome = ("refused", f"{name} could not be read ({type(exc).__name__}: {exc}).")
    try:
        conn.send(outcome)
    except MemoryError:
        conn.send(("refused", f"{name} is too large to send back from the reader; simplify it."))
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
    """:func:`app.upload.body_from_upload` in a worker process with memory and time limits.

    Raises
    ------
    NotWatertightError
        As :func:`~app.upload.body_from_upload` (with the convex hull to offer).
    ReadersBusy
        :data:`READERS` workers are reading other uploads (a ValueError: the message says to try again).
    ValueError
        Every other refusal, including a file over the declared-size limits, a worker that ran out of
        memory or time; the message names the file and the limit.
    """
    name = PurePath(filename or "upload").name
    if len(content) > upload.MAX_BYTES:  # before anything else reads it (read at call time: tests lower it)
        upload.read_mesh(filename, content)
    check_declared_size(filename, content)
    if not _readers.acquire(blocking=False):
        raise ReadersBusy(
            f"{name} was not read: the server is reading {READERS} other uploads just now. "
            "Upload it again in a few seconds."
        )
    try:
        return _read_in_worker(name, filename, content, use_convex_hull, memory_limit, time_limit)
    finally:
        _readers.release()


def _read_in_worker(
    name: str, filename: str, content: bytes, use_convex_hull: bool, memory_limit: int, time_limit: float
) -> UploadedBody:
    """One worker process reads the file (the caller holds a reader's place)."""
    context = multiprocessing.get_context("forkserver")
    receiver, sender = context.Pipe(duplex=False)
    worker = context.Process(target=_read, args=(sender, filename, content, use_convex_hull, memory_limit), daemon=True)
    worker.start()
    sender.close()
    try:
        if not receiver.poll(time_limit):
            raise ValueError(f"{name} took more than {time_limit:.0f} s to read; simplify it and upload it again.")
        try:
            outcome = receiver.recv()
        except EOFError:
            raise ValueError(
                f"{name} needs more than {memory_limit / 2**30:.0f} GB of memory to read; simplify it."
            ) from None
    finally:
        receiver.close()
        if worker.is_alive():
            worker.kill()
        worker.join(timeout=5.0)
    kind = outcome[0]
    if kind == "body":
        body: UploadedBody = outcome[1]
        return body
    if kind == "open":
        raise NotWatertightError(outcome[1], outcome[2])
    raise ValueError(outcome[1])
