"""``rigid-body-lab rooms`` running a department on loopback, driven as browsers drive it through nginx.

One department for the module (two presenter rooms and a private pool of two processes, on 127.0.0.2 and
127.0.0.3 standing in for two machines): routing of ``/NAME/`` with viser's websocket through the proxy,
isolation of the rooms, stickiness by cookie and spreading, Chromium on a room's page, a process
restarted after SIGKILL, and the clean stop (last: it stops the department).
"""

from __future__ import annotations

import contextlib
import html
import os
import re
import signal
import time
from collections import Counter
from collections.abc import Iterator
from pathlib import Path
from typing import Any

import pytest

from app.language.words import translate
from app.rooms.supervisor import answers, port_free
from tests.harness import received, wait_for
from tests.rooms.running import (
    SUBPROTOCOL,
    RunningDepartment,
    alive,
    backend_of,
    get,
    nginx_or_skip,
    proxied,
    room_cookie,
    rooms_file,
    running_department,
)

LECTURE_NODE = "/scene/top"  # the heavy top's body
PENDULUM_NODES = {"/scene/axle", "/scene/cop"}  # the physical pendulum's own nodes


@pytest.fixture(scope="module")
def department(tmp_path_factory: pytest.TempPathFactory) -> Iterator[RunningDepartment]:
    nginx_or_skip()
    path, port = rooms_file(
        tmp_path_factory.mktemp("rooms"),
        [
            {"name": "mech101", "mode": "presenter", "pin": "111111", "scene": "heavy_top"},
            {"name": "phys202", "mode": "presenter", "pin": "222222", "scene": "pendulum"},
            {"name": "homework", "mode": "private", "scene": "pendulum", "free_hosts": ["127.0.0.2", "127.0.0.3"]},
        ],
    )
    with running_department(path, port) as running:
        yield running


def pool(department: RunningDepartment) -> list[str]:
    """The pool's two backends (``host:port``) in order, from the log's start lines."""
    found = dict(re.findall(r"started (homework \d) \(pid \d+\) on (\S+)", department.log()))
    return [found["homework 1"], found["homework 2"]]


def scene_and_nodes(messages: list[dict[str, Any]]) -> tuple[str | None, bool | None, set[str]]:
    """What a client was shown: the Scene picker's last value, whether the picker is disabled (a follower),
    and every scene node named."""
    picker, value, disabled = None, None, None
    nodes: set[str] = set()
    for m in messages:
        if isinstance(m.get("name"), str):
            nodes.add(m["name"])
        if m["type"] == "GuiDropdownMessage" and m["props"].get("label") == "Scene":
            picker, value, disabled = m["uuid"], m["value"], m["props"].get("disabled")
        elif m["type"] == "GuiUpdateMessage" and m.get("uuid") == picker:
            value = m["updates"].get("value", value)
            disabled = m["updates"].get("disabled", disabled)
    return value, disabled, nodes


def shown_to(ws: Any, title: str, nodes: set[str], timeout: float = 20.0) -> tuple[str | None, bool | None, set[str]]:
    """:func:`scene_and_nodes` of what a follower is sent on joining: read until viser's end of the replay
    of the room's state has come, the picker shows a scene starting with ``title`` (enabled or not) and the
    scene's ``nodes`` are there (a room showing another scene is read for ``timeout`` and then fails on what it showed)."""
    messages: list[dict[str, Any]] = []
    deadline = time.monotonic() + timeout
    while time.monotonic() < deadline:
        messages += received(ws, 0.05)
        value, disabled, named = scene_and_nodes(messages)
        replayed = any(m["type"] == "ReplayDoneMessage" for m in messages)
        if replayed and value is not None and value.startswith(title) and disabled is not None and nodes <= named:
            break
    return scene_and_nodes(messages)


def test_the_landing_page_lists_the_rooms_and_a_bare_room_address_is_redirected(department: RunningDepartment) -> None:
    landing = get(department.port, "/")
    assert landing.status == 200 and landing.getheader("Content-Type") == "text/html"
    page = landing.body.decode()  # type: ignore[attr-defined]
    for name, scene in (("mech101", "heavy_top"), ("phys202", "pendulum"), ("homework", "pendulum")):
        assert re.search(rf'<a href="/{name}/">{name}</a></td><td>[^<]+</td><td>{scene}</td>', page), page
    bare = get(department.port, "/mech101")
    assert bare.status == 301 and bare.getheader("Location") == "/mech101/"  # relative: right behind any proxy
    room = get(department.port, "/mech101/")
    assert room.status == 200 and b"<!doctype html>" in room.body[:200].lower()  # type: ignore[attr-defined]
    assert get(department.port, "/nowhere/").status == 404


@pytest.mark.parametrize(
    ("accept", "lang"), [("de-DE,de;q=0.9,en;q=0.8", "de"), ("zh-CN,zh;q=0.9", "zh"), ("es", "es"), ("fr-FR,fr", "en")]
)
def test_the_landing_page_is_in_the_browsers_first_language(
    department: RunningDepartment, accept: str, lang: str
) -> None:
    """nginx picks the page in the language the browser asks for first, if the app speaks it (else English),
    and says it varies with Accept-Language (a cache keeps one per language)."""
    landing = get(department.port, "/", headers={"Accept-Language": accept})
    page = landing.body.decode()  # type: ignore[attr-defined]
    assert landing.status == 200 and landing.getheader("Vary") == "Accept-Language"
    assert f'<html lang="{lang}">' in page
    assert html.escape(translate("Choose your room:", lang), quote=True) in page
    assert '<a href="/mech101/">mech101</a>' in page


def test_each_room_routes_to_its_process_and_a_follower_sees_only_its_rooms_scene(
    department: RunningDepartment,
) -> None:
    ports = dict(re.findall(r"started (mech101|phys202) \(pid \d+\) on 127\.0\.0\.1:(\d+)", department.log()))
    shown = {}
    for room in ("mech101", "phys202"):
        with proxied(department.port, room) as ws:
            assert ws.subprotocol == SUBPROTOCOL  # viser's subprotocol passed through both ways
            assert backend_of(ws) == f"127.0.0.1:{ports[room]}"
            expected = ("Heavy top", {LECTURE_NODE}) if room == "mech101" else ("Physical pendulum", PENDULUM_NODES)
            shown[room] = shown_to(ws, *expected)
    lecture, pendulum = shown["mech101"], shown["phys202"]
    assert lecture[0] == "Heavy top" and lecture[1] is True  # a follower: the picker is disabled
    assert LECTURE_NODE in lecture[2] and not PENDULUM_NODES & lecture[2]
    assert pendulum[0] is not None and pendulum[0].startswith("Physical pendulum") and pendulum[1] is True
    assert PENDULUM_NODES <= pendulum[2] and LECTURE_NODE not in pendulum[2]


def test_a_private_pool_keeps_a_browser_by_its_cookie_and_spreads_browsers_behind_one_address(
    department: RunningDepartment,
) -> None:
    backends = Counter()
    for _ in range(16):  # sixteen browsers, all from 127.0.0.1 (one NAT address)
        cookie, first = room_cookie(department.port, "homework")
        assert re.fullmatch(r"rbl_homework=[01]", cookie)  # the number of the process that answered
        for _ in range(2):  # the page's websocket, then a reconnect: the same process each time
            with proxied(department.port, "homework", cookie) as ws:
                assert backend_of(ws) == first
                assert ws.recv(timeout=20)
        backends[first] += 1
    assert set(backends) == set(pool(department)), backends  # both processes took browsers
    # A cookie that names the process is kept, not replaced; one that names none gets a process's number.
    again = get(department.port, "/homework/rooms-probe", cookie=cookie)
    assert again.getheader("Set-Cookie") is None
    forged = get(department.port, "/homework/rooms-probe", cookie="rbl_homework=" + "ab" * 16)
    assert re.match(r"rbl_homework=[01];", forged.getheader("Set-Cookie") or ""), forged.getheaders()


def test_a_pool_spreads_forty_browsers_twenty_and_twenty_and_keeps_each_over_reconnects(
    department: RunningDepartment,
) -> None:
    """Forty browsers from one address join one after another, each keeping its websocket open (a student's
    tab): the least-loaded process takes each first visit, so each process has twenty; a browser that
    reconnects (a reload) comes back to its own process, by its cookie."""
    processes = pool(department)
    with contextlib.ExitStack() as tabs:
        joined = []
        for _ in range(40):
            cookie, first = room_cookie(department.port, "homework")
            ws = tabs.enter_context(proxied(department.port, "homework", cookie))
            assert backend_of(ws) == first
            joined.append((cookie, first))
        assert Counter(backend for _, backend in joined) == {processes[0]: 20, processes[1]: 20}
        for cookie, first in joined:
            with proxied(department.port, "homework", cookie) as again:
                assert backend_of(again) == first


@pytest.mark.browser
def test_chromium_opens_a_room_under_its_prefix(department: RunningDepartment, chromium: Any) -> None:
    """The real page at /homework: redirected to /homework/, its script opens viser's websocket at
    /homework (relative to the page, in a web worker) through the proxy with the room's cookie, and the
    room's panel comes. nginx's access log shows the upgrade (101) with that cookie, on the page's process
    (the one the cookie names)."""
    folder = re.search(r"nginx configuration and logs in (\S+)", department.log())
    assert folder is not None
    access = Path(folder.group(1)) / "logs" / "access.log"
    before = len(access.read_text().splitlines())  # this page's lines are the ones after
    context = chromium.new_context(viewport={"width": 640, "height": 480})
    try:
        page = context.new_page()
        page.goto(department.url("/homework"), wait_until="domcontentloaded")
        assert page.url == department.url("/homework/")
        page.wait_for_function(
            "() => [...document.querySelectorAll('label')].some(l => l.textContent.trim() === 'Scene')",
            timeout=60_000,
        )
        cookies = {c["name"]: c for c in context.cookies()}
        assert cookies["rbl_homework"]["path"] == "/homework"
        value = cookies["rbl_homework"]["value"]
    finally:
        context.close()  # nginx logs a websocket when it closes

    def lines(request: str, cookie: str | None = None) -> list[str]:
        ours = access.read_text().splitlines()[before:]
        return [line for line in ours if request in line and (cookie is None or f"room_cookie={cookie}" in line)]

    upgraded = wait_for(
        lambda: lines('"GET /homework HTTP/1.1" 101', value), timeout=10, what="the websocket's log line"
    )
    page_line = lines('"GET /homework/ HTTP/1.1" 200')  # the first visit: no cookie yet, the answer sets it
    assert len(upgraded) == 1 and len(page_line) == 1
    upstream = re.compile(r"upstream=(\S+)")
    assert upstream.search(upgraded[0]).group(1) == upstream.search(page_line[0]).group(1)  # type: ignore[union-attr]
    assert upstream.search(upgraded[0]).group(1) == pool(department)[int(value)]  # type: ignore[union-attr]


def test_a_killed_pool_process_is_restarted_and_joins_meanwhile_land_on_the_living(
    department: RunningDepartment,
) -> None:
    """The supervisor restarts a killed room process at once; joins meanwhile land on the living one. How
    soon it is back is a cold start of the room's process (under 10 s on two idle cores; 19 s on CI's loaded
    ones, as the department's own start showed): a clock in a test would measure the machine's load."""
    first, second = pool(department)
    # A browser on the process that stays: it keeps receiving while the other dies.
    while True:
        cookie, backend = room_cookie(department.port, "homework")
        if backend == second:
            break
    with proxied(department.port, "homework", cookie) as survivor:
        survivor.recv(timeout=20)
        start = len(department.lines)
        victim = department.pids()["homework 1"]
        killed = time.monotonic()
        os.kill(victim, signal.SIGKILL)
        department.wait_line(rf"homework 1 \(pid {victim}\) killed by SIGKILL .*restarting", 5, start)
        host, port = first.split(":")
        joined = []  # (the process that took it, whether the killed one's port refused just before the join)
        # Every join within 5 s of the kill works, until one lands on the restarted process or the supervisor
        # says it is back. The supervisor says so at its next look, so a join can reach the new process
        # before the line: a join that lands there is fine, since only a living process answers.
        while time.monotonic() - killed < 5.0:
            if any("homework 1 is back" in line for line in department.lines[start:]):
                break
            down = not answers(host, int(port))
            fresh, _ = room_cookie(department.port, "homework")
            with proxied(department.port, "homework", fresh) as ws:
                joined.append((backend_of(ws), down))
                assert ws.recv(timeout=10)
            # Still connected and served (a lost process would end the stream): a join builds its own session
            # on the survivor's process, which holds that process's frames for a few seconds on a loaded machine.
            assert survivor.recv(timeout=20)
            if joined[-1][0] == first:
                break
        # Joins were made while the killed process was down, and they landed on the living one.
        assert any(down and backend == second for backend, down in joined), joined
        department.wait_line(r"homework 1 is back", 90.0, start)
        assert answers(host, int(port))
        assert department.pids()["homework 1"] != victim and alive(department.pids()["homework 1"])
        assert survivor.recv(timeout=20)  # and the survivor never lost its process


def test_a_killed_nginx_is_restarted_with_its_workers_gone(department: RunningDepartment) -> None:
    """nginx's workers outlive a master killed with SIGKILL and hold its port: the supervisor clears the
    group and starts nginx again, and the rooms answer through it."""
    start = len(department.lines)
    master = department.pids()["nginx"]
    workers = [int(p) for p in Path(f"/proc/{master}/task/{master}/children").read_text().split()]
    assert workers
    killed = time.monotonic()
    os.kill(master, signal.SIGKILL)
    department.wait_line(r"nginx is back", 10.0, start)
    assert time.monotonic() - killed < 10.0
    assert not [pid for pid in workers if alive(pid)]
    assert get(department.port, "/").status == 200
    with proxied(department.port, "mech101") as ws:
        assert ws.recv(timeout=20)


def test_no_pin_is_on_a_command_line_and_each_lecture_has_its_own(department: RunningDepartment) -> None:
    """``ps`` shows every user each process's command line: no PIN is on one; each presenter room's process
    has its PIN in its environment (readable by its own user alone)."""
    pins = {b"111111": b"--port", b"222222": b"--port"}
    lectures = []
    for proc in Path("/proc").iterdir():
        try:
            argv = (proc / "cmdline").read_bytes() if proc.name.isdigit() else b""
            environ = (proc / "environ").read_bytes() if b"--presenter" in argv else b""
        except OSError:  # a process that just ended
            continue
        assert not any(pin in argv for pin in pins), argv
        if environ:
            lectures.append(environ.split(b"\0"))
    found = sorted(v for env in lectures for v in env if v.startswith(b"RBL_PIN="))
    assert found == [b"RBL_PIN=111111", b"RBL_PIN=222222"], found


def test_sigint_stops_nginx_and_every_process(department: RunningDepartment) -> None:
    pids = department.pids()
    assert set(pids) == {"mech101", "phys202", "homework 1", "homework 2", "nginx"}
    assert all(alive(pid) for pid in pids.values())
    assert department.stop(signal.SIGINT) == 0  # Ctrl-C
    assert "stopped: nginx and every room process" in department.log()
    assert not [pid for pid in pids.values() if alive(pid)]
    assert port_free("127.0.0.1", department.port)
    for backend in pool(department):
        host, port = backend.split(":")
        assert port_free(host, int(port))


def test_sigterm_stops_a_department_started_on_its_own(tmp_path: Path) -> None:
    """A second, one-room department stopped by SIGTERM (systemd's, a terminal closing): nothing left."""
    nginx_or_skip()
    path, port = rooms_file(tmp_path, [{"name": "demo", "mode": "shared", "free_hosts": ["127.0.0.1"]}])
    with running_department(path, port) as running:
        pids = running.pids()
        with proxied(port, "demo") as ws:
            assert ws.recv(timeout=20)
        assert running.stop(signal.SIGTERM) == 0
        assert set(pids) == {"demo", "nginx"} and not [pid for pid in pids.values() if alive(pid)]
    assert port_free("127.0.0.1", port)


def test_a_department_killed_with_sigkill_takes_its_processes_with_it(tmp_path: Path) -> None:
    """No handler runs on SIGKILL: each child was started to get SIGTERM when the supervisor dies."""
    nginx_or_skip()
    path, port = rooms_file(tmp_path, [{"name": "demo", "mode": "shared", "free_hosts": ["127.0.0.1"]}])
    with running_department(path, port) as running:
        pids = running.pids()
        assert running.stop(signal.SIGKILL) == -signal.SIGKILL
        wait_for(lambda: not [pid for pid in pids.values() if alive(pid)], timeout=10, what="the children to go")
    assert port_free("127.0.0.1", port)
