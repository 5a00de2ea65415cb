"""The projector look in headless Chromium: every scene's body contrast against what is behind
it, the panel's text size, the body framed clear of the panel, at 1280×800, 1024×768 and on a 390×844 phone
in the light look and at 1280×800 in the dark one; the key controls above the fold, the panel collapsible.
The contrast figures are recorded in docs/look.md (``python docs/look.py``), which the test checks."""

from __future__ import annotations

import io
import time
from pathlib import Path

import numpy as np
import pytest
from PIL import Image
from scipy.ndimage import binary_erosion

from app.panel.look import MIN_TEXT_PX
from app.scenes import scene_names
from app.serving.framing import framing_of, free_region
from tests.harness import click, control_id, open_page, running_app, wait_for

pytestmark = pytest.mark.browser

VIEWS = [(1280, 800), (1024, 768), (390, 844)]
LOOK_MD = Path(__file__).resolve().parents[2] / "docs" / "look.md"

CLOSE_NOTIFICATIONS = "() => document.querySelectorAll('.mantine-Notification-closeButton').forEach(b => b.click())"
OPEN_NOTIFICATIONS = "() => document.querySelectorAll('.mantine-Notification-root').length"

PANEL_VISIBLE = """(visible) => document.querySelectorAll('.mantine-Paper-root').forEach(
    p => { p.style.visibility = visible ? '' : 'hidden'; })"""
"""Hide or show the control panel (and any notice): its own changes (a slider's mark fading, a readout) are
not the body, and hidden it shows what it would cover. ``visibility`` keeps its layout, so the view's size
and the camera's framing stay."""

PANEL_RECT = """(id) => { const p = document.getElementById(id).closest('.mantine-Paper-root');
    const r = p.getBoundingClientRect(); return [r.left, r.top, r.right, r.bottom]; }"""

SMALLEST_TEXT = """(id) => { const panel = document.getElementById(id).closest('.mantine-Paper-root');
    const bounds = panel.getBoundingClientRect(); let smallest = 1e9, where = '';
    for (const el of panel.querySelectorAll('*')) {
      const own = [...el.childNodes].some(n => n.nodeType === 3 && n.textContent.trim());
      const r = el.getBoundingClientRect();
      if (!own || r.height === 0 || r.bottom < bounds.top || r.top > bounds.bottom) continue;
      const size = parseFloat(getComputedStyle(el).fontSize);
      if (size < smallest) { smallest = size; where = el.textContent.trim().slice(0, 40); }
    }
    return [smallest, where]; }"""


def _shot(page) -> np.ndarray:
    return np.asarray(Image.open(io.BytesIO(page.screenshot())).convert("RGB")).astype(float)


def _luminance(rgb: np.ndarray) -> np.ndarray:
    """WCAG 2 relative luminance of sRGB pixels (..., 3) in 0-255."""
    c = rgb / 255.0
    linear = np.where(c <= 0.04045, c / 12.92, ((c + 0.055) / 1.055) ** 2.4)
    return linear @ np.array([0.2126, 0.7152, 0.0722])


SCENE_TIME = 1.0
"""s: every scene is measured paused at this time, so a measurement is of one pose and repeats exactly."""


def _settled(page, unlike: np.ndarray | None = None, timeout: float = 30.0) -> np.ndarray:
    """A screenshot once the page has drawn what it was sent: two shots in a row the same (and, with
    ``unlike``, different from that one in at least 300 pixels)."""
    previous = _shot(page)
    deadline = time.monotonic() + timeout
    while True:
        shot = _shot(page)
        same = np.abs(shot - previous).max() <= 2.0
        changed = unlike is None or (np.abs(shot - unlike).max(axis=-1) > 24).sum() >= 300
        if same and changed:
            return shot
        if time.monotonic() > deadline:
            raise AssertionError("the page did not settle on a new picture")
        previous = shot


FRAMES = "() => window.rblFrames ?? null"
"""How many frames the page has drawn (tests.harness.PACE_FRAMES counts them; null in a page without it)."""


def _drawn_again(page) -> None:
    """Wait until the page has drawn two more frames: the screenshots after it are of what the server sent
    before this call (two screenshots alike can both come before a slow page's next frame)."""
    start = page.evaluate(FRAMES)
    if start is not None:
        wait_for(lambda: page.evaluate(FRAMES) >= start + 2, 30, what="the page to draw two frames")


def _view(app) -> list:
    """What the browsers see the scene from: each one's camera and the size it renders at."""
    return [
        (c.camera.image_width, c.camera.image_height, tuple(np.round(c.camera.position, 6)))
        for c in app.server.get_clients().values()
    ]


def body_pixels(page, app, name: str | None = None) -> tuple[np.ndarray, np.ndarray, np.ndarray]:
    """(mask, with the body, without it) of scene ``name`` (default: the current one), paused at
    :data:`SCENE_TIME`: the body shown, hidden, then shown again. Taken again if the camera or the picture moved in
    between: a page whose frame rate drops renders at a lower pixel ratio and reports the new size, and a page
    still easing to a new framing shifts the whole scene."""
    for _ in range(3):
        view = _view(app)
        mask, shown, hidden, again = _body_pixels(page, app, name)
        # The same picture with the body shown again: nothing else moved between the shots (a page still
        # easing its camera to a new framing after a resize shifts the whole scene by a fraction of a pixel).
        if _view(app) == view and not (np.abs(again - shown).max(axis=-1) > 24).any():
            return mask, shown, hidden
    raise AssertionError("the camera kept moving while the body was measured")


def _body_pixels(page, app, name: str | None) -> tuple[np.ndarray, np.ndarray, np.ndarray, np.ndarray]:
    with app.simulation.lock:
        if name is not None and app.scene.name != name:
            app.switch_scene(name)
        app.set_playing(False)
        app.restart()  # the traces cleared: the picture is of the pose alone, whatever ran before
        app.simulation.set_time(SCENE_TIME)
        app.simulation.request_redraw()
        drawn = app.frames
    wait_for(lambda: app.frames > drawn, 30, what="the paused frame")
    _drawn_again(page)
    # viser's "software WebGL" notice (headless Chromium has no GPU) may arrive late and cover the body.
    page.evaluate(CLOSE_NOTIFICATIONS)
    wait_for(lambda: page.evaluate(OPEN_NOTIFICATIONS) == 0, 10, what="the notices to close")
    page.evaluate(PANEL_VISIBLE, False)
    try:
        shown = _settled(page)
        with app.simulation.lock:
            app.scene.body.handle.visible = False
        _drawn_again(page)
        hidden = _settled(page, unlike=shown)
        with app.simulation.lock:
            app.scene.body.handle.visible = True
        _drawn_again(page)
        again = _settled(page, unlike=hidden)
    finally:
        page.evaluate(PANEL_VISIBLE, True)
    mask = np.abs(shown - hidden).max(axis=-1) > 24
    return mask, shown, hidden, again


def contrast(mask: np.ndarray, shown: np.ndarray, hidden: np.ndarray) -> tuple[float, float, float]:
    """WCAG contrast ratio between the body's median luminance and that of what is behind it, over the
    body's inner pixels (two pixels in from its outline: no antialiased edge); and the two luminances."""
    inner = binary_erosion(mask, iterations=2)
    body, behind = np.median(_luminance(shown[inner])), np.median(_luminance(hidden[inner]))
    bright, dark = max(body, behind), min(body, behind)
    return float((bright + 0.05) / (dark + 0.05)), float(body), float(behind)


def _open_at_full_resolution(chromium, app, width: int, height: int) -> tuple:
    """The app in a page that renders at one pixel per CSS pixel throughout (viser's ``?fixedDpr=1``): without
    it viser lowers the pixel ratio when software rendering gets slow, and a thin body's median then depends
    on how fast the machine was."""
    before = set(app.server.get_clients())
    page = chromium.new_page(viewport={"width": width, "height": height})
    page.goto(f"{app.url}/?fixedDpr=1", wait_until="domcontentloaded")
    # A minute or two: on a shared machine under load the page's first load is slow.
    new = wait_for(lambda: set(app.server.get_clients()) - before, 120, what="the page to connect")
    page.wait_for_selector("canvas", timeout=120_000)
    return page, app.server.get_clients()[next(iter(new))]


def _framed(client) -> bool:
    """The page reported its size and the server framed the camera for that size.

    Whether the page's camera got there is judged on the page's own picture (the screenshots below wait
    until it is still, and the body must then be in the view and clear of the panel), not on the camera
    position the page last echoed: the page eases to a new camera and throttles its echoes, so on a
    loaded machine the last echo can be a point on the way (a CI run waited 60 s for one that never came).
    """
    framing = framing_of(client)
    size = (client.camera.image_width, client.camera.image_height)
    return framing is not None and size != (0, 0) and framing.size == size


LOOKS = [(w, h, False) for w, h in VIEWS] + [(1280, 800, True)]
"""Every scene is measured at each view in the light look, and at 1280×800 in the dark look."""


def placement(page, scene_id: str, mask: np.ndarray, width: int, height: int) -> str | None:
    """What is wrong with where the body is drawn: pixels under the panel, or outside the free view; None
    when it is clear of the panel and inside the view the panel leaves free."""
    left, top, right, bottom = page.evaluate(PANEL_RECT, scene_id)
    ys, xs = np.nonzero(mask)
    if not len(xs):
        return None  # no body at all: the pixel-count assertion names that
    under = (xs >= left) & (xs <= right) & (ys >= top) & (ys <= bottom)
    if under.any():
        return f"{under.sum()} body pixels under the panel {left, top, right, bottom}"
    free = free_region(width, height)
    if xs.max() > free[2] or ys.max() > free[3] + 0.02 * height:
        return f"outside the free view {free} (body to x = {xs.max()}, y = {ys.max()})"
    return None


def measure(chromium, width: int, height: int, dark: bool, check: bool = True) -> list[dict]:
    """Every scene's body contrast at one view and look (and, with ``check``, the test's other claims:
    the body in the view, clear of the panel, the panel's text size)."""
    rows = []
    with running_app("heavy_top", dark=dark) as app:
        page, client = _open_at_full_resolution(chromium, app, width, height)
        scene_id = control_id(page, "Scene")
        # The page reports its size once its layout settles; the camera is framed for the size it reported.
        wait_for(lambda: _framed(client), 60, what="the camera framed for the page's size")
        for name in scene_names():
            mask, shown, hidden = body_pixels(page, app, name)
            if check and placement(page, scene_id, mask, width, height):
                # A page on a loaded machine can still be easing to the camera it was just framed with while
                # two screenshots in a row come out the same (no frame rendered between them): measure again
                # once. A body that is really out of place is out of place both times and fails below.
                mask, shown, hidden = body_pixels(page, app, name)
            inner = int(binary_erosion(mask, iterations=2).sum())
            ratio, body, behind = contrast(mask, shown, hidden) if inner else (0.0, 0.0, 0.0)
            rows.append(
                {"scene": name, "view": f"{width}×{height}", "look": "dark" if dark else "light", "ratio": ratio}
                | {"body": body, "behind": behind, "pixels": inner}
            )
            print(f"{name} {width}x{height} {'dark' if dark else 'light'}: body contrast {ratio:.2f}:1", flush=True)
            if not check:
                continue
            # In the view (300 pixels: a thin racket or bat on a phone is that small), and the median is taken
            # over at least 50 inner pixels (the racket's open head on a phone leaves 81).
            assert mask.sum() >= 300 and inner >= 50, f"{name}: the body is not in the view ({mask.sum()} px)"
            assert ratio >= 3.0, f"{name}: body contrast {ratio:.2f}:1"
            # Framed clear of the panel: no pixel of the body under it (the shots hide the panel, so one would
            # show), and inside the view the panel leaves free.
            problem = placement(page, scene_id, mask, width, height)
            assert problem is None, f"{name}: {problem}"
            # Large in it: at the lecture's 1280×800 the drawn body's longer side spans a third of the free
            # view's height; in a narrower view (1024×768: the free part is taller than wide, so a scene framed
            # for its width is smaller in its height) and a phone's, above its sheet, a quarter. The racket
            # spinning flat is wide, not tall, half of every turn: its longer side is taken.
            free = free_region(width, height)
            ys, xs = np.nonzero(mask)
            share = max(np.ptp(ys), np.ptp(xs)) / (free[3] - free[1])
            least = 1 / 3 if (width, height) == (1280, 800) else 1 / 4
            assert share >= least, f"{name}: the body spans {share:.2f} of the free view ({least:.2f} asked)"
        smallest, where = page.evaluate(SMALLEST_TEXT, scene_id)
        if check:
            assert smallest >= MIN_TEXT_PX, f"{smallest} px text in the panel: {where!r}"
        page.close()
    return rows


def recorded() -> dict[tuple[str, str, str], float]:
    """The contrast ratios docs/look.md records, by (scene, view, look)."""
    table = {}
    for line in LOOK_MD.read_text(encoding="utf-8").splitlines():
        cells = [c.strip() for c in line.strip().strip("|").split("|")]
        if len(cells) >= 4 and cells[3].endswith(":1"):
            table[(cells[0], cells[1], cells[2])] = float(cells[3][:-2])
    return table


@pytest.mark.parametrize(
    ("width", "height", "dark"), LOOKS, ids=[f"{w}x{h}-{'dark' if d else 'light'}" for w, h, d in LOOKS]
)
def test_every_body_stands_out_framed_clear_of_the_panel(chromium, width, height, dark) -> None:
    """Every scene's body at least 3:1 against what is behind it, in the view and clear of the panel; the
    figures are those docs/look.md records (python docs/look.py writes it from this measurement)."""
    rows = measure(chromium, width, height, dark)
    table = recorded()
    for row in rows:
        key = (row["scene"], row["view"], row["look"])
        assert key in table, f"docs/look.md has no row for {key}: rerun python docs/look.py"
        # One pose, one renderer: the same picture each time, to the last pixel's rounding.
        assert row["ratio"] == pytest.approx(table[key], abs=0.05), (key, row["ratio"], table[key])


# Each scene's main controls: (its sliders and dropdowns by label, its own buttons by name).
MAIN_CONTROLS = {
    "heavy_top": (("spin ω₃ (rad/s)", "tilt θ₀ (°)"), ()),
    "wobble": (("I₃/I₁ (shape)", "|ω| (rad/s)", "angle of ω from the axis (°)"), ()),
    "free_fall": (("I₃/I₁ (shape)", "|ω| (rad/s)", "angle of ω from the axis (°)"), ()),
    "inertia_explorer": (("Body", "radius / size a (m)"), ()),
    "pendulum": (("Body", "pivot below the knob end (m)", "release angle θ₀ (°)"), ("Strike!",)),
    "tennis_racket": (("Body", "Spin about principal axis", "spin Ω (rad/s)", "push off the axis, log₁₀ ε"), ()),
}


def test_key_controls_above_the_fold_and_the_panel_collapses(chromium) -> None:
    """Each scene's main controls and its clock's buttons inside the panel and above the fold at 1280×800,
    on one page that is shown every scene in turn (the panel a scene builds is the same whether the app
    started on it or switched to it); then the panel collapses."""
    with running_app("heavy_top") as app:
        page, _ = open_page(chromium, app, viewport={"width": 1280, "height": 800})
        for scene in sorted(MAIN_CONTROLS):
            sliders, buttons = MAIN_CONTROLS[scene]
            with app.simulation.lock:
                if app.scene.name != scene:
                    app.switch_scene(scene)
            for label in sliders:
                control_id(page, label)  # the scene's panel is drawn
            scene_id = control_id(page, "Scene")
            panel_bottom = page.evaluate(PANEL_RECT, scene_id)[3]
            for label in ("Scene", *sliders):
                box = page.locator(f"[id='{control_id(page, label)}']").bounding_box()
                assert box is not None and box["y"] + box["height"] <= min(panel_bottom, 800), (scene, label)
            clock = () if app.scene.static else ("Pause", "Reset")  # a still scene has no clock to run
            for name in (*clock, *buttons):
                box = page.get_by_role("button", name=name).first.bounding_box()
                assert box is not None and box["y"] + box["height"] <= min(panel_bottom, 800), (scene, name)
            if app.scene.static:
                wait_for(lambda: not page.get_by_role("button", name="Pause").first.is_visible(), 10, what="no clock")
        assert not app.scene.static  # the last scene (wobble) has a clock: its Reset goes when the panel collapses
        click(page.get_by_label("Minimize panel"))
        wait_for(
            lambda: not page.get_by_role("button", name="Reset").first.is_visible(), 10, what="the panel to collapse"
        )
        page.close()
