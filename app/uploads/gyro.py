"""Reading an uploaded gyroscope recording (phyphox's CSV or zip) and fitting the free body to its tosses, or a
ValueError saying what to fix.

Pure functions (nothing touches viser), run in the upload worker (:func:`app.uploads.worker.toss_fit_in_worker`).
The result is plain data: the fitted moments, the plot's points and lines, and the fitted motion sampled for
the replay (attitudes, ω and L in space), so that the server only draws it.
"""

from __future__ import annotations

import csv
import functools
import io
import tempfile
from dataclasses import dataclass
from pathlib import Path, PurePath

import numpy as np
from numpy.typing import NDArray

from app.language.words import mark, say
from app.uploads.limits import RECORDING_FORMATS
from physics.gyro import (
    FreeBodyFit,
    Recording,
    Toss,
    fit_free_body,
    free_flights,
    read_gyroscope,
    synthetic_recording,
)
from physics.gyro.fit import MIN_DURATION, MIN_SPIN, check_segment
from physics.gyro.model import rotation_from_vector
from physics.rotations import frame_from_axis

Floats = NDArray[np.float64]

__all__ = [
    "MAX_FITTED",
    "REPLAY_STEP",
    "TossFit",
    "example_csv",
    "fit_recording",
    "fit_toss_upload",
    "recording_csv",
]

MAX_FITTED = 30
"""Most tosses fitted together ("all tosses"): 30 take about 5 s of a worker's CPU."""
REPLAY_STEP = 0.002
"""s of the toss between the replay's samples (at 0.2× a frame at 60 frames/s advances 3.3 ms)."""
SUBSTEPS = 4
"""Rotation steps between two replay samples (each exp(ω dt) with ω at the step's middle)."""

EXAMPLE_MOMENTS = (0.8, 0.21, 1.0)
"""The bundled example's phone: moments along x, y, z (a bare phone's ratios, docs/app-notes.md)."""
EXAMPLE_TOSSES = (Toss(1.0, 1.0, (18.0, 1.0, 0.6)), Toss(3.0, 0.9, (-22.0, 0.7, -0.8)))
"""Two tosses about the intermediate axis (x), each with a flip, ω0 in rad/s."""
EXAMPLE_DRAG = (0.1, 0.02, 0.05)
"""1/s on the scale of the largest moment: 6-10% of |L| in a toss, as real phones lose."""
EXAMPLE_SEED = 2026
EXAMPLE_NAME = mark("example toss (made by the project's model)")


@dataclass(frozen=True)
class TossFit:
    """A recording's tosses fitted: what the phone-toss scene shows.

    Attributes
    ----------
    source : str
        The file's name (or the bundled example's).
    device : str or None
        The phone's model when the export names it.
    windows : tuple of (float, float)
        Every free flight found, (release, catch) in the recording's time, s.
    chosen : int or None
        The flight fitted alone (index into ``windows``), or None: all (up to :data:`MAX_FITTED`) together.
    fitted : tuple of int
        The flights fitted (indices into ``windows``).
    left_out : tuple of str
        Why each flight not fitted with "all" was left out.
    fit : FreeBodyFit
        The fit (moments along the phone's x, y, z with the largest 1, their σ, residual, drag).
    plot_times : ndarray (n,)
        s: the fitted flights' sample times, a NaN between two flights (a gap in the plot's lines).
    measured, model : ndarray (n, 3)
        ω in the phone's axes, rad/s: the samples and the fitted model at the same times.
    replay_times : ndarray (m,)
        s of flight from the first fitted flight's release, the flights one after the other.
    replay_toss : ndarray (m,) of int
        Which fitted flight (index into ``fitted``) each replay sample belongs to.
    attitudes : ndarray (m, 3, 3)
        The phone's axes in space (columns), L of each flight's release along +z.
    omega_space, l_space : ndarray (m, 3)
        ω (rad/s) and L (per unit of the largest moment, rad/s) in space.
    """

    source: str
    device: str | None
    windows: tuple[tuple[float, float], ...]
    chosen: int | None
    fitted: tuple[int, ...]
    left_out: tuple[str, ...]
    fit: FreeBodyFit
    plot_times: Floats
    measured: Floats
    model: Floats
    replay_times: Floats
    replay_toss: NDArray[np.int64]
    attitudes: Floats
    omega_space: Floats
    l_space: Floats

    @property
    def duration(self) -> float:
        """s of free flight replayed (every fitted flight)."""
        return float(self.replay_times[-1])


def fit_toss_upload(filename: str, content: bytes, chosen: int | None = None) -> TossFit:
    """Read an uploaded recording and fit the free body to one of its tosses, or to all of them.

    Parameters
    ----------
    filename : str
        The file's name: ``.zip`` (phyphox's shared export) or ``.csv`` (its ``Raw Data.csv``, or a bare CSV of
        time and three rates with their units).
    content : bytes
        The file's bytes (their size checked already: :func:`app.uploads.limits.check_upload`).
    chosen : int or None
        The toss to fit (0-based, in time order) or None for all of them together.

    Raises
    ------
    ValueError
        Not a recording this app reads, not gyroscope data, no toss in it, or the toss cannot be fitted (too
        short, too slow, mostly clipped); the message names the file and says what to do.
    """
    name = PurePath(filename or "upload").name
    ext = PurePath(name).suffix.lower().lstrip(".")
    if ext not in RECORDING_FORMATS:
        got = "." + ext if ext else mark("no extension")
        raise ValueError(
            say(
                "{name} is not a recording this scene reads: upload phyphox's export of "
                '"Gyroscope (rotation rate)" as CSV (Raw Data.csv) or the .zip it shares (got {got}).',
                name=name,
                got=got,
            )
        )
    if not content:
        raise ValueError(say("{name} is empty (0 bytes): there is no recording in it.", name=name))
    # phyphox's reader takes a path: the bytes go to a file of our naming (never the uploaded name).
    with tempfile.TemporaryDirectory(prefix="rbl-gyro-") as folder:
        path = Path(folder) / f"upload.{ext}"
        path.write_bytes(content)
        try:
            recording = read_gyroscope(path)
        except (ValueError, csv.Error) as exc:  # csv.Error: a cell over the csv module's 128 kB limit
            raise ValueError(
                say("{name} is not a gyroscope recording this app reads: {reason}.", name=name, reason=str(exc))
            ) from None
    return fit_recording(name, recording.times, recording.omega, recording.breaks, recording.device, chosen)


def fit_recording(
    name: str,
    times: Floats,
    omega: Floats,
    breaks: tuple[float, ...] = (),
    device: str | None = None,
    chosen: int | None = None,
) -> TossFit:
    """Find the tosses of a recording (``times`` (n,) s, ``omega`` (n, 3) rad/s) and fit one or all of them."""
    recording = Recording(np.asarray(times, dtype=float), np.asarray(omega, dtype=float), device, tuple(breaks))
    flights = free_flights(recording)
    if not flights:
        fastest = float(np.max(np.linalg.norm(omega, axis=1))) if len(omega) else 0.0
        raise ValueError(
            say(
                "no toss found in {name}: a toss is at least {duration:g} s of free flight spinning at "
                "{spin:g} rad/s or more between two jolts (release and catch); the fastest spin in the file is "
                "{fastest:.3g} rad/s. Toss the phone higher and spin it harder, about its axis across the screen.",
                name=name,
                duration=MIN_DURATION,
                spin=MIN_SPIN,
                fastest=fastest,
            )
        )
    windows = tuple((s.start, s.end) for s in flights)
    if chosen is not None:
        if not 0 <= chosen < len(flights):
            raise ValueError(
                say(
                    "{name} has {count} toss(es); toss {number} is not one of them.",
                    name=name,
                    count=len(flights),
                    number=chosen + 1,
                )
            )
        check_segment(flights[chosen], f"toss {chosen + 1} of {name}")
        picked, left_out = [chosen], list[str]()
    else:
        picked, left_out = list[int](), list[str]()
        for k, seg in enumerate(flights):
            try:
                check_segment(seg, f"toss {k + 1}")
            except ValueError as exc:
                left_out.append(str(exc))
                continue
            if len(picked) == MAX_FITTED:
                left_out.append(f"toss {k + 1} and later: at most {MAX_FITTED} tosses are fitted together")
                break
            picked.append(k)
        if not picked:
            raise ValueError(say("no toss of {name} can be fitted: {reasons}.", name=name, reasons="; ".join(left_out)))
    fit = fit_free_body([flights[k] for k in picked])
    plot_times, measured, model = _plot(fit)
    replay = _replay(fit)
    return TossFit(
        name, device, windows, chosen, tuple(picked), tuple(left_out), fit, plot_times, measured, model, *replay
    )


def _plot(fit: FreeBodyFit) -> tuple[Floats, Floats, Floats]:
    """The samples and the model at their times, flights one after the other, a NaN row between two."""
    times, measured, model = [], [], []
    for k, seg in enumerate(fit.segments):
        if k:
            times.append(np.array([np.nan]))
            measured.append(np.full((1, 3), np.nan))
            model.append(np.full((1, 3), np.nan))
        times.append(seg.times)
        measured.append(seg.omega)
        model.append(fit.predict(seg.times, k))
    return np.concatenate(times), np.concatenate(measured), np.concatenate(model)


def _replay(fit: FreeBodyFit) -> tuple[Floats, NDArray[np.int64], Floats, Floats, Floats]:
    """The fitted motion of each flight sampled every :data:`REPLAY_STEP` s: its attitude, ω and L in space.

    The attitude follows Ṙ = R hat(ω) with the fitted ω (the exact solution, with the drag stepped by the
    project's integrators: ``fit.predict``), each sub-step the rotation exp(hat(ω dt)) about ω at its middle
    (second order: over a 1 s toss at 20 rad/s the attitude is off by about 1e-6 rad, far below a pixel).
    """
    inertia = fit.rotation @ np.diag(fit.moments) @ fit.rotation.T  # in the phone's axes (largest moment 1)
    times, tosses, attitudes, omegas, momenta = [], [], [], [], []
    offset = 0.0
    for k, seg in enumerate(fit.segments):
        n = max(int(np.ceil(seg.duration / REPLAY_STEP)), 1)
        fine = seg.start + np.linspace(0.0, n * REPLAY_STEP, n * SUBSTEPS + 1)
        middles = fit.predict(0.5 * (fine[:-1] + fine[1:]), k)
        at_samples = fit.predict(fine[::SUBSTEPS], k)
        dt = REPLAY_STEP / SUBSTEPS
        R = frame_from_axis(inertia @ at_samples[0]).T  # L at the release along +z
        frames = [R]
        for j, w in enumerate(middles):
            R = R @ rotation_from_vector(w * dt)
            if (j + 1) % SUBSTEPS == 0:
                frames.append(R)
        rs = np.array(frames)
        times.append(offset + REPLAY_STEP * np.arange(n + 1))
        tosses.append(np.full(n + 1, k))
        attitudes.append(rs)
        omegas.append(np.einsum("kij,kj->ki", rs, at_samples))
        momenta.append(np.einsum("kij,kj->ki", rs, at_samples @ inertia.T))
        offset += n * REPLAY_STEP + REPLAY_STEP
    return (
        np.concatenate(times),
        np.concatenate(tosses).astype(np.int64),
        np.concatenate(attitudes),
        np.concatenate(omegas),
        np.concatenate(momenta),
    )


def recording_csv(times: Floats, omega: Floats) -> bytes:
    """A recording as phyphox exports it (``Raw Data.csv``): time (s), ω x, y, z and |ω| (rad/s)."""
    out = io.StringIO()
    out.write('"Time (s)","Gyroscope x (rad/s)","Gyroscope y (rad/s)","Gyroscope z (rad/s)","Absolute (rad/s)"\n')
    for t, w in zip(np.asarray(times, dtype=float), np.asarray(omega, dtype=float)):
        out.write(f"{t:.9E},{w[0]:.9E},{w[1]:.9E},{w[2]:.9E},{float(np.linalg.norm(w)):.9E}\n")
    return out.getvalue().encode("utf-8")


@functools.cache
def example_csv() -> bytes:
    """The bundled example: two tosses of a bare phone made by the project's own model
    (:func:`physics.gyro.synthetic_recording`, a fixed seed), as phyphox's CSV (made once per process)."""
    recording, _ = synthetic_recording(EXAMPLE_MOMENTS, EXAMPLE_TOSSES, drag=EXAMPLE_DRAG, seed=EXAMPLE_SEED)
    return recording_csv(recording.times, recording.omega)
