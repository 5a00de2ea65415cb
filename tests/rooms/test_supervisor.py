"""The supervisor alone, with tiny child processes: restart with back-off, and a stop that leaves nothing."""

from __future__ import annotations

import re
import signal
import sys
import time

from app.rooms.cli import SERVING
from app.rooms.supervisor import ChildSpec, Supervisor
from tests.harness import wait_for
from tests.rooms.running import alive

STUBBORN = """
import signal, subprocess, sys, time
signal.signal(signal.SIGTERM, signal.SIG_IGN)
grandchild = subprocess.Popen([sys.executable, "-c", "import time; time.sleep(60)"])
print("grandchild", grandchild.pid, flush=True)
time.sleep(60)
"""


def test_a_child_that_keeps_dying_is_restarted_with_a_back_off_and_the_log_says_so() -> None:
    lines: list[str] = []
    supervisor = Supervisor(lines.append)
    supervisor.add(ChildSpec("crash", (sys.executable, "-c", "raise SystemExit(3)"), "127.0.0.1", 1))
    try:
        for child in supervisor.children:
            child.start()
        deadline = time.monotonic() + 20
        while sum("restarted crash" in line for line in lines) < 3 and time.monotonic() < deadline:
            supervisor.check()
            time.sleep(0.05)
    finally:
        supervisor.stop()
    deaths = [line for line in lines if "exited with code 3" in line]
    assert deaths[0].endswith("; restarting")  # the first death: at once
    assert deaths[1].endswith("restarting in 1 s (it keeps dying at start-up)")
    assert deaths[2].endswith("restarting in 2 s (it keeps dying at start-up)")
    assert supervisor.children[0].restarts >= 3


def test_stop_kills_a_child_that_ignores_sigterm_and_whatever_it_started() -> None:
    lines: list[str] = []
    supervisor = Supervisor(lines.append)
    child = supervisor.add(ChildSpec("stubborn", (sys.executable, "-c", STUBBORN), "127.0.0.1", 1))
    child.start()
    found = wait_for(lambda: [re.search(r"grandchild (\d+)", line) for line in lines if "grandchild" in line], 20)
    grandchild = int(found[0].group(1))
    pid = child.pid
    assert pid is not None and alive(pid) and alive(grandchild)
    start = time.monotonic()
    for c in supervisor.children:
        c.stop(grace=0.5)
    assert time.monotonic() - start < 5.0
    assert not alive(pid) and not alive(grandchild)
    assert "stubborn (pid" in lines[-1] and "did not stop within 0.5 s: killed" in lines[-1]


def test_a_child_serving_on_another_port_than_its_own_is_stopped() -> None:
    """viser moves to the next port when its own is taken; nginx would never reach it: stopped, said so."""
    lines: list[str] = []
    supervisor = Supervisor(lines.append)
    said = "import time; print('Rigid Body Lab serving on http://127.0.0.1:8102', flush=True); time.sleep(60)"
    spec = ChildSpec("moved", (sys.executable, "-c", said), "127.0.0.1", 8101, port_said=SERVING)
    child = supervisor.add(spec)
    child.start()
    try:
        assert child.process is not None
        child.process.wait(timeout=20)
        assert child.process.returncode == -signal.SIGTERM
        assert "moved serves on port 8102, not 8101 (taken?): stopping it" in lines
    finally:
        supervisor.stop()
