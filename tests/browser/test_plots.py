"""Plots keep their data and their axes in the page after Reset, a preset, a slider change and a scene
switch (viser's uPlot test points give each chart's scales in the page)."""

from __future__ import annotations

import math

import pytest

from tests.harness import click, open_page, pick_scene, running_app, wait_for

pytestmark = pytest.mark.browser

CHARTS = """() => Object.values((window.__viserTestpoints || {}).uplots || {}).map(v => ({
    title: v.chart.root.querySelector('.u-title') ? v.chart.root.querySelector('.u-title').textContent : '',
    x: [v.chart.scales.x.min, v.chart.scales.x.max],
    points: v.chart.data.length > 1 ? v.chart.data[1].length : 0,
}))"""


def _chart(page, title: str) -> dict | None:
    return next((c for c in page.evaluate(CHARTS) if c["title"].startswith(title)), None)


def _drawn(page, title: str) -> bool:
    chart = _chart(page, title)
    return bool(
        chart
        and chart["points"] > 1
        and all(v is not None and math.isfinite(v) for v in chart["x"])
        and chart["x"][1] > chart["x"][0]
    )


SERIES = """(title) => { const v = Object.values((window.__viserTestpoints || {}).uplots || {}).find(v =>
    v.chart.root.querySelector('.u-title') && v.chart.root.querySelector('.u-title').textContent.startsWith(title));
    return v ? JSON.stringify(v.chart.data.slice(1)) : null; }"""


def _changed_and_still_drawn(page, title: str, change, updates: int = 3) -> None:
    """Make a change, then wait until the page has taken ``updates`` new versions of the plot's data (its
    "now" point moves with θ at every refresh, so each refresh differs); the chart must be drawn after them.
    The refreshes come after the change on the one websocket, so whatever the change sent (new scales, new
    data) has reached the page by then: a plot that went blank fails, with no fixed sleep."""
    change()
    seen = [page.evaluate(SERIES, title)]

    def refreshed() -> bool:
        now = page.evaluate(SERIES, title)
        if now != seen[-1]:
            seen.append(now)
        return len(seen) > updates

    wait_for(refreshed, 30, what=f"{updates} refreshes of {title!r}")
    assert _drawn(page, title), _chart(page, title)


def test_the_effective_potential_survives_reset_preset_and_sliders(chromium) -> None:
    with running_app("heavy_top") as app:
        page, _ = open_page(chromium, app, viewport={"width": 1280, "height": 800})
        title = "Effective potential"
        wait_for(lambda: _drawn(page, title), 30, what="the U(θ) plot")
        _changed_and_still_drawn(page, title, lambda: click(page.get_by_role("button", name="Reset")))

        def under_lock(change):
            def run() -> None:
                with app.simulation.lock:
                    assert change()

            return run

        preset = "loops (φ̇0 = −1 × steady)"
        _changed_and_still_drawn(page, title, under_lock(lambda: app.scene.presets.choose(preset)))
        _changed_and_still_drawn(page, title, under_lock(lambda: app.scene.params.offer({"mgl": 2.0})))
        pick_scene(page, "Torque-free wobble")
        wait_for(lambda: getattr(app.scene, "name", None) == "wobble", 30, what="the wobble")
        wait_for(lambda: _drawn(page, "Invariants"), 30, what="the wobble's drift plot")
        pick_scene(page, "Heavy top")
        wait_for(lambda: _drawn(page, title), 30, what="the U(θ) plot back")
        page.close()


WATCH = """(title) => {
  // Counts, in the page, every time the plot's data restarts (fewer points, or an earlier newest time than
  // the look 5 ms before): a loaded page may take longer to show the restart than the old data had run.
  const find = () => Object.values((window.__viserTestpoints || {}).uplots || {}).find(v =>
    v.chart.root.querySelector('.u-title') && v.chart.root.querySelector('.u-title').textContent.startsWith(title));
  window.rblRestarts = window.rblRestarts || {};
  window.rblWatch = window.rblWatch || {};
  clearInterval(window.rblWatch[title]);
  window.rblRestarts[title] = 0;
  // The plot as it is now, before the change is made: a loaded page may run the first interval only after
  // the restarted data has come, which would then be the baseline and the restart never seen.
  const now = find();
  let last = now && now.chart.data[0] ? [now.chart.data[0].length, now.chart.data[0].length ? now.chart.data[0][now.chart.data[0].length - 1] : null] : null;
  window.rblWatch[title] = setInterval(() => {
    const v = find();
    if (!v || !v.chart.data[0]) return;
    const x = v.chart.data[0], n = x.length, newest = n ? x[n - 1] : null;
    if (last && (n < last[0] || (newest !== null && last[1] !== null && newest < last[1]))) window.rblRestarts[title]++;
    last = [n, newest];
  }, 5);
}"""


def _restarted_and_drawn(page, title: str, change) -> None:
    """Make a change that restarts a plot's data; wait until the page shows it restarted (fewer points or an
    earlier newest time than just before, watched in the page) and then drawn again: data and a finite x
    scale. A plot that went blank (viser's client dropping its auto x scale) fails one wait or the other."""
    wait_for(lambda: (c := _chart(page, title)) and c["points"] >= 8, 30, what=f"{title!r} to fill")
    page.evaluate(WATCH, title)
    change()
    # Long waits: the page's main thread is busy drawing in software (see tests.harness.open_page).
    wait_for(lambda: page.evaluate("(t) => window.rblRestarts[t]", title) > 0, 90, what=f"{title!r} to restart")
    wait_for(lambda: _drawn(page, title), 90, what=f"{title!r} drawn again")


def test_the_racket_and_drift_plots_survive_reset_choices_presets_and_sliders(chromium) -> None:
    omega, drift = "ω in body axes", "Invariants"
    with running_app("tennis_racket") as app:
        page, _ = open_page(chromium, app, viewport={"width": 1280, "height": 800})
        for title in (omega, drift):
            wait_for(lambda title=title: _drawn(page, title), 30, what=f"the {title!r} plot")

        def locked(action):
            def run() -> None:
                with app.simulation.lock:
                    assert action() is not False

            return run

        for title in (omega, drift):
            _restarted_and_drawn(page, title, lambda: click(page.get_by_role("button", name="Reset")))
            _restarted_and_drawn(page, title, locked(lambda: app.scene.params.offer({"spin": 8.0})))
            # The racket's presets are its dropdowns: the axis it spins about, the body.
            axis = "1 — largest moment" if app.scene.axis.value != "1 — largest moment" else "3 — smallest moment"
            _restarted_and_drawn(page, title, locked(lambda axis=axis: setattr(app.scene.axis, "value", axis)))
        # A preset proper: the wobble's drift plot.
        pick_scene(page, "Torque-free wobble")
        wait_for(lambda: getattr(app.scene, "name", None) == "wobble", 30, what="the wobble")
        wait_for(lambda: _drawn(page, drift), 30, what="the wobble's drift plot")
        _restarted_and_drawn(page, drift, locked(lambda: app.scene.presets.choose("disc (oblate)")))
        _restarted_and_drawn(page, drift, locked(lambda: app.scene.presets.choose("rod-like (prolate)")))
        page.close()
