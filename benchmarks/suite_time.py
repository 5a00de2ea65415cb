"""How long the README's test command takes, and whether it passes every time, with the cores busy or not.

Runs ``python -m pytest`` (the README's test command after its install; ``--quick`` adds ``-m "not browser"``)
``--runs`` times in a row, each in a fresh process. With ``--burn N``, N processes spin on the CPU for the
whole time (another user of a shared machine): a test that passes only on an idle machine shows up as a
failed run. Every run's wall time, its outcome and its closing line go to ``benchmarks/results/suite_time.md``
(rewritten after each run, so a run cut short keeps what it measured) with a bar chart beside it
(``suite_time.png``). Each run is bounded by ``--timeout``.

Run: python -m benchmarks.suite_time [--runs 3] [--burn 2] [--quick] [--timeout 1800] [--out PATH]
"""

from __future__ import annotations

import argparse
import contextlib
import multiprocessing
import os
import subprocess
import sys
import time
from collections.abc import Iterator
from dataclasses import dataclass
from pathlib import Path
from typing import Any

RESULTS = Path(__file__).resolve().parent / "results" / "suite_time.md"
ROOT = Path(__file__).resolve().parents[1]


@dataclass(frozen=True)
class Run:
    """One run of the suite: its wall time (s), exit code, pytest's closing line and the tests that failed or
    erred (pytest's ``FAILED``/``ERROR`` summary lines)."""

    seconds: float
    returncode: int
    summary: str
    failures: tuple[str, ...] = ()
    report: str = ""
    """pytest's ``FAILURES``/``ERRORS`` sections of a failed run (printed: a failure under load is rare)."""

    @property
    def passed(self) -> bool:
        return self.returncode == 0


def _spin(stop: Any) -> None:  # a multiprocessing.Event
    x = 0.0
    while not stop.is_set():
        for _ in range(100_000):
            x = x * 0.5 + 1.0


@contextlib.contextmanager
def burning(processes: int) -> Iterator[list[multiprocessing.Process]]:
    """``processes`` processes keep one core each busy until the block ends; yields them."""
    stop = multiprocessing.Event()
    burners = [multiprocessing.Process(target=_spin, args=(stop,), daemon=True) for _ in range(processes)]
    for p in burners:
        p.start()
    try:
        yield burners
    finally:
        stop.set()
        for p in burners:
            p.join(timeout=5)
            if p.is_alive():
                p.kill()


def closing_line(output: str) -> str:
    """pytest's last ``=== ... ===`` line (the counts and the time), or the output's last line."""
    lines = [line.strip("= ").strip() for line in output.splitlines() if line.strip()]
    closing = [line for line in lines if " in " in line and ("passed" in line or "failed" in line or "error" in line)]
    return closing[-1] if closing else (lines[-1] if lines else "")


def failures(output: str) -> tuple[str, ...]:
    """pytest's short summary lines of the tests that failed or erred (``FAILED path::test - why``)."""
    return tuple(line.strip() for line in output.splitlines() if line.startswith(("FAILED ", "ERROR ")))


def failure_report(output: str) -> str:
    """pytest's ``FAILURES`` and ``ERRORS`` sections, up to the short summary (empty when all passed)."""
    lines = output.splitlines()
    starts = [i for i, line in enumerate(lines) if line.startswith("=") and line.strip("= ") in ("FAILURES", "ERRORS")]
    if not starts:
        return ""
    ends = [i for i, line in enumerate(lines) if line.startswith("=") and "short test summary" in line]
    end = next((i for i in ends if i > starts[0]), len(lines))
    return "\n".join(lines[starts[0] : end])


def run_suite(quick: bool, timeout: float) -> Run:
    """One run of the test command in a fresh process from the repository's root."""
    command = [sys.executable, "-m", "pytest", "-q", "-p", "no:cacheprovider"] + (
        ["-m", "not browser"] if quick else []
    )
    start = time.perf_counter()
    try:
        done = subprocess.run(command, cwd=ROOT, capture_output=True, text=True, timeout=timeout, env=os.environ.copy())
    except subprocess.TimeoutExpired as exc:
        out = exc.stdout.decode() if isinstance(exc.stdout, bytes) else (exc.stdout or "")
        return Run(
            time.perf_counter() - start,
            -1,
            f"timed out after {timeout:g} s: {closing_line(out)}",
            failures(out),
            failure_report(out),
        )
    out = done.stdout
    return Run(time.perf_counter() - start, done.returncode, closing_line(out), failures(out), failure_report(out))


def write_table(runs: list[Run], quick: bool, burn: int, path: Path) -> str:
    """Write the table (and the bar chart beside it); returns the table's text."""
    what = 'the quick run (`-m "not browser"`)' if quick else "the README's test command"
    load = f"{burn} processes spinning on the CPU besides" if burn else "nothing else running on purpose"
    lines = [
        "# Test suite time",
        "",
        f"`python -m benchmarks.suite_time --runs {len(runs)}{f' --burn {burn}' if burn else ''}"
        f"{' --quick' if quick else ''}`: {what}, {len(runs)} runs in a row on {os.cpu_count()} cores, {load}.",
        "",
        "| run | wall (s) | outcome | pytest's closing line |",
        "| --- | --- | --- | --- |",
    ]
    lines += [
        f"| {i} | {r.seconds:.0f} | {'passed' if r.passed else f'**failed** ({r.returncode})'} | {r.summary} |"
        for i, r in enumerate(runs, 1)
    ]
    passed = sum(r.passed for r in runs)
    lines += ["", f"{passed} of {len(runs)} runs passed; slowest {max(r.seconds for r in runs):.0f} s."]
    for i, r in enumerate(runs, 1):
        lines += [f"- run {i}: {line}" for line in r.failures]
    text = "\n".join(lines) + "\n"
    path.parent.mkdir(parents=True, exist_ok=True)
    path.write_text(text, encoding="utf-8")
    _plot(runs, path.with_suffix(".png"), what, load)
    return text


def _plot(runs: list[Run], path: Path, what: str, load: str) -> None:
    import matplotlib

    matplotlib.use("Agg")
    import matplotlib.pyplot as plt

    fig, ax = plt.subplots(figsize=(6, 3.2), dpi=120)
    colours = ["#2b7a3d" if r.passed else "#b3261e" for r in runs]
    ax.bar(range(1, len(runs) + 1), [r.seconds for r in runs], color=colours)
    ax.set_xlabel("run")
    ax.set_ylabel("wall time (s)")
    ax.set_xticks(range(1, len(runs) + 1))
    ax.set_title(f"{what.split(' (')[0]}; {load}", fontsize=9)
    fig.tight_layout()
    fig.savefig(path)
    plt.close(fig)


def main(argv: list[str] | None = None) -> int:
    p = argparse.ArgumentParser(description=__doc__.split("\n\n")[0])
    p.add_argument("--runs", type=int, default=3, help="runs in a row")
    p.add_argument("--burn", type=int, default=0, help="processes spinning on the CPU during the runs")
    p.add_argument("--quick", action="store_true", help='the quick run: -m "not browser"')
    p.add_argument("--timeout", type=float, default=1800.0, help="the bound on one run, s")
    p.add_argument("--out", type=Path, default=None, help="the table (default benchmarks/results/suite_time.md)")
    args = p.parse_args(argv)
    if args.runs < 1 or args.burn < 0 or args.timeout <= 0:
        p.error(f"expected --runs >= 1, --burn >= 0, --timeout > 0; got {args.runs}, {args.burn}, {args.timeout}")
    out = args.out or (RESULTS.with_name("suite_time_quick.md") if args.quick else RESULTS)
    runs: list[Run] = []
    with burning(args.burn):
        for i in range(args.runs):
            runs.append(run_suite(args.quick, args.timeout))
            print(f"run {i + 1}: {runs[-1].seconds:.0f} s, {runs[-1].summary}", flush=True)
            if runs[-1].report:
                print(runs[-1].report, flush=True)
            write_table(runs, args.quick, args.burn, out)
    return 0 if all(r.passed for r in runs) else 1


if __name__ == "__main__":
    sys.exit(main())
