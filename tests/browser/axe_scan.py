"""The axe-core scan of the browser tests: npm's ``axe-core``, installed into
``tests/browser/axe/`` from its committed package.json and package-lock.json, injected into a page and run
with the WCAG 2.0/2.1 A and AA rules.

:func:`axe_source` installs it (``npm ci``) the first time it is asked for on a fresh machine and fails
clearly when npm is missing; :func:`scan` runs it in a page and returns its violations.
"""

from __future__ import annotations

import shutil
import subprocess
from pathlib import Path
from typing import Any

import pytest

AXE_DIR = Path(__file__).resolve().parent / "axe"
AXE_JS = AXE_DIR / "node_modules" / "axe-core" / "axe.min.js"
WCAG_TAGS = ("wcag2a", "wcag2aa", "wcag21a", "wcag21aa")
"""The rules run: WCAG 2.0 and 2.1, levels A and AA (axe-core's tags)."""

RUN = """async (tags) => {
    const result = await axe.run(document, {runOnly: {type: 'tag', values: tags}, resultTypes: ['violations']});
    return result.violations.map(v => ({id: v.id, impact: v.impact, count: v.nodes.length,
        nodes: v.nodes.map(n => n.target.join(' ') + ' ' + n.html.slice(0, 120))}));
}"""


def axe_source() -> str:
    """axe-core's script, installed with ``npm ci --prefix tests/browser/axe`` if it is not there yet."""
    if not AXE_JS.is_file():
        npm = shutil.which("npm")
        if npm is None:
            pytest.fail(
                "npm is missing: the accessibility scan needs npm's axe-core (apt-get install npm, then "
                f"npm ci --prefix {AXE_DIR})"
            )
        done = subprocess.run(
            [npm, "ci", "--prefix", str(AXE_DIR), "--no-audit", "--no-fund"],
            capture_output=True,
            text=True,
            timeout=300,
        )
        if done.returncode != 0 or not AXE_JS.is_file():
            pytest.fail(f"npm ci --prefix {AXE_DIR} failed ({done.returncode}):\n{done.stdout}\n{done.stderr}")
    return AXE_JS.read_text(encoding="utf-8")


def scan(page: Any, source: str) -> list[dict[str, Any]]:
    """The WCAG A/AA violations axe-core finds in ``page`` now: rule id, impact, count of elements, and
    each element (its selector and the start of its HTML)."""
    if not page.evaluate("() => typeof window.axe === 'object'"):
        page.add_script_tag(content=source)
    return page.evaluate(RUN, list(WCAG_TAGS))


def counts(violations: list[dict[str, Any]]) -> dict[str, int]:
    """Rule id -> elements in violation."""
    return {v["id"]: v["count"] for v in violations}
