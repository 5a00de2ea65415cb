"""The clock in a real browser: at 1× the free fall's time readout advances one second per wall second
(the free fall "runs about a second too fast"; each throw lasts its real flight time, 1.02 s)."""

from __future__ import annotations

import time

import numpy as np
import pytest

from app.serving.clock import MAX_FRAME_DT
from tests.harness import open_page, running_app, wait_for

pytestmark = pytest.mark.browser

READOUT = """(text) => { for (const el of document.querySelectorAll('label[for]')) {
        if (el.textContent.trim() !== text) continue;
        const input = el.closest('.mantine-Flex-root').querySelector('input');
        return input ? input.value : null; }
    return null; }"""


RECORD = """(text) => {
    // Every change of the readout, timed by the page's own clock: [last look without it, first look with it,
    // value] in ms. Looking every 5 ms in the page keeps a loaded machine's round trips to the page out of the
    // timing.
    const shown = READOUT;
    const read = () => { const v = shown(text); return v === null ? null : parseFloat(v); };
    window.rblReadout = [];
    let last = read(), before = performance.now();
    setInterval(() => {
      const now = performance.now(), value = read();
      if (value !== last && value !== null && !Number.isNaN(value)) window.rblReadout.push([before, now, value]);
      last = value; before = now;
    }, 5);
}""".replace("READOUT", READOUT)


def _time_shown(page) -> float | None:
    text = page.evaluate(READOUT, "Time (s)")
    try:
        return float(text)
    except (TypeError, ValueError):
        return None


def test_the_free_fall_clock_runs_at_one_second_per_second(chromium) -> None:
    with running_app("free_fall") as app:
        page, _ = open_page(chromium, app, viewport={"width": 1280, "height": 800})
        wait_for(lambda: (_time_shown(page) or 0.0) > 1.0, 30, what="the clock to run in the page")
        page.evaluate(RECORD, "Time (s)")
        first = _time_shown(page) or 0.0
        clock = app.shared.clock
        start, dropped, simulated = time.monotonic(), clock.dropped, clock.t
        wait_for(lambda: (_time_shown(page) or 0.0) >= first + 5.5, 30, interval=0.005, what="5.5 s more")
        elapsed = time.monotonic() - start
        stalled, advanced, shown = clock.dropped - dropped, clock.t - simulated, _time_shown(page)
        # Timed by the readout itself, in the page: the rate of its changes over the 5.5 s, a line fitted through
        # each change's value at the middle of the 5 ms look that saw it. The page looks late when its main thread
        # is busy (here up to 0.2 s); a fit through ~28 changes leaves about a tenth of that in the rate.
        changes = np.array(page.evaluate("() => window.rblReadout"))
        assert len(changes) >= 10, changes
        rate = np.polyfit((changes[:, 0] + changes[:, 1]) / 2000.0, changes[:, 2], 1)[0]
        # Never fast: 1.04 would be a clock 4 % fast (the bug was a second fast over a throw of 1 s, 100 %).
        assert rate <= 1.04, (rate, changes)
        # Never slow: over the same wall seconds the simulation advanced by all of them but what a loaded machine
        # dropped (a frame that stalls longer than MAX_FRAME_DT advances by that much, by design, and the clock
        # counts the rest), to the frame in progress at either end (at most MAX_FRAME_DT each): 0.2 s in 5 s, a
        # clock 4 % slow.
        assert abs(advanced - (elapsed - stalled)) <= 2 * MAX_FRAME_DT, (advanced, elapsed, stalled)
        # And the page shows that clock: its readout is the simulation's time, behind it only by what the page
        # has not drawn yet (on a loaded machine a few frames; a clock of its own would drift off by seconds).
        # The clock is read just before and just after the page (a busy page answers in up to a second or so,
        # and the clock read after a slow answer had run on by that long: CI saw 1.16 s).
        before = clock.t
        shown = _time_shown(page)
        after = clock.t
        assert shown is not None and shown <= after and before - shown <= 1.0, (before, shown, after)
        page.close()
