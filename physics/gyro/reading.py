"""Reading a gyroscope recording: phyphox's export (its folder, its ``Raw Data.csv``, the ``.zip`` it shares) or
a bare CSV of time and three rates, into a :class:`~physics.gyro.recording.Recording`.

Everything that is not gyroscope data is refused with a ValueError that says what was expected and what came:
a file too large (:data:`MAX_BYTES`), no header naming time and three rates with their units, a row that is not
numbers, NaN, times that do not increase, rates no gyroscope measures (above :data:`MAX_RATE`).
"""

from __future__ import annotations

import csv
import io
import re
import zipfile
from pathlib import Path

import numpy as np

from physics.gyro.recording import Recording

MAX_BYTES = 64 * 1024 * 1024
"""Largest file read, bytes: an hour at 100 Hz is about 30 MB of CSV."""
MAX_SAMPLES = 2_000_000
"""Most samples accepted (5.5 h at 100 Hz)."""
MAX_RATE = 1000.0
"""rad/s: no phone gyroscope measures more (they saturate at 35 to 70 rad/s)."""
GAP_STEPS = 5.0
"""A step between samples longer than this many median steps is a break in the recording."""
RAW_DATA = "Raw Data.csv"

__all__ = ["MAX_BYTES", "MAX_RATE", "MAX_SAMPLES", "read_gyroscope", "parse_gyroscope_csv"]

_UNIT = re.compile(r"[\(\[]\s*([^\)\]]*?)\s*[\)\]]")
_RATE_UNITS = {"rad/s": 1.0, "deg/s": np.pi / 180.0, "°/s": np.pi / 180.0, "degree/s": np.pi / 180.0}
_TIME_UNITS = {"s": 1.0, "ms": 1e-3}


def read_gyroscope(path: str | Path) -> Recording:
    """Read a gyroscope recording.

    Parameters
    ----------
    path : str or Path
        A phyphox export folder (``Raw Data.csv`` and ``meta/``), its ``Raw Data.csv`` (the ``meta/`` beside it
        is read when present), the ``.zip`` phyphox shares, or a CSV whose header names the time (s or ms)
        and three rates with their unit, rad/s or deg/s (``"Time (s)","Gyroscope x (rad/s)",...``); further
        columns (phyphox's "Absolute") are ignored. Comma, semicolon or tab separated; with semicolons or
        tabs a decimal comma is read too.

    Returns
    -------
    Recording
        Times (s), ω (rad/s, phone axes), the device's model name and the pauses (``meta/time.csv``).

    Raises
    ------
    ValueError
        The path does not exist, is not one of the above, or holds no gyroscope data (the message says why).
    """
    p = Path(path)
    if p.is_dir():
        raw = p / RAW_DATA
        if not raw.is_file():
            raise ValueError(f"{p} is a folder without {RAW_DATA!r}: expected a phyphox export folder")
        return _from_files(_read_bytes(raw), _optional(p / "meta" / "time.csv"), _optional(p / "meta" / "device.csv"))
    if not p.is_file():
        raise ValueError(f"no such file or folder: {p}")
    if p.suffix.lower() == ".zip":
        return _from_zip(p)
    meta = p.parent / "meta"
    return _from_files(_read_bytes(p), _optional(meta / "time.csv"), _optional(meta / "device.csv"))


def _read_bytes(path: Path) -> bytes:
    size = path.stat().st_size
    if size > MAX_BYTES:
        raise ValueError(f"{path.name} is {size:,} bytes; a gyroscope recording is at most {MAX_BYTES:,}")
    return path.read_bytes()


def _optional(path: Path) -> bytes | None:
    return _read_bytes(path) if path.is_file() else None


def _from_zip(path: Path) -> Recording:
    """phyphox's shared zip: ``Raw Data.csv`` and ``meta/`` at its root or in one folder."""
    try:
        archive = zipfile.ZipFile(path)
    except (zipfile.BadZipFile, OSError) as exc:
        raise ValueError(f"{path.name} is not a readable zip archive ({exc})") from None
    with archive:
        infos = archive.infolist()
        if len(infos) > 1000:
            raise ValueError(f"{path.name} holds {len(infos)} entries; a phyphox export holds a handful")
        by_name = {info.filename: info for info in infos}
        raws = sorted((n for n in by_name if n.rsplit("/", 1)[-1] == RAW_DATA), key=len)
        if not raws:
            raise ValueError(f"{path.name} holds no {RAW_DATA!r}: expected phyphox's exported zip")
        prefix = raws[0][: -len(RAW_DATA)]

        def member(name: str) -> bytes | None:
            info = by_name.get(prefix + name)
            if info is None:
                return None
            if info.file_size > MAX_BYTES:
                raise ValueError(f"{name} in {path.name} unpacks to {info.file_size:,} bytes; at most {MAX_BYTES:,}")
            try:
                data = archive.read(info)
            except (zipfile.BadZipFile, OSError, RuntimeError, NotImplementedError) as exc:
                raise ValueError(f"{name} in {path.name} cannot be unpacked ({exc})") from None
            return data

        raw = member(RAW_DATA)
        assert raw is not None  # found above
        return _from_files(raw, member("meta/time.csv"), member("meta/device.csv"))


def _from_files(raw: bytes, time_csv: bytes | None, device_csv: bytes | None) -> Recording:
    times, omega = parse_gyroscope_csv(raw)
    breaks = set(_resumes(time_csv)) if time_csv is not None else set()
    steps = np.diff(times)
    if steps.size:
        gap = GAP_STEPS * float(np.median(steps))
        breaks |= {float(times[i + 1]) for i in np.nonzero(steps > gap)[0]}
    inside = sorted(b for b in breaks if times[0] < b <= times[-1])
    return Recording(times, omega, _device(device_csv) if device_csv is not None else None, tuple(inside))


def _text(data: bytes, what: str) -> str:
    try:
        return data.decode("utf-8-sig")
    except UnicodeDecodeError:
        raise ValueError(f"{what} is not text (UTF-8): expected a CSV of time and three rotation rates") from None


def _rows(text: str) -> list[list[str]]:
    first = text.split("\n", 1)[0]
    delimiter = max((",", ";", "\t"), key=first.count)
    return [row for row in csv.reader(io.StringIO(text), delimiter=delimiter) if any(c.strip() for c in row)]


def _unit(name: str, units: dict[str, float]) -> float | None:
    match = _UNIT.search(name)
    return units.get(match.group(1).strip().lower().replace(" ", "")) if match else None


def parse_gyroscope_csv(data: bytes) -> tuple[np.ndarray, np.ndarray]:
    """Times (n,) in s and ω (n, 3) in rad/s from a CSV's bytes (the format of :func:`read_gyroscope`)."""
    if len(data) > MAX_BYTES:
        raise ValueError(f"the CSV is {len(data):,} bytes; a gyroscope recording is at most {MAX_BYTES:,}")
    rows = _rows(_text(data, "the CSV"))
    if not rows:
        raise ValueError("the CSV is empty: expected a header and rows of time and three rotation rates")
    header = [h.strip() for h in rows[0]]
    if len(header) < 4:
        raise ValueError(
            f"the CSV's header has {len(header)} column(s) {header[:4]}; expected time and three rotation rates, "
            'e.g. "Time (s)","Gyroscope x (rad/s)","Gyroscope y (rad/s)","Gyroscope z (rad/s)"'
        )
    if "time" not in header[0].lower() and header[0].split("(")[0].strip().lower() != "t":
        raise ValueError(f"the CSV's first column is {header[0]!r}; expected the time, e.g. 'Time (s)'")
    time_scale = _unit(header[0], _TIME_UNITS)
    if time_scale is None and _UNIT.search(header[0]):
        raise ValueError(f"the time column {header[0]!r} has a unit other than s or ms")
    scales = [_unit(h, _RATE_UNITS) for h in header[1:4]]
    if any(s is None for s in scales):
        raise ValueError(
            f"the columns {header[1:4]} must be rotation rates with their unit in brackets, rad/s or deg/s "
            '(e.g. "Gyroscope x (rad/s)"); an accelerometer or a magnetometer export is not gyroscope data'
        )
    body = rows[1:]
    if not body:
        raise ValueError("the CSV has a header but no samples")
    if len(body) > MAX_SAMPLES:
        raise ValueError(f"the CSV has {len(body):,} samples; at most {MAX_SAMPLES:,} are read")
    decimal_comma = "," not in rows[0] and any("," in c for c in body[0][:4])
    values = np.empty((len(body), 4))
    for i, row in enumerate(body):
        if len(row) < 4:
            raise ValueError(f"row {i + 2} has {len(row)} value(s); expected time and three rates")
        try:
            values[i] = [float(c.replace(",", ".") if decimal_comma else c) for c in row[:4]]
        except ValueError:
            raise ValueError(f"row {i + 2} is not four numbers: {','.join(row[:4])[:80]!r}") from None
    bad = ~np.all(np.isfinite(values), axis=1)
    if np.any(bad):
        raise ValueError(f"row {int(np.argmax(bad)) + 2} holds NaN or infinity; expected finite numbers")
    times = values[:, 0] * (time_scale if time_scale is not None else 1.0)
    omega = values[:, 1:4] * np.array(scales, dtype=float)
    back = np.nonzero(np.diff(times) <= 0.0)[0]
    if back.size:
        k = int(back[0])
        raise ValueError(
            f"the time must increase from row to row: row {k + 3} has {times[k + 1]:g} s after {times[k]:g} s"
        )
    fast = np.abs(omega) > MAX_RATE
    if np.any(fast):
        k = int(np.argmax(np.any(fast, axis=1)))
        raise ValueError(
            f"row {k + 2} has a rotation rate of {np.max(np.abs(omega[k])):.4g} rad/s; no phone gyroscope "
            f"measures above {MAX_RATE:g} (is the unit right?)"
        )
    return times, omega


def _resumes(data: bytes) -> list[float]:
    """Experiment times of the START events after the first (phyphox's ``meta/time.csv``)."""
    rows = _rows(_text(data, "meta/time.csv"))
    starts = []
    for row in rows[1:]:
        if len(row) >= 2 and row[0].strip().upper() == "START":
            try:
                starts.append(float(row[1]))
            except ValueError:
                raise ValueError(f"meta/time.csv has a START event at {row[1]!r}, not a time in s") from None
    return [s for s in starts[1:] if np.isfinite(s)]


def _device(data: bytes) -> str | None:
    for row in _rows(_text(data, "meta/device.csv"))[1:]:
        if len(row) >= 2 and row[0].strip() == "deviceModel" and row[1].strip():
            return row[1].strip()[:80]
    return None
