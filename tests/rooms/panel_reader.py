"""A raw browser through the proxy that keeps its panel as the page would: every GUI element's label,
value and properties, updated as messages come, read on a thread of its own.

Used by ``tests/rooms/test_teacher_pool.py`` and ``benchmarks/rooms.py`` to drive the teacher's view of a
pool (type the PIN, open the view, read the table, choose a session, Spotlight) without Chromium.
"""

from __future__ import annotations

import re
import threading
import time
from collections.abc import Callable
from typing import Any

from websockets.exceptions import ConnectionClosed

from tests.harness import click_button, received, send_value
from tests.rooms.running import backend_of, proxied

__all__ = ["PanelReader", "table_numbers"]


def table_numbers(content: str) -> list[int]:
    """The session numbers of a teacher's table (its rows' first cells)."""
    return [int(n) for n in re.findall(r'<tr><th scope="row">(\d+)', content)]


class PanelReader:
    """One browser of ``/room`` (with ``cookie``: the process it names), its panel kept up to date."""

    def __init__(self, port: int, room: str, cookie: str | None = None) -> None:
        self.ws = proxied(port, room, cookie)
        self.backend = backend_of(self.ws)
        self.elements: dict[str, dict[str, Any]] = {}  # uuid -> {"type", "value", "props"}
        self.notifications: list[tuple[str, str]] = []
        self.changed = threading.Condition()
        self.closed = False
        self._thread = threading.Thread(target=self._read, daemon=True)
        self._thread.start()

    def _read(self) -> None:
        while not self.closed:
            try:
                messages = received(self.ws)  # what has come, at once: a wait measures the server, not this
                if not messages:
                    messages = received(self.ws, 0.05)
            except (ConnectionClosed, OSError):
                break
            with self.changed:
                for m in messages:
                    self._apply(m)
                if messages:
                    self.changed.notify_all()
        self.closed = True
        with self.changed:
            self.changed.notify_all()

    def _apply(self, m: dict[str, Any]) -> None:
        kind = m.get("type", "")
        if kind == "GuiUpdateMessage" and m.get("uuid") in self.elements:
            element = self.elements[m["uuid"]]
            for key, value in m["updates"].items():
                if key == "value":
                    element["value"] = value
                else:
                    element["props"][key] = value
        elif kind == "GuiRemoveMessage":
            self.elements.pop(m.get("uuid"), None)
        elif kind.startswith("Gui") and "props" in m and isinstance(m.get("uuid"), str):
            self.elements[m["uuid"]] = {"type": kind, "value": m.get("value"), "props": dict(m["props"])}
        elif kind in ("NotificationShowMessage", "NotificationUpdateMessage"):
            props = m.get("props", m)
            self.notifications.append((str(props.get("title", "")), str(props.get("body", ""))))

    def wait(self, condition: Callable[[], Any], timeout: float = 30.0, what: str = "the panel") -> Any:
        """Wait until ``condition()`` (called under the reader's lock) is truthy; AssertionError after ``timeout``."""
        deadline = time.monotonic() + timeout
        with self.changed:
            while True:
                value = condition()
                if value:
                    return value
                left = deadline - time.monotonic()
                if left <= 0 or self.closed:
                    raise AssertionError(f"no {what} within {timeout} s (closed: {self.closed})")
                self.changed.wait(min(left, 0.2))

    def find(self, label: str, kind: str | None = None) -> str | None:
        """The uuid of the element labelled ``label`` (of message type ``kind``), or None."""
        for uuid, element in list(self.elements.items()):
            if element["props"].get("label") == label and (kind is None or element["type"] == kind):
                return uuid
        return None

    def value(self, label: str) -> Any:
        uuid = self.find(label)
        return None if uuid is None else self.elements[uuid]["value"]

    def set(self, label: str, value: Any, timeout: float = 30.0) -> None:
        """Set the control labelled ``label`` as the page does, once it is there."""
        uuid = self.wait(lambda: self.find(label), timeout, f"control {label!r}")
        with self.changed:
            self.elements[uuid]["value"] = value  # the page shows what it sent (the server does not echo it)
        send_value(self.ws, uuid, value)

    def press(self, label: str, timeout: float = 30.0) -> None:
        uuid = self.wait(lambda: self.find(label, "GuiButtonMessage"), timeout, f"button {label!r}")
        click_button(self.ws, uuid)

    def markdown(self, pattern: str) -> re.Match[str] | None:
        """The first Markdown element matching ``pattern``."""
        for element in list(self.elements.values()):
            found = re.search(pattern, str(element["props"].get("_markdown", "")))
            if found:
                return found
        return None

    def session_number(self, timeout: float = 30.0) -> int:
        """This browser's session number, as its panel says it ("**Session N**")."""
        found = self.wait(lambda: self.markdown(r"\*\*Session (\d+)\*\*"), timeout, "the session's number")
        return int(found.group(1))

    def table(self) -> str:
        """The teacher's table (the Html element holding it), or ""."""
        for element in list(self.elements.values()):
            content = str(element["props"].get("content", ""))
            if 'class="rbl-teacher"' in content:
                return content
        return ""

    def open_teachers_view(self, pin: str, timeout: float = 30.0) -> None:
        self.set("Teacher PIN", pin, timeout)
        # The PIN's value must be there before the button: both go on the same websocket, in order.
        self.press("Open teacher's view", timeout)
        self.wait(lambda: self.table(), timeout, "the teacher's table")

    def close(self) -> None:
        self.closed = True
        self.ws.close()
        self._thread.join(timeout=5)
