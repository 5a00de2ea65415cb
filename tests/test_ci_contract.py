"""The CI contract: under RBL_NO_SKIP=1 a skipped test fails the run (tests/conftest.py)."""

from __future__ import annotations

import os
import shutil
import subprocess
import sys
from pathlib import Path

import pytest

HERE = Path(__file__).parent


def _run(tmp_path: Path, body: str, strict: bool, workers: int = 0) -> int:
    shutil.copy(HERE / "conftest.py", tmp_path / "conftest.py")
    (tmp_path / "test_sample.py").write_text(body)
    env = {k: v for k, v in os.environ.items() if k != "RBL_NO_SKIP"}
    if strict:
        env["RBL_NO_SKIP"] = "1"
    result = subprocess.run(
        [sys.executable, "-m", "pytest", "-q", "-p", "no:cacheprovider", "-n", str(workers), str(tmp_path)],
        cwd=tmp_path,
        env=env,
        capture_output=True,
        text=True,
        timeout=120,
    )
    return result.returncode


SKIPPING = "import pytest\n\ndef test_a():\n    pytest.skip('no browser')\n\ndef test_b():\n    pass\n"


@pytest.mark.parametrize("workers", [0, 2])  # in one process, and across workers as the README's command runs
@pytest.mark.parametrize("strict, expected", [(True, 1), (False, 0)])
def test_a_skip_fails_only_under_rbl_no_skip(tmp_path, strict, expected, workers):
    assert _run(tmp_path, SKIPPING, strict, workers) == expected


def test_a_clean_run_passes_under_rbl_no_skip(tmp_path):
    assert _run(tmp_path, "def test_ok():\n    pass\n", strict=True) == 0


def _marks_browser(path: Path) -> bool:
    """The module assigns ``pytestmark`` to ``pytest.mark.browser`` (alone or in a list)."""
    import ast

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
