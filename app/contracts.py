"""The contracts between app/'s packages, at the bottom of its imports: what a scene and the panel pieces it
builds may use of the simulation that runs them (:class:`SceneContext`).

Declared here, below ``scenes/``, ``panel/`` and ``drawing/``, so each of them can be typed against it; the
simulation (:class:`app.serving.simulation.Simulation`) implements it.
"""

from __future__ import annotations

import threading
from collections.abc import Callable
from typing import Any, Protocol

import viser

__all__ = ["SceneContext"]


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

    def notify(self, title: str, body: str, client: Any = None, error: bool = False) -> None: ...

    def restart(self) -> None: ...

    def clear_status(self) -> None: ...

    def request_redraw(self) -> None: ...

    def pause(self, reason: str | None = None) -> None: ...

    def switch_to(self, name: str, payload: Any = None) -> None: ...

    def refusal(self, client_id: Any) -> str | None:
        """Why this browser may not drive the simulation (presenter mode's followers), or None."""
        ...

    def set_time(self, t: float) -> None: ...

    def set_playing(self, playing: bool) -> None: ...
