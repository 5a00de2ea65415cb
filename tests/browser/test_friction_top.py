"""The friction top in the page: chosen from the page's preset dropdown, it spins down, falls
and lies on the table; its lowest point is never below the table in any frame the page is sent."""

from __future__ import annotations

import time

import numpy as np
import pytest

from app.scenes.heavy_top import TOP_MESH, TOUCH
from tests.harness import click, control_id, open_page, running_app, wait_for

pytestmark = pytest.mark.browser

FRICTION = "sleeping top with friction: falls"


def test_the_friction_top_lies_on_the_table_and_never_below_it(chromium) -> None:
    with running_app("heavy_top") as app:
        page, _ = open_page(chromium, app, viewport={"width": 1024, "height": 768})
        click(page.locator(f"[id='{control_id(page, 'Preset')}']"))
        click(page.get_by_role("option", name=FRICTION, exact=True))
        wait_for(lambda: app.scene.presets.last == FRICTION, 30, what="the preset from the page")
        app.set_speed(10.0)
        lowest = []
        deadline = time.monotonic() + 60.0
        while not app.scene.landed and time.monotonic() < deadline:
            with app.simulation.lock:
                R = app.scene.R.copy()
            lowest.append(float(np.min(TOP_MESH.vertices @ R.T[:, 2])))  # what the last frame drew (m)
            time.sleep(0.02)
        assert app.scene.landed, "the top never came down"
        with app.simulation.lock:
            R = app.scene.R.copy()
        lowest.append(float(np.min(TOP_MESH.vertices @ R.T[:, 2])))
        assert min(lowest) >= -1e-12 and lowest[-1] == pytest.approx(0.0, abs=1e-12)
        assert np.degrees(np.arccos(R[2, 2])) == pytest.approx(np.degrees(TOUCH), abs=1e-9)
        shown = "() => [...document.querySelectorAll('input')].some(i => i.value.includes('lying on the table'))"
        wait_for(lambda: page.evaluate(shown), 20, what="the readout in the page")
        page.close()
