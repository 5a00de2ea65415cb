"""Caps on connections and sessions, per address and per process: a connection over one is closed as it
opens with a reason (close 1002, which viser's page shows), nothing is built for it, and the others go on.
127.0.0.x stand in for the machines of a classroom."""

from __future__ import annotations

import time
from typing import Any

import pytest
import viser
from websockets.exceptions import ConnectionClosed
from websockets.sync.client import connect

from app.guards.admission import Caps
from app.guards.gate import REFUSED_CODE
from tests.app.reading import received_until
from tests.harness import CAMERA_MESSAGE, click_button, raw_client, running_app, still_connected, wait_for


def _refused(app: Any, source: str) -> str:
    """Open a connection from ``source`` that the server refuses; the reason it was given."""
    with connect(
        f"ws://127.0.0.1:{app.port}",
        subprotocols=[f"viser-v{viser.__version__}"],  # type: ignore[list-item]
        source_address=(source, 0),
        open_timeout=30,
    ) as ws:
        with pytest.raises(ConnectionClosed):
            ws.send(CAMERA_MESSAGE)  # what a page sends first: it may find the connection closed already
            for _ in range(1_000):
                ws.recv(timeout=30)
        assert ws.close_code == REFUSED_CODE
        return ws.close_reason or ""


def test_caps_are_checked() -> None:
    assert Caps() == Caps(connections=400, per_address=4, sessions=300, sessions_per_address=4, opens_per_minute=10)
    for bad in ({"connections": 0}, {"per_address": 2.5}, {"sessions": True}, {"sessions_per_address": 10**6}):
        with pytest.raises(ValueError, match="caps: .* must be a whole number from 1 to 100000, got"):
            Caps(**bad)


def test_connections_per_address_and_per_process() -> None:
    with running_app(start_loop=False, caps=Caps(connections=3, per_address=2, opens_per_minute=6000)) as app:
        with raw_client(app, source="127.0.0.5") as first, raw_client(app, source="127.0.0.5"):
            assert "at most 2 browser tabs from one address" in _refused(app, "127.0.0.5")
            with raw_client(app, source="127.0.0.6") as other:  # another machine: room for it
                assert "the server is full (3 browsers)" in _refused(app, "127.0.0.7")
                assert still_connected(other, app=app) and still_connected(first, app=app)
        assert app.admission.refused == {"address": 1, "full": 1}
        wait_for(lambda: not app.server.get_clients(), what="the connections to be gone")
        with raw_client(app, source="127.0.0.5"), raw_client(app, source="127.0.0.5"):  # their places freed
            assert len(app.server.get_clients()) == 2


def test_private_sessions_per_address_and_nothing_built_for_a_refused_one() -> None:
    with running_app(start_loop=False, private=True, caps=Caps(sessions_per_address=1)) as app:
        with raw_client(app, source="127.0.0.8"):
            wait_for(lambda: len(app.sessions) == 1, 60, what="the session")
            assert "at most 1 browser tabs from one address" in _refused(app, "127.0.0.8")
            assert len(app.sessions) == 1 and len(app.server.get_clients()) == 1
            with raw_client(app, source="127.0.0.9"):
                wait_for(lambda: len(app.sessions) == 2, 60, what="another machine's session")


def test_explorers_copies_per_address() -> None:
    with running_app(start_loop=False, presenter=True, caps=Caps(sessions_per_address=1)) as app:
        with raw_client(app, source="127.0.0.10") as first, raw_client(app, source="127.0.0.10") as second:
            ids = sorted(app.server.get_clients())
            panels = [wait_for(lambda cid=cid: app.classroom._panels.get(cid), what="the panel") for cid in ids]
            click_button(first, panels[0].explore._impl.uuid)
            wait_for(lambda: ids[0] in app.sessions, 60, what="the first copy")
            click_button(second, panels[1].explore._impl.uuid)
            told = received_until(second, lambda got: any("copies from one address" in repr(m) for m in got), 30)
            assert any("at most 1 copies from one address" in repr(m) for m in told)
            assert ids[1] not in app.sessions
            assert still_connected(first, app=app)


def test_new_connections_per_address_are_paced_and_this_machine_is_not_capped() -> None:
    with running_app(start_loop=False, caps=Caps(per_address=2, opens_per_minute=1)) as app:
        for _ in range(2):  # the burst: as many as the tabs an address may hold
            with raw_client(app, source="127.0.0.11"):
                pass
        assert "too many new connections from your address" in _refused(app, "127.0.0.11")
        with raw_client(app, source="127.0.0.12"):  # another machine is not slowed
            pass
        # The server's own machine (127.0.0.1, no proxy header) is its operator's: no per-address cap.
        with raw_client(app), raw_client(app), raw_client(app):
            assert len(app.server.get_clients()) == 3
        assert app.admission.refused == {"opening": 1}


def test_an_address_just_refused_is_turned_away_before_its_websocket_opens_while_it_is_over(monkeypatch) -> None:
    """A refused address reconnecting in a loop gets HTTP 429 for QUIET_SECONDS (no websocket, no handler, no
    close handshake), each answer held back HOLD_SECONDS (a script reconnecting at once is slowed to one
    attempt a hold), and only while it is still over its caps: a tab closed, its next connection opens."""
    from websockets.exceptions import InvalidStatus

    monkeypatch.setattr("app.guards.admission.QUIET_SECONDS", 600.0)  # all of the test is within it
    monkeypatch.setattr("app.guards.admission.HOLD_SECONDS", 0.4)  # read as the server starts
    with running_app(start_loop=False, caps=Caps(per_address=1, opens_per_minute=6000)) as app:
        with raw_client(app, source="127.0.0.21") as first:
            assert "at most 1 browser tabs from one address" in _refused(app, "127.0.0.21")  # told why, once
            for _ in range(3):
                asked = time.monotonic()
                with pytest.raises(InvalidStatus) as refused:
                    connect(
                        f"ws://127.0.0.1:{app.port}",
                        subprotocols=[f"viser-v{viser.__version__}"],  # type: ignore[list-item]
                        source_address=("127.0.0.21", 0),
                        open_timeout=30,
                    )
                assert refused.value.response.status_code == 429
                assert time.monotonic() - asked >= 0.4  # held back, not answered at once
                assert b"too many connections from your address" in refused.value.response.body
            assert app.admission.refused == {"address": 1, "turned away": 3}
            assert still_connected(first, app=app)
            with raw_client(app, source="127.0.0.22"):  # another machine is not affected
                pass
        wait_for(lambda: not app.server.get_clients(), what="the connection to be gone")
        # Still within the quiet time, but the address is under its cap again: it is let in.
        with raw_client(app, source="127.0.0.21"):
            assert len(app.server.get_clients()) == 1
