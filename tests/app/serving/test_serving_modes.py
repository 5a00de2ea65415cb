"""How the server is started: presenter mode on a non-loopback host, and viser's share button only with
``--share``.

The command is run as a person runs it (``python -m app``) and its terminal read; what a page is told
(viser's theme message, with ``show_share_button``) is read by a websocket client speaking viser's
protocol (tests/harness.py's ``raw_client``), in shared, private and presenter mode and in an explorer's
own copy.
"""

from __future__ import annotations

import contextlib
import queue
import re
import subprocess
import sys
import threading
from collections.abc import Iterator
from types import SimpleNamespace
from typing import Any

import pytest

from app.serving.app import App
from tests.app.reading import received_until
from tests.harness import click_button, free_port, raw_client, running_app, wait_for


@contextlib.contextmanager
def command(*args: str) -> Iterator[tuple[int, Any]]:
    """``python -m app --port P ARGS``; yields the port and a function returning the next line it prints
    (or None once ``timeout`` seconds pass without one)."""
    port = free_port()
    proc = subprocess.Popen(
        [sys.executable, "-m", "app", "--port", str(port), *args],
        stdout=subprocess.PIPE,
        stderr=subprocess.DEVNULL,
        text=True,
    )
    lines: queue.Queue[str] = queue.Queue()
    threading.Thread(target=lambda: [lines.put(line) for line in proc.stdout], daemon=True).start()

    def next_line(timeout: float = 60.0) -> str | None:
        try:
            return lines.get(timeout=timeout)
        except queue.Empty:
            return None

    try:
        yield port, next_line
    finally:
        proc.terminate()
        proc.wait(timeout=10)


def _banner(next_line: Any, last: str) -> list[str]:
    """The lines the command prints after viser's banner, up to the one starting with ``last``."""
    printed: list[str] = []
    while True:
        line = next_line()
        assert line is not None, f"the command stopped printing before {last!r}: {printed}"
        printed.append(line.rstrip("\n"))
        if line.startswith(last):
            return [p for p in printed if not p.startswith(("│", "╭", "╰"))]


def test_a_non_loopback_host_serves_presenter_mode_and_prints_the_pin():
    with command("--host", "0.0.0.0") as (port, next_line):
        printed = _banner(next_line, "Presenter PIN")
    assert "Rigid Body Lab serving on the local network; students open:" in printed
    addresses = [p.strip() for p in printed if p.startswith("  http://")]
    assert addresses and not any("0.0.0.0" in a for a in addresses)  # an address students can open
    assert all(a.endswith(f":{port}") for a in addresses)
    assert re.fullmatch(
        r"Presenter PIN: \d{6}  \(type it in the panel's “Presenter PIN” box to drive the lecture\)", printed[-1]
    )
    with command("--host", "0.0.0.0", "--pin", "Lecture7") as (_, next_line):
        assert _banner(next_line, "Presenter PIN")[-1].startswith("Presenter PIN: Lecture7 ")


def test_loopback_is_shared_and_a_non_loopback_host_is_presenter_mode_in_the_app():
    for host, mode in (("127.0.0.1", "shared"), ("localhost", "shared"), ("0.0.0.0", "presenter")):
        app = App(host=host, port=free_port(), start_loop=False)
        try:
            assert app.mode == mode
            assert (app.classroom is not None) == (mode == "presenter")
            assert re.fullmatch(r"\d{6}", app.pin)
        finally:
            app.stop()


def _themes(ws: Any, enough: Any) -> list[bool]:
    """``show_share_button`` of every theme message the page receives, once ``enough(themes)``."""

    def shown(messages: list[dict[str, Any]]) -> list[bool]:
        return [m["show_share_button"] for m in messages if m.get("type") == "ThemeConfigurationMessage"]

    themes = shown(received_until(ws, lambda messages: enough(shown(messages)), timeout=20.0))
    assert enough(themes), f"the page's theme did not come: {themes}"
    return themes


@pytest.mark.parametrize("share", [False, True])
@pytest.mark.parametrize("mode", ["shared", "private", "presenter"])
def test_the_share_button_is_shown_only_with_share(mode, share):
    with running_app("wobble", private=mode == "private", presenter=mode == "presenter", share=share) as app:
        with raw_client(app) as ws:
            if mode == "private":  # the server's theme, then the browser's own session's
                wait_for(lambda: app.sessions, what="the browser's session")
                themes = _themes(ws, lambda t: len(t) >= 2)
            else:
                themes = _themes(ws, lambda t: len(t) >= 1)
            assert themes and all(shown is share for shown in themes), themes
            if mode == "presenter":  # an explorer's own copy is themed the same way
                (cid,) = app.server.get_clients()
                wait_for(lambda: cid in app.classroom._panels, what="the browser's own panel")
                click_button(ws, app.classroom._panels[cid].explore._impl.uuid)
                wait_for(lambda: cid in app.sessions, what="the explorer's copy")
                more = _themes(ws, lambda t: len(t) >= 1)
                assert all(shown is share for shown in more), more


@pytest.mark.parametrize("share", [False, True])
def test_the_command_passes_share_to_the_page(share):
    args = ["--host", "0.0.0.0", *(["--share"] if share else [])]
    with command(*args) as (port, next_line):
        _banner(next_line, "Presenter PIN")  # serving
        with raw_client(SimpleNamespace(port=port), wait=False) as ws:
            themes = _themes(ws, lambda t: len(t) >= 1)
    assert all(shown is share for shown in themes), themes
