"""What ``rigid-body-lab`` prints and publishes: the addresses students can open, never 0.0.0.0, and no
share button (a public tunnel) unless asked for."""

from __future__ import annotations

import ipaddress
import subprocess
import sys

from viser import _messages

from app.serving.addresses import is_loopback, lan_addresses, urls
from tests.harness import free_port, running_app


def test_loopback_hosts_are_recognised():
    assert is_loopback("127.0.0.1") and is_loopback("127.3.2.1") and is_loopback("::1") and is_loopback("localhost")
    assert not is_loopback("0.0.0.0") and not is_loopback("192.168.1.20") and not is_loopback("lab-pc")


def test_an_any_address_bind_lists_this_machines_lan_addresses_never_0_0_0_0():
    listed = urls("0.0.0.0", 8080)
    assert listed == [f"http://{a}:8080" for a in lan_addresses()]
    for url in listed:
        host = url.removeprefix("http://").rsplit(":", 1)[0]
        address = ipaddress.ip_address(host)
        assert not address.is_loopback and not address.is_unspecified
    assert urls("192.168.1.20", 9000) == ["http://192.168.1.20:9000"]


def _theme_messages(app):
    buffer = app.server._websock_server.get_message_buffer()
    return [m for m in buffer.message_from_id.values() if isinstance(m, _messages.ThemeConfigurationMessage)]


def test_no_share_button_unless_asked_for():
    with running_app(start_loop=False) as app:
        themes = _theme_messages(app)
        assert themes and themes[-1].show_share_button is False


def test_command_on_the_lan_prints_addresses_students_can_open():
    port = free_port()
    proc = subprocess.Popen(
        [sys.executable, "-m", "app", "--host", "0.0.0.0", "--port", str(port)],
        stdout=subprocess.PIPE,
        stderr=subprocess.DEVNULL,
        text=True,
    )
    lines: list[str] = []
    try:
        for _ in range(60):
            line = proc.stdout.readline()
            if not line:
                break
            lines.append(line)
            if line.startswith("Rigid Body Lab"):
                break
        shown = [proc.stdout.readline().strip() for _ in range(max(1, len(lan_addresses())))]
    finally:
        proc.terminate()
        proc.wait(timeout=10)
    assert lines and lines[-1].startswith("Rigid Body Lab serving on the local network")
    assert all("0.0.0.0" not in s for s in shown)
    expected = [f"http://{a}:{port}" for a in lan_addresses()] or [f"http://<this machine's IP address>:{port}"]
    assert shown == expected
