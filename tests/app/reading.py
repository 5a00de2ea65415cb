"""Reading what the server sends a raw client until what a test waits for has come.

``tests.harness.received(ws, seconds)`` reads for a fixed time; a test that waits for a message it expects
reads with :func:`received_until` instead, which ends as soon as the message is there (the same check
follows on everything read). A check that something is *not* sent still reads for a fixed time.
"""

from __future__ import annotations

import time
from collections.abc import Callable
from typing import Any

from tests.harness import received

__all__ = ["received_until"]


def received_until(
    ws: Any, condition: Callable[[list[dict[str, Any]]], Any], timeout: float = 10.0
) -> list[dict[str, Any]]:
    """Every message read from ``ws`` until ``condition(messages so far)`` holds, or ``timeout`` seconds
    have passed (then the messages read, for the test's own assertion to fail on)."""
    messages: list[dict[str, Any]] = []
    deadline = time.monotonic() + timeout
    while True:
        messages += received(ws, 0.02)
        if condition(messages) or time.monotonic() > deadline:
            return messages
