"""The contracts between app/'s packages, at the bottom of its imports: what a scene and the panel pieces it
builds may use of the simulation that runs them (:class:`SceneContext`), how a browser is named
(:data:`ClientId`), and the table of per-browser simulations that serving/ keeps and teaching/ changes
(:class:`Sessions`).

Declared here, below ``scenes/``, ``panel/`` and ``drawing/``, so each of them can be typed against it; the
simulation (:class:`app.serving.simulation.Simulation`) implements it.
"""

from __future__ import annotations

import threading
from collections.abc import Callable, Iterator, Mapping
from typing import Any, Protocol, TypeAlias, TypeVar

import viser

__all__ = ["ClientId", "SceneContext", "Sessions"]

ClientId: TypeAlias = int
"""A browser's connection, as viser numbers it (``viser.ClientHandle.client_id``)."""

S = TypeVar("S")


class Sessions(Mapping[ClientId, S]):
    """Simulations by browser, shared by the loop, the network threads and the teaching pieces.

    Read like a read-only dict (``sessions[cid]``, ``cid in sessions``, ``len``, iteration, ``get``), each read
    under the table's lock and iteration over a copy, so a browser leaving meanwhile never breaks a reader;
    changed only through :meth:`put`, :meth:`put_new` and :meth:`pop`.
    """

    def __init__(self) -> None:
        self._by_client: dict[ClientId, S] = {}
        self._lock = threading.Lock()

    def __getitem__(self, client_id: ClientId) -> S:
        with self._lock:
            return self._by_client[client_id]

    def __iter__(self) -> Iterator[ClientId]:
        with self._lock:
            return iter(list(self._by_client))

    def __len__(self) -> int:
        with self._lock:
            return len(self._by_client)

    def __contains__(self, client_id: object) -> bool:
        with self._lock:
            return client_id in self._by_client

    def get(self, client_id: ClientId, default: S | None = None) -> S | None:  # type: ignore[override]
        with self._lock:
            return self._by_client.get(client_id, default)

    def values(self) -> list[S]:  # type: ignore[override]  # a copy: the table may change while one reads it
        with self._lock:
            return list(self._by_client.values())

    def items(self) -> list[tuple[ClientId, S]]:  # type: ignore[override]
        with self._lock:
            return list(self._by_client.items())

    def put(self, client_id: ClientId, simulation: S) -> None:
        """Give a browser its simulation (replacing any it had)."""
        with self._lock:
            self._by_client[client_id] = simulation

    def put_new(self, client_id: ClientId, simulation: S) -> S:
        """Give a browser ``simulation`` unless it has one already; returns the one it has now."""
        with self._lock:
            return self._by_client.setdefault(client_id, simulation)

    def pop(self, client_id: ClientId) -> S | None:
        """Take a browser's simulation out of the table (None if it had none)."""
        with self._lock:
            return self._by_client.pop(client_id, None)


class SceneContext(Protocol):
    """What a scene may use from its simulation (:class:`app.serving.simulation.Simulation` implements it)."""

    server: viser.ViserServer
    root: str
    lock: threading.RLock
    dark: bool  # the dark look (plots draw their lines to be read on it)

    @property
    def time(self) -> float: ...

    @property
    def playing(self) -> bool: ...

    def guarded(self, fn: Callable[..., Any]) -> Callable[..., Any]: ...

    def notify(self, title: str, body: str, client: viser.ClientHandle | None = None, error: bool = False) -> None: ...

    def restart(self) -> None: ...

    def clear_status(self) -> None: ...

    def request_redraw(self) -> None: ...

    def pause(self, reason: str | None = None) -> None: ...

    def switch_to(self, name: str, payload: Any = None) -> None: ...

    def refusal(self, client_id: ClientId) -> str | None:
        """Why this browser may not drive the simulation (presenter mode's followers), or None."""
        ...

    def set_time(self, t: float) -> None: ...

    def set_playing(self, playing: bool) -> None: ...
