"""Speed against error: our integrators and closed forms against scipy ``solve_ivp`` and MuJoCo.

Run ``python -m benchmarks.work_precision`` (full: 32 min wall measured on this 2-core machine while other
work kept its load at 2 to 12; every scipy method, and mpmath's check of each numerical reference) or with
``--quick`` (under a minute: shorter long run, smaller per-run budget, scipy's DOP853, RK45 and LSODA only) or
``--smoke`` (seconds: four cases, each run timed once, for the test suite); ``--cases a,b --update`` re-runs
those cases into the existing table (:mod:`benchmarks.work_precision_merge`). Output in ``--out`` (default ``benchmarks/results``):
``work_precision.md`` (tables, with a summary of the best peer's CPU ÷ ours per case and level, the worst
cell, and our fastest method in each cell) and one PNG per case plus ``long_run_energy.png``.

For every case (benchmarks/cases.py) and every method/setting it records, at the final time, the
attitude error (rad, :func:`physics.rotations.rotation_angle`), the relative ω error, the relative energy
error (against the initial energy, or on a case with friction or drag against the reference's final
energy), and the CPU time (``time.process_time``, best of 3 runs when a run is shorter than 0.05 s). The
error used for the tables is ``max(attitude error, relative ω error)``. Sweeps: our integrators by halving
the step from about 1/8 of the case's time scale; scipy at rtol = atol/scale = 1e-3 ... 1e-13 (a run is
abandoned as 'not reached' after 5x the per-run budget of CPU); MuJoCo
by halving its timestep (quick: steps / 4, every other tolerance). A sweep stops when the error is
below 1e-12, one run takes longer than the per-run budget (1.5 s full, 0.1 s quick; 8x that for the long
run, full mode only), the error stagnates
at round-off, or (ours and MuJoCo) the run is 20x slower than a run of the same family that was at least
as accurate (it can then no longer be the fastest at any error level; its row shows '—' beyond).
"""

from __future__ import annotations

import argparse
import math
import os
import sys
import time
from dataclasses import dataclass

import numpy as np

from benchmarks.cases import Case, all_cases, check_with_mpmath
from benchmarks.peers import PeerTimeout, mujoco_run, scipy_energy_series, scipy_run
from benchmarks.work_precision_merge import NOTE_START, merge_cases
from physics.integrators import (
    BlanesMoan6,
    ExactFreeSplitting,
    KahanLi8,
    LiePoissonStrang,
    LieRK4,
    SofroniouSpaletta10,
    Suzuki4,
    Yoshida4,
    Yoshida6,
    Yoshida8,
    integrate,
    kinetic_energy,
)
from physics.integrators.warm import warm
from physics.rotations import rotation_angle

LEVELS = [1e-4, 1e-5, 1e-6, 1e-7, 1e-8, 1e-9, 1e-10]
SCIPY_METHODS = ("DOP853", "RK45", "RK23", "Radau", "BDF", "LSODA")
PEERS = ("scipy", "mujoco")
SMOKE_CASES = ("free_generic", "top_cusps", "top_spin_friction", "body_air_drag")
TARGET = 10.0  # the target: the best peer needs at least 10x our CPU time at every level


@dataclass
class Run:
    family: str  # "ours", "exact", "scipy", "mujoco"
    method: str
    setting: str
    cpu: float
    angle: float
    omega: float
    energy: float

    @property
    def error(self) -> float:
        return max(self.angle, self.omega)


def _timed(fn, budget_repeat=0.05, repeats=3):
    t0 = time.process_time()
    out = fn()
    best = time.process_time() - t0
    if best < budget_repeat:
        for _ in range(repeats - 1):
            t0 = time.process_time()
            out = fn()
            best = min(best, time.process_time() - t0)
    return out, best


def _measure(case: Case, family, method, setting, fn, repeats: int = 3) -> Run:
    (R, w), cpu = _timed(fn, repeats=repeats)
    R_ref, w_ref = case.reference()
    if not (np.all(np.isfinite(R)) and np.all(np.isfinite(w))):
        return Run(family, method, setting, cpu, math.inf, math.inf, math.inf)
    angle = float(rotation_angle(R, R_ref))
    om = float(np.linalg.norm(w - w_ref) / np.linalg.norm(w_ref))
    e_ref = case.energy_reference()
    e = case.energy(R, case.moments * w)
    return Run(family, method, setting, cpu, angle, om, float(abs(e - e_ref) / abs(e_ref)))


def our_methods(case: Case, quick: bool = False):
    torque = case.torques() or None
    # Highest order first: the domination rule below then cuts the low orders' sweeps short.
    methods = [
        SofroniouSpaletta10(case.moments, torque),
        # L in double-double through the rotations: the same methods with a lower round-off floor, for the
        # motions that amplify round-off (free_separatrix); they cost about 1.1 times as much per step.
        SofroniouSpaletta10(case.moments, torque, compensated=True),
        KahanLi8(case.moments, torque),
        KahanLi8(case.moments, torque, compensated=True),
        Yoshida8(case.moments, torque),
        BlanesMoan6(case.moments, torque),
        Yoshida6(case.moments, torque),
        Suzuki4(case.moments, torque),
        Yoshida4(case.moments, torque),
        LiePoissonStrang(case.moments, torque),
        LieRK4(case.moments, torque),
    ]
    symmetric = case.moments[0] == case.moments[1]
    if case.mass and symmetric:  # with a torque the exact free flow is a real integrator (inline: symmetric top)
        methods = [
            ExactFreeSplitting(case.moments, torque, composition=c)
            for c in ("yoshida8", "yoshida6", "yoshida4", "strang")
        ] + methods
    if quick:  # Suzuki 4 is never the fastest here; Lie RK4 stays as the baseline
        methods = [m for m in methods if not isinstance(m, Suzuki4)]
    return methods


def _stop(r: Run, history: list[Run], family_runs: list[Run], budget: float) -> bool:
    """End a sweep: error at round-off, over budget, stagnating, or dominated (20x slower than a run of
    the same family that was at least as accurate: it can no longer be the fastest at any level)."""
    if r.error < 1e-12 or r.cpu > budget or not math.isfinite(r.cpu):
        return True
    if len(history) >= 3 and history[-1].error > 0.5 * history[-3].error and history[-3].error < 1e-6:
        return True  # round-off plateau
    better = [q.cpu for q in family_runs if q.error <= r.error and q is not r]
    return bool(better) and r.cpu > 20.0 * min(better)


def sweep_case(
    case: Case, budget: float, log, factor: int = 2, rtols=range(3, 14), quick: bool = False, repeats: int = 3
) -> list[Run]:
    """Every method's runs on ``case`` (see the module's docstring); a run shorter than 0.05 s is timed
    ``repeats`` times and its best kept."""
    runs: list[Run] = []
    budget = budget * (1.0 if quick else case.budget_scale)
    # Our closed form, timed like a method (a case without one has a numerical reference instead).
    if case.closed_form:
        runs.append(_measure(case, "exact", "closed form", "-", case.exact, repeats))
    else:
        case.reference()
    # Our integrators.
    for m in our_methods(case, quick):
        n = max(4, int(math.ceil(8 * case.t_end / case.time_scale / (m.order / 2))))
        while True:
            dt = case.t_end / n

            def fn(m=m, n=n, dt=dt):
                tr = integrate(m, case.R0, case.L0, dt, n, save_every=n)
                return tr.attitude[-1], tr.L_body[-1] / case.moments

            r = _measure(case, "ours", m.name, f"n={n}", fn, repeats)
            runs.append(r)
            log(f"  {m.name:34s} n={n:<9d} err={r.error:.2e} cpu={r.cpu:.3g}s")
            if _stop(r, [q for q in runs if q.method == m.name], [q for q in runs if q.family == "ours"], budget):
                break
            n *= factor
    # scipy
    # Every solve_ivp method in the full run; --quick keeps the three that are ever the fastest (RK23 is low
    # order, Radau and BDF are implicit with a finite-difference Jacobian: never competitive on these
    # non-stiff problems, and slow).
    for meth in ("DOP853", "RK45", "LSODA") if quick else SCIPY_METHODS:
        for k in rtols:
            rtol = 10.0**-k

            def fn(meth=meth, rtol=rtol):
                R, w, _ = scipy_run(case, meth, rtol, cpu_cap=5.0 * budget)
                return R, w

            try:
                r = _measure(case, "scipy", meth, f"rtol=1e-{k}", fn, repeats)
            except PeerTimeout:
                r = Run("scipy", meth, f"rtol=1e-{k}", 5.0 * budget, math.inf, math.inf, math.inf)
            runs.append(r)
            log(f"  scipy {meth:28s} rtol=1e-{k:<3d} err={r.error:.2e} cpu={r.cpu:.3g}s")
            if r.error < 1e-12 or r.cpu > budget:
                break
    # MuJoCo
    for integ in ("Euler", "implicitfast", "RK4"):
        n = max(4, int(math.ceil(8 * case.t_end / case.time_scale)))
        while True:
            dt = case.t_end / n

            def fn(integ=integ, dt=dt):
                R, w, _ = mujoco_run(case, integ, dt)
                return R, w

            r = _measure(case, "mujoco", f"MuJoCo {integ}", f"dt={dt:.3g}", fn, repeats)
            runs.append(r)
            log(f"  MuJoCo {integ:27s} dt={dt:.3g} err={r.error:.2e} cpu={r.cpu:.3g}s")
            if _stop(r, [q for q in runs if q.method == r.method], [q for q in runs if q.family == "mujoco"], budget):
                break
            n *= factor
    return runs


def _best(runs, level, family=None, method=None):
    """The cheapest run reaching ``level``, of a family (a name or a tuple of names) or a method."""
    families = (family,) if isinstance(family, str) else family
    ok = [
        r
        for r in runs
        if r.error <= level and (families is None or r.family in families) and (method is None or r.method == method)
    ]
    return min(ok, key=lambda r: r.cpu) if ok else None


def _cell(r):
    return "—" if r is None else f"{r.method} {r.setting}: {r.cpu * 1e3:.3g} ms"


def _ratio(a, b):
    if a is None and b is None:
        return "neither"
    if b is None:
        return "— (we did not reach it)"
    if a is None:
        return "∞ (not reached)"
    return f"{a.cpu / b.cpu:.3g}"


def case_table(case: Case, runs: list[Run]) -> list[str]:
    lines = [
        f"### {case.name}",
        "",
        case.description,
        "",
        "| error ≤ | ours (integrator) | ours (closed form) | best scipy | best MuJoCo | best peer / ours "
        "| scipy / ours | MuJoCo / ours |",
        "| --- | --- | --- | --- | --- | --- | --- | --- |",
    ]
    for lev in LEVELS:
        ours = _best(runs, lev, "ours")
        exact = _best(runs, lev, "exact")
        sp = _best(runs, lev, "scipy")
        mj = _best(runs, lev, "mujoco")
        lines.append(
            f"| {lev:.0e} | {_cell(ours)} | {_cell(exact)} | {_cell(sp)} | {_cell(mj)} | "
            f"{_ratio(_best(runs, lev, PEERS), ours)} | {_ratio(sp, ours)} | {_ratio(mj, ours)} |"
        )
    lines += ["", "Fastest setting of each method reaching the level (CPU ms; — = not reached within the budget):", ""]
    methods = []
    for r in runs:
        if r.method not in methods:
            methods.append(r.method)
    drift = (
        "energy error at best run (vs the reference's final energy)" if case.dissipative else "energy drift at best run"
    )
    lines.append("| method | " + " | ".join(f"{lev:.0e}" for lev in LEVELS) + f" | {drift} |")
    lines.append("| --- " * (len(LEVELS) + 2) + "|")
    for m in methods:
        cells = []
        for lev in LEVELS:
            b = _best(runs, lev, method=m)
            cells.append("—" if b is None else f"{b.cpu * 1e3:.3g}")
        mine = [r for r in runs if r.method == m]
        best = min(mine, key=lambda r: r.error)
        lines.append(f"| {m} | " + " | ".join(cells) + f" | {best.energy:.1e} |")
    lines.append("")
    return lines


def plot_case(case: Case, runs: list[Run], path: str, timing: str = "best of 3") -> None:
    import matplotlib

    matplotlib.use("Agg")
    import matplotlib.pyplot as plt

    fig, ax = plt.subplots(figsize=(8, 5.5))
    styles = {"ours": "-", "exact": "", "scipy": "--", "mujoco": ":"}
    markers = {"ours": "o", "exact": "*", "scipy": "s", "mujoco": "^"}
    methods = []
    for r in runs:
        if (r.family, r.method) not in methods:
            methods.append((r.family, r.method))
    for fam, m in methods:
        rs = [r for r in runs if r.method == m]
        err = np.maximum([r.error for r in rs], 1e-16)
        cpu = np.maximum([r.cpu for r in rs], 1e-6)
        ax.loglog(
            cpu,
            err,
            linestyle=styles[fam] or "none",
            marker=markers[fam],
            markersize=10 if fam == "exact" else 4,
            label=("exact: " if fam == "exact" else "") + m,
        )
    for lev in (1e-4, 1e-10):
        ax.axhline(lev, color="grey", lw=0.5)
    ax.set_xlabel(f"CPU time, s ({timing})")
    ax.set_ylabel("final error: max(attitude angle, relative ω error)")
    ax.set_title(f"{case.name}: {case.description}", fontsize=8)
    ax.legend(fontsize=6, ncol=2)
    ax.grid(True, which="major", alpha=0.3)
    fig.tight_layout()
    fig.savefig(path, dpi=90)
    plt.close(fig)


def long_run_energy(out_dir: str, n_steps: int, log) -> list[str]:
    """Energy error of the free generic body over n_steps steps of 0.01 s (Strang, Lie RK4) and DOP853."""
    import matplotlib

    matplotlib.use("Agg")
    import matplotlib.pyplot as plt

    case = all_cases(quick=True)[0]
    I, dt = case.moments, 0.01
    e0 = kinetic_energy(I, case.L0)
    save = max(1, n_steps // 2000)
    fig, ax = plt.subplots(figsize=(8, 5))
    lines = [f"Long run: free generic body, {n_steps:.0e} steps of dt = 0.01 s (t = {n_steps * dt:.0f} s):", ""]
    for m in (LiePoissonStrang(I), LieRK4(I)):
        t0 = time.process_time()
        tr = integrate(m, case.R0, case.L0, dt, n_steps, save_every=save)
        cpu = time.process_time() - t0
        err = np.abs(kinetic_energy(I, tr.L_body) / e0 - 1.0)
        ax.loglog(tr.t[1:], np.maximum(err[1:], 1e-17), label=f"{m.name} (dt = 0.01 s)")
        lines.append(f"- {m.name}: max |ΔE/E| = {err.max():.2e}, final {err[-1]:.2e}, CPU {cpu:.1f} s")
        log(lines[-1])
    t_eval = tr.t
    for rtol in (1e-8, 1e-12):
        t0 = time.process_time()
        e, _, nfev = scipy_energy_series(case, "DOP853", rtol, t_eval)
        cpu = time.process_time() - t0
        err = np.abs(e / e0 - 1.0)
        ax.loglog(t_eval[1:], np.maximum(err[1:], 1e-17), "--", label=f"scipy DOP853 rtol {rtol:.0e} (adaptive)")
        lines.append(
            f"- scipy DOP853 rtol {rtol:.0e} (its own adaptive steps, {nfev} RHS evaluations): "
            f"max |ΔE/E| = {err.max():.2e}, final {err[-1]:.2e}, CPU {cpu:.1f} s"
        )
        log(lines[-1])
    ax.set_xlabel("t, s")
    ax.set_ylabel("|E(t)/E(0) − 1|")
    ax.set_title(f"Energy error over {n_steps:.0e} steps (free body I = (2, 1.5, 1))", fontsize=9)
    ax.legend(fontsize=7)
    ax.grid(True, alpha=0.3)
    fig.tight_layout()
    fig.savefig(os.path.join(out_dir, "long_run_energy.png"), dpi=90)
    plt.close(fig)
    return lines + ["", "![long run](long_run_energy.png)", ""]


def summary_rows(results: list[tuple[Case, list[Run]]]) -> list[str]:
    """The summary table (best peer's CPU ÷ ours at every level, and per family) and the worst-cell lines."""
    lines = [
        "## Summary: ratio of the best peer's CPU time to our best integrator's",
        "",
        "Each cell: **best peer** (the fastest scipy or MuJoCo setting that reaches the level) ÷ our fastest "
        "integrator, then the best of each family.",
        "",
        "| case | " + " | ".join(f"{lev:.0e}" for lev in LEVELS) + " |",
        "| --- " * (len(LEVELS) + 1) + "|",
    ]
    cells, lost = [], []
    for case, runs in results:
        row = []
        for lev in LEVELS:
            ours, peer = _best(runs, lev, "ours"), _best(runs, lev, PEERS)
            sp, mj = _best(runs, lev, "scipy"), _best(runs, lev, "mujoco")
            families = f" (scipy {_ratio(sp, ours)}, MuJoCo {_ratio(mj, ours)})" if ours and peer else ""
            row.append(f"**{_ratio(peer, ours)}**{families}")
            if ours is not None and peer is not None:
                cells.append((peer.cpu / ours.cpu, case.name, lev, peer))
            elif peer is not None:
                lost.append((case.name, lev))
        lines.append(f"| {case.name} | " + " | ".join(row) + " |")
    lines += [
        "",
        "'— (we did not reach it)': our integrators did not reach the level within the budget; "
        "'∞': the peer did not; 'neither': nobody did.",
        "",
    ]
    if cells:
        worst = min(cells, key=lambda c: c[0])
        below = sorted((c for c in cells if c[0] < TARGET), key=lambda c: c[0])
        lines.append(
            f"**Worst ratio: {worst[0]:.3g}** ({worst[1]} at {worst[2]:.0e}, best peer {worst[3].method} "
            f"{worst[3].setting}). Cells below the {TARGET:.0f}x target: {len(below)} of {len(cells)}"
            + (": " + ", ".join(f"{n} at {lev:.0e} ({r:.3g})" for r, n, lev, _ in below) if below else "")
            + "."
        )
    if lost:
        lines.append("Levels a peer reached and we did not: " + ", ".join(f"{n} at {lev:.0e}" for n, lev in lost) + ".")
    lines += [
        "",
        "Our fastest integrator in each cell (the run the ratio above divides by; cases without a closed form "
        "marked *):",
        "",
        "| case | " + " | ".join(f"{lev:.0e}" for lev in LEVELS) + " |",
        "| --- " * (len(LEVELS) + 1) + "|",
    ]
    for case, runs in results:
        row = []
        for lev in LEVELS:
            ours = _best(runs, lev, "ours")
            row.append("—" if ours is None else f"{ours.method} {ours.setting}")
        mark = "" if case.closed_form else "*"
        lines.append(f"| {case.name}{mark} | " + " | ".join(row) + " |")
    return lines + [""]


def main(argv=None) -> int:
    p = argparse.ArgumentParser(description=__doc__.split("\n\n")[0])
    p.add_argument("--quick", action="store_true", help="under a minute: short long run, small budget")
    p.add_argument("--smoke", action="store_true", help="seconds: four cases, tiny budget (for the tests)")
    p.add_argument("--out", default=os.path.join(os.path.dirname(__file__), "results"))
    p.add_argument("--cases", default="", help="comma-separated case names (default all)")
    p.add_argument(
        "--update",
        action="store_true",
        help="with --cases: put these cases into the existing work_precision.md of --out (the full run's), "
        "keeping every other case and the long run (not re-run)",
    )
    args = p.parse_args(argv)
    if args.update and not args.cases:
        p.error("--update needs --cases (the cases to re-run into the existing table)")
    os.makedirs(args.out, exist_ok=True)
    quick = args.quick or args.smoke
    budget = 0.02 if args.smoke else (0.1 if args.quick else 1.5)
    factor = 4 if quick else 2
    rtols = range(3, 14, 2) if quick else range(3, 14)
    cases = all_cases(quick=quick)
    if args.smoke:
        cases = [c for c in cases if c.name in SMOKE_CASES]
    if args.cases:
        wanted = args.cases.split(",")
        cases = [c for c in cases if c.name in wanted]
    log = (lambda s: None) if args.smoke else (lambda s: print(s, flush=True))
    # Compile (or load from numba's cache) the kernels first: a compile (seconds, after a kernel changed)
    # would count as the first run's CPU and end that method's sweep at once.
    log(f"kernels ready in {warm():.1f} s")
    t_start = time.perf_counter()
    mode = "--smoke" if args.smoke else ("--quick" if args.quick else "full")
    scipy_methods = ", ".join(("DOP853", "RK45", "LSODA") if quick else SCIPY_METHODS)
    md = [
        "# Work-precision benchmark",
        "",
        f"Generated by `python -m benchmarks.work_precision{'' if mode == 'full' else ' ' + mode}` "
        f"(per-run budget {budget} s). Error = max(attitude angle (rad), relative ω error) at the final time against "
        "the case's reference: the closed forms (physics.free_body, physics.heavy_top) where they exist, else a "
        "Taylor series in extended precision (benchmarks/taylor.py), whose checks are stated under each such case. "
        f"CPU = `time.process_time`, {'one run each' if args.smoke else 'best of 3 for runs under 0.05 s'}, on this "
        "machine (2 cores shared with other "
        "work: timings are noisy to ±30 %).",
        "",
        "Families: ours (integrators: compiled numba kernels, one body; 'compensated': the same method with "
        "L carried in double-double through its rotations, see docs/physics-notes.md), ours (closed form), "
        "scipy `solve_ivp` "
        f"({scipy_methods}; quaternion + Euler's equations), MuJoCo 4.0 (Euler, implicitfast, RK4 "
        "through `mujoco.rollout`; friction and drag as velocity-biased actuators). Ratios > 1: we are faster.",
        "",
        "The closed form is the reference where there is one, so its error here is 0 by construction (plotted at "
        "1e-16); its own accuracy (about 1e-12 relative, from 30-digit mpmath) is established in "
        "tests/physics/test_free_body.py and tests/physics/test_heavy_top.py. Its CPU time is real.",
        "",
    ]
    body = []
    exact_rows = [
        "## Our closed forms against the best peer",
        "",
        "CPU of the closed-form final state (ms) and the best peer's CPU divided by it:",
        "",
        "| case | closed form, ms | scipy at 1e-4 | scipy at 1e-10 | MuJoCo at 1e-4 | MuJoCo at 1e-10 |",
        "| --- | --- | --- | --- | --- | --- |",
    ]
    results = []
    for case in cases:
        log(f"case {case.name}")
        # The smoke run checks that the benchmark runs and writes its report, not its timings: one run each.
        runs = sweep_case(case, budget, log, factor, rtols, quick, repeats=1 if args.smoke else 3)
        results.append((case, runs))
        body += case_table(case, runs)
        plot_case(case, runs, os.path.join(args.out, f"{case.name}.png"), "one run" if args.smoke else "best of 3")
        body += [f"![{case.name}]({case.name}.png)", ""]
        ex = _best(runs, 1e-10, "exact")
        if ex is None:  # no closed form: its reference is stated with the case
            if mode == "full":  # an independent check by mpmath's Taylor integrator (10-20 s of CPU a case)
                log(f"  mpmath check: {check_with_mpmath(case):.1e}")
            body += [f"*{case.name}* has no closed form; {case.reference_note}.", ""]
            continue
        peer = [_best(runs, lev, "scipy") for lev in (1e-4, 1e-10)] + [
            _best(runs, lev, "mujoco") for lev in (1e-4, 1e-10)
        ]
        exact_rows.append(
            f"| {case.name} | {ex.cpu * 1e3:.3g} | "
            + " | ".join("not reached" if p_ is None else f"{p_.cpu / ex.cpu:.3g}" for p_ in peer)
            + " |"
        )
    long_lines = (
        []  # the full run's long run stays in the table
        if args.update
        else long_run_energy(args.out, 2000 if args.smoke else (20_000 if quick else 1_000_000), log)
    )
    elapsed = time.perf_counter() - t_start
    md += summary_rows(results)
    md += exact_rows + [""]
    md += ["## Long run", ""] + long_lines + ["## Cases", ""] + body
    md += [f"Total wall time of this run: {elapsed:.0f} s.", ""]
    path = os.path.join(args.out, "work_precision.md")
    text = "\n".join(md)
    if args.update:
        with open(path) as f:
            full = f.read()
        command = (
            f"python -m benchmarks.work_precision{'' if mode == 'full' else ' ' + mode} --cases {args.cases} --update"
        )
        note = (
            f"{NOTE_START}{time.strftime('%Y-%m-%d', time.gmtime())} ({mode} mode, {elapsed:.0f} s wall, load average "
            f"{os.getloadavg()[0]:.1f} at its end): {', '.join(c.name for c in cases)}, with `{command}`; their rows "
            "and sections below are from that run, every other case and the long run from the full run. A ratio "
            "compares runs of one process; CPU times of different runs differ with the machine's load. The "
            "worst-ratio line is recomputed.*"
        )
        text = merge_cases(full, text, [c.name for c in cases], note, TARGET)
    with open(path, "w") as f:
        f.write(text)
    log(f"wrote {os.path.join(args.out, 'work_precision.md')} in {elapsed:.0f} s")
    return 0


if __name__ == "__main__":
    sys.exit(main())
