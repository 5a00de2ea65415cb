"""Notifications: a message to one browser or to every browser a simulation is drawn for, and its status line.

Sent from callback threads, the loop and viser's event loop (a refused input or upload), so the list of
messages, the notifications showing and the status line have a plain lock of their own, always the
innermost (no other lock is taken while it is held) and held for microseconds.
"""

from __future__ import annotations

import threading
import time
from collections.abc import Callable
from typing import Any

import viser

from app.guards.text import markdown_text
from app.language.words import say

__all__ = ["NOTIFY_SECONDS", "Notices"]

_STATUS = "⚠ **{title}**: {body}"
"""The status line (markup alone, not for the translators): the title and the body are translated as values."""

NOTIFY_SECONDS = 6.0
"""A notification closes by itself after this long (s); an identical one is not stacked meanwhile."""


class Notices:
    """The notifications of one simulation.

    Parameters
    ----------
    clients : callable() -> list
        The browsers the simulation is drawn for (everyone a notification without a client goes to).
    status : viser markdown handle
        The scene's status line.
    own_browser : bool
        The simulation is one browser's own (a private session or an explorer's copy): that browser's errors
        go to the status line too.
    """

    def __init__(self, clients: Callable[[], list[viser.ClientHandle]], status: Any, own_browser: bool) -> None:
        self.lock = threading.Lock()
        self.messages: list[tuple[str, str]] = []  # every notification sent (title, body), newest last
        self._clients = clients
        self._status = status
        self._own_browser = own_browser
        self._shown: dict[tuple[Any, str, str], float] = {}  # (client id, title, body) -> when it was sent

    def notify(self, title: str, body: str, client: viser.ClientHandle | None = None, error: bool = False) -> None:
        """A notification to one client (the one who acted) or, without one, to every connected client.

        The same notification is not sent to the same browser again while the first is still showing. An
        error for everyone (a numerical failure, a lecture step) also goes to the status line; an error for
        one browser (a refused input or upload) only on a simulation that browser has to itself.
        """
        with self.lock:
            self.messages.append((title, body))
            del self.messages[:-50]
        clients = [client] if client is not None else self._clients()
        now = time.monotonic()
        for c in clients:
            key = (getattr(c, "client_id", None), title, body)
            with self.lock:
                self._shown = {k: v for k, v in self._shown.items() if now - v < NOTIFY_SECONDS}
                if key in self._shown:
                    continue
                self._shown[key] = now
            try:
                c.add_notification(title, body, color="red" if error else "blue", auto_close_seconds=NOTIFY_SECONDS)
            except Exception:  # noqa: BLE001 - a client that just left must not break the caller
                pass
        if error and (client is None or self._own_browser):
            with self.lock:
                self._status.content = say(_STATUS, title=markdown_text(title), body=markdown_text(body))

    def clear_status(self) -> None:
        """Empty the status line (a change was accepted, or the scene changed)."""
        with self.lock:
            if self._status.content:
                self._status.content = ""
