"""Wrong PINs count per browser (its cookie) and per address, not per connection: a script that keeps
reconnecting with wrong PINs is stopped, and cannot stop the right PIN from another browser at another
address (127.0.0.x stand in for the machines of a classroom)."""

from __future__ import annotations

import urllib.request
from types import SimpleNamespace
from typing import Any

import pytest

from app.guards.responses import connection_address, peer_address
from app.rooms.config import PIN_VARIABLE
from app.teaching.pin_gate import ADDRESS_ATTEMPTS, ATTEMPTS, CLASS_ATTEMPTS, GUESSER
from app.teaching.voters import COOKIE
from tests.app.reading import received_until
from tests.app.serving.test_serving_modes import command
from tests.harness import click_button, raw_client, running_app, send_value, wait_for

PIN = "Lab2718"


def _titles(messages: list[dict[str, Any]]) -> list[str]:
    return [m["props"]["title"] for m in messages if m.get("type") == "NotificationShowMessage"]


def _press(app: Any, ws: Any, typed: str) -> Any:
    """Type ``typed`` in this raw client's Presenter PIN box and press Present; its client id."""
    cid = max(app.server.get_clients())  # the newest connection: this one
    panel = wait_for(lambda: app.classroom._panels.get(cid), what="its panel")
    send_value(ws, panel.pin._impl.uuid, typed)
    wait_for(lambda: panel.pin.value == typed, what="the PIN to arrive")
    click_button(ws, panel.present._impl.uuid)
    return cid


def _try(app: Any, ws: Any, typed: str) -> str:
    """:func:`_press`, then "Presenting" or the title of the notification that refused it."""
    cid = _press(app, ws, typed)
    told = received_until(ws, lambda got: cid in app.classroom.presenters or _titles(got), timeout=30)
    return "Presenting" if cid in app.classroom.presenters else (_titles(told) or ["nothing"])[-1]


def _attempt(app: Any, typed: str, source: str, headers: dict | None = None) -> str:
    """One connection from ``source`` types ``typed`` once, then leaves (a reconnecting script)."""
    with raw_client(app, source=source, headers=headers) as ws:
        return _try(app, ws, typed)


def test_a_reconnecting_guesser_cannot_lock_out_the_right_pin_from_elsewhere() -> None:
    with running_app(presenter=True, pin=PIN, start_loop=False) as app:
        # One address, a new connection (no cookie) for every wrong PIN: the address's limit stops it.
        answers = [_attempt(app, "000000", "127.0.0.1") for _ in range(ADDRESS_ATTEMPTS + 1)]
        assert answers == ["Wrong PIN"] * ADDRESS_ATTEMPTS + ["Too many wrong PINs"]
        assert _attempt(app, PIN, "127.0.0.1") == "Too many wrong PINs"  # even the right PIN, from there
        # Guessers at many addresses spend the room's budget, three tries each...
        addresses = [f"127.0.0.{k}" for k in range(10, 10 - (ADDRESS_ATTEMPTS - CLASS_ATTEMPTS) // GUESSER)]
        for address in addresses:
            with raw_client(app, source=address) as ws:
                before = app.classroom.gate.wrong_last_minute()
                assert _try(app, ws, "000000") == "Wrong PIN"
                for k in range(1, GUESSER):  # the same notice again is not repeated: the count says it
                    _press(app, ws, f"00000{k}")
                    wait_for(lambda k=k, b=before: app.classroom.gate.wrong_last_minute() == b + k + 1, what="the try")
        assert app.classroom.gate.wrong_last_minute() >= CLASS_ATTEMPTS
        assert _attempt(app, PIN, addresses[0]) == "Too many wrong PINs"
        # ...and the lecturer's right PIN from another machine still works.
        assert _attempt(app, PIN, "127.0.0.2") == "Presenting"


def test_a_browser_with_its_cookie_keeps_its_count_across_reconnects() -> None:
    with running_app(presenter=True, pin=PIN, start_loop=False) as app:
        with urllib.request.urlopen(app.url, timeout=30) as response:  # the page sets the browser's cookie
            cookie = response.headers["Set-Cookie"].split(";")[0]
        assert cookie.startswith(COOKIE + "=")
        headers = {"Cookie": cookie}
        for _ in range(ATTEMPTS):
            assert _attempt(app, "000000", "127.0.0.1", headers) == "Wrong PIN"
        assert _attempt(app, PIN, "127.0.0.1", headers) == "Too many wrong PINs"  # reconnecting resets nothing
        assert _attempt(app, PIN, "127.0.0.1") == "Presenting"  # another browser at that address may


class _Connection:
    def __init__(self, host: str, real_ip: str | None) -> None:
        self.remote_address = (host, 50000)
        self.request = SimpleNamespace(headers={} if real_ip is None else {"X-Real-IP": real_ip})


def test_an_address_is_the_proxys_real_ip_only_from_loopback() -> None:
    assert connection_address(_Connection("127.0.0.1", "10.1.2.3")) == "10.1.2.3"  # behind the rooms' nginx
    assert connection_address(_Connection("::ffff:127.0.0.1", "10.1.2.3")) == "10.1.2.3"
    assert connection_address(_Connection("192.168.1.5", "10.1.2.3")) == "192.168.1.5"  # a forged header
    assert connection_address(_Connection("192.168.1.5", None)) == "192.168.1.5"
    with running_app(presenter=True, pin=PIN, start_loop=False) as app:
        with raw_client(app, source="127.0.0.4", headers={"X-Real-IP": "10.9.9.9"}):
            assert peer_address(app.server, max(app.server.get_clients())) == "10.9.9.9"
        with raw_client(app, source="127.0.0.4"):
            assert peer_address(app.server, max(app.server.get_clients())) == "127.0.0.4"


def test_the_app_takes_its_pin_from_the_environment(monkeypatch: pytest.MonkeyPatch) -> None:
    """A room's process gets its PIN in RBL_PIN (app.rooms.config.pin_environment), never in its argv."""
    monkeypatch.setenv(PIN_VARIABLE, "Zz9876")
    printed: list[str] = []
    with command("--presenter") as (_, next_line):
        while not printed or not printed[-1].startswith("Presenter PIN"):
            line = next_line()
            assert line is not None, printed  # it said nothing for a minute
            printed.append(line)
    assert printed[-1].startswith("Presenter PIN: Zz9876"), printed
