"""No public tunnel unless the server was started with --share, and then only a driver opens it (app.guards.tunnel).

viser answers a ``ShareUrlRequest`` from any websocket client by publishing the server; a hidden share
button does not stop a page or a script from sending one. These tests send the messages through a real
websocket, as a page's script would, with viser's tunnel calls replaced by recorders (no network).
"""

from __future__ import annotations

import contextlib
import time

import msgspec
import pytest

from app.guards.tunnel import NOT_SHARED
from tests.app.reading import received_until
from tests.harness import click_button, drain, raw_client, received, running_app, send_value, still_connected, wait_for


def _ask(ws, kind: str) -> None:
    ws.send(msgspec.msgpack.encode({"type": kind}))


def _recorded(app, monkeypatch) -> list[str]:
    calls: list[str] = []
    monkeypatch.setattr(app.server, "request_share_url", lambda *a, **k: calls.append("open"))
    monkeypatch.setattr(app.server, "disconnect_share_url", lambda *a, **k: calls.append("close"))
    return calls


def _told(messages, text: str) -> bool:
    return any(text in str(m) for m in messages if m.get("type") == "NotificationShowMessage")


@pytest.mark.parametrize("mode", ["shared", "private", "presenter"])
def test_without_share_no_browser_opens_or_closes_a_tunnel(mode, monkeypatch):
    with running_app("heavy_top", private=mode == "private", presenter=mode == "presenter") as app:
        calls = _recorded(app, monkeypatch)
        with raw_client(app) as ws, raw_client(app) as other:
            drain(ws)  # the state each page is sent on joining (no notification in it)
            drain(other)
            _ask(ws, "ShareUrlRequest")
            _ask(ws, "ShareUrlDisconnect")
            messages = received_until(ws, lambda m: _told(m, NOT_SHARED))
            assert _told(messages, NOT_SHARED), "the asking browser is told why"
            assert not _told(received(other, 0.3), NOT_SHARED), "nobody else hears of it"
            assert still_connected(ws, app=app if mode != "private" else None)
            assert still_connected(other, app=app if mode != "private" else None)
        time.sleep(0.2)  # a request would have been handed to viser's thread pool by now
        assert calls == []


def test_with_share_a_driver_opens_the_tunnel():
    with contextlib.ExitStack() as stack:
        app = stack.enter_context(running_app("heavy_top", share=True))
        mp = stack.enter_context(pytest.MonkeyPatch.context())
        calls = _recorded(app, mp)
        ws = stack.enter_context(raw_client(app))
        _ask(ws, "ShareUrlRequest")
        wait_for(lambda: calls == ["open"], what="the tunnel to be requested")
        _ask(ws, "ShareUrlDisconnect")
        wait_for(lambda: calls == ["open", "close"], what="the tunnel to be closed")


def test_with_share_in_presenter_mode_only_the_presenter_opens_it():
    pin = "4321"
    with contextlib.ExitStack() as stack:
        app = stack.enter_context(running_app("heavy_top", presenter=True, pin=pin, share=True))
        mp = stack.enter_context(pytest.MonkeyPatch.context())
        calls = _recorded(app, mp)
        before = set(app.server.get_clients())
        ws = stack.enter_context(raw_client(app))
        cid = (set(app.server.get_clients()) - before).pop()
        wait_for(lambda: cid in app.classroom._panels, what="the browser's own panel")
        # The state a page is sent on joining, to viser's end of its replay: no refusal in it.
        received_until(ws, lambda ms: any(m.get("type") == "ReplayDoneMessage" for m in ms))
        _ask(ws, "ShareUrlRequest")  # a follower: refused, told why
        assert _told(received_until(ws, lambda ms: _told(ms, "PIN")), "PIN"), "the follower's refusal"
        assert calls == []
        panel = app.classroom._panels[cid]
        send_value(ws, panel.pin._impl.uuid, pin)
        wait_for(lambda: panel.pin.value == pin, what="the PIN to arrive")
        click_button(ws, panel.present._impl.uuid)
        wait_for(lambda: cid in app.classroom.presenters, what="the browser to become a presenter")
        _ask(ws, "ShareUrlRequest")
        wait_for(lambda: calls == ["open"], what="the presenter's tunnel request")
