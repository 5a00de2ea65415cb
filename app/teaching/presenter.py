"""Presenter mode: one lecture on the projector, followed by every browser, driven only with the PIN.

More in docs/app-notes.md (``app.teaching.presenter``).
"""

from __future__ import annotations

import threading
from collections.abc import Callable
from typing import TYPE_CHECKING, Any

import viser

from app.contracts import ClientId
from app.guards.broadcast import BroadcastView
from app.guards.callbacks import shielded_handler
from app.guards.inputs import guard_inputs
from app.language.words import mark
from app.teaching.pin_gate import ATTEMPTS, CLASS_ATTEMPTS, LOCKOUT, PinGate, check_pin, new_pin
from app.teaching.presenter_panel import EXPLORING, FOLLOWING, PRESENTING, PresenterPanel

if TYPE_CHECKING:  # annotations only: the app and its simulations are above teaching/
    from app.serving.app import App
    from app.serving.simulation import Simulation

__all__ = ["ATTEMPTS", "CLASS_ATTEMPTS", "LOCKOUT", "Classroom", "new_pin", "check_pin"]


class Classroom:
    """Presenter mode for an :class:`app.serving.app.App`: followers, presenters and explorers.

    Parameters
    ----------
    app : app.serving.app.App
        The lecture (the shared simulation). Its ``sessions`` dict receives the explorers' copies.
    pin : str
        The presenter PIN (see :func:`check_pin`).
    copy : callable(client) -> Simulation
        Makes a browser's own copy of the lecture, at the lecture's current state.
    """

    def __init__(self, app: App, pin: str, copy: Callable[[viser.ClientHandle], Simulation]) -> None:
        self.app = app
        self.gate = PinGate(pin, mark("The presenter PIN is shown where the server was started."), identify=app.who)
        self.pin = self.gate.pin
        self._copy = copy
        self.presenters: set[Any] = set()
        self._panels: dict[Any, PresenterPanel] = {}
        self._toggling: dict[Any, threading.Lock] = {}  # one explore/follow at a time per browser
        self._lock = threading.RLock()
        self.on_present: list[Callable[[viser.ClientHandle], None]] = []  # told when a browser starts presenting
        self.view = BroadcastView(app.server, read_only=lambda client_id: client_id not in self.presenters)
        app.server.on_client_connect(self._joined)
        app.server.on_client_disconnect(self._left)

    # ------------------------------------------------------------------ who may do what
    def refusal(self, client_id: ClientId) -> str | None:
        """None for a presenter; for anyone else, why the lecture's controls do not take their changes."""
        if client_id in self.presenters:
            return None
        return mark("You are following the lecturer: enter the presenter PIN to drive, or press “Explore on my own”.")

    def exploring(self, client_id: ClientId) -> bool:
        """Whether this browser has a copy of its own (and so no longer follows the lecture)."""
        return client_id in self.app.sessions

    # ------------------------------------------------------------------ browsers come and go
    def _joined(self, client: viser.ClientHandle) -> None:
        guard_inputs(
            client.gui,
            lambda _id, message: self.app.simulation.notify(mark("Refused"), message, client=client, error=True),
        )
        panel = PresenterPanel(client)
        with self._lock:
            self._panels[client.client_id] = panel
        panel.present.on_click(self._safely(lambda event: self.present(event.client, panel.pin.value)))
        panel.explore.on_click(self._safely(lambda event: self.toggle(event.client)))

    def _left(self, client: viser.ClientHandle) -> None:
        with self._lock:
            self._panels.pop(client.client_id, None)
            self.presenters.discard(client.client_id)
            self._toggling.pop(client.client_id, None)
        self.app.sessions.pop(client.client_id)
        self.view.forget(client.client_id)
        self.gate.forget(client.client_id)

    def _safely(self, fn: Callable[[Any], object]) -> Callable[[Any], None]:
        # A browser that left while we worked for it: drop what was made for it.
        return shielded_handler(fn, self._tell, left=self._left)

    def _tell(self, client: viser.ClientHandle | None, title: str, body: str) -> None:
        self.app.simulation.notify(title, body, client=client, error=True)

    # ------------------------------------------------------------------ the three actions
    def present(self, client: viser.ClientHandle, pin: str) -> bool:
        """Make ``client`` a presenter if ``pin`` is right; returns whether it now presents."""
        cid = client.client_id
        with self._lock:
            if cid in self.presenters:
                return True
            refused = self.gate.refusal(cid, pin)
            if refused is not None:
                title, body = refused
                self.app.simulation.notify(title, body, client=client, error=title != "Wrong PIN")
                return False
            self.presenters.add(cid)
            panel = self._panels.get(cid)
        self.view.unlock(cid)
        if panel is not None:
            panel.presenting()
            if self.exploring(cid):
                panel.status.content = EXPLORING
        for listener in list(self.on_present):
            listener(client)
        return True

    def toggle(self, client: viser.ClientHandle) -> None:
        """The explore/follow button: explore if following, follow if exploring."""
        with self._client_lock(client.client_id):  # two quick presses must not make two copies
            if self.exploring(client.client_id):
                self.follow(client)
            else:
                self.explore(client)

    def _client_lock(self, client_id: ClientId) -> threading.Lock:
        with self._lock:
            return self._toggling.setdefault(client_id, threading.Lock())

    def explore(self, client: viser.ClientHandle) -> Simulation:
        """Give ``client`` its own copy of the lecture, from the lecture's current state; returns it."""
        cid = client.client_id
        existing = self.app.sessions.get(cid)
        if existing is not None:
            return existing
        copy = self._copy(client)
        self.app.sessions.put(cid, copy)
        self.view.detach(cid)
        if cid not in self.app.server.get_clients():  # it left while its copy was being made
            self._left(client)
            return copy
        panel = self._panels.get(cid)
        if panel is not None:
            panel.explore.label = mark("Follow the lecturer")
            panel.status.content = EXPLORING
        return copy

    def follow(self, client: viser.ClientHandle) -> None:
        """Drop ``client``'s own copy and show it the lecture as it is now."""
        cid = client.client_id
        copy = self.app.sessions.pop(cid)
        if copy is not None:
            copy.close()
        self.view.attach(cid)
        panel = self._panels.get(cid)
        if panel is not None:
            panel.explore.label = mark("Explore on my own")
            panel.status.content = PRESENTING if cid in self.presenters else FOLLOWING
