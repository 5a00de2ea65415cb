"""Put a re-run of some cases into the full work-precision table (``python -m benchmarks.work_precision
--cases NAME[,NAME] --update``), when the full run (half an hour on an idle machine) cannot be repeated.

The cases' rows in the three summary tables and their sections come from the new run; every other line
from the full run. The worst-ratio and the cells-below-target lines are recomputed from the merged summary
table, and a note under the header says which cases were re-run, when, and with which command.
"""

from __future__ import annotations

import re

__all__ = ["NOTE_START", "merge_cases"]

NOTE_START = "*Re-run alone on "
"""How the note of a re-run begins (:func:`merge_cases` replaces the note of an earlier re-run of the same cases)."""

_BOLD = re.compile(r"\*\*([^*]+)\*\*")


def _rows(lines: list[str], name: str) -> list[int]:
    """Indices of the table rows of case ``name`` (``| name |`` or ``| name* |``), in order."""
    return [i for i, line in enumerate(lines) if line.startswith((f"| {name} |", f"| {name}* |"))]


def _sections(lines: list[str]) -> dict[str, tuple[int, int]]:
    """``### name`` sections: name -> (first line, one past the last), up to the next section or the end line."""
    starts = [(i, line[4:].strip()) for i, line in enumerate(lines) if line.startswith("### ")]
    end = next((i for i, line in enumerate(lines) if line.startswith("Total wall time")), len(lines))
    out = {}
    for k, (i, name) in enumerate(starts):
        out[name] = (i, starts[k + 1][0] if k + 1 < len(starts) else end)
    return out


def _best_peer(lines: list[str], section: tuple[int, int], level: str) -> str:
    """The best peer's ``method setting`` at ``level`` in a case's section (the faster of scipy and MuJoCo)."""
    for line in lines[section[0] : section[1]]:
        cells = [c.strip() for c in line.split("|")[1:-1]]
        if cells and cells[0] == level and len(cells) >= 5:
            timed = [c for c in cells[3:5] if c.endswith(" ms")]
            best = min(timed, key=lambda c: float(c.rsplit(":", 1)[1].split()[0]))
            return best.rsplit(":", 1)[0]
    return "?"


def _verdict(lines: list[str], target: float) -> list[str]:
    """The worst-ratio line (and the lost-levels line) from the summary table and the sections."""
    start = next(i for i, line in enumerate(lines) if line.startswith("## Summary"))
    header = next(i for i in range(start, len(lines)) if lines[i].startswith("| case |"))
    levels = [c.strip() for c in lines[header].split("|")[2:-1]]
    sections = _sections(lines)
    cells, lost = [], []
    for line in lines[header + 2 :]:
        if not line.startswith("| "):
            break
        parts = [c.strip() for c in line.split("|")[1:-1]]
        name = parts[0]
        for level, cell in zip(levels, parts[1:]):
            ratio = _BOLD.match(cell)
            value = ratio.group(1) if ratio else ""
            if value.startswith("—"):
                lost.append((name, level))
            elif value and value[0].isdigit():
                cells.append((float(value), name, level))
    out = []
    if cells:
        worst = min(cells, key=lambda c: c[0])  # as the full run picks it: the first of equal ratios
        below = sorted((c for c in cells if c[0] < target), key=lambda c: c[0])
        peer = _best_peer(lines, sections[worst[1]], worst[2])
        out.append(
            f"**Worst ratio: {worst[0]:.3g}** ({worst[1]} at {worst[2]}, best peer {peer}). Cells below the "
            f"{target:.0f}x target: {len(below)} of {len(cells)}"
            + (": " + ", ".join(f"{n} at {lev} ({r:.3g})" for r, n, lev in below) if below else "")
            + "."
        )
    if lost:
        out.append("Levels a peer reached and we did not: " + ", ".join(f"{n} at {lev}" for n, lev in lost) + ".")
    return out


def merge_cases(full: str, rerun: str, names: list[str], note: str, target: float) -> str:
    """The full run's markdown ``full`` with the cases ``names`` from ``rerun`` (a run of those cases).

    Raises ValueError when a case is missing from either, or its tables differ in shape (not the same
    benchmark).
    """
    old, new = full.split("\n"), rerun.split("\n")
    for name in names:
        rows_old, rows_new = _rows(old, name), _rows(new, name)
        if not rows_old or len(rows_old) != len(rows_new):
            raise ValueError(
                f"case {name!r}: {len(rows_old)} table rows in the full results, {len(rows_new)} in the re-run"
            )
        for i, j in zip(rows_old, rows_new):
            old[i] = new[j]
        so, sn = _sections(old).get(name), _sections(new).get(name)
        if so is None or sn is None:
            raise ValueError(f"case {name!r} has no section in the {'full results' if so is None else 're-run'}")
        old[so[0] : so[1]] = new[sn[0] : sn[1]]
    # The verdict lines: replaced where they stand (the first verdict line up to the blank line after it).
    first = next(i for i, line in enumerate(old) if line.startswith(("**Worst ratio", "Levels a peer")))
    last = next(i for i in range(first, len(old)) if not old[i].strip())
    old[first:last] = _verdict(old, target)
    # The note: after the header's paragraphs, before the summary, replacing an earlier re-run of these cases.
    for i in reversed(range(len(old))):
        line = old[i]
        if line.startswith(NOTE_START) and "): " in line and ", with `" in line:
            rerun_names = line.split("): ", 1)[1].split(", with `", 1)[0].split(", ")
            if set(rerun_names) <= set(names):
                del old[i : i + 2]  # the note and its blank line
    summary = next(i for i, line in enumerate(old) if line.startswith("## Summary"))
    old[summary:summary] = [note, ""]
    return "\n".join(old)
