"""``rigid-body-lab rooms ROOMS.toml --write DIR``: nginx accepts what is written (``nginx -t``), the units
run the right processes, remote ``hosts`` become backends, and the landing page lists every room."""

from __future__ import annotations

import configparser
import html
import re
import shlex
import stat
import subprocess
import sys
from pathlib import Path

import pytest

from app.rooms.cli import main as rooms_main
from app.rooms.cli import write_private
from app.rooms.config import PIN_VARIABLE, parse_rooms
from app.rooms.landing import landing_html
from app.rooms.nginx import find_nginx, nginx_command, rooms_conf
from app.rooms.units import MEMORY_MAX

ROOMS = """
listen = "0.0.0.0:8080"
title = "Mechanics: it's $5 \\\\ free"
[[room]]
name = "mech101"
mode = "presenter"
pin = "111111"
scene = "heavy_top"
[[room]]
name = "demo-room"
mode = "shared"
scene = "pendulum"
port = 9100
[[room]]
name = "homework"
mode = "private"
hosts = ["10.0.0.5:8101", "10.0.0.6:8101", "127.0.0.1:8101"]
"""


@pytest.fixture(scope="module")
def written(tmp_path_factory: pytest.TempPathFactory) -> Path:
    folder = tmp_path_factory.mktemp("deploy")
    path = folder / "rooms.toml"
    path.write_text(ROOMS)
    assert rooms_main([str(path), "--write", str(folder / "out")]) == 0
    return folder / "out"


def test_nginx_accepts_the_written_configuration(written: Path) -> None:
    nginx = find_nginx()
    result = subprocess.run(nginx_command(nginx, written, test=True), capture_output=True, text=True, timeout=30)
    assert result.returncode == 0, result.stderr
    # And it is really this configuration nginx read: a broken one is refused the same way.
    broken = written.parent / "broken"
    broken.mkdir()
    (broken / "logs").mkdir()
    (broken / "nginx.conf").write_text((written / "nginx.conf").read_text())
    (broken / "rooms.conf").write_text((written / "rooms.conf").read_text().replace("least_conn", "least_cnno", 1))
    refused = subprocess.run(nginx_command(nginx, broken, test=True), capture_output=True, text=True, timeout=30)
    assert refused.returncode != 0 and "least_cnno" in refused.stderr


def test_remote_hosts_are_backends_of_the_pool(written: Path) -> None:
    conf = (written / "rooms.conf").read_text()
    pool = conf[conf.index("upstream rbl_homework {") :].split("}", 1)[0]
    assert "least_conn;" in pool and "zone rbl_homework 64k;" in pool
    for address in ("10.0.0.5:8101", "10.0.0.6:8101", "127.0.0.1:8101"):
        assert f"server {address} max_fails=1" in pool
    assert "listen 0.0.0.0:8080;" in conf
    assert "X-Room-Backend" not in conf  # a deployment does not show its backends' addresses
    assert "upstream rbl_demo_room {\n    server 127.0.0.1:9100;\n}" in conf
    assert "location = /demo-room {" in conf and "location /demo-room/ {" in conf


def _service(path: Path) -> configparser.ConfigParser:
    unit = configparser.ConfigParser(interpolation=None, strict=False)
    unit.optionxform = str  # type: ignore[assignment,method-assign]
    unit.read_string(path.read_text())
    return unit


def test_one_unit_per_process_running_the_rooms_command_line(written: Path) -> None:
    units = written / "systemd"
    names = sorted(p.name for p in units.iterdir())
    assert names == [
        "rigid-body-lab-demo-room.service",
        "rigid-body-lab-homework-1.service",
        "rigid-body-lab-homework-2.service",
        "rigid-body-lab-homework-3.service",
        "rigid-body-lab-mech101.service",
        "rigid-body-lab-proxy.service",
        "rigid-body-lab.target",
    ]
    lecture = shlex.split(_service(units / "rigid-body-lab-mech101.service")["Service"]["ExecStart"])
    assert lecture[1:] == [
        "-m", "app", "--host", "127.0.0.1", "--port", "8081", "--scene", "heavy_top", "--presenter",
    ]  # fmt: skip
    demo = shlex.split(_service(units / "rigid-body-lab-demo-room.service")["Service"]["ExecStart"])
    assert demo[3:] == ["--host", "127.0.0.1", "--port", "9100", "--scene", "pendulum", "--shared"]
    remote = _service(units / "rigid-body-lab-homework-2.service")
    assert shlex.split(remote["Service"]["ExecStart"])[3:] == ["--host", "10.0.0.6", "--port", "8101", "--private"]
    assert remote["Service"]["Restart"] == "always"
    proxy = shlex.split(_service(units / "rigid-body-lab-proxy.service")["Service"]["ExecStart"])
    assert proxy[1:] == ["-p", f"{written}/", "-c", f"{written}/nginx.conf", "-g", "daemon off;"]
    target = _service(units / "rigid-body-lab.target")["Unit"]["Wants"].split()
    # The target of the proxy's machine wants its own processes and the proxy, not the other machines'.
    assert sorted(target) == [
        "rigid-body-lab-demo-room.service",
        "rigid-body-lab-homework-3.service",
        "rigid-body-lab-mech101.service",
        "rigid-body-lab-proxy.service",
    ]
    readme = (written / "README.txt").read_text()
    assert "10.0.0.5: rigid-body-lab-homework-1.service" in readme
    assert "10.0.0.6: rigid-body-lab-homework-2.service" in readme


def test_the_landing_page_lists_every_room_with_its_link() -> None:
    department = parse_rooms(
        {
            "title": "Mechanics: it's $5 \\ free",
            "room": [
                {"name": "mech101", "mode": "presenter", "pin": "111111", "scene": "heavy_top"},
                {"name": "homework", "mode": "private", "processes": 2},
            ],
        }
    )
    page = landing_html(department)
    assert '<a href="/mech101/">mech101</a>' in page and '<a href="/homework/">homework</a>' in page
    assert "<td>heavy_top</td>" in page and "<td>the first scene</td>" in page
    assert "lecture: follow the lecturer" in page and "private: a simulation of your own" in page
    assert "111111" not in page  # never the PIN
    # Quote, dollar and backslash escaped: the page is one nginx string without variables.
    assert not {"'", "$", "\\"} & set(page)
    assert html.unescape(page).count("Mechanics: it's $5 \\ free") == 2  # title and heading
    assert page in rooms_conf(department)


APP_UNITS = (
    "rigid-body-lab-demo-room.service",
    "rigid-body-lab-homework-1.service",
    "rigid-body-lab-homework-2.service",
    "rigid-body-lab-homework-3.service",
    "rigid-body-lab-mech101.service",
)


def test_every_app_unit_runs_sandboxed(written: Path) -> None:
    """No root, a read-only system, hidden homes, a private /tmp, no new privileges, a memory ceiling."""
    for name in APP_UNITS:
        service = _service(written / "systemd" / name)["Service"]
        for key, value in [
            ("DynamicUser", "yes"),
            ("NoNewPrivileges", "yes"),
            ("ProtectSystem", "strict"),
            ("PrivateTmp", "yes"),
            ("MemoryMax", MEMORY_MAX),
        ]:
            assert service[key] == value, (name, key)
        assert "User" not in service  # DynamicUser= makes a user of its own
        if service["ProtectHome"] == "tmpfs":  # Python or the app under a home: only they are seen there
            bound = service["BindReadOnlyPaths"].split()
            assert bound and all(p.startswith(("/home/", "/root", "/run/user/")) for p in bound), bound
            assert sys.prefix in bound or not sys.prefix.startswith(("/home/", "/root"))
        else:
            assert service["ProtectHome"] == "yes"


def test_no_pin_is_on_a_command_line_or_in_a_file_others_can_read(written: Path) -> None:
    for path in (written / "systemd").iterdir():
        assert "111111" not in path.read_text(), path.name
    secrets = written / "secrets"
    assert stat.S_IMODE(secrets.stat().st_mode) == 0o700
    pin_file = secrets / "rigid-body-lab-mech101.env"
    assert pin_file.read_text() == f"{PIN_VARIABLE}=111111\n"
    lecture = _service(written / "systemd" / "rigid-body-lab-mech101.service")["Service"]
    assert lecture["EnvironmentFile"] == str(pin_file)
    assert "EnvironmentFile" not in _service(written / "systemd" / "rigid-body-lab-demo-room.service")["Service"]
    holding = [p for p in written.rglob("*") if p.is_file() and "111111" in p.read_text(errors="replace")]
    assert sorted(p.name for p in holding) == ["README.txt", "rigid-body-lab-mech101.env"]
    for path in holding:
        assert stat.S_IMODE(path.stat().st_mode) == 0o600, path.name


def test_a_pin_file_written_again_is_0600_even_if_it_was_not(tmp_path: Path) -> None:
    path = tmp_path / "README.txt"
    path.write_text("old")
    path.chmod(0o644)
    write_private(path, "PIN 1234\n")
    assert stat.S_IMODE(path.stat().st_mode) == 0o600 and path.read_text() == "PIN 1234\n"


def test_systemd_accepts_the_units(written: Path) -> None:
    """``systemd-analyze verify`` and ``security`` on the app units (Debian's systemd 252 has both, and runs
    them on unit files without a running systemd)."""
    result = subprocess.run(
        ["systemd-analyze", "verify", *(str(written / "systemd" / name) for name in APP_UNITS)],
        capture_output=True,
        text=True,
        timeout=120,
    )
    assert result.returncode == 0 and result.stderr.strip() == "", result.stderr  # a bad directive is a warning
    for name in APP_UNITS:  # systemd's own rating of the sandbox: 9.6 "UNSAFE" for a unit with none
        rating = subprocess.run(
            ["systemd-analyze", "security", "--offline=yes", str(written / "systemd" / name)],
            capture_output=True,
            text=True,
            timeout=120,
        ).stdout
        exposure = float(re.search(r"Overall exposure level for \S+: ([0-9.]+)", rating).group(1))  # type: ignore[union-attr]
        assert exposure < 5.0, (name, rating[-300:])


TWO_MACHINES = """
listen = "0.0.0.0:80"
redis = "10.0.0.5:6379"
[[room]]
name = "homework"
mode = "private"
pin = "246810"
hosts = ["10.0.0.5:8101", "10.0.0.6:8101"]
"""


def test_a_pool_over_two_machines_gets_a_redis_unit_and_its_address(tmp_path: Path) -> None:
    path = tmp_path / "rooms.toml"
    path.write_text(TWO_MACHINES)
    out = tmp_path / "out"
    assert rooms_main([str(path), "--write", str(out)]) == 0
    units = out / "systemd"
    redis_unit = _service(units / "rigid-body-lab-redis.service")
    service = redis_unit["Service"]
    command = shlex.split(service["ExecStart"])
    # The password: in a 0600 file of root's, handed to the service as a credential, never on a command line.
    assert command[0].endswith("redis-server") and command[1] == "${CREDENTIALS_DIRECTORY}/redis.conf"
    assert service["LoadCredential"] == f"redis.conf:{out / 'secrets' / 'redis.conf'}"
    conf = out / "secrets" / "redis.conf"
    assert stat.S_IMODE(conf.stat().st_mode) == 0o600
    password = re.fullmatch(r"requirepass (\S{24,})\n", conf.read_text()).group(1)  # type: ignore[union-attr]
    flags = dict(zip(command[2::2], command[3::2], strict=True))
    # On the address the other machine reaches; nothing written to disk; a memory ceiling.
    assert flags["--bind"] == "10.0.0.5" and flags["--port"] == "6379" and flags["--save"] == ""
    assert flags["--appendonly"] == "no" and flags["--maxmemory"] == "64mb" and flags["--protected-mode"] == "no"
    assert redis_unit["Unit"]["Before"] == "rigid-body-lab-homework-1.service"  # the process on its machine
    for index in (1, 2):
        unit = (units / f"rigid-body-lab-homework-{index}.service").read_text()
        assert 'Environment="RBL_REDIS=10.0.0.5:6379"' in unit
        assert f'Environment="RBL_POOL=homework {index} 2"' in unit
        assert "246810" not in unit and password not in unit  # secrets: in the environment files only
        environment = (out / "secrets" / f"rigid-body-lab-homework-{index}.env").read_text()
        assert environment == f"{PIN_VARIABLE}=246810\nRBL_REDIS_PASSWORD={password}\n"
    assert password not in (units / "rigid-body-lab-redis.service").read_text()
    readme = (out / "README.txt").read_text()
    assert "10.0.0.5: rigid-body-lab-redis.service rigid-body-lab-homework-1.service" in readme
    assert "Redis at 10.0.0.5:6379" in readme and "firewall" in readme
    result = subprocess.run(
        ["systemd-analyze", "verify", str(units / "rigid-body-lab-redis.service")],
        capture_output=True,
        text=True,
        timeout=120,
    )
    assert result.returncode == 0 and result.stderr.strip() == "", result.stderr


def test_a_pool_on_this_machine_gets_redis_on_loopback(tmp_path: Path) -> None:
    path = tmp_path / "rooms.toml"
    path.write_text(
        'listen = "127.0.0.1:8000"\n[[room]]\nname = "lab"\nmode = "private"\nprocesses = 2\npin = "1234"\n'
    )
    out = tmp_path / "out"
    assert rooms_main([str(path), "--write", str(out)]) == 0
    command = shlex.split(_service(out / "systemd" / "rigid-body-lab-redis.service")["Service"]["ExecStart"])
    flags = dict(zip(command[2::2], command[3::2], strict=True))
    assert (flags["--bind"], flags["--port"], flags["--protected-mode"]) == ("127.0.0.1", "8003", "yes")
    target = _service(out / "systemd" / "rigid-body-lab.target")["Unit"]["Wants"].split()
    assert "rigid-body-lab-redis.service" in target
