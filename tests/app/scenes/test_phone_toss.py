"""The phone-toss scene headless: the bundled toss shown before any upload, an uploaded recording (made by
the project's own model) fitted in the worker and shown with physics' own fit, one toss or all, refusals
that reach only the browser that sent the file, uploads fitted outside the lock, presenter and private modes.
"""

from __future__ import annotations

from types import SimpleNamespace

import numpy as np
import pytest
from viser import UploadedFile

import app.scenes.phone_toss as toss_module
from app.teaching.states import state_text
from app.uploads.gyro import EXAMPLE_MOMENTS, example_csv, fit_toss_upload, recording_csv
from app.uploads.limits import MAX_BYTES
from physics.gyro import Toss, fit_free_body, free_flights, read_gyroscope, synthetic_recording
from tests.harness import FRAME, click_button, open_scene, raw_client, running_app, wait_for
from tests.uploading import lock_is_free, zip_bytes

# A phone unlike the bundled one (x intermediate still), two tosses with a flip each, drag and noise as real.
MOMENTS = (0.75, 0.25, 1.0)
TOSSES = [Toss(1.0, 0.9, (17.0, 0.9, -0.5)), Toss(3.0, 0.8, (-20.0, 0.6, 0.7))]


def _recording() -> tuple[np.ndarray, np.ndarray]:
    rec, _ = synthetic_recording(MOMENTS, TOSSES, drag=(0.08, 0.02, 0.04), noise=0.02, seed=11)
    return rec.times, rec.omega


def _csv() -> bytes:
    return recording_csv(*_recording())


def _physics_fit(tmp_path, content: bytes, chosen: int | None = None):
    """physics' own reading and fit of the same file: what the scene must show."""
    path = tmp_path / "Raw Data.csv"
    path.write_bytes(content)
    flights = free_flights(read_gyroscope(path))
    return flights, fit_free_body(flights if chosen is None else flights[chosen])


def test_the_bundled_toss_is_shown_before_any_upload(app):
    sc = open_scene(app, "phone_toss")
    result = sc.result
    assert result.source.startswith("example toss") and len(result.windows) == 2 and result.fitted == (0, 1)
    # The project's own model made it: the fit recovers its moments (noise 0.02 rad/s over ~170 samples of
    # ~20 rad/s: σ about 1e-4; 2e-3 allows the drag's and the noise's bias, as tests/physics/test_gyro_fit.py).
    np.testing.assert_allclose(result.fit.moments, EXAMPLE_MOMENTS, atol=2e-3)
    assert result.fit.axes == "zxy"  # z largest, x intermediate: it flips about x
    assert "x, across the screen" in sc.flip_axis_readout.text
    times, *series = sc.plot.data
    assert len(series) == 6 and times.size == result.measured.shape[0]
    # Two flights: one NaN row between them (a gap in the lines), finite elsewhere.
    assert np.isnan(times).sum() == 1 and np.all(np.isfinite(np.concatenate(series)[~np.isnan(np.tile(times, 6))]))
    before = np.array(sc.body.handle.wxyz)
    for _ in range(30):
        app.frame(FRAME)
    assert not np.allclose(before, sc.body.handle.wxyz)  # the replay turns the phone


def test_an_uploaded_recording_shows_physics_own_fit(app, tmp_path):
    sc = open_scene(app, "phone_toss")
    content = _csv()
    assert sc.load_upload("Raw Data.csv", content)
    flights, fit = _physics_fit(tmp_path, content)
    # The same file, the same functions, in a worker: the same numbers to round-off.
    np.testing.assert_allclose(sc.result.fit.moments, fit.moments, rtol=1e-9)
    np.testing.assert_allclose(sc.result.fit.moments_sigma, fit.moments_sigma, rtol=1e-6)
    assert sc.result.fit.residual == pytest.approx(fit.residual, rel=1e-9)
    assert sc.result.windows == tuple((s.start, s.end) for s in flights)
    # And those are the model's moments (noise 0.02 rad/s: within 2e-3, as the bundled toss).
    np.testing.assert_allclose(fit.moments, MOMENTS, atol=2e-3)
    # The panel states them with their σ; the plot holds the samples and the fitted lines.
    for value, sigma in zip(fit.moments[:2], fit.moments_sigma[:2]):
        assert f"{value:.4f} ± {sigma:.4f}" in sc.ratios_readout.text
    times, *series = sc.plot.data
    seg = flights[0]
    n = seg.times.size
    np.testing.assert_array_equal(times[:n], seg.times)
    np.testing.assert_array_equal(np.array(series[:3]).T[:n], seg.omega)
    np.testing.assert_allclose(np.array(series[3:]).T[:n], fit.predict(seg.times, 0), rtol=0, atol=1e-9)
    assert sc.toss.options == (
        "all tosses together",
        *(f"toss {k + 1}: {a:.2f} to {b:.2f} s" for k, (a, b) in enumerate(sc.result.windows)),
    )
    assert "Raw Data.csv" in sc.note.content and "2 toss(es) found, 2 fitted" in sc.note.content


def test_choosing_one_toss_fits_it_alone(app, tmp_path):
    sc = open_scene(app, "phone_toss")
    content = _csv()
    assert sc.load_upload("Raw Data.csv", content)
    sc.toss.value = sc.toss.options[2]  # what the page's dropdown does: the worker fits the second toss
    assert sc.result.chosen == 1 and sc.result.fitted == (1,)
    _, fit = _physics_fit(tmp_path, content, chosen=1)
    np.testing.assert_allclose(sc.result.fit.moments, fit.moments, rtol=1e-9)
    np.testing.assert_allclose(sc.result.plot_times, fit.segments[0].times)
    sc.toss.value = "all tosses together"
    assert sc.result.chosen is None and sc.result.fitted == (0, 1)


def test_a_zip_as_phyphox_shares_it_is_read_with_its_device(app):
    sc = open_scene(app, "phone_toss")
    meta = b'"property","value"\n"deviceModel","iPhone14,5"\n'
    content = zip_bytes({"Toss/Raw Data.csv": _csv(), "Toss/meta/device.csv": meta})
    assert sc.load_upload("toss.zip", content)
    assert sc.result.device == "iPhone14,5" and "iPhone14,5" in sc.note.content


def _slow_recording() -> bytes:
    rec, _ = synthetic_recording(MOMENTS, [Toss(1.0, 0.9, (2.0, 0.1, 0.1))], noise=0.02, total=3.0)
    return recording_csv(rec.times, rec.omega)


def _clipped_recording() -> bytes:
    rec, _ = synthetic_recording(MOMENTS, [Toss(1.0, 0.9, (60.0, 0.5, 0.5))], noise=0.02, seed=3)
    return recording_csv(rec.times, rec.omega)


def _short_recording() -> bytes:
    rec, _ = synthetic_recording(MOMENTS, [Toss(1.0, 0.12, (18.0, 1.0, 0.6))], noise=0.02, total=3.0)
    return recording_csv(rec.times, rec.omega)


def _bomb() -> bytes:
    # 60 MB of one character packs to about 60 kB: a thousand times over.
    return zip_bytes({"Raw Data.csv": b"0" * (60 * 1024 * 1024)})


HEADER = '"Time (s)","Gyroscope x (rad/s)","Gyroscope y (rad/s)","Gyroscope z (rad/s)"\n'
BAD_FILES = [
    (
        "accelerometer.csv",
        b'"Time (s)","Acceleration x (m/s^2)","Acceleration y (m/s^2)","Acceleration z (m/s^2)"\n0,1,2,3\n',
        "not gyroscope data",
    ),
    ("nan.csv", (HEADER + "0,1,2,3\n0.01,nan,2,3\n").encode(), "NaN or infinity"),
    ("markup.csv", b'"<script>alert(1)</script>","<b>x</b>","y","z"\n0,1,2,3\n', "expected the time"),
    ("long.csv", b'"' + b"<img src=x>" * 20_000 + b'",x,y,z\n0,1,2,3\n', "not a gyroscope recording"),
    ("notes.txt", b"Time (s),x,y,z", "is not a recording this scene reads"),
    ("empty.csv", b"", "is empty"),
    ("binary.csv", bytes(range(256)) * 4, "not text"),
    ("huge.csv", b"0" * (MAX_BYTES + 1), "Record a shorter stretch"),
    ("bomb.zip", _bomb(), "times over"),
    ("many.zip", zip_bytes({f"f{i}.csv": b"x" for i in range(100)}), "holds 100 files"),
    ("broken.zip", b"PK\x03\x04 this is no zip at all", "not a zip archive"),
    ("no-raw-data.zip", zip_bytes({"notes.txt": b"hello"}), "holds no 'Raw Data.csv'"),
    ("slow.csv", _slow_recording(), "no toss found"),
    ("short.csv", _short_recording(), "no toss found"),
    ("clipped.csv", _clipped_recording(), "mostly clipped"),
]


@pytest.mark.parametrize("filename, content, reason", BAD_FILES, ids=[b[0] for b in BAD_FILES])
def test_a_bad_file_is_refused_with_its_reason_and_the_previous_fit_stays(app, filename, content, reason):
    sc = open_scene(app, "phone_toss")
    shown, refusals = sc.result, sc.upload_refusals
    assert not sc.load_upload(filename, content)
    assert sc.upload_refusals == refusals + 1 and sc.result is shown
    assert reason in sc.last_upload_message, sc.last_upload_message
    assert len(sc.last_upload_message) <= 600  # a quoted cell does not make the message long
    title, body = app.messages[-1]
    assert title.startswith("Recording refused") and reason in body
    for _ in range(3):
        assert app.frame(FRAME)  # the scene keeps running


def test_a_refusal_reaches_only_the_browser_that_sent_the_file(app, monkeypatch):
    sc = open_scene(app, "phone_toss")
    sender, other = _Client(1), _Client(2)
    monkeypatch.setattr(app.simulation.notices, "_clients", lambda: [sender, other])  # both watch it
    assert not sc.load_upload("nan.csv", (HEADER + "0,nan,2,3\n").encode(), client=sender)
    assert [n[0] for n in sender.notes] == ["Recording refused — the previous one stays"]
    assert other.notes == []
    app.simulation.notify("for everyone", "a notice without a client")  # the fake browsers do hear the class
    assert other.notes == [("for everyone", "a notice without a client")]


class _Client:
    def __init__(self, client_id: int) -> None:
        self.client_id = client_id
        self.notes: list[tuple[str, str]] = []

    def add_notification(self, title: str, body: str, **_kw) -> None:
        self.notes.append((title, body))


def test_the_upload_is_fitted_outside_the_lock_and_adopted_under_it(app, monkeypatch):
    sc = open_scene(app, "phone_toss")
    seen = {}

    real_fit = toss_module.toss_fit_in_worker

    def fit(filename, content, chosen=None):
        seen["free while fitting"] = lock_is_free(app.simulation.lock)
        return real_fit(filename, content, chosen)

    real_adopt = sc.adopt

    def adopt(result, content=None):
        seen["held while adopting"] = not lock_is_free(app.simulation.lock)
        real_adopt(result, content)

    monkeypatch.setattr(toss_module, "toss_fit_in_worker", fit)
    monkeypatch.setattr(sc, "adopt", adopt)
    sc.upload._impl.value = UploadedFile("Raw Data.csv", _csv())  # what viser stores when a file arrives
    for callback in sc.upload._impl.update_cb:  # the callback viser runs for the real upload button
        callback(SimpleNamespace(client=None, target=sc.upload))
    assert seen == {"free while fitting": True, "held while adopting": True}
    assert sc.result.source == "Raw Data.csv"


def test_a_fit_finished_after_the_user_left_is_dropped(app, monkeypatch):
    sc = open_scene(app, "phone_toss")
    real_fit = toss_module.toss_fit_in_worker

    def fit_while_someone_switches(filename, content, chosen=None):
        app.switch_scene("wobble")
        return real_fit(filename, content, chosen)

    monkeypatch.setattr(toss_module, "toss_fit_in_worker", fit_while_someone_switches)
    assert not sc.load_upload("Raw Data.csv", _csv())
    assert app.scene.name == "wobble"
    for _ in range(3):
        assert app.frame(FRAME)


def test_in_presenter_mode_a_follower_upload_is_refused_and_the_lecturer_shows_the_class(tmp_path):
    with running_app("phone_toss", presenter=True, pin="8642", start_loop=False) as lecture:
        sc = lecture.scene
        follower = SimpleNamespace(client_id=987654, add_notification=lambda *a, **k: None)
        reason = lecture.simulation.refusal(follower.client_id)
        assert reason  # a browser that has not entered the PIN follows
        sc.upload._impl.value = UploadedFile("Raw Data.csv", _csv())
        for callback in sc.upload._impl.update_cb:
            callback(SimpleNamespace(client=follower, target=sc.upload))
        assert sc.result.source.startswith("example toss") and reason in sc.last_upload_message
        # The lecturer's upload (no follower: the server's own call) is what every browser of the class sees.
        assert sc.load_upload("Raw Data.csv", _csv())
        assert lecture.scene.result.source == "Raw Data.csv"


def test_private_sessions_each_fit_their_own():
    with running_app("phone_toss", private=True, start_loop=False) as app, raw_client(app), raw_client(app):
        wait_for(lambda: len(app.sessions) == 2, what="two sessions")
        (_, a), (_, b) = sorted(app.sessions.items())
        assert a.scene is not b.scene
        assert a.scene.load_upload("mine.csv", _csv(), client=a.server)
        assert a.scene.result.source == "mine.csv"
        assert b.scene.result.source.startswith("example toss")  # the other student's session is untouched


def test_the_bundled_example_is_the_models_own_and_deterministic():
    assert example_csv() == example_csv()
    assert example_csv().startswith(b'"Time (s)","Gyroscope x (rad/s)"')


def test_the_description_and_export_columns_state_the_fit(app):
    sc = open_scene(app, "phone_toss")
    state = sc.compute(1.0, FRAME)
    text = sc.describe(state)
    assert "0.8 : 0.21 : 1" in text and "x axis" in text
    columns = sc.columns(state)
    assert all(name.endswith(")") for name in columns) and all(np.isfinite(list(columns.values())))
    # The replay at 0.2×: scene time 1 s is 0.2 s of flight.
    assert state["flight_time"] == pytest.approx(toss_module.SLOW * 1.0, abs=0.002)


def test_a_students_own_copy_shows_the_lecturers_recording_and_its_state_text_is_refused():
    with running_app("phone_toss", presenter=True, pin="8642") as app:
        assert app.scene.load_upload("Raw Data.csv", _csv())
        app.scene.toss.value = app.scene.toss.options[2]  # the lecturer shows the second toss alone
        shown = app.scene.result
        assert shown.chosen == 1
        before = set(app.server.get_clients())
        with raw_client(app) as student:
            (cid,) = wait_for(lambda: set(app.server.get_clients()) - before, what="the student")
            wait_for(lambda: cid in app.classroom._panels, what="the student's panel")
            click_button(student, app.classroom._panels[cid].explore._impl.uuid)
            wait_for(lambda: cid in app.sessions, what="the student's own copy")
            copy = app.sessions[cid]
            wait_for(lambda: copy.scene is not None and copy.scene.result is shown, what="the recording copied")
            assert copy.scene.toss.value == app.scene.toss.value and copy.scene.source_content == _csv()
            assert not [b for t, b in copy.messages if t.startswith(("Refused", "Recording refused"))], copy.messages
        with pytest.raises(ValueError, match="uploaded mesh or recording"):
            state_text(app.simulation.snapshot())


def test_the_bundled_tosses_state_text_opens_on_the_same_toss():
    with running_app("phone_toss", start_loop=False) as app:
        app.scene.toss.value = app.scene.toss.options[1]
        assert app.scene.result.chosen == 0
        text = app.state_text()
    with running_app(state=text, start_loop=False) as again:
        assert again.scene.name == "phone_toss" and again.scene.result.chosen == 0
        assert again.scene.result.source.startswith("example toss")


def test_adopting_a_fit_whose_tosses_differ_does_not_fit_again_when_viser_resets_the_dropdown(app, monkeypatch):
    sc = open_scene(app, "phone_toss")
    sc.toss.value = sc.toss.options[2]  # the bundled second toss, alone
    assert sc.result.chosen == 1
    fits = []
    monkeypatch.setattr(toss_module, "toss_fit_in_worker", lambda *args: fits.append(args))
    # A copy adopts another recording's second toss (prepare): the bundled "toss 2: …" is not among its
    # options, so viser puts the dropdown on its first option, and runs the callback, before adopt sets it.
    other = fit_toss_upload("Raw Data.csv", _csv(), 1)
    with app.simulation.lock:
        sc.adopt(other, _csv())
    assert fits == [] and sc.result is other and sc.toss.value == sc.toss.options[2]
