"""The phone-toss scene in Debian's headless Chromium: a recording made by the project's own model goes through
the page's upload button; the page's plot then holds its samples as points and the fitted model as lines (viser's
uPlot test points give the chart's data and series in the page), and the panel states the fitted ratios. A bad
file is refused with a notification in that page. One server and one browser serve the module, in file order.
"""

from __future__ import annotations

import numpy as np
import pytest

from app.scenes.phone_toss import ratios_text
from app.uploads.gyro import recording_csv
from physics.gyro import Toss, synthetic_recording
from tests.harness import open_page, running_app, wait_for
from tests.uploading import upload

pytestmark = pytest.mark.browser

TITLE = "ω in the phone's axes"

CHART = """(title) => {
  const v = Object.values((window.__viserTestpoints || {}).uplots || {}).find(v =>
    v.chart.root.querySelector('.u-title') && v.chart.root.querySelector('.u-title').textContent.startsWith(title));
  if (!v) return null;
  return {
    data: v.chart.data.map(column => Array.from(column, x => (x === null || Number.isNaN(x)) ? null : x)),
    // uPlot keeps each series' points.show as a function of (chart, series index): what it draws now.
    series: v.chart.series.slice(1).map((s, i) => ({label: s.label, width: s.width, points: s.points.show(v.chart, i + 1) === true})),
  };
}"""


@pytest.fixture(scope="module")
def toss_app():
    with running_app("phone_toss") as app:
        yield app


@pytest.fixture(scope="module")
def page(toss_app, chromium):
    page, _ = open_page(chromium, toss_app)
    yield page
    page.close()


def _recording() -> bytes:
    rec, _ = synthetic_recording(
        (0.78, 0.23, 1.0), [Toss(1.0, 0.9, (19.0, 0.8, -0.6))], drag=(0.08, 0.02, 0.05), seed=5
    )
    return recording_csv(rec.times, rec.omega)


def test_an_uploaded_recording_shows_points_lines_and_ratios(toss_app, page):
    page.get_by_text("Upload a phyphox recording (CSV, ZIP)").first.wait_for(timeout=60_000)
    upload(page, "Raw Data.csv", _recording())
    wait_for(lambda: toss_app.scene.result.source == "Raw Data.csv", 120, what="the recording to be fitted")
    result = toss_app.scene.result
    expected = [result.plot_times, *result.measured.T, *result.model.T]

    def shown():
        chart = page.evaluate(CHART, TITLE)
        return chart if chart and len(chart["data"][0]) == result.plot_times.size else None

    chart = wait_for(shown, 90, what="the page's plot to hold the upload's samples")
    # Three series of points (the samples: no line) and three of lines (the model: no points).
    series = chart["series"]
    assert [s["label"] for s in series] == [f"ω_{a} measured" for a in "xyz"] + [f"ω_{a} fitted" for a in "xyz"]
    assert all(s["points"] and s["width"] == 0 for s in series[:3])
    assert all(not s["points"] and s["width"] == 2 for s in series[3:])
    # The data the page draws are the server's: the samples, and the model at their times.
    for column, values in zip(chart["data"], expected, strict=True):
        np.testing.assert_allclose(np.array(column, dtype=float), values, rtol=1e-12)
    # The measured points and the model's lines differ by the noise only (0.02 rad/s rms).
    assert float(np.sqrt(np.mean((result.measured - result.model) ** 2))) < 0.05
    # The panel states the fitted ratios with their σ.
    page.get_by_text(ratios_text(result)).first.wait_for(timeout=60_000)
    page.get_by_text("Recording fitted").first.wait_for(timeout=60_000)


def test_a_file_that_is_not_gyroscope_data_is_refused_in_the_page(toss_app, page):
    scene = toss_app.scene
    refusals = scene.upload_refusals
    upload(page, "accelerometer.csv", b'"Time (s)","Acceleration x (m/s^2)","y (m/s^2)","z (m/s^2)"\n0,1,2,3\n')
    wait_for(lambda: scene.upload_refusals == refusals + 1, 120, what="the refusal")
    page.get_by_text("Recording refused").first.wait_for(timeout=60_000)
    page.get_by_text("not gyroscope data").first.wait_for(timeout=60_000)
    assert scene.result.source == "Raw Data.csv"  # the previous recording stays


def test_a_refusal_shows_only_in_the_page_that_sent_the_file(toss_app, page, chromium):
    other, _ = open_page(chromium, toss_app)
    try:
        other.get_by_text("Upload a phyphox recording (CSV, ZIP)").first.wait_for(timeout=60_000)
        scene = toss_app.scene
        refusals = scene.upload_refusals
        upload(page, "nan.csv", b'"Time (s)","x (rad/s)","y (rad/s)","z (rad/s)"\n0,1,2,3\n0.01,nan,2,3\n')
        wait_for(lambda: scene.upload_refusals == refusals + 1, 120, what="the refusal")
        page.get_by_text("NaN or infinity").first.wait_for(timeout=60_000)
        # A notice to every page, sent after the refusal: once the other page shows it, it has taken every
        # message sent to it before, and the refusal was not among them.
        toss_app.simulation.notify("Everyone", "a notice for the whole class")
        other.get_by_text("a notice for the whole class").first.wait_for(timeout=60_000)
        assert other.get_by_text("NaN or infinity").count() == 0
        assert other.get_by_text("Recording refused").count() == 0
    finally:
        other.close()
