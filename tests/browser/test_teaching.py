"""The teaching controls in a real browser: the integrator ghost chosen in the page appears beside the
exact body and its error plot fills.
"""

from __future__ import annotations

import pytest

from app.scenes.tennis_racket import TennisRacket
from tests.harness import click, control_id, open_page, pick_scene, running_app, wait_for

pytestmark = pytest.mark.browser

SPLIT = "Lie–Poisson splitting (order 2)"


def test_the_integrator_ghost_from_the_page(chromium) -> None:
    with running_app("heavy_top") as app:
        page, _ = open_page(chromium, app, viewport={"width": 1400, "height": 760})
        pick_scene(page, TennisRacket.title)
        wait_for(lambda: app.scene is not None and app.scene.name == "tennis_racket", 30, what="the racket scene")
        click(page.locator(f"[id='{control_id(page, 'Compare with integrator')}']"))
        click(page.get_by_role("option", name=SPLIT, exact=True))
        ghost = app.scene.ghost
        wait_for(lambda: ghost.method is not None and ghost.steps > 20, 30, what="the ghost to run")
        assert ghost.body.handle.visible and ghost.plot.handle.visible
        page.get_by_text("Ghost − exact").first.wait_for(timeout=30_000)  # the error plot is in the panel
        assert len(ghost.plot.times) >= 2 and ghost.plot.latest()["angle"] > -17.0
        page.close()
