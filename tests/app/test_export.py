"""``rigid-body-lab export`` and :mod:`app.export`: the files, their numbers against the physics API, refusals.

The CSV is checked against an independent evaluation of the same motion by the physics package (the heavy
top released from rest at the scene's default body), to 1e-12: both evaluate the same closed form at the
same times, so they agree to a few ulps; the Euler angles go through atan2 and back (a few 1e-16).
"""

from __future__ import annotations

import csv
import io
import math
import zipfile
from pathlib import Path

import numpy as np
import pytest

from app.__main__ import main
from app.export import export, export_zip
from app.scenes import scene_names
from physics.euler_angles import euler_attitude
from physics.heavy_top import HeavyTop
from tests.harness import running_app

CUSPS = "cusps (released from rest)"  # spin 10 rad/s, tilt 60°, φ̇0 = 0, no friction; I1 0.4, I3 0.2, M g ℓ 1


def read_csv(path: Path) -> tuple[list[str], np.ndarray]:
    with path.open(newline="", encoding="utf-8") as handle:
        rows = list(csv.reader(handle))
    return rows[0], np.array(rows[1:], dtype=float)


def column(header: list[str], table: np.ndarray, name: str) -> np.ndarray:
    return table[:, header.index(name)]


def test_heavy_top_export_matches_the_physics_api(tmp_path: Path) -> None:
    written = export("heavy_top", tmp_path, 2.0, preset=CUSPS)
    assert written.frames == 61 and written.html.exists() and written.png.exists()
    assert written.png.read_bytes()[:8] == b"\x89PNG\r\n\x1a\n"
    header, table = read_csv(written.csv)
    assert header[0] == "t (s)" and "E (J)" in header and "theta (rad)" in header
    t = column(header, table, "t (s)")
    np.testing.assert_allclose(t, np.arange(61) / 30.0, rtol=0, atol=1e-13)

    motion = HeavyTop(0.4, 0.2, 1.0).trajectory(math.pi / 3, 0.0, 0.0, 10.0)
    exact = motion.at(t)
    R_csv = euler_attitude(*(column(header, table, f"{a} (rad)") for a in ("phi", "theta", "psi")))
    assert np.abs(R_csv - exact.attitude).max() < 1e-12
    omega = np.einsum("nij,nj->ni", exact.attitude, exact.omega_body)
    L = np.einsum("nij,nj->ni", exact.attitude, np.array([0.4, 0.4, 0.2]) * exact.omega_body)
    for k, axis in enumerate("xyz"):
        assert np.abs(column(header, table, f"omega_{axis} (rad/s)") - omega[:, k]).max() < 1e-12 * 10.0
        assert np.abs(column(header, table, f"L_{axis} (kg m^2/s)") - L[:, k]).max() < 1e-12 * 2.0
    # The conserved quantities are conserved in the file too.
    energy = column(header, table, "E (J)")
    assert np.ptp(energy) < 1e-12 * abs(energy[0])
    assert np.ptp(column(header, table, "L_z (kg m^2/s)")) < 1e-12 * 2.0
    assert np.all(column(header, table, "L_3 (kg m^2/s)") == 2.0)


@pytest.mark.parametrize("name", scene_names())
def test_every_scene_exports(tmp_path: Path, name: str) -> None:
    written = export(name, tmp_path, 0.5)
    header, table = read_csv(written.csv)
    assert written.csv.name == f"{name}.csv" and table.shape == (16, len(header)) and len(header) >= 2
    assert np.all(np.isfinite(table))
    assert all(h.endswith(")") for h in header), header  # every column states its unit
    html = written.html.read_text(encoding="utf-8")
    assert "__VISER_EMBED_DATA__" in html and len(html) > 100_000  # the client build and the recording
    if "E (J)" in header and name != "inertia_explorer":
        energy = column(header, table, "E (J)")
        assert np.ptp(energy) <= 1e-12 * max(1.0, abs(energy[0])), name  # exact solutions: E is constant


def test_a_state_text_exports_from_its_time(tmp_path: Path) -> None:
    with running_app("pendulum", start_loop=False) as app:
        app.set_playing(True)
        for _ in range(30):
            app.frame(1.0 / 60.0)
        text = app.state_text()
        t0 = app.time
    written = export(None, tmp_path, 1.0, state=text)
    header, table = read_csv(written.csv)
    assert written.csv.name == "pendulum.csv"
    assert table[0, 0] == pytest.approx(t0, abs=1e-12) and table[-1, 0] == pytest.approx(t0 + 1.0, abs=1e-12)


@pytest.mark.parametrize(
    "kwargs, message",
    [
        ({"seconds": float("nan")}, "finite"),
        ({"seconds": 0.0}, "between"),
        ({"seconds": 1e9}, "between"),
        ({"seconds": "ten"}, "number"),
        ({"seconds": 10**400}, ""),
        ({"seconds": 1.0, "preset": "no such preset"}, "no preset"),
        ({"seconds": 1.0, "preset": CUSPS, "state": "rbl1:x"}, "not both"),
        ({"seconds": 1.0, "state": "not a state"}, ""),
        ({"seconds": 1.0, "fps": 0.0}, "fps"),
    ],
)
def test_bad_requests_are_refused_and_write_nothing(tmp_path: Path, kwargs: dict, message: str) -> None:
    out = tmp_path / "out"
    with pytest.raises(ValueError, match=message):
        export("heavy_top", out, **kwargs)
    assert not out.exists()


def test_command_line(tmp_path: Path, capsys: pytest.CaptureFixture[str]) -> None:
    main(["export", "--scene", "wobble", "--seconds", "1", "--out", str(tmp_path)])
    captured = capsys.readouterr()
    assert "31 frames written" in captured.out and "31/30" not in captured.err and "30/30 frames" in captured.err
    assert {p.name for p in tmp_path.iterdir()} == {"index.html", "wobble.csv", "wobble.png"}
    with pytest.raises(SystemExit) as refused:
        main(["export", "--scene", "wobble", "--seconds", "inf", "--out", str(tmp_path / "x")])
    assert refused.value.code == 2 and "seconds must be finite" in capsys.readouterr().err
    with pytest.raises(SystemExit):
        main(["export", "--seconds", "1", "--out", str(tmp_path / "x")])
    assert "give --scene" in capsys.readouterr().err


def test_the_panel_zip_holds_the_three_files() -> None:
    with running_app("heavy_top", start_loop=False) as app:
        text = app.state_text()
    archive = zipfile.ZipFile(io.BytesIO(export_zip(text, 0.5)))
    assert sorted(archive.namelist()) == ["heavy_top.csv", "heavy_top.png", "index.html"]
    assert archive.read("heavy_top.csv").startswith(b"t (s),")


class _Client:
    """A browser as the Export folder sees it: notifications (their final props recorded) and downloads."""

    def __init__(self) -> None:
        from types import SimpleNamespace

        self._websock_connection = SimpleNamespace(get_message_buffer=lambda: SimpleNamespace(done=False))
        self.notes: list[SimpleNamespace] = []
        self.downloads: list[str] = []

    def add_notification(self, title: str, body: str, **props):
        from types import SimpleNamespace

        note = SimpleNamespace(title=title, body=body, color=None, auto_close_seconds=None, **props)
        self.notes.append(note)
        return note

    def send_file_download(self, name: str, content: bytes, save_immediately: bool = False) -> None:
        self.downloads.append(name)


@pytest.mark.parametrize(
    "outcome, title",
    [(b"zip", "Exported"), (ValueError("no such state"), "Export refused"), (RuntimeError("disk"), "Export failed")],
)
def test_the_export_notes_close_by_themselves(monkeypatch: pytest.MonkeyPatch, outcome, title: str) -> None:
    """The progress note ends as "Exported", "Export refused" or "Export failed", not loading, and closes after
    NOTIFY_SECONDS like every other notification (it stayed open until clicked)."""
    import app.export_button as export_button
    from app.server import NOTIFY_SECONDS

    def fake_export(text, seconds, progress):
        progress(1, 2)
        if isinstance(outcome, Exception):
            raise outcome
        return outcome

    monkeypatch.setattr(export_button, "export_zip", fake_export)
    client = _Client()
    export_button.ExportFolder._run(None, client, "rbl1:x", 2.0, "pendulum")  # type: ignore[arg-type]
    (note,) = client.notes
    assert note.title == title and note.loading is False
    assert note.auto_close_seconds == NOTIFY_SECONDS
    assert client.downloads == (["rigid-body-lab-pendulum.zip"] if title == "Exported" else [])
