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
        # The heavy top has a "Compare with integrator" too: look it up once the page has drawn the racket's own
        # controls (the server removes a scene's panel before it adds the next one's).
        control_id(page, "Spin about principal axis")
        click(page.locator(f"[id='{control_id(page, 'Compare with integrator')}']"))
        click(page.get_by_role("option", name=SPLIT, exact=True))
        ghost = app.scene.ghost
        wait_for(lambda: ghost.method is not None and ghost.steps > 20, 30, what="the ghost to run")
        assert ghost.body.handle.visible and ghost.plot.handle.visible
        page.get_by_text("Ghost − exact").first.wait_for(timeout=30_000)  # the error plot is in the panel
        assert len(ghost.plot.times) >= 2 and ghost.plot.latest()["angle"] > -17.0
        page.close()


def test_a_lecture_steps_forward_and_back_from_the_page(chromium) -> None:
    """rigid-body-lab --lecture rigid-body-motion: the page shows "step k of n" and the step's caption;
    Next and Previous in the page change the step, its scene and its text."""
    with running_app(lecture="rigid-body-motion") as app:
        steps = app.simulation.lecture.steps
        page, _ = open_page(chromium, app, viewport={"width": 1280, "height": 800})
        total = len(steps)
        page.get_by_text(f"step 1 of {total}").first.wait_for(timeout=30_000)
        assert app.simulation.step_index == 0 and app.scene.name == steps[0].scene
        click(page.get_by_role("button", name="Next"))
        wait_for(lambda: app.simulation.step_index == 1, 30, what="the second step")
        page.get_by_text(f"step 2 of {total}").first.wait_for(timeout=30_000)
        assert app.scene.name == steps[1].scene
        words = steps[1].caption.split("**")[1]  # the step's bold title, as the page renders it
        page.get_by_text(words).first.wait_for(timeout=30_000)
        for target in (2, 3):  # each click once the page shows the step before (the buttons sit under its text)
            click(page.get_by_role("button", name="Next"))
            wait_for(lambda t=target: app.simulation.step_index == t, 30, what=f"step {target + 1}")
            page.get_by_text(f"step {target + 1} of {total}").first.wait_for(timeout=30_000)
        assert app.scene.name == steps[3].scene
        click(page.get_by_role("button", name="Previous"))
        wait_for(lambda: app.simulation.step_index == 2, 30, what="the step before")
        page.get_by_text(f"step 3 of {total}").first.wait_for(timeout=30_000)
        assert app.scene.name == steps[2].scene
        page.close()
