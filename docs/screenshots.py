"""Take a screenshot of every scene in headless Chromium: ``python docs/screenshots.py [--out DIR]``.

Starts the app on a free port, opens it in Debian's Chromium (the browser tests' helpers in
``tests/harness.py``), lets each scene run a few seconds at its defaults and saves ``<scene>.png``.
The curated screenshots in ``docs/`` (presets, body view, refused upload) were taken the same way.
"""

from __future__ import annotations

import argparse
import io
import sys
import time
import zipfile
from pathlib import Path

ROOT = Path(__file__).resolve().parent.parent
sys.path.insert(0, str(ROOT))

from app.scenes import scene_names  # noqa: E402
from tests.harness import DEVICES, launch_chromium, open_page, paced_context, running_app, wait_for  # noqa: E402

_CLOSE_NOTIFICATIONS = "() => document.querySelectorAll('.mantine-Notification-closeButton').forEach(b => b.click())"


def main(argv: list[str] | None = None) -> None:
    parser = argparse.ArgumentParser(description=__doc__.splitlines()[0])
    parser.add_argument("--out", type=Path, default=ROOT / "docs" / "scenes")
    parser.add_argument("--seconds", type=float, default=5.0, help="run time before each shot (s)")
    parser.add_argument("--teaching", action="store_true", help="only the README's 'Teaching with it' shot")
    parser.add_argument("--readme", action="store_true", help="the README's screenshots (into --out, e.g. docs)")
    parser.add_argument("--gallery", action="store_true", help="the README's gallery: every scene and a phone")
    parser.add_argument("--projector", action="store_true", help="projector mode in the lecture (into --out)")
    parser.add_argument(
        "--phone-toss",
        type=Path,
        metavar="RECORDING",
        help="the phone-toss scene with this phyphox recording (a folder, its Raw Data.csv or a .zip) uploaded "
        "and fitted, into --out/phone_toss.png (the README's uses a real toss, not the project's to commit)",
    )
    parser.add_argument("--toss", type=int, default=1, help="with --phone-toss: the toss shown (1: the first)")
    parser.add_argument(
        "--language",
        metavar="LANG",
        help="the README's shot in another language: the shipped lecture's racket step in a browser reading "
        "LANG (de, es, zh), into --out/language_LANG.png",
    )
    args = parser.parse_args(argv)
    args.out.mkdir(parents=True, exist_ok=True)
    if args.language is not None:
        language(args.out / f"language_{args.language}.png", args.language)
        return
    if args.phone_toss is not None:
        phone_toss(args.out / "phone_toss.png", args.phone_toss, args.toss - 1)
        return
    if args.gallery:
        gallery(args.out)
        projector(args.out / "projector.png")
        return
    if args.projector:
        projector(args.out / "projector.png")
        return
    if args.teaching:
        teaching(args.out / "teaching.png")
        return
    if args.readme:
        readme(args.out)
        teaching(args.out / "teaching.png")
        return
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


# The README's pictures: (file, scene, preset or None, viewport, dark look, the panel scrolled to the plot
# whose title starts with this text, or None).
README_SHOTS = [
    ("heavy_top.png", "heavy_top", None, (1280, 800), False, None),
    ("heavy_top_loops.png", "heavy_top", "loops (φ̇0 = −1 × steady)", (1280, 800), False, None),
    ("heavy_top_potential.png", "heavy_top", None, (1280, 800), False, "Effective potential"),
    ("heavy_top_dark.png", "heavy_top", "waves (φ̇0 = ½ × steady)", (1024, 768), True, None),
    ("heavy_top_phone.png", "heavy_top", None, (390, 844), False, None),
    ("wobble.png", "wobble", None, (1280, 800), False, None),
    ("scene_explorer.png", "inertia_explorer", None, (1280, 800), False, None),
    ("scene_pendulum.png", "pendulum", None, (1280, 800), False, None),
    ("scene_racket_plot.png", "tennis_racket", None, (1280, 800), False, "ω in body axes"),
    ("free_fall.png", "free_fall", None, (1280, 800), False, None),
    ("wobble_body_view.png", "wobble", None, (1280, 800), False, None),
    ("heavy_top_friction.png", "heavy_top", "sleeping top with friction: falls", (1280, 800), False, None),
]


def _ride_with_the_body(app) -> None:
    app.scene.body_view.value = True  # runs its callback: the scene restarts in body axes


def _fast_forward(app) -> None:
    app.set_speed(4.0)  # 24 s of the friction top in 6 s: it spins down, falls and lies on the table


# Anything a shot needs beyond its preset, done under the app's lock before the wait.
SETUPS = {"wobble_body_view.png": _ride_with_the_body, "heavy_top_friction.png": _fast_forward}

_SCROLL_TO_PLOT = """(title) => { for (const el of document.querySelectorAll('.u-title')) {
    if (el.textContent.startsWith(title)) { el.scrollIntoView({block: 'start'}); return true; } }
  return false; }"""


def readme(out: Path, seconds: float = 6.0) -> None:
    """The README's screenshots, each from a fresh server at its viewport and look."""
    for file, scene, preset, (width, height), dark, scroll in README_SHOTS:
        with running_app(scene, dark=dark) as app, launch_chromium() as browser:
            page, _client = open_page(browser, app, viewport={"width": width, "height": height})
            if preset is not None:
                with app.simulation.lock:
                    assert app.scene.presets.choose(preset), preset
            if file in SETUPS:
                with app.simulation.lock:
                    SETUPS[file](app)
            time.sleep(seconds)
            page.evaluate(_CLOSE_NOTIFICATIONS)
            if scroll is not None:
                assert page.evaluate(_SCROLL_TO_PLOT, scroll), f"no plot titled {scroll!r}"
            time.sleep(0.5)
            page.screenshot(path=str(out / file))
            print(f"{file}: {out / file}", flush=True)


def gallery(out: Path, seconds: float = 5.0) -> None:
    """The README's gallery (``--gallery --out docs/gallery``): every scene at 1280×800 with the panel open,
    and the shipped lecture's first question on an emulated iPhone 13 (Playwright's descriptor: 390×664 CSS
    px, device pixel ratio 3, touch, a mobile user agent)."""
    with running_app() as app, launch_chromium() as browser:
        page, _client = open_page(browser, app, timeout=120.0, viewport={"width": 1280, "height": 800})
        for name in scene_names():
            app.switch_scene(name)
            app.set_playing(True)
            time.sleep(seconds)
            app.set_playing(False)  # paused: the labels (drawn apart from the 3D picture) catch up with it
            page.evaluate(_CLOSE_NOTIFICATIONS)
            time.sleep(2.0)
            page.screenshot(path=str(out / f"{name}.png"))
            print(f"{name}: {out / name}.png", flush=True)
    with running_app(presenter=True, lecture="rigid-body-motion") as app, launch_chromium() as browser:
        app.go_to_step(6)  # the racket's question: held back, waiting at t = 0
        phone = paced_context(browser, **DEVICES["iPhone 13"]).new_page()
        before = set(app.server.get_clients())
        phone.goto(app.url, wait_until="domcontentloaded")
        wait_for(lambda: set(app.server.get_clients()) - before, 120, what="the phone to connect")
        phone.wait_for_selector("canvas", timeout=120_000)
        time.sleep(seconds)
        phone.evaluate(_CLOSE_NOTIFICATIONS)
        time.sleep(0.5)
        phone.screenshot(path=str(out / "phone.png"), scale="css")
        print(f"phone: {out / 'phone.png'}", flush=True)


def projector(path: Path, seconds: float = 9.0) -> None:
    """Projector mode (``--projector --out docs/gallery``) at 1280×800: the shipped lecture's tennis racket
    after its question's reveal, run for ``seconds`` so that its ω₁ω₂ω₃ plot shows the flips."""
    with running_app(presenter=True, lecture="rigid-body-motion", projector=True) as app, launch_chromium() as browser:
        app.go_to_step(6)  # the racket's question
        page, _client = open_page(browser, app, timeout=120.0, viewport={"width": 1280, "height": 800})
        app.questions.reveal(None)  # the caption and the answer back
        with app.simulation.lock:
            app.set_playing(True)
        time.sleep(seconds)
        with app.simulation.lock:
            app.set_playing(False)  # paused: the labels (drawn apart from the 3D picture) catch up with it
        page.evaluate(_CLOSE_NOTIFICATIONS)
        time.sleep(2.0)
        page.screenshot(path=str(path))
        print(f"projector: {path}", flush=True)


def teaching(path: Path) -> None:
    """The tennis racket with the Lie–Poisson ghost at a coarse step: the ghost flips late, the plots show it."""
    with running_app("tennis_racket") as app, launch_chromium() as browser:
        page, client = open_page(browser, app, viewport={"width": 1500, "height": 900})
        scene = app.scene
        with app.simulation.lock:
            scene.ghost.step_slider.value = 0.1
            scene.ghost.choice.value = "Lie–Poisson splitting (order 2)"
            app.restart()
        time.sleep(8.0)
        page.evaluate(_CLOSE_NOTIFICATIONS)
        page.evaluate(
            "() => { const p = document.querySelector('.mantine-ScrollArea-viewport'); if (p) p.scrollTop = 1e6; }"
        )
        time.sleep(0.5)
        page.screenshot(path=str(path))
        print(f"teaching: {path}", flush=True)


def _upload_bytes(recording: Path) -> tuple[str, bytes]:
    """A recording as the page would send it: a folder zipped as phyphox shares it (with its meta/), else the file."""
    if not recording.is_dir():
        return recording.name, recording.read_bytes()
    out = io.BytesIO()
    with zipfile.ZipFile(out, "w", zipfile.ZIP_DEFLATED) as archive:
        for path in sorted(recording.rglob("*")):
            if path.is_file():
                archive.write(path, str(path.relative_to(recording.parent)))
    return recording.name + ".zip", out.getvalue()


def phone_toss(path: Path, recording: Path, toss: int, seconds: float = 4.0) -> None:
    """The phone-toss scene with ``recording`` uploaded through the page, toss ``toss`` (0-based) fitted alone:
    the phone replaying the fitted flip, and the panel scrolled to the plot of measured points and fitted lines."""
    name, content = _upload_bytes(recording)
    with running_app("phone_toss") as app, launch_chromium() as browser:
        page, _client = open_page(browser, app, timeout=120.0, viewport={"width": 1500, "height": 900})
        page.get_by_text("Upload a phyphox recording").first.wait_for(timeout=120_000)
        page.locator("input[type=file]").first.set_input_files(
            {"name": name, "mimeType": "application/octet-stream", "buffer": content}
        )
        wait_for(lambda: app.scene.result.source == name, 120, what="the recording to be fitted")
        if toss != app.scene.result.chosen:
            app.scene.toss.value = app.scene.toss.options[toss + 1]  # fitted in the worker, as the page's choice
        wait_for(lambda: app.scene.result.chosen == toss, 120, what="the toss to be fitted")
        time.sleep(seconds)
        with app.simulation.lock:
            app.set_playing(False)  # paused: the labels (drawn apart from the 3D picture) catch up with it
        page.evaluate(_CLOSE_NOTIFICATIONS)
        # The panel from the fitted ratios down to the plot.
        page.get_by_text("fitted moments I_x").first.evaluate("e => e.scrollIntoView({block: 'start'})")
        time.sleep(2.0)
        page.screenshot(path=str(path))
        print(f"phone toss: {path}", flush=True)


LOCALES = {"de": "de-DE", "es": "es-ES", "zh": "zh-CN"}


def language(path: Path, lang: str, seconds: float = 8.0) -> None:
    """The shipped lecture at its tennis-racket step in a browser whose language is ``lang``: every word of
    the panel and the step's caption in it, numbers written as it writes them."""
    with running_app("tennis_racket", lecture="rigid-body-motion") as app, launch_chromium() as browser:
        page = browser.new_page(viewport={"width": 1280, "height": 800}, locale=LOCALES[lang])
        page.goto(app.url, wait_until="domcontentloaded")
        page.wait_for_selector("canvas", timeout=90_000)
        steps = app.simulation.lecture.steps
        app.go_to_step(next(k for k, step in enumerate(steps) if step.scene == "tennis_racket"))
        app.set_playing(True)
        time.sleep(seconds)
        page.evaluate(_CLOSE_NOTIFICATIONS)
        time.sleep(0.5)
        page.screenshot(path=str(path))
        print(f"{lang}: {path}", flush=True)


if __name__ == "__main__":
    main()
