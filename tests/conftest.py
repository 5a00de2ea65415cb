"""Shared test configuration.

Under ``RBL_NO_SKIP=1`` (set by ``.ci/run``) any skipped test fails the session: in CI nothing that
should run may quietly not run.
"""

from __future__ import annotations

import os

import pytest
from hypothesis import settings

# Property tests draw the same examples on every run (a fixed seed): CI is reproducible, and a failure
# seen once is seen again. Widen the search locally with `--hypothesis-seed=N` or HYPOTHESIS_PROFILE=explore.
settings.register_profile("fixed", derandomize=True, database=None, print_blob=True)
settings.register_profile("explore", derandomize=False)
settings.load_profile(os.environ.get("HYPOTHESIS_PROFILE", "fixed"))

_skipped: list[str] = []


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
# App fixtures (issue 4; helpers in tests/harness.py). Module-scoped: one Chromium per test module.
# --------------------------------------------------------------------------------------------------


@pytest.fixture(scope="module")
def chromium():
    """A headless Debian Chromium (Playwright sync API); skipped when missing unless RBL_REQUIRE_BROWSER=1."""
    from tests.harness import launch_chromium

    with launch_chromium() as browser:
        yield browser


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
