"""Reading gyroscope recordings (physics.gyro.read_gyroscope): phyphox's folder, its Raw Data.csv, the zip it
shares and a bare CSV, on small files written here; and a precise refusal of each kind of file that is not
gyroscope data."""

from __future__ import annotations

import zipfile
from pathlib import Path

import numpy as np
import pytest

from physics.gyro import reading
from physics.gyro.reading import read_gyroscope

HEADER = '"Time (s)","Gyroscope x (rad/s)","Gyroscope y (rad/s)","Gyroscope z (rad/s)","Absolute (rad/s)"'
TIME_CSV = (
    '"event","experiment time","system time","system time text"\n'
    '"START",0.000000000000000E0,1.75E9,"a"\n'
    '"PAUSE",2.0E-2,1.75E9,"b"\n'
    '"START",2.0E-2,1.75E9,"c"\n'
    '"PAUSE",5.0E-2,1.75E9,"d"\n'
)
DEVICE_CSV = '"property","value"\n"version","1.1.16"\n"deviceModel","iPhone14,5"\n'
ROWS = [(0.005, 1.0, -2.0, 3.0), (0.015, 1.5, -2.5, 3.5), (0.025, 2.0, -3.0, 4.0), (0.035, 2.5, -3.5, 4.5)]


def raw_csv(rows: list[tuple[float, float, float, float]] = ROWS, header: str = HEADER) -> str:
    lines = [header] + [",".join(f"{v:.9E}" for v in (*r, np.linalg.norm(r[1:]))) for r in rows]
    return "\n".join(lines) + "\n"


def phyphox_folder(root: Path) -> Path:
    folder = root / "Gyroscope rotation rate 2025-06-24 20-10-14"
    (folder / "meta").mkdir(parents=True)
    (folder / "Raw Data.csv").write_text(raw_csv())
    (folder / "meta" / "time.csv").write_text(TIME_CSV)
    (folder / "meta" / "device.csv").write_text(DEVICE_CSV)
    return folder


def check_the_rows(
    rec: reading.Recording, device: str | None = "iPhone14,5", breaks: tuple[float, ...] = (0.02,)
) -> None:
    assert np.array_equal(rec.times, [r[0] for r in ROWS])
    assert np.array_equal(rec.omega, [r[1:] for r in ROWS])
    assert rec.device == device
    assert rec.breaks == breaks
    # The pause at 0.02 s splits the samples into two continuous pieces.
    assert rec.pieces() == ([(0, 2), (2, 4)] if breaks else [(0, 4)])


def test_a_phyphox_folder_its_raw_data_and_its_zip(tmp_path: Path) -> None:
    folder = phyphox_folder(tmp_path)
    check_the_rows(read_gyroscope(folder))
    check_the_rows(read_gyroscope(folder / "Raw Data.csv"))
    check_the_rows(read_gyroscope(str(folder)))
    for prefix in ("", "Gyroscope rotation rate 2025-06-24 20-10-14/"):
        archive = tmp_path / f"shared{len(prefix)}.zip"
        with zipfile.ZipFile(archive, "w") as z:
            z.writestr(prefix + "Raw Data.csv", raw_csv())
            z.writestr(prefix + "meta/time.csv", TIME_CSV)
            z.writestr(prefix + "meta/device.csv", DEVICE_CSV)
        check_the_rows(read_gyroscope(archive))


def test_a_bare_csv_in_degrees_with_semicolons_and_decimal_commas(tmp_path: Path) -> None:
    text = "Time (ms);Gyroscope x (deg/s);Gyroscope y (deg/s);Gyroscope z (deg/s)\n"
    text += "".join(f"{r[0] * 1000:.3f};{r[1]};{r[2]};{r[3]}\n".replace(".", ",") for r in ROWS)
    path = tmp_path / "toss.csv"
    path.write_text(text)
    rec = read_gyroscope(path)
    assert np.allclose(rec.times, [r[0] for r in ROWS], rtol=0, atol=1e-15)
    assert np.allclose(rec.omega, np.radians([r[1:] for r in ROWS]), rtol=1e-15, atol=0)
    assert rec.device is None and rec.breaks == ()


def test_a_gap_in_time_is_a_break(tmp_path: Path) -> None:
    rows = ROWS + [(0.5, 1.0, 1.0, 1.0), (0.51, 1.0, 1.0, 1.0)]
    path = tmp_path / "gap.csv"
    path.write_text(raw_csv(rows))
    assert read_gyroscope(path).breaks == (0.5,)


@pytest.mark.parametrize(
    ("text", "message"),
    [
        ("", "empty"),
        (HEADER + "\n", "no samples"),
        ('"Time (s)","x","y"\n0,1,2\n', "3 column"),
        ('"Acceleration x (m/s^2)","y","z","w"\n0,1,2,3\n', "expected the time"),
        (
            '"Time (s)","Acceleration x (m/s^2)","Acceleration y (m/s^2)","Acceleration z (m/s^2)"\n0,1,2,3\n',
            "not gyroscope data",
        ),
        (
            '"Time (h)","Gyroscope x (rad/s)","Gyroscope y (rad/s)","Gyroscope z (rad/s)"\n0,1,2,3\n',
            "other than s or ms",
        ),
        (raw_csv([(0.0, 1.0, float("nan"), 1.0)]), "row 2 holds NaN"),
        (
            raw_csv([(0.0, 1.0, 1.0, 1.0), (0.01, 1.0, 1.0, 1.0), (0.01, 1.0, 1.0, 1.0)]),
            "row 4 has 0.01 s after 0.01 s",
        ),
        (raw_csv([(0.0, 1.0, 1.0, 1.0), (0.01, 1.0, 5000.0, 1.0)]), "5000 rad/s"),
        (HEADER + "\n0.0,1.0,<b>2</b>,3.0,4\n", "row 2 is not four numbers"),
        (HEADER + "\n0.0,1.0\n", "row 2 has 2 value"),
    ],
    ids=lambda value: value if len(value) < 40 else "",
)
def test_not_gyroscope_data_is_refused_by_name(tmp_path: Path, text: str, message: str) -> None:
    path = tmp_path / "bad.csv"
    path.write_text(text)
    with pytest.raises(ValueError, match=message.replace("(", r"\(").replace(")", r"\)")):
        read_gyroscope(path)


def test_files_that_are_not_text_or_not_there(tmp_path: Path, monkeypatch: pytest.MonkeyPatch) -> None:
    binary = tmp_path / "photo.csv"
    binary.write_bytes(b"\x89PNG\r\n\x1a\n\xff\xfe\x00")
    with pytest.raises(ValueError, match="not text"):
        read_gyroscope(binary)
    with pytest.raises(ValueError, match="no such file"):
        read_gyroscope(tmp_path / "missing.csv")
    with pytest.raises(ValueError, match="folder without 'Raw Data.csv'"):
        read_gyroscope(tmp_path)
    broken = tmp_path / "broken.zip"
    broken.write_bytes(b"PK\x03\x04 not a zip")
    with pytest.raises(ValueError, match="not a readable zip"):
        read_gyroscope(broken)
    empty_zip = tmp_path / "other.zip"
    with zipfile.ZipFile(empty_zip, "w") as z:
        z.writestr("readme.txt", "hello")
    with pytest.raises(ValueError, match="holds no 'Raw Data.csv'"):
        read_gyroscope(empty_zip)
    # Enormous files: the limit is lowered so that the test writes kilobytes, not 64 MB.
    monkeypatch.setattr(reading, "MAX_BYTES", 200)
    big = tmp_path / "big.csv"
    big.write_text(raw_csv(ROWS * 3))
    with pytest.raises(ValueError, match="at most 200"):
        read_gyroscope(big)
    bomb = tmp_path / "bomb.zip"
    with zipfile.ZipFile(bomb, "w", compression=zipfile.ZIP_DEFLATED) as z:
        z.writestr("Raw Data.csv", HEADER + "\n" + "0" * 5000)
    with pytest.raises(ValueError, match="unpacks to 5,"):
        read_gyroscope(bomb)
