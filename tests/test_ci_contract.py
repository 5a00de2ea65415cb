"""The CI contract: under RBL_NO_SKIP=1 a skipped test fails the run (tests/conftest.py)."""

from __future__ import annotations

import ast
from pathlib import Path

import pytest

pytest_plugins = ["pytester"]

HERE = Path(__file__).parent


def _run(pytester: pytest.Pytester, monkeypatch: pytest.MonkeyPatch, body: str, strict: bool, workers: int = 0) -> int:
    """The exit code of a pytest run, in this process, of ``body`` beside the suite's own conftest."""
    pytester.makeconftest((HERE / "conftest.py").read_text(encoding="utf-8"))
    pytester.makepyfile(test_sample=body)
    if strict:
        monkeypatch.setenv("RBL_NO_SKIP", "1")
    else:
        monkeypatch.delenv("RBL_NO_SKIP", raising=False)
    return int(pytester.runpytest_inprocess("-q", "-p", "no:cacheprovider", "-n", str(workers)).ret)


SKIPPING = "import pytest\n\ndef test_a():\n    pytest.skip('no browser')\n\ndef test_b():\n    pass\n"


@pytest.mark.parametrize("workers", [0, 2])  # in one process, and across workers as the README's command runs
@pytest.mark.parametrize("strict, expected", [(True, 1), (False, 0)])
def test_a_skip_fails_only_under_rbl_no_skip(pytester, monkeypatch, strict, expected, workers):
    assert _run(pytester, monkeypatch, SKIPPING, strict, workers) == expected


def test_a_clean_run_passes_under_rbl_no_skip(pytester, monkeypatch):
    assert _run(pytester, monkeypatch, "def test_ok():\n    pass\n", strict=True) == 0


def _marks_browser(path: Path) -> bool:
    """The module assigns ``pytestmark`` to ``pytest.mark.browser`` (alone or in a list)."""
    for node in ast.parse(path.read_text(encoding="utf-8")).body:
        if isinstance(node, ast.Assign) and any(getattr(t, "id", None) == "pytestmark" for t in node.targets):
            if "pytest.mark.browser" in ast.unparse(node.value):
                return True
    return False


def test_every_browser_module_is_marked_browser():
    # `-m "not browser"` is the quick run: a browser test without the marker would run in it anyway.
    modules = sorted((HERE / "browser").glob("test_*.py"))
    assert modules
    unmarked = [p.name for p in modules if not _marks_browser(p)]
    assert not unmarked, f"missing pytestmark = pytest.mark.browser: {unmarked}"
