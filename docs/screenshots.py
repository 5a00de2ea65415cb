"""Take a screenshot of every scene in headless Chromium: ``python docs/screenshots.py [--out DIR]``.

Starts the app on a free port, opens it in Debian's Chromium (the browser tests' helpers in
``tests/harness.py``), lets each scene run a few seconds at its defaults and saves ``<scene>.png``.
The curated screenshots in ``docs/`` (presets, body view, refused upload) were taken the same way.
"""

from __future__ import annotations

import argparse
import sys
import time
from pathlib import Path

ROOT = Path(__file__).resolve().parent.parent
sys.path.insert(0, str(ROOT))

from app.scenes import scene_names  # noqa: E402
from tests.harness import launch_chromium, open_page, running_app  # noqa: E402

_CLOSE_NOTIFICATIONS = "() => document.querySelectorAll('.mantine-Notification-closeButton').forEach(b => b.click())"


def main(argv: list[str] | None = None) -> None:
    parser = argparse.ArgumentParser(description=__doc__.splitlines()[0])
    parser.add_argument("--out", type=Path, default=ROOT / "docs" / "scenes")
    parser.add_argument("--seconds", type=float, default=5.0, help="run time before each shot (s)")
    args = parser.parse_args(argv)
    args.out.mkdir(parents=True, exist_ok=True)
    with running_app() as app, launch_chromium() as browser:
        page, _client = open_page(browser, app)
        for name in scene_names():
            app.switch_scene(name)
            app.set_playing(True)
            time.sleep(args.seconds)
            page.evaluate(_CLOSE_NOTIFICATIONS)  # the "Software WebGL" banner of SwiftShader
            time.sleep(0.5)
            path = args.out / f"{name}.png"
            page.screenshot(path=str(path))
            print(f"{name}: {path}", flush=True)


if __name__ == "__main__":
    main()
