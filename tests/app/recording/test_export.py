"""``rigid-body-lab export`` and :mod:`app.recording.export`: the files, their numbers against the physics API, refusals.

The CSV is checked against an independent evaluation of the same motion by the physics package, for every
scene driven by a closed form (the heavy top released from rest; the wobble, the free fall and the tennis
racket at their defaults, through ``FreeBody``; the pendulum, through ``PhysicalPendulum``), to 1e-12
*relative*: each column's difference is divided by the size of its quantity (|ω| for the components of ω,
|L| for L, |E| for the energy, 1 rad for angles, the height of the throw for the centre). Relative, because
the columns range from 1e-3 (the racket's L in kg m²/s) to 10 (ω in rad/s): a fixed absolute bound would
be loose for the one and tight for the other. Both sides evaluate the same closed forms at the same times
(the scene one time at a time on Python floats, the test on arrays), so they agree to a few ulps; the Euler
angles go through atan2 and back (a few 1e-16).
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
from app.scenes import scene_names
from app.serving.app import App, export, export_zip
from physics import G
from physics.euler_angles import euler_attitude
from physics.free_body import FreeBody
from physics.heavy_top import HeavyTop
from physics.inertia import solid_cylinder
from physics.pendulum import PhysicalPendulum
from physics.rotations import frame_from_axis
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


RELATIVE = 1e-12


def _close(csv_values: np.ndarray, exact: np.ndarray, size: float, what: str) -> None:
    """Agreement to :data:`RELATIVE` of the quantity's size (see the module docstring)."""
    error = float(np.max(np.abs(np.asarray(csv_values) - np.asarray(exact)))) / size
    assert error < RELATIVE, f"{what}: {error:.2e} of its size"


def _free_body_columns(header, table, moments, omega0, body_omega: bool) -> None:
    """A torque-free export (wobble, free fall, racket) against FreeBody's closed form, L along +z at t = 0."""
    t = column(header, table, "t (s)")
    L_body0 = moments * omega0
    attitude0 = frame_from_axis(L_body0).T
    body = FreeBody(moments)
    R, w = body.attitude(omega0, t, attitude0), body.omega(omega0, t)
    R_csv = euler_attitude(*(column(header, table, f"{a} (rad)") for a in ("phi", "theta", "psi")))
    _close(R_csv, R, 1.0, "attitude")
    if body_omega:
        omega = w
        names = [f"omega_{k} (rad/s)" for k in "123"]
    else:
        omega = np.einsum("nij,nj->ni", R, w)
        names = [f"omega_{k} (rad/s)" for k in "xyz"]
    size = float(np.linalg.norm(omega0))
    for k, name in enumerate(names):
        _close(column(header, table, name), omega[:, k], size, name)
    L = np.einsum("nij,nj->ni", R, moments * w)
    L0 = attitude0 @ L_body0
    np.testing.assert_allclose(L0 / np.linalg.norm(L0), [0.0, 0.0, 1.0], atol=1e-15)  # L along +z
    for k, axis in enumerate("xyz"):
        _close(column(header, table, f"L_{axis} (kg m^2/s)"), L[:, k], float(np.linalg.norm(L_body0)), f"L_{axis}")
    energy = 0.5 * float(omega0 @ L_body0)
    _close(column(header, table, "E (J)"), np.full(t.size, energy), energy, "E")


@pytest.mark.parametrize("name", ["wobble", "free_fall"])
def test_wobble_and_free_fall_exports_match_the_physics_api(tmp_path: Path, name: str) -> None:
    from app.scenes.free_fall import START, VELOCITY, FreeFall
    from app.scenes.wobble import Wobble

    written = export(name, tmp_path, 2.0)
    header, table = read_csv(written.csv)
    # The defaults: a solid cylinder of 1 kg with I₃/I₁ = 1.6 (h² = a² (6/1.6 − 3)), its larger dimension 1 m
    # (the scene's own size in free fall), |ω| = 3 rad/s at 20° from the axis.
    size = FreeFall.size if name == "free_fall" else Wobble.size
    assert Wobble.size == 1.0
    h_over_a = math.sqrt(6.0 / 1.6 - 3.0)
    a = size / max(2.0, h_over_a)
    moments, _ = solid_cylinder(1.0, a, a * h_over_a).principal()
    moments = moments[[1, 2, 0]]  # the symmetry axis (the largest moment here, I₃ > I₁) as body axis 3
    alpha = math.radians(20.0)
    omega0 = 3.0 * np.array([math.sin(alpha), 0.0, math.cos(alpha)])
    assert moments[2] / moments[0] == pytest.approx(1.6, rel=1e-14)
    _free_body_columns(header, table, moments, omega0, body_omega=False)
    t = column(header, table, "t (s)")
    if name == "free_fall":
        tau = t % (2.0 * VELOCITY[2] / G)
        centre = START + VELOCITY * tau[:, None] - 0.5 * G * tau[:, None] ** 2 * np.array([0.0, 0.0, 1.0])
        height = VELOCITY[2] ** 2 / (2.0 * G)
        assert tau.max() > 0.9 and t.max() > 1.9  # a whole throw and the start of the next
    else:
        centre = np.tile([0.0, 0.0, 1.0], (t.size, 1))
        height = 1.0
    for k, axis in enumerate("xyz"):
        _close(column(header, table, f"centre_{axis} (m)"), centre[:, k], height, f"centre_{axis}")


def test_tennis_racket_export_matches_the_physics_api(tmp_path: Path) -> None:
    from assets import mass_properties

    written = export("tennis_racket", tmp_path, 3.0)
    header, table = read_csv(written.csv)
    # The defaults: the racket mesh (its catalogue mass), spun at 6 rad/s about axis 2 with ε = 1e-3 on the others.
    moments, _ = mass_properties("tennis_racket").principal()
    omega0 = np.array([6e-3, 6.0, 6e-3])
    _free_body_columns(header, table, moments, omega0, body_omega=True)
    w2 = column(header, table, "omega_2 (rad/s)")
    assert w2[0] == pytest.approx(6.0) and w2.min() < 5.0  # the flip has begun within 3 s


def test_pendulum_export_matches_the_physics_api(tmp_path: Path) -> None:
    from app.scenes.pendulum import AXIS, HANG_HEIGHT
    from assets import mass_properties

    written = export("pendulum", tmp_path, 3.0)
    header, table = read_csv(written.csv)
    t = column(header, table, "t (s)")
    # The defaults: the bat hanging from its knob at HANG_HEIGHT (its +z, knob to tip, turned down), the pivot
    # 0.08 m below the knob, released at 30° from rest.
    props = mass_properties("baseball_bat").transformed(np.diag([1.0, -1.0, -1.0]), [0.0, 0.0, HANG_HEIGHT])
    bat = PhysicalPendulum(props, [0.0, 0.0, HANG_HEIGHT - 0.08], AXIS)
    theta, theta_dot = bat.trajectory(math.radians(30.0), 0.0).at(t)
    _close(column(header, table, "theta (rad)"), theta, 1.0, "theta")
    _close(column(header, table, "theta_dot (rad/s)"), theta_dot, float(np.max(np.abs(theta_dot))), "theta_dot")
    energy = bat.energy(theta, theta_dot)
    _close(column(header, table, "E (J)"), energy, float(abs(energy[0])), "E")
    assert theta.min() < 0.0 < theta.max()  # a whole swing


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
        ({"seconds": 10**400}, "seconds must be within the float range"),
        ({"seconds": 1.0, "preset": "no such preset"}, "no preset"),
        ({"seconds": 1.0, "preset": CUSPS, "state": "rbl1:x"}, "not both"),
        ({"seconds": 1.0, "state": "not a state"}, "not a Rigid Body Lab state"),
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
        self.client_id = 7
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
    from app.recording.export_folder import ExportFolder
    from app.serving.notices import NOTIFY_SECONDS

    def fake_export(text, seconds, progress, lang):
        assert lang == "de"  # the pressing browser's language
        progress(1, 2)
        if isinstance(outcome, Exception):
            raise outcome
        return outcome

    client = _Client()
    from types import SimpleNamespace

    folder = SimpleNamespace(export=fake_export, auto_close_seconds=NOTIFY_SECONDS, language={7: "de"}.get)
    ExportFolder._run(folder, client, "rbl1:x", 2.0, "pendulum")  # type: ignore[arg-type]
    (note,) = client.notes
    assert note.title == title and note.loading is False
    assert note.auto_close_seconds == NOTIFY_SECONDS
    assert client.downloads == (["rigid-body-lab-pendulum.zip"] if title == "Exported" else [])


def test_an_export_whose_browser_left_stops_at_its_next_frame() -> None:
    """A browser that leaves while its export runs frees the process's one export place at once (the export
    stopped at its next frame), instead of holding it for the minutes a long export takes."""
    from types import SimpleNamespace

    from app.recording.export import one_at_a_time
    from app.recording.export_folder import ExportFolder
    from app.serving.notices import NOTIFY_SECONDS

    client = _Client()
    frames: list[int] = []

    def long_export(text, seconds, progress, lang):
        with one_at_a_time():
            for k in range(1, 18_001):
                frames.append(k)
                if k == 100:  # the browser leaves
                    client._websock_connection = SimpleNamespace(get_message_buffer=lambda: SimpleNamespace(done=True))
                progress(k, 18_000)
        return b"zip"

    folder = SimpleNamespace(export=long_export, auto_close_seconds=NOTIFY_SECONDS, language=lambda _: "en")
    ExportFolder._run(folder, client, "rbl1:x", 600.0, "pendulum")  # type: ignore[arg-type]
    assert frames[-1] == 100 and client.downloads == []
    with one_at_a_time():  # the place is free again
        pass


def test_a_state_of_another_scene_is_refused_writes_nothing_and_frees_the_export(tmp_path: Path) -> None:
    app = App.headless("pendulum")
    try:
        text = app.state_text()
    finally:
        app.stop()
    out = tmp_path / "out"
    with pytest.raises(ValueError, match="the state is of the scene 'pendulum', not 'heavy_top'"):
        export("heavy_top", out, 0.5, state=text)
    assert not out.exists()
    written = export("pendulum", out, 0.1, state=text)  # the one export place was given back
    assert written.csv.name == "pendulum.csv" and written.frames == 4
