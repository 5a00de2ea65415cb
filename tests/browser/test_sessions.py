"""Private sessions in real browsers: two pages of one ``--private`` server run two different scenes."""

from __future__ import annotations

import pytest

from app.scenes import REGISTRY
from tests.harness import open_page, pick_scene, running_app, wait_for

pytestmark = pytest.mark.browser


def test_two_browsers_of_a_private_server_run_two_scenes(chromium):
    with running_app("heavy_top", private=True) as app:
        small = {"width": 640, "height": 480}  # two pages rendering on the CPU (SwiftShader): keep them small
        first, first_client = open_page(chromium, app, viewport=small)
        # Paused, a page re-renders only on changes: the other page and the clicks get the CPU.
        app.sessions[first_client.client_id].set_playing(False)
        second, second_client = open_page(chromium, app, viewport=small)
        try:
            wait_for(lambda: len(app.sessions) == 2, what="one session per page")
            mine = app.sessions[first_client.client_id]
            theirs = app.sessions[second_client.client_id]
            theirs.set_playing(False)
            pick_scene(first, REGISTRY["wobble"].title)
            wait_for(lambda: getattr(mine.scene, "name", None) == "wobble", what="the first page's session to switch")
            first.get_by_text(REGISTRY["wobble"].caption.split("**")[1]).first.wait_for(timeout=30_000)
            assert theirs.scene is not None and theirs.scene.name == "heavy_top"
            theirs.set_playing(True)
            frames = theirs.frames
            wait_for(lambda: theirs.frames > frames + 10, what="the second page's heavy top to go on")
        finally:
            first.close()
            second.close()
        wait_for(lambda: not app.sessions, what="both sessions to be freed")
