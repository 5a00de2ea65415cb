"""Measure every scene's body contrast in headless Chromium and write the table: ``python docs/look.py``.

The measurement is the browser test's (``tests/browser/test_look.py``, :func:`measure`): each scene paused at
t = 1 s, a screenshot with the body and one without it, the WCAG contrast ratio between the median
luminance of the body's inner pixels and of what is behind them. It writes ``docs/look.md``; the test checks
that every ratio is at least 3:1 and that the table records what it measures.
"""

from __future__ import annotations

import argparse
import sys
from pathlib import Path

ROOT = Path(__file__).resolve().parent.parent
sys.path.insert(0, str(ROOT))

from app.draw import COLOURS  # noqa: E402
from tests.browser.test_look import LOOK_MD, LOOKS, measure  # noqa: E402
from tests.harness import launch_chromium  # noqa: E402

HEADER = """# The look, measured

The body's contrast against what is behind it, in headless Chromium (Debian's, SwiftShader, one pixel per
CSS pixel: viser's `?fixedDpr=1`), for every scene at each view in the light look and at 1280×800 in the dark
look. Each scene is paused at t = 1 s with its traces cleared; the ratio is WCAG's
(L_bright + 0.05)/(L_dark + 0.05) between the median relative luminance of the body's inner pixels (two
pixels in from its outline; their number is the last column) and of the same pixels with the body hidden
(the background, the floor grid, and whatever translucent guide lies behind or over the body, e.g. the
explorer's inertia ellipsoid). The target is at least 3:1. The body is slate, RGB {body}
(`app.draw.COLOURS["body"]`), opaque in every scene; the scenes are lit by `app.draw.light`.

Written by `python docs/look.py`; `tests/browser/test_look.py` measures the same (and that every body is in
the view, clear of the panel) and fails if a ratio is below 3:1 or differs from this table by more than 0.05.

| scene | view | look | contrast | body luminance | behind | inner pixels |
| --- | --- | --- | --- | --- | --- | --- |
"""


def main(argv: list[str] | None = None) -> None:
    parser = argparse.ArgumentParser(description=__doc__.splitlines()[0])
    parser.add_argument("--out", type=Path, default=LOOK_MD)
    args = parser.parse_args(argv)
    rows = []
    with launch_chromium() as browser:
        for width, height, dark in LOOKS:
            rows += measure(browser, width, height, dark, check=False)
    rows.sort(key=lambda r: (r["scene"], r["look"] != "light", r["view"]))
    lines = [
        f"| {r['scene']} | {r['view']} | {r['look']} | {r['ratio']:.2f}:1 | {r['body']:.3f} | {r['behind']:.3f} "
        f"| {r['pixels']} |"
        for r in rows
    ]
    summary = ""
    for look in ("light", "dark"):
        some = [r for r in rows if r["look"] == look]
        worst = min(some, key=lambda r: r["ratio"])
        summary += (
            f"\n{look.capitalize()}: {worst['ratio']:.2f}:1 to {max(r['ratio'] for r in some):.2f}:1; the lowest is "
            f"{worst['scene']} at {worst['view']}.\n"
        )
    args.out.write_text(HEADER.format(body=COLOURS["body"]) + "\n".join(lines) + "\n" + summary, encoding="utf-8")
    print(args.out.read_text(encoding="utf-8"), flush=True)


if __name__ == "__main__":
    main()
