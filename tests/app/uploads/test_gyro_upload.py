"""An uploaded gyroscope recording: the checks before the worker (size, a zip's declared contents), the read
and fit in the worker (CSV, phyphox's zip, one toss or all), and refusals that stay short and clear."""

from __future__ import annotations

import zipfile

import numpy as np
import pytest

import app.uploads.gyro as gyro
from app.uploads import limits
from app.uploads.gyro import MAX_FITTED, fit_recording, fit_toss_upload, recording_csv
from app.uploads.worker import toss_fit_in_worker
from physics.gyro import Toss, fit_free_body, free_flights, read_gyroscope, synthetic_recording
from tests.uploading import zip_bytes

MOMENTS = (0.8, 0.21, 1.0)


@pytest.fixture(scope="module")
def recording():
    rec, windows = synthetic_recording(
        MOMENTS, [Toss(1.0, 0.9, (18.0, 1.0, 0.6)), Toss(3.0, 0.8, (-21.0, 0.7, -0.6))], drag=(0.1, 0.02, 0.05)
    )
    return rec, windows


def test_a_csv_and_a_zip_in_a_folder_give_physics_own_fit(recording, tmp_path):
    rec, windows = recording
    content = recording_csv(rec.times, rec.omega)
    (tmp_path / "Raw Data.csv").write_bytes(content)
    flights = free_flights(read_gyroscope(tmp_path / "Raw Data.csv"))
    fit = fit_free_body(flights)
    np.testing.assert_allclose(fit.moments, MOMENTS, atol=2e-3)  # the model's own, to the noise's bias
    for name, data in (("Raw Data.csv", content), ("shared.zip", zip_bytes({"Toss 1/Raw Data.csv": content}))):
        result = fit_toss_upload(name, data)
        # The same samples through the same functions: the same numbers, to round-off.
        np.testing.assert_allclose(result.fit.moments, fit.moments, rtol=1e-12)
        assert result.windows == tuple((s.start, s.end) for s in flights)
        assert result.source == name and result.chosen is None and result.fitted == (0, 1)
    # The windows found lie within 50 ms of the true release and catch.
    for (start, end), (release, catch) in zip(result.windows, windows):
        assert abs(start - release) < 0.05 and abs(end - catch) < 0.05


def test_one_toss_is_fitted_alone_and_a_toss_that_is_not_there_is_refused(recording):
    rec, _ = recording
    content = recording_csv(rec.times, rec.omega)
    one = fit_toss_upload("r.csv", content, 1)
    assert one.fitted == (1,) and one.chosen == 1 and len(one.fit.segments) == 1
    with pytest.raises(ValueError, match="r.csv has 2 toss"):
        fit_toss_upload("r.csv", content, 2)


def test_the_replay_keeps_l_fixed_without_drag_and_turns_the_phone_as_omega_says():
    rec, _ = synthetic_recording(MOMENTS, [Toss(1.0, 0.9, (18.0, 1.0, 0.6))], noise=0.0)
    result = fit_recording("clean", rec.times, rec.omega)
    # The fit found no drag worth a coefficient? Either way L in space moves only as the drag turns it:
    # without drag (fitted on a noiseless drag-free toss) it stays on +z to the replay's second-order steps.
    assert np.max(result.fit.drag) < 1e-3
    l_hat = result.l_space / np.linalg.norm(result.l_space, axis=1, keepdims=True)
    # exp(ω dt) at the middle of 0.5 ms steps: the error grows as dt² |ω|² |ω̇| t ≈ 1e-5 over the toss.
    assert np.max(np.linalg.norm(l_hat - [0.0, 0.0, 1.0], axis=1)) < 1e-4
    # Each attitude is a rotation.
    gram = np.einsum("kji,kjl->kil", result.attitudes, result.attitudes)
    np.testing.assert_allclose(gram, np.broadcast_to(np.eye(3), gram.shape), atol=1e-12)


def test_all_tosses_fits_at_most_max_fitted_and_says_which_were_left_out(monkeypatch):
    tosses = [Toss(1.0 + 1.5 * k, 0.6, (18.0, 1.0, 0.6)) for k in range(MAX_FITTED + 2)]
    rec, _ = synthetic_recording(MOMENTS, tosses, noise=0.02)
    flights = free_flights(rec)
    assert len(flights) == MAX_FITTED + 2
    # Fitting thirty tosses takes seconds: the fit itself is replaced by a stand-in that only counts.
    seen = {}

    def counted(segments):
        seen["n"] = len(segments)
        return fit_free_body(segments[:1])

    monkeypatch.setattr(gyro, "fit_free_body", counted)
    result = fit_recording("many", rec.times, rec.omega)
    assert seen["n"] == MAX_FITTED and len(result.fitted) == MAX_FITTED
    assert result.left_out == (f"toss {MAX_FITTED + 1} and later: at most {MAX_FITTED} tosses are fitted together",)


def test_a_zip_bomb_and_a_crowded_zip_are_refused_before_a_worker_reads_them():
    bomb = zip_bytes({"Raw Data.csv": b"0" * (8 * 1024 * 1024)})
    assert len(bomb) < 64 * 1024  # packed about 1000 times over
    with pytest.raises(ValueError, match=r"times over \(a recording packs at most 100 times\)"):
        limits.check_upload("bomb.zip", bomb)
    with pytest.raises(ValueError, match="holds 65 files"):
        limits.check_upload("crowd.zip", zip_bytes({f"{i}.csv": b"" for i in range(65)}))
    stored = zip_bytes({"Raw Data.csv": b"1" * 100, "b": b""}, zipfile.ZIP_STORED)
    limits.check_upload("ok.zip", stored)  # a small honest zip passes
    with pytest.raises(ValueError, match="not a zip archive"):
        limits.check_upload("fake.zip", b"PK\x03\x04" + b"\0" * 100)


def test_a_zip_that_declares_more_than_the_limit_unpacked_is_refused(monkeypatch):
    monkeypatch.setattr(limits, "MAX_UNPACKED", 1000)
    with pytest.raises(ValueError, match="unpacks to 2 kB; the limit is 1 kB"):
        limits.check_upload("big.zip", zip_bytes({"Raw Data.csv": bytes(range(256)) * 8}, zipfile.ZIP_STORED))


def test_the_size_refusal_advises_for_what_the_file_is():
    assert "Record a shorter stretch" in limits.size_refusal("toss.csv", limits.MAX_BYTES + 1)
    assert "Record a shorter stretch" in limits.size_refusal("toss.zip", limits.MAX_BYTES + 1)
    assert "Simplify the mesh" in limits.size_refusal("body.stl", limits.MAX_BYTES + 1)


def test_a_refusal_from_the_worker_is_short_whatever_the_file_quotes():
    cell = "<b>" + "x" * 100_000 + "</b>"
    content = f'"{cell}","a (rad/s)","b (rad/s)","c (rad/s)"\n0,1,2,3\n'.encode()
    with pytest.raises(ValueError) as refused:
        toss_fit_in_worker("quoted.csv", content)
    message = str(refused.value)
    assert len(message) <= limits.MAX_MESSAGE and message.startswith("quoted.csv is not a gyroscope recording")


def test_the_worker_is_stopped_by_its_time_and_memory_limits(recording):
    rec, _ = recording
    content = recording_csv(rec.times, rec.omega)
    with pytest.raises(ValueError, match="took more than 0 s to read"):
        toss_fit_in_worker("slow.csv", content, time_limit=0.001)
    with pytest.raises(ValueError, match="needs more than"):
        toss_fit_in_worker("big.csv", content, memory_limit=64 * 1024 * 1024)
