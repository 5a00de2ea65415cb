"""The rooms file: what it builds, and every refusal naming the room and the key, before anything starts."""

from __future__ import annotations

import socket
import subprocess
import sys
from pathlib import Path
from typing import Any

import pytest

import app.serving.app
from app.__main__ import main as app_main
from app.rooms.cli import check_ports
from app.rooms.cli import main as rooms_main
from app.rooms.config import (
    PIN_VARIABLE,
    Backend,
    RoomsError,
    app_arguments,
    parse_rooms,
    pin_environment,
    pool_environment,
    read_rooms,
)
from app.rooms.nginx import NginxMissing, find_nginx
from tests.harness import free_port

ROOT = Path(__file__).resolve().parents[2]
EXAMPLE = ROOT / "examples" / "rooms.toml"


def department(rooms: list[dict[str, Any]], **top: Any) -> Any:
    return parse_rooms({"listen": "127.0.0.1:8000", **top, "room": rooms}, source="t.toml", pin_source=lambda: "424242")


def test_the_example_file_is_the_issues_department() -> None:
    d = read_rooms(EXAMPLE)
    assert (d.listen_host, d.listen_port) == ("127.0.0.1", 8000)
    assert [(r.name, r.mode, r.scene, r.pin) for r in d.rooms] == [
        ("mech101", "presenter", "heavy_top", "111111"),
        ("phys202", "presenter", "pendulum", "222222"),
        ("homework", "private", None, None),
    ]
    # Ports after the proxy's, in the file's order: one per presenter room, two for the pool.
    assert [[b.address for b in r.backends] for r in d.rooms] == [
        ["127.0.0.1:8001"],
        ["127.0.0.1:8002"],
        ["127.0.0.1:8003", "127.0.0.1:8004"],
    ]


def test_automatic_ports_never_take_a_port_a_later_room_names() -> None:
    d = department(
        [
            {"name": "a", "mode": "private", "processes": 2},
            {"name": "b", "mode": "shared", "port": 8002},
            {"name": "c", "mode": "private", "hosts": ["10.0.0.5:8101", "10.0.0.6:8101"]},
        ]
    )
    assert [b.port for b in d.room("a").backends] == [8003, 8004]  # 8002 is b's: the pool goes after it
    assert d.room("b").backends == (Backend("127.0.0.1", 8002, 1),)
    assert d.room("c").backends == (Backend("10.0.0.5", 8101, 1), Backend("10.0.0.6", 8101, 2))


def test_each_mode_is_the_apps_command_line() -> None:
    d = department(
        [
            {"name": "lecture", "mode": "presenter", "pin": "1234", "scene": "pendulum"},
            {"name": "lab", "mode": "private", "processes": 2, "dark": True},
            {"name": "demo", "mode": "shared", "hosts": ["10.0.0.7:9000"]},
            {"name": "nopin", "mode": "presenter"},
        ]
    )
    lecture, lab, demo, nopin = d.rooms
    assert app_arguments(lecture, lecture.backends[0]) == [
        "--host", "127.0.0.1", "--port", "8001", "--scene", "pendulum", "--presenter",
    ]  # fmt: skip
    assert pin_environment(lecture) == {PIN_VARIABLE: "1234"}  # the PIN: in the environment, never in argv
    assert pin_environment(lab) == {} and pin_environment(demo) == {}
    assert app_arguments(lab, lab.backends[1]) == ["--host", "127.0.0.1", "--port", "8003", "--private", "--dark"]
    # A shared room on another machine's address: --shared, or the app would default to presenter mode there.
    assert app_arguments(demo, demo.backends[0]) == ["--host", "10.0.0.7", "--port", "9000", "--shared"]
    assert (nopin.pin, nopin.pin_given) == ("424242", False)  # drawn once, so a restart keeps it


def test_a_pool_with_a_teacher_pin_shares_its_table_through_redis() -> None:
    d = department(
        [
            {"name": "lab", "mode": "private", "processes": 2, "pin": "2468"},
            {"name": "solo", "mode": "private", "pin": "1357"},  # one process: its table is its own
            {"name": "open", "mode": "private", "processes": 2},  # no teacher PIN: no table
        ]
    )
    lab, solo, open_ = d.rooms
    assert d.redis == ("127.0.0.1", 8006) and not d.redis_given  # started here, after the rooms' ports
    assert (lab.shares_table, solo.shares_table, open_.shares_table) == (True, False, False)
    assert pin_environment(lab) == {PIN_VARIABLE: "2468"} and pin_environment(open_) == {}
    assert pool_environment(d, lab, lab.backends[1]) == {"RBL_REDIS": "127.0.0.1:8006", "RBL_POOL": "lab 2 2"}
    assert pool_environment(d, solo, solo.backends[0]) == {} == pool_environment(d, open_, open_.backends[0])
    # Two machines: the Redis named in the file, which both reach.
    far = department(
        [{"name": "lab", "mode": "private", "pin": "2468", "hosts": ["10.0.0.5:8101", "10.0.0.6:8101"]}],
        redis="10.0.0.5:6379",
    )
    assert far.redis == ("10.0.0.5", 6379) and far.redis_given
    assert pool_environment(far, far.rooms[0], far.rooms[0].backends[0])["RBL_REDIS"] == "10.0.0.5:6379"
    assert department([{"name": "a", "mode": "private", "processes": 2}]).redis is None  # no teacher: no Redis


REFUSALS = [
    # (rooms, top-level keys, words the message must contain)
    (
        [{"name": "a", "mode": "shared"}, {"name": "a", "mode": "private"}],
        {},
        ["room 'a' (room 2)", "'name'", "duplicate"],
    ),
    (
        [{"name": "a", "mode": "shared", "port": 8101}, {"name": "b", "mode": "shared", "port": 8101}],
        {},
        ["room 'b' (room 2)", "'port'", "duplicate port", "127.0.0.1:8101", "room 'a'"],
    ),
    ([{"name": "a", "mode": "shared", "port": 8000}], {}, ["room 'a'", "'port'", "duplicate port", "proxy"]),
    (
        [{"name": "a", "mode": "private", "port": 8101, "processes": 2}, {"name": "b", "mode": "shared", "port": 8102}],
        {},
        ["room 'b'", "'port'", "duplicate port", "127.0.0.1:8102"],
    ),
    (
        [{"name": "a", "mode": "private", "hosts": ["10.0.0.5:8101", "10.0.0.5:8101"]}],
        {},
        ["room 'a'", "'hosts'", "duplicate port", "10.0.0.5:8101"],
    ),
    ([{"name": "a", "mode": "lecture"}], {}, ["room 'a' (room 1)", "'mode'", "unknown mode 'lecture'", "presenter"]),
    ([{"name": "a"}], {}, ["room 'a'", "'mode'", "missing"]),
    ([{"name": "a", "mode": "presenter", "pin": "123"}], {}, ["room 'a'", "'pin'", "4 to 12 digits", "'123'"]),
    ([{"name": "a", "mode": "presenter", "pin": "1234567890123"}], {}, ["room 'a'", "'pin'", "4 to 12 digits"]),
    ([{"name": "a", "mode": "presenter", "pin": "12ab56"}], {}, ["room 'a'", "'pin'", "4 to 12 digits"]),
    ([{"name": "a", "mode": "presenter", "pin": 123456}], {}, ["room 'a'", "'pin'", "as a string"]),
    ([{"name": "a", "mode": "shared", "pin": "123456"}], {}, ["room 'a'", "'pin'", "teacher's view", "shared"]),
    ([{"name": "a", "mode": "private", "pin": "12"}], {}, ["room 'a'", "'pin'", "4 to 12 digits"]),
    ([{"name": "a", "mode": "shared"}], {"redis": "nowhere:x"}, ["'redis'", "port"]),
    ([{"name": "a", "mode": "shared"}], {"redis": "127.0.0.1:8000"}, ["'redis'", "already used", "proxy"]),
    (
        [{"name": "a", "mode": "private", "pin": "1234", "hosts": ["10.0.0.5:8101", "10.0.0.6:8101"]}],
        {},
        ["'redis'", "room 'a'", "other machines", "loopback", "redis = "],
    ),
    ([{"name": "a", "mode": "private", "processes": 0}], {}, ["room 'a'", "'processes'", "at least 1, got 0"]),
    ([{"name": "a", "mode": "private", "processes": -2}], {}, ["room 'a'", "'processes'", "at least 1"]),
    ([{"name": "a", "mode": "presenter", "processes": 2}], {}, ["room 'a'", "'processes'", "only a private room"]),
    ([{"name": "a", "mode": "private", "processes": "2"}], {}, ["room 'a'", "'processes'", "whole number"]),
    (
        [{"name": "a", "mode": "private", "processes": 3, "hosts": ["h:1", "h:2"]}],
        {},
        ["room 'a'", "'processes'", "3 processes but 2 hosts"],
    ),
    ([{"name": "a", "mode": "shared", "scene": "spinner"}], {}, ["room 'a'", "'scene'", "unknown scene 'spinner'"]),
    ([{"name": "A b", "mode": "shared"}], {}, ["room 1", "'name'", "lower-case"]),
    ([{"mode": "shared"}], {}, ["room 1", "'name'", "missing"]),
    ([{"name": "a-b", "mode": "shared"}, {"name": "a_b", "mode": "shared"}], {}, ["room 'a_b'", "'name'", "cookie"]),
    ([{"name": "a", "mode": "shared", "procesess": 2}], {}, ["room 'a'", "'procesess'", "unknown key"]),
    ([{"name": "a", "mode": "shared", "port": 70000}], {}, ["room 'a'", "'port'", "65535"]),
    ([{"name": "a", "mode": "shared", "hosts": ["nowhere"]}], {}, ["room 'a'", "'hosts'", "port"]),
    ([{"name": "a", "mode": "shared"}], {"listen": "localhost"}, ["'listen'", "port"]),
    ([{"name": "a", "mode": "shared"}], {"listn": "x"}, ["'listn'", "unknown key"]),
    ([], {}, ["'room'", "at least one [[room]]"]),
]


@pytest.mark.parametrize(("rooms", "top", "words"), REFUSALS)
def test_a_bad_file_is_refused_naming_the_room_and_the_key(rooms: Any, top: Any, words: list[str]) -> None:
    with pytest.raises(RoomsError) as refused:
        department(rooms, **top)
    message = str(refused.value)
    assert message.startswith("t.toml: ")
    for word in words:
        assert word in message, f"{word!r} not in {message!r}"


def test_missing_nginx_is_refused_with_the_line_that_installs_it(tmp_path: Path) -> None:
    with pytest.raises(NginxMissing, match=r"install it with: sudo apt-get install nginx"):
        find_nginx(search_path=str(tmp_path))  # a PATH without nginx
    with pytest.raises(NginxMissing, match=r"apt-get install nginx"):
        find_nginx(str(tmp_path / "nginx"))
    assert find_nginx(search_path="/usr/sbin:/usr/bin").endswith("nginx")  # the real one is found


def test_the_command_refuses_before_anything_starts(tmp_path: Path, capsys: pytest.CaptureFixture[str]) -> None:
    """Missing nginx: exit status 2, the install line, and nothing listening (the file's ports stay free)."""
    path = tmp_path / "rooms.toml"
    path.write_text('listen = "127.0.0.1:1"\n[[room]]\nname = "a"\nmode = "shared"\n')
    assert rooms_main([str(path), "--nginx", str(tmp_path / "no-nginx")]) == 2
    err = capsys.readouterr().err
    assert "refused: nginx not found" in err and "sudo apt-get install nginx" in err
    path.write_text('[[room]]\nname = "a"\nmode = "presenter"\npin = "12"\n')
    assert rooms_main([str(path)]) == 2
    assert "room 'a' (room 1), key 'pin'" in capsys.readouterr().err


def test_the_rigid_body_lab_command_dispatches_rooms(tmp_path: Path) -> None:
    """``rigid-body-lab rooms FILE`` (python -m app rooms) reaches app.rooms and refuses a bad file with 2."""
    path = tmp_path / "rooms.toml"
    path.write_text('[[room]]\nname = "hw"\nmode = "private"\nprocesses = 0\n')
    result = subprocess.run(
        [sys.executable, "-m", "app", "rooms", str(path)], cwd=ROOT, capture_output=True, text=True, timeout=60
    )
    assert result.returncode == 2, result.stderr
    assert "room 'hw' (room 1), key 'processes': must be at least 1, got 0" in result.stderr


def test_shared_is_a_mode_on_any_host(monkeypatch: pytest.MonkeyPatch, capsys: pytest.CaptureFixture[str]) -> None:
    """A shared room on another machine binds a non-loopback address, where the app's default is presenter
    mode: ``--shared`` keeps it shared (``presenter=False``), and only one of the three modes may be given."""
    given: dict[str, Any] = {}

    class Started(Exception):
        pass

    class StandIn:
        def __init__(self, **kwargs: Any) -> None:
            given.update(kwargs)
            raise Started

    monkeypatch.setattr(app.serving.app, "App", StandIn)
    with pytest.raises(Started):
        app_main(["--host", "10.0.0.5", "--port", "0", "--shared"])
    assert given["presenter"] is False and given["private"] is False
    with pytest.raises(Started):
        app_main(["--host", "10.0.0.5", "--port", "0"])
    assert given["presenter"] is None  # the default: presenter mode off loopback
    with pytest.raises(SystemExit):
        app_main(["--shared", "--private"])
    assert "choose one of --presenter, --private and --shared" in capsys.readouterr().err


def test_a_port_in_use_is_refused_and_another_machines_backend_is_not_started() -> None:
    with socket.socket() as taken:
        taken.bind(("127.0.0.1", 0))
        taken.listen()
        port = taken.getsockname()[1]
        free = free_port()
        d = department(
            [
                {"name": "lab", "mode": "private", "hosts": [f"127.0.0.1:{free}", "192.0.2.7:8101"]},
                {"name": "demo", "mode": "shared", "port": port},
            ],
            listen=f"127.0.0.1:{free_port()}",
        )
        with pytest.raises(RoomsError, match=rf"room 'demo' \(room 2\), key 'port': 127.0.0.1:{port} is in use"):
            check_ports(d)
    # Once the port is free: only this machine's backends are started (192.0.2.7 is not an address here).
    assert [(room.name, backend.address) for room, backend in check_ports(d)] == [
        ("lab", f"127.0.0.1:{free}"),
        ("demo", f"127.0.0.1:{port}"),
    ]
