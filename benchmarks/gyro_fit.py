"""Real phone tosses fitted: ``python -m benchmarks.gyro_fit [--data DIR] [--out DIR] [--baseline-every N]``.

Reads the shared phone-gyroscope recordings (default: the folder ``shared/data/phone-gyro`` beside this
repository's folder; they are not the project's and are never committed) and, for every toss the recorders
hand-marked (and kept), reports: the automatic windows (``physics.gyro.free_flights``) against the hand marks
(start and end, ms); the fit (``physics.gyro.fit_free_body``, one toss at a time, on the automatic window):
the moments' ratios per phone with their spread, the residual as a share of |ω|, the CPU time per toss
(``time.process_time``), the predicted against the measured half turns; and two baselines on the same
windows: the published student method (Bubbar and Zhu, UBC 2025: Euler's method on Euler's equations from
the first sample, the two ratios fitted) and ``scipy.integrate.solve_ivp`` (RK45, rtol 1e-6: its error, ~1e-5 of |ω|, is far below the noise) inside
``scipy.optimize.least_squares`` (ratios and initial ω fitted; no drag, axes as the phone's). The bare-phone
files of the third phone (no hand marks) are fitted on their automatic windows. Writes
``benchmarks/results/gyro_fit.md`` and ``gyro_fit.png``. Stops with a message when the folder is absent.
"""

from __future__ import annotations

import argparse
import csv
import hashlib
import sys
import time
from dataclasses import dataclass, field
from pathlib import Path

import numpy as np
from scipy.integrate import solve_ivp
from scipy.optimize import least_squares

from physics.gyro import FreeBodyFit, Recording, Segment, fit_free_body, free_flights, read_gyroscope

REPO = Path(__file__).resolve().parents[1]
DEFAULT_DATA = REPO.parent / "shared" / "data" / "phone-gyro"
# The third phone's files from 12-22 on are another, flatter object (the data's PROVENANCE.md).
BARE_PHONE_UNTIL = "2022-05-03 12-20"


@dataclass
class Toss:
    phone: str
    name: str
    hand: tuple[float, float] | None
    axis: str
    segment: Segment | None = None
    offsets_ms: tuple[float, float] | None = None
    fit: FreeBodyFit | None = None
    refusal: str = ""
    cpu: float = 0.0
    relative: float = float("nan")
    relative_no_drag: float = float("nan")
    student: float = float("nan")
    scipy_fit: float = float("nan")
    scipy_cpu: float = float("nan")
    student_cpu: float = float("nan")
    half_turns: list[float] = field(default_factory=list)  # predicted − measured, ms
    period: list[tuple[float, float, float]] = field(default_factory=list)  # measured, ours, student half period


def rms_share(model: np.ndarray, seg: Segment) -> float:
    good = ~seg.clipped
    return float(np.sqrt(np.mean((model - seg.omega)[good] ** 2)) / np.sqrt(np.mean(np.sum(seg.omega**2, axis=1))))


def euler_method(ratios: np.ndarray, w0: np.ndarray, t: np.ndarray) -> np.ndarray:
    """Forward Euler on Euler's equations (phone axes principal), one step per sample."""
    ix, iy, iz = ratios[0], ratios[1], 1.0
    out = np.empty((t.size, 3))
    w = w0.copy()
    out[0] = w
    for k in range(1, t.size):
        if not np.all(np.abs(w) < 1e3):
            out[k:] = np.nan
            break
        h = t[k] - t[k - 1]
        x, y, z = w
        w = w + h * np.array([(iy - iz) * y * z / ix, (iz - ix) * z * x / iy, (ix - iy) * x * y / iz])
        out[k] = w
    return out


def student_fit(seg: Segment) -> tuple[np.ndarray, np.ndarray]:
    """The published method: ω0 the first sample, the ratios (x, y over z) fitted by least squares."""
    t, good = seg.times - seg.start, ~seg.clipped
    w0 = seg.omega[0]

    def residuals(p: np.ndarray) -> np.ndarray:
        # Forward Euler can blow up for a poor guess: a diverged run is a large, finite misfit.
        with np.errstate(all="ignore"):
            error = np.clip((euler_method(p, w0, t) - seg.omega) * good, -1e3, 1e3)
        return np.nan_to_num(error, nan=1e3).ravel()

    p = least_squares(residuals, [0.8, 0.2], bounds=([0.01, 0.01], [1.0, 1.0])).x
    with np.errstate(all="ignore"):
        return p, np.nan_to_num(np.clip(euler_method(p, w0, t), -1e3, 1e3), nan=1e3)


def scipy_fit(seg: Segment) -> np.ndarray:
    """solve_ivp (RK45) inside least_squares: ratios and initial ω, no drag, phone axes principal."""
    t, good = seg.times - seg.start, ~seg.clipped

    def solve(p: np.ndarray) -> np.ndarray:
        inertia = np.array([p[0], p[1], 1.0])

        def rhs(_: float, w: np.ndarray) -> np.ndarray:
            return np.cross(inertia * w, w) / inertia

        sol = solve_ivp(rhs, (0.0, t[-1]), p[2:], t_eval=t, rtol=1e-6, atol=1e-6)
        return sol.y.T if sol.y.shape[1] == t.size else np.full((t.size, 3), 1e3)

    def residuals(p: np.ndarray) -> np.ndarray:
        return np.asarray(((solve(p) - seg.omega) * good).ravel())

    p0 = np.concatenate([[0.8, 0.2], seg.omega[0]])
    p = least_squares(residuals, p0, bounds=([0.01, 0.01, -60, -60, -60], [1.0, 1.0, 60, 60, 60])).x
    return solve(p)


def crossings(t: np.ndarray, v: np.ndarray) -> np.ndarray:
    k = np.nonzero(np.sign(v[:-1]) * np.sign(v[1:]) < 0.0)[0]
    return np.asarray(t[k] + (t[k + 1] - t[k]) * v[k] / (v[k] - v[k + 1]))


def load(data: Path) -> tuple[list[tuple[str, Recording, list[Toss]]], int]:
    """(phone, recording, its tosses) for every recording; the number of duplicate files skipped."""
    out: list[tuple[str, Recording, list[Toss]]] = []
    seen: set[str] = set()
    duplicates = 0
    for marks in sorted(data.glob("*/*/meta/segments.csv")):
        folder = marks.parent.parent
        rec = read_gyroscope(folder)
        tosses = []
        for row in csv.DictReader(marks.open()):
            comment = (row.get("comment") or "").strip()
            if (row.get("keep") or "").strip().lower() == "false" or comment.lower() == "not a trial":
                continue
            axis = comment.split(" axis")[0] if "axis" in comment else "Intermediate"
            tosses.append(
                Toss(rec.device or folder.parent.name, folder.name, (float(row["start"]), float(row["end"])), axis)
            )
        out.append((rec.device or folder.parent.name, rec, tosses))
    for path in sorted((data / "dvarkian-phone" / "data").glob("*")):
        if path.suffix == ".xls" or path.name[len("Gyroscope rotation rate ") :] >= BARE_PHONE_UNTIL:
            continue
        rec = read_gyroscope(path)
        digest = hashlib.sha1(np.round(rec.omega, 6).tobytes()).hexdigest()
        if digest in seen:
            duplicates += 1
            continue
        seen.add(digest)
        phone = rec.device or "iPhone14,2"
        out.append((phone, rec, [Toss(phone, path.name, None, "Intermediate")]))
    return out, duplicates


def analyse(recordings: list[tuple[str, Recording, list[Toss]]], baseline_every: int) -> list[Toss]:
    done: list[Toss] = []
    count = 0
    for _, rec, tosses in recordings:
        print(
            f"gyro_fit: {len(done)} tosses done, next a recording of {rec.times[-1]:.0f} s", file=sys.stderr, flush=True
        )
        flights = free_flights(rec)
        if tosses and tosses[0].hand is None:
            # No hand marks: every automatic flight is a toss.
            tosses = [Toss(tosses[0].phone, tosses[0].name, None, "Intermediate", segment=s) for s in flights]
        for toss in tosses:
            if toss.hand is not None:
                a, b = toss.hand
                overlap = [(min(s.end, b) - max(s.start, a), s) for s in flights if s.start < b and s.end > a]
                if overlap:
                    toss.segment = max(overlap, key=lambda x: x[0])[1]
                    toss.offsets_ms = ((toss.segment.start - a) * 1e3, (toss.segment.end - b) * 1e3)
                else:
                    toss.refusal = "no automatic window overlaps the hand marks"
                    done.append(toss)
                    continue
            seg = toss.segment
            assert seg is not None
            try:
                start = time.process_time()
                toss.fit = fit_free_body(seg)
                toss.cpu = time.process_time() - start
            except ValueError as exc:
                toss.refusal = str(exc)
                done.append(toss)
                continue
            toss.relative = float(toss.fit.relative_residuals[0])
            toss.relative_no_drag = float(fit_free_body(seg, drag="none", misalignment=False).relative_residuals[0])
            start = time.process_time()
            ratios, student = student_fit(seg)
            toss.student_cpu = time.process_time() - start
            toss.student = rms_share(student, seg)
            if count % baseline_every == 0:
                start = time.process_time()
                toss.scipy_fit = rms_share(scipy_fit(seg), seg)
                toss.scipy_cpu = time.process_time() - start
            count += 1
            turns = toss.fit.half_turn_times[0]
            if len(turns.predicted) == len(turns.measured):
                toss.half_turns = list((turns.predicted - turns.measured) * 1e3)
            axis = toss.fit.rotation[:, "xyz".index(toss.fit.axes[1])]
            measured = np.diff(turns.measured)
            theirs = np.diff(crossings(seg.times, student @ axis))
            ours = np.diff(turns.predicted)
            for k in range(min(len(measured), len(ours), len(theirs))):
                toss.period.append((measured[k], ours[k], theirs[k]))
            done.append(toss)
    return done


def fmt(values: list[float], digits: int = 3) -> str:
    arr = np.asarray([v for v in values if np.isfinite(v)])
    if arr.size == 0:
        return "—"
    return f"{np.median(arr):.{digits}f} (worst {np.max(arr):.{digits}f})"


def report(tosses: list[Toss], duplicates: int, out: Path, command: str) -> str:
    fitted = [t for t in tosses if t.fit is not None]
    marked = [t for t in tosses if t.hand is not None]
    lines = [
        "# Real phone tosses fitted (physics.gyro)",
        "",
        f"`{command}`; {len(tosses)} tosses ({len(marked)} hand-marked, kept by the recorders; the rest the third "
        f"phone's automatic windows), {len(fitted)} fitted, {duplicates} duplicate file(s) skipped. Every fit is one "
        "toss on its automatic window; shares are RMS(measured − model) over RMS |ω|, clipped components left out.",
        "",
        "## Windows against the hand marks",
        "",
    ]
    offs = np.array([t.offsets_ms for t in marked if t.offsets_ms is not None])
    if offs.size:
        both = np.mean(np.all(np.abs(offs) <= 50.0, axis=1))
        lines += [
            "| | median | 5% | 95% | within 50 ms |",
            "| --- | --- | --- | --- | --- |",
            f"| start − hand start (ms) | {np.median(offs[:, 0]):.0f} | {np.percentile(offs[:, 0], 5):.0f} | "
            f"{np.percentile(offs[:, 0], 95):.0f} | {np.mean(np.abs(offs[:, 0]) <= 50):.0%} |",
            f"| end − hand end (ms) | {np.median(offs[:, 1]):.0f} | {np.percentile(offs[:, 1], 5):.0f} | "
            f"{np.percentile(offs[:, 1], 95):.0f} | {np.mean(np.abs(offs[:, 1]) <= 50):.0%} |",
            "",
            f"Both ends within 50 ms: **{both:.0%}** of {len(offs)} hand-marked tosses (target 90%); "
            f"{len(marked) - len(offs)} without an automatic window.",
            "",
        ]
    lines += ["## Ratios per phone (tosses about the intermediate axis)", ""]
    lines += ["| phone | tosses | I_x (median, σ) | I_y (median, σ) | share within ±0.02 of the median (both) | axes |"]
    lines += ["| --- | --- | --- | --- | --- | --- |"]
    for phone in sorted({t.phone for t in fitted}):
        fits = [t.fit for t in fitted if t.phone == phone and t.axis == "Intermediate" and t.fit is not None]
        if not fits:
            continue
        m = np.array([f.moments for f in fits])
        med = np.median(m, axis=0)
        agree = np.mean(np.all(np.abs(m[:, :2] - med[:2]) <= 0.02, axis=1))
        axes = ", ".join(sorted({f.axes for f in fits}))
        lines.append(
            f"| {phone} | {len(fits)} | {med[0]:.3f}, {np.std(m[:, 0]):.3f} | {med[1]:.3f}, {np.std(m[:, 1]):.3f} | "
            f"{agree:.0%} | {axes} |"
        )
    cpu = [t.cpu for t in fitted]
    lines += [
        "",
        "## Residuals and CPU time per toss",
        "",
        "| fit | residual / |ω|: median (worst) | tosses | CPU s per toss: median (worst) |",
        "| --- | --- | --- | --- |",
        f"| ours: exact free body + per-axis linear drag + misalignment | {fmt([t.relative for t in fitted], 4)} | "
        f"{len(fitted)} | {fmt(cpu)} |",
        f"| ours without drag or misalignment | {fmt([t.relative_no_drag for t in fitted], 4)} | {len(fitted)} | — |",
        f"| student method (Euler's method from the first sample, ratios fitted) | "
        f"{fmt([t.student for t in fitted], 4)} | {len(fitted)} | {fmt([t.student_cpu for t in fitted])} |",
        f"| solve_ivp RK45 + least_squares (ratios, ω0) | {fmt([t.scipy_fit for t in fitted], 4)} | "
        f"{sum(np.isfinite(t.scipy_fit) for t in fitted)} | {fmt([t.scipy_cpu for t in fitted])} |",
        "",
    ]
    paired = [(t.relative, t.student, t.scipy_fit) for t in fitted]
    below_student = np.mean([a < b for a, b, _ in paired])
    with_scipy = [(a, c) for a, _, c in paired if np.isfinite(c)]
    below_scipy = np.mean([a < c for a, c in with_scipy]) if with_scipy else float("nan")
    lines += [
        f"Ours below the student method's residual on {below_student:.0%} of the tosses, below solve_ivp's on "
        f"{below_scipy:.0%} of those it ran on.",
        "",
        "## Half turns of the flip",
        "",
    ]
    turns = np.array([d for t in fitted for d in t.half_turns])
    periods = np.array([p for t in fitted for p in t.period])
    if turns.size:
        lines.append(
            f"Predicted − measured time of each half turn (the intermediate component's sign change), {turns.size} "
            f"half turns: median |Δ| {np.median(np.abs(turns)):.1f} ms, 95% {np.percentile(np.abs(turns), 95):.1f} ms."
        )
    if periods.size:
        ours = np.abs(periods[:, 1] / periods[:, 0] - 1.0)
        theirs = np.abs(periods[:, 2] / periods[:, 0] - 1.0)
        lines.append(
            f"Time between successive half turns, {len(periods)} pairs: ours off by median {np.median(ours):.1%} "
            f"(worst {np.max(ours):.1%}), the student method's by {np.median(theirs):.1%} (worst {np.max(theirs):.1%})."
        )
    refused = [t for t in tosses if t.refusal]
    lines += ["", "## Refused", ""]
    lines += [f"- {t.name} {t.hand}: {t.refusal}" for t in refused] or ["None."]
    text = "\n".join(lines) + "\n"
    out.mkdir(parents=True, exist_ok=True)
    (out / "gyro_fit.md").write_text(text)
    plot(fitted, out / "gyro_fit.png")
    return text


def plot(fitted: list[Toss], path: Path) -> None:
    import matplotlib

    matplotlib.use("Agg")
    import matplotlib.pyplot as plt

    with_flip = [t for t in fitted if t.fit is not None and len(t.half_turns) >= 2 and t.segment is not None]
    toss = sorted(with_flip or fitted, key=lambda t: t.relative)[len(with_flip or fitted) // 2]
    seg, fit = toss.segment, toss.fit
    assert seg is not None and fit is not None
    fig, (top, bottom) = plt.subplots(2, 1, figsize=(9, 7))
    fine = np.linspace(seg.start, seg.end, 400)
    ours = fit.predict(fine)
    _, student = student_fit(seg)
    for i, (name, colour) in enumerate(zip("xyz", ("tab:red", "tab:green", "tab:blue"))):
        top.plot(seg.times - seg.start, seg.omega[:, i], ".", color=colour, ms=4, label=f"measured ω_{name}")
        top.plot(fine - seg.start, ours[:, i], "-", color=colour, lw=1.2, label=f"ours ω_{name}")
        top.plot(seg.times - seg.start, student[:, i], ":", color=colour, lw=1.0, label=f"student method ω_{name}")
    top.set_xlabel("time since release (s)")
    top.set_ylabel("ω (rad/s)")
    top.set_title(f"{toss.name} {toss.hand}: the median toss with two half turns (residual {toss.relative:.1%})")
    top.legend(ncol=3, fontsize=7)
    bins = np.linspace(0.0, 0.2, 41)
    for values, label in (
        ([t.relative for t in fitted], "ours"),
        ([t.student for t in fitted], "student method"),
        ([t.scipy_fit for t in fitted if np.isfinite(t.scipy_fit)], "solve_ivp + least_squares"),
    ):
        bottom.hist(np.clip(values, 0, 0.2), bins=bins, histtype="step", label=label)
    bottom.set_xlabel("residual / |ω| per toss (clipped at 0.2)")
    bottom.set_ylabel("tosses")
    bottom.legend()
    fig.tight_layout()
    fig.savefig(path, dpi=110)
    plt.close(fig)


def main(argv: list[str] | None = None) -> int:
    parser = argparse.ArgumentParser(description=__doc__.split("\n")[0])
    parser.add_argument("--data", type=Path, default=DEFAULT_DATA, help="the phone-gyro folder")
    parser.add_argument("--out", type=Path, default=REPO / "benchmarks" / "results")
    parser.add_argument("--baseline-every", type=int, default=1, help="run solve_ivp on every Nth toss")
    args = parser.parse_args(argv)
    if not args.data.is_dir():
        print(
            f"gyro_fit: no recordings at {args.data}: the shared phone-gyroscope folder is absent "
            "(pass --data DIR); nothing measured.",
            file=sys.stderr,
        )
        return 2
    recordings, duplicates = load(args.data)
    command = " ".join(["python -m benchmarks.gyro_fit", *(sys.argv[1:] if argv is None else argv)])
    print(report(analyse(recordings, args.baseline_every), duplicates, args.out, command))
    return 0


if __name__ == "__main__":
    sys.exit(main())
