"""Write tests/file_seconds.json, the seconds each test file took, from a JUnit XML report of a run of the
suite (``python -m pytest --junitxml=PATH``); tests/conftest.py orders the files longest first across workers.

Run: python -m tests.file_seconds PATH
"""

from __future__ import annotations

import json
import sys
import xml.etree.ElementTree as ET
from collections import defaultdict
from pathlib import Path

OUT = Path(__file__).with_name("file_seconds.json")


def file_seconds(junit: Path) -> dict[str, float]:
    """Seconds per test file (its path from the repository's root), summed over the file's test cases."""
    totals: dict[str, float] = defaultdict(float)
    for case in ET.parse(junit).iter("testcase"):
        path = case.get("classname", "").split(".")
        # classname is the dotted module, then the class if any: tests.app.test_x[.TestY]
        while path and not path[-1].startswith("test_"):
            path.pop()
        if path:
            totals["/".join(path) + ".py"] += float(case.get("time", 0.0))
    return {name: round(seconds, 1) for name, seconds in sorted(totals.items(), key=lambda kv: -kv[1])}


def main(argv: list[str] | None = None) -> int:
    args = sys.argv[1:] if argv is None else argv
    if len(args) != 1:
        print(__doc__.strip().splitlines()[-1], file=sys.stderr)
        return 2
    seconds = file_seconds(Path(args[0]))
    OUT.write_text(json.dumps(seconds, indent=1, ensure_ascii=False) + "\n", encoding="utf-8")
    print(f"{len(seconds)} files, {sum(seconds.values()):.0f} s in all -> {OUT}")
    return 0


if __name__ == "__main__":
    raise SystemExit(main())
