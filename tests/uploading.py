"""Helpers for the tests of uploads: a zip made in memory, a file sent through a page's upload button, and
whether a simulation's lock is free (an upload is read outside it)."""

from __future__ import annotations

import io
import threading
import zipfile
from typing import Any

__all__ = ["lock_is_free", "upload", "zip_bytes"]


def zip_bytes(files: dict[str, bytes], method: int = zipfile.ZIP_DEFLATED) -> bytes:
    """A zip archive of ``files`` (name in the archive -> content), made in memory."""
    out = io.BytesIO()
    with zipfile.ZipFile(out, "w", method) as archive:
        for name, data in files.items():
            archive.writestr(name, data)
    return out.getvalue()


def upload(page: Any, name: str, content: bytes) -> None:
    """Send a file through the page's first upload button (its hidden <input type=file>)."""
    page.locator("input[type=file]").first.set_input_files(
        {"name": name, "mimeType": "application/octet-stream", "buffer": content}
    )


def lock_is_free(lock: Any) -> bool:
    """Could another thread take ``lock`` now (a frame run)? Asked from another thread: this one could
    re-enter its own RLock."""
    out: list[bool] = []

    def probe() -> None:
        out.append(lock.acquire(blocking=False))
        if out[0]:
            lock.release()

    thread = threading.Thread(target=probe)
    thread.start()
    thread.join()
    return out[0]
