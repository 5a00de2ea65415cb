"""Exports in a real browser: the exported page plays from a static web server, the panel's button downloads.

A static server (``http.server`` on 127.0.0.1, no viser) serves the export directory; headless Chromium
opens ``index.html`` and must show the scene and move it (a later screenshot differs from the first, and
the player's clock advances). The panel's Export button in a live app must hand the browser a zip with the
page, the CSV and the PNG.
"""

from __future__ import annotations

import functools
import http.server
import io
import threading
import zipfile
from pathlib import Path

import numpy as np
import pytest
from PIL import Image

from app.serving.app import export
from app.serving.notices import NOTIFY_SECONDS
from tests.harness import click, click_until, free_port, image_difference, image_stats, open_page, running_app, wait_for

pytestmark = pytest.mark.browser

SCROLL_TO_EXPORT = """() => {
  const button = [...document.querySelectorAll("button")].find((b) => b.textContent.trim() === "Export");
  if (button) button.scrollIntoView({ block: "center" });
}"""


def _screenshot(page) -> np.ndarray:
    return np.array(Image.open(io.BytesIO(page.screenshot())))


def test_the_exported_page_plays_from_a_static_server(tmp_path: Path, chromium) -> None:
    export("heavy_top", tmp_path, 6.0, preset="waves (φ̇0 = ½ × steady)")
    handler = functools.partial(http.server.SimpleHTTPRequestHandler, directory=str(tmp_path))
    httpd = http.server.ThreadingHTTPServer(("127.0.0.1", free_port()), handler)
    threading.Thread(target=httpd.serve_forever, daemon=True).start()
    try:
        page = chromium.new_page(viewport={"width": 960, "height": 720})
        errors: list[str] = []
        page.on("pageerror", lambda exc: errors.append(str(exc)))
        page.goto(f"http://127.0.0.1:{httpd.server_address[1]}/index.html")
        page.wait_for_selector("canvas", timeout=30_000)
        clock = page.locator("input").first  # the player's time box (s)
        wait_for(lambda: float(clock.input_value() or 0) > 0.5, 30, what="the recording to play")
        before, shown = float(clock.input_value()), _screenshot(page)
        assert image_stats(shown) > 10.0  # not a blank page: the top, the grid, the trace
        # Its clock runs (it loops after 6 s) and the picture moves: watched until both, not for a fixed second.
        wait_for(
            lambda: float(clock.input_value() or before) != before and image_difference(shown, _screenshot(page)) > 0.2,
            30,
            what="the exported page's clock to run and its picture to move",
        )
        assert errors == []
        page.close()
    finally:
        httpd.shutdown()


def test_the_panel_export_button_downloads_a_zip(chromium) -> None:
    with running_app("pendulum") as app:
        page, _ = open_page(chromium, app)
        click(page.get_by_text("Export a recording").first)
        folder = app.simulation.export_folder
        # The opened folder's button sits at the panel's bottom edge, half clipped by the panel's scroll:
        # scrolled to the middle first (one evaluation in the page), or a click at its centre hits the edge.
        page.evaluate(SCROLL_TO_EXPORT)
        with page.expect_download(timeout=60_000) as download:
            # Not the folder "Export a recording"; a click lost to a panel that re-laid itself out is pressed
            # again, as a user would, until the server has started the export.
            click_until(
                page.get_by_role("button", name="Export", exact=True),
                lambda: folder.running is not None,
                what="the export to start",
            )
        # The note says so with the download; it closes by itself after NOTIFY_SECONDS, so it is looked for
        # before the archive is read: on a loaded machine, waiting for the saved file can outlast it.
        exported = page.get_by_text("Exported").first
        exported.wait_for(timeout=30_000)
        path = download.value.path()
        archive = zipfile.ZipFile(path)
        assert sorted(archive.namelist()) == ["index.html", "pendulum.csv", "pendulum.png"]
        rows = archive.read("pendulum.csv").decode().splitlines()
        assert rows[0] == "t (s),theta (rad),theta_dot (rad/s),E (J)" and len(rows) == 302  # 10 s at 30 fps
        # It closes by itself, as every notification does (it stayed until clicked).
        exported.wait_for(state="hidden", timeout=(NOTIFY_SECONDS + 15.0) * 1000)
        page.close()
