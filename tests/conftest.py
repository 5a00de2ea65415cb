"""Shared test configuration.

Under ``RBL_NO_SKIP=1`` (set by ``.ci/run``) any skipped test fails the session: in CI nothing that
should run may quietly not run.
"""

from __future__ import annotations

import json
import os
from pathlib import Path
from typing import Any

import pytest
from hypothesis import settings
from xdist.scheduler import LoadFileScheduling

# Property tests draw the same examples on every run (a fixed seed): CI is reproducible, and a failure
# seen once is seen again. Widen the search locally with `--hypothesis-seed=N` or HYPOTHESIS_PROFILE=explore.
settings.register_profile("fixed", derandomize=True, database=None, print_blob=True)
settings.register_profile("explore", derandomize=False)
settings.load_profile(os.environ.get("HYPOTHESIS_PROFILE", "fixed"))

_skipped: list[str] = []

FILE_SECONDS = Path(__file__).with_name("file_seconds.json")
"""Seconds each test file took in one measured run (``python -m tests.file_seconds JUNIT_XML`` writes it)."""
UNMEASURED_SECONDS = 5.0
"""What a file not in FILE_SECONDS is taken to last, s."""


HEAVY = ("tests/browser/", "tests/rooms/")
"""Test files that drive Chromium or start processes of their own: one worker runs them all, one after another."""


def pytest_collection_modifyitems(config: pytest.Config, items: list[pytest.Item]) -> None:
    """Across workers: the heavy files (:data:`HEAVY`) first, as the one unit of work that lasts longest, then
    the others longest first; each worker takes the next unit when it is free, so no long file is left alone
    at the end while the other worker idles. One process keeps the collection's order."""
    if not hasattr(config, "workerinput"):
        return
    seconds = json.loads(FILE_SECONDS.read_text(encoding="utf-8")) if FILE_SECONDS.is_file() else {}
    first: dict[str, int] = {}
    for index, item in enumerate(items):
        first.setdefault(item.nodeid.split("::")[0], index)
    order = sorted(
        first, key=lambda path: (not path.startswith(HEAVY), -seconds.get(path, UNMEASURED_SECONDS), first[path])
    )
    rank = {path: k for k, path in enumerate(order)}
    items.sort(key=lambda item: rank[item.nodeid.split("::")[0]])


class OneHeavyWorker(LoadFileScheduling):
    """``--dist loadfile`` with every heavy file (:data:`HEAVY`) in one unit of work, so one worker runs them."""

    def _split_scope(self, nodeid: str) -> str:
        return "heavy" if nodeid.startswith(HEAVY) else super()._split_scope(nodeid)


def pytest_xdist_make_scheduler(config: pytest.Config, log: Any) -> LoadFileScheduling | None:
    """On two cores, two Chromiums (each with its software-rendering GPU process and an app to serve it)
    starved each other's pages into timeouts; one of them beside the quick tests does not. Other modes than
    ``--dist loadfile``: xdist's own scheduler."""
    if config.getoption("dist") != "loadfile":
        return None
    return OneHeavyWorker(config, log)


def pytest_runtest_logreport(report: pytest.TestReport) -> None:
    if report.skipped:
        _skipped.append(report.nodeid)


def pytest_sessionfinish(session: pytest.Session, exitstatus: int) -> None:
    if os.environ.get("RBL_NO_SKIP") == "1" and _skipped and exitstatus == 0:
        session.exitstatus = 1


def pytest_terminal_summary(terminalreporter, exitstatus: int, config: pytest.Config) -> None:
    if os.environ.get("RBL_NO_SKIP") == "1" and _skipped:
        terminalreporter.write_line(
            f"RBL_NO_SKIP=1: {len(_skipped)} test(s) skipped that must run: " + ", ".join(_skipped),
            red=True,
        )


# --------------------------------------------------------------------------------------------------
# App fixtures (helpers in tests/harness.py). Module-scoped: one Chromium per test module.
# --------------------------------------------------------------------------------------------------


@pytest.fixture(scope="session")
def _one_chromium():
    """The worker's one headless Debian Chromium (Playwright sync API), launched on first use."""
    from tests.harness import launch_chromium

    with launch_chromium() as browser:
        yield browser


@pytest.fixture(scope="module")
def chromium(_one_chromium):
    """A headless Chromium for a test module (skipped when missing unless RBL_REQUIRE_BROWSER=1): the
    worker's one browser, launched once, with every page and context the module opened closed at its end
    (a page left open would keep rendering and reconnecting to a server that is gone)."""
    from tests.harness import ModuleBrowser

    browser = ModuleBrowser(_one_chromium)
    yield browser
    browser.close_opened()


@pytest.fixture(scope="module")
def live_app():
    """The app with its real-time loop on a free port (first scene: the heavy top)."""
    from tests.harness import running_app

    with running_app("heavy_top") as app:
        yield app


@pytest.fixture(scope="module")
def app():
    """The app on a free port without its loop thread: tests drive frames with ``App.frame(dt)``."""
    from tests.harness import running_app

    with running_app(start_loop=False) as a:
        yield a
