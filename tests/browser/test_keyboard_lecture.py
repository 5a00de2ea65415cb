"""The whole app by keyboard alone: the shipped lecture walked from its
first step to its last with what a presentation clicker sends (Page Down, →, ↓ and back with Page Up, ←,
↑), every scene's main controls (a slider, a dropdown, a button) and the clock's reached with Tab and
operated with keys, the Tab order and its focus ring, the keyboard help, and the live description read
from the page before and after a change and checked against the physics API.

No mouse event: only ``page.keyboard``; the focus moves with Tab. Each change is read from the server's
state (the app object, in this process).
"""

from __future__ import annotations

import re
from typing import Any

import pytest

from app.panel.access import KEYS
from app.scenes.free_fall import FreeFall
from tests.app.scenes.test_motion_words import heavy_top_says
from tests.harness import FRAME, open_page, running_app, wait_for

pytestmark = pytest.mark.browser

FOCUSED = """() => { const e = document.activeElement;
  if (!e || e === document.body) return {name: '', role: '', tag: 'BODY'};
  const by = e.getAttribute('aria-labelledby'), label = by && document.getElementById(by);
  const name = e.getAttribute('aria-label') || (label ? label.textContent : '')
    || (e.labels && e.labels.length ? e.labels[0].textContent : '') || e.textContent;
  const s = getComputedStyle(e), r = e.getBoundingClientRect();
  let box = e.parentElement;
  while (box && !(box.scrollHeight > box.clientHeight + 1 && /(auto|scroll)/.test(getComputedStyle(box).overflowY)))
    box = box.parentElement;
  return {name: name.replace(/\\s+/g, ' ').trim(), role: e.getAttribute('role') || e.tagName.toLowerCase(),
          tag: e.tagName, outline: s.outlineStyle, width: parseFloat(s.outlineWidth), colour: s.outlineColor,
          shadow: s.boxShadow, middle: r.top + r.height / 2 + (box ? box.scrollTop : 0), panel: !!e.closest('.mantine-Paper-root'),
          id: e.id || ''}; }"""
"""The focused element: its accessible name (as the patch gives it), role, focus ring and the height of its
middle in the panel's scrolled content, CSS px."""

LIVE = """() => { const el = document.querySelector('[aria-live=polite]');
  const view = document.querySelector('canvas[data-engine]');
  return el ? [el.textContent, view ? view.getAttribute('aria-label') : null] : null; }"""

HIGHLIGHTED = """() => { const o = [...document.querySelectorAll('[role=option][data-combobox-selected]')]
    .find(e => e.offsetParent); return o ? o.textContent : null; }"""
"""The option the keyboard has reached in the open list (Mantine marks it data-combobox-selected)."""
CLOSED = "(the list closed)"
"""What :func:`choose` sees when a re-render closed the list it was moving through."""


def focused(page: Any) -> dict[str, Any]:
    return page.evaluate(FOCUSED)


def tab_to(page: Any, name: str, role: str | None = None, limit: int = 90, back: bool = False) -> int:
    """Press Tab (``back``: Shift+Tab) until the control named ``name`` (a prefix of its name, and of
    ``role``) has the focus; returns how many presses it took."""
    for presses in range(1, limit + 1):
        page.keyboard.press("Shift+Tab" if back else "Tab")
        now = focused(page)
        if now["name"].startswith(name) and (role is None or now["role"] == role):
            return presses
    raise AssertionError(f"Tab never reached {name!r} ({role}) in {limit} presses")


def _moved(page: Any, before: str) -> str | None:
    """The highlighted option (or CLOSED) once it is not ``before``; None while it still is."""
    now = page.evaluate(HIGHLIGHTED) or CLOSED
    return now if now != before else None


def _open_list(page: Any, label: str) -> str:
    """Press ↓ on the focused dropdown until its list is open (at most five presses, as a user would press
    again when a busy page did not take the key or a re-render took the focus); returns the highlighted
    option."""
    for press in range(1, 6):
        now = focused(page)
        if not (now["name"].startswith(label) and now["role"] == "combobox"):
            tab_to(page, label, "combobox", back=True)  # a re-render took the focus away: back to the dropdown
        page.keyboard.press("ArrowDown")
        try:
            return wait_for(lambda: page.evaluate(HIGHLIGHTED), 4, what=f"the open list of {label!r}")
        except AssertionError:
            if press == 5:
                raise
    raise AssertionError("unreachable")


def choose(page: Any, label: str, option: str, done: Any, what: str) -> None:
    """Choose ``option`` in the dropdown labelled ``label``: Tab to it, ↓ opens the list, ↓ moves through
    it, Enter takes the highlighted option; until ``done()`` holds on the server. As a user would, a key the
    page did not take is pressed again (at most 40 presses), and a list that a re-render closed, before or
    after Enter, is opened again (at most twice)."""
    for attempt in (1, 2, 3):
        tab_to(page, label, "combobox", back=True)
        now = _open_list(page, label)
        for _ in range(40):
            if now == CLOSED or now.strip() == option:
                break
            page.keyboard.press("ArrowDown")
            try:
                now = wait_for(lambda n=now: _moved(page, n), 3, what=f"the next option of {label!r}")
            except AssertionError:
                continue  # the key was not taken (a busy page, or a re-render put the highlight back): again
        else:
            raise AssertionError(f"{option!r} never highlighted in {label!r}")
        if now == CLOSED:
            if attempt == 3:
                raise AssertionError(f"the list of {label!r} closed three times before {option!r} was reached")
            continue
        page.keyboard.press("Enter")
        try:
            wait_for(done, 10, what=what)
            return
        except AssertionError:
            if attempt == 3:
                raise


def slider_step(app: Any, key: str) -> tuple[float, float, float]:
    """(step, min, max) of the scene's slider ``key``."""
    handle = app.scene.params.sliders[key]
    return float(handle.step), float(handle.min), float(handle.max)


def value(app: Any, key: str) -> float:
    return float(app.scene.params.values[key])


def live(page: Any) -> tuple[str, str]:
    return page.evaluate(LIVE)


def clock_by_keyboard(page: Any, app: Any, back: bool = True) -> None:
    """Pause, Step, the speed slider, Reset and Play: each reached with Tab (``back``: Shift+Tab to Pause),
    each pressed with a key."""
    tab_to(page, "Pause", "button", back=back)
    page.keyboard.press("Enter")
    wait_for(lambda: not app.shared.playing, 10, what="Enter on Pause to pause")
    paused = app.time
    tab_to(page, "Step", "button")
    page.keyboard.press("Space")  # Space on a focused button presses it (not the play/pause shortcut)
    wait_for(lambda: app.time > paused, 10, what="Space on Step to step")
    assert app.time - paused == pytest.approx(FRAME, rel=1e-6) and not app.shared.playing
    tab_to(page, "Speed", "slider")
    page.keyboard.press("ArrowRight")
    wait_for(lambda: app.shared.speed > 1.0, 10, what="→ on the speed slider")
    page.keyboard.press("ArrowLeft")
    wait_for(lambda: app.shared.speed == pytest.approx(1.0), 10, what="← on the speed slider")
    tab_to(page, "Reset", "button")
    page.keyboard.press("Enter")
    wait_for(lambda: app.time == 0.0, 10, what="Enter on Reset")
    tab_to(page, "Play", "button", back=True)
    page.keyboard.press("Enter")
    wait_for(lambda: app.shared.playing, 10, what="Enter on Play")
    # Paused for the rest: a page redrawing its readouts every frame on a software renderer is slow to
    # take keys, and nothing below needs the clock.
    page.keyboard.press("Space")
    wait_for(lambda: not app.shared.playing, 10, what="Space on the focused Pause button")


def nudge(page: Any, app: Any, key: str, label: str, press: str, expect: float) -> None:
    """Tab to the slider ``label`` and press ``press``; the server's value of ``key`` becomes ``expect``."""
    tab_to(page, label, "slider")
    page.keyboard.press(press)
    wait_for(lambda: abs(value(app, key) - expect) < 1e-9, 10, what=f"{press} on {label!r} to give {expect}")


def scene_by_keyboard(page: Any, app: Any, name: str) -> None:
    """The scene's main controls: a slider (arrows, Page Up, End), a dropdown and a button, by keys."""
    if name == "inertia_explorer":
        step, _, _ = slider_step(app, "length")
        nudge(page, app, "length", "length L (m)", "ArrowRight", value(app, "length") + step)
        box = "Box (L × 2a × a)"
        choose(page, "Body", box, lambda: app.scene.choice.value == box, "the box from the Body dropdown")
    elif name == "pendulum":
        step, _, _ = slider_step(app, "strike")
        nudge(page, app, "strike", "strike point below the pivot", "ArrowLeft", value(app, "strike") - step)
        tab_to(page, "Strike!", "button")
        page.keyboard.press("Enter")
        wait_for(lambda: app.scene.last_strike is not None, 10, what="Enter on Strike!")
    elif name == "wobble":
        _, _, top = slider_step(app, "spin")
        nudge(page, app, "spin", "|ω| (rad/s)", "End", top)
        rod = "rod-like (prolate)"  # not the step's own preset: choosing that again would change nothing
        choose(page, "Preset", rod, lambda: app.scene.presets.last == rod, "the rod-like preset")
    elif name == "tennis_racket":
        step, _, top = slider_step(app, "spin")
        # Page Up: ten steps (the patch's; Mantine's slider has none), within the range.
        nudge(page, app, "spin", "spin Ω (rad/s)", "PageUp", min(top, value(app, "spin") + 10 * step))
        split = "Lie–Poisson splitting (order 2)"
        choose(page, "Compare with integrator", split, lambda: app.scene.ghost.method is not None, "the ghost")
    elif name == "heavy_top":
        # Item 3: the live description the page holds, before and after a change by keyboard, says the
        # numbers of the physics API (HeavyTop(...).trajectory) for the server's values.
        # The live region and the view's label are two updates: on a loaded page the second can come a few
        # frames after the first, so wait until both say what the server says now.
        text, view = wait_for(
            lambda: (
                (now := live(page))
                and now[0] == app.shared.panel.said
                and now[1] == f"3D view of the simulation: {now[0]}"
                and now
            ),
            10,
            what="the live text and the view's label to say the heavy top",
        )
        heavy_top_says(text, dict(app.scene.params.values))
        step, _, _ = slider_step(app, "spin")
        nudge(page, app, "spin", "spin ω₃ (rad/s)", "ArrowRight", value(app, "spin") + step)
        page.wait_for_function(f"() => document.querySelector('[aria-live=polite]').textContent !== {text!r}")
        # Compared with the newest words said (they change as the motion goes: its last event).
        wait_for(
            lambda: (
                page.evaluate("() => document.querySelector('[aria-live=polite]').textContent") == app.shared.panel.said
            ),
            30,
            what="the live text to say the server's words",
        )
        after, _ = live(page)
        assert after != text
        heavy_top_says(after, dict(app.scene.params.values))
    elif name == "free_fall":
        step, _, _ = slider_step(app, "tilt")
        nudge(page, app, "tilt", "angle of ω from the axis", "ArrowLeft", value(app, "tilt") - step)
    elif name == "phone_toss":
        first = app.scene.toss.options[1]  # the bundled first toss alone, fitted again in the upload worker
        choose(page, "Toss", first, lambda: app.scene.result.chosen == 0, "the first toss from the Toss dropdown")
    else:
        raise AssertionError(f"no keyboard walk for scene {name!r}")


def focus_cycle(page: Any) -> list[dict[str, Any]]:
    """One full turn of Tab from the page's start: every stop, in order, until the first comes again."""
    stops: list[dict[str, Any]] = []
    for _ in range(120):
        page.keyboard.press("Tab")
        now = focused(page)
        if stops and now["name"] == stops[0]["name"] and now["role"] == stops[0]["role"]:
            return stops
        if now["tag"] != "BODY":  # past the last control the focus leaves the page for a press
            stops.append(now)
    raise AssertionError("Tab never came back to where it started")


def test_a_whole_lecture_and_every_scenes_controls_by_keyboard_alone(chromium) -> None:
    with running_app(lecture="rigid-body-motion") as app:
        steps = app.simulation.lecture.steps
        total = len(steps)
        page, _ = open_page(chromium, app, viewport={"width": 1280, "height": 800})
        try:
            page.wait_for_function("() => window.rblAccess === true", timeout=30_000)
            page.get_by_text(f"step 1 of {total}").first.wait_for(timeout=30_000)

            # Tab order: every stop has a name and a visible focus ring (2 px, not 'none'); the panel's
            # stops go down the panel (a slider and its number box share a row); the lecture before the
            # scene picker, the clock, the scene's controls, then the State, Export and Keyboard folders.
            stops = focus_cycle(page)
            assert all(s["name"] for s in stops), [s for s in stops if not s["name"]]
            assert all(s["outline"] != "none" and s["width"] >= 2 for s in stops), [
                s for s in stops if s["outline"] == "none" or s["width"] < 2
            ]
            panel = [s for s in stops if s["panel"]]
            tops = [s["middle"] for s in panel]
            assert all(b >= a - 4 for a, b in zip(tops, tops[1:], strict=False)), [
                (s["name"], s["middle"]) for s in panel
            ]
            names = [s["name"] for s in panel]
            # The lecture opens on the still inertia explorer: its clock is paused, its buttons disabled and
            # out of the tab order.
            landmarks = ["Previous", "Next", "length L (m)", "State", "Export a recording"]
            where = [next(i for i, n in enumerate(names) if n.startswith(m)) for m in landmarks]
            assert not any(n.startswith(("Play", "Pause", "Step", "Reset")) for n in names), names
            assert where == sorted(where), list(zip(landmarks, where, strict=True))
            assert names[-1] == "Keyboard"

            # The keyboard help: a folder opened with Enter, listing every key.
            tab_to(page, "Keyboard", "button")
            page.keyboard.press("Enter")
            page.wait_for_function(
                "() => [...document.querySelectorAll('.rbl-folder')].some(f => f.textContent.trim() === 'Keyboard' "
                "&& f.getAttribute('aria-expanded') === 'true')",
                timeout=10_000,
            )
            # The folder's content is drawn once its opening has run (a few frames on a slow page).
            first = f"{KEYS[0][0]}: {KEYS[0][1]}"
            page.wait_for_function("(text) => document.body.innerText.includes(text)", arg=first, timeout=10_000)
            shown = page.evaluate("() => document.body.innerText")
            for key, what in KEYS:
                assert f"{key}: {what}" in shown, key

            assert not app.shared.playing and app.shared.play_button.disabled  # the explorer has no clock

            # The lecture, as a clicker steps it, from a button (not a slider, which takes the arrows).
            tab_to(page, "Next", "button")
            visited: list[str] = []
            clicker = ("PageDown", "ArrowRight", "ArrowDown")
            for k in range(total):
                if k > 0:
                    page.keyboard.press(clicker[k % 3])
                    wait_for(
                        lambda k=k: (
                            app.simulation.step_index == k
                            and app.scene is not None
                            and app.scene.name == steps[k].scene
                        ),
                        20,
                        what=f"{clicker[k % 3]} to step {k + 1}",
                    )
                    page.get_by_text(f"step {k + 1} of {total}").first.wait_for(timeout=30_000)
                    app.set_playing(False)  # a step plays its scene; paused, the page takes keys faster
                if steps[k].scene not in visited:
                    visited.append(steps[k].scene)
                    if steps[k].scene == "pendulum":  # the first moving scene: its clock by keyboard
                        app.set_playing(True)
                        clock_by_keyboard(page, app, back=False)
                    scene_by_keyboard(page, app, steps[k].scene)
                    tab_to(page, "Next", "button", back=True)
            for k, key in zip((total - 2, total - 3, total - 4), ("PageUp", "ArrowLeft", "ArrowUp"), strict=True):
                page.keyboard.press(key)
                wait_for(
                    lambda k=k: (
                        app.simulation.step_index == k and app.scene is not None and app.scene.name == steps[k].scene
                    ),
                    20,
                    what=f"{key} back to step {k + 1}",
                )
            app.set_playing(False)  # as on the way forward: paused, the page takes keys faster
            # The one scene the lecture does not visit, chosen in the Scene dropdown by keyboard.
            choose(
                page,
                "Scene",
                FreeFall.title,
                lambda: app.scene is not None and app.scene.name == "free_fall",
                "the free fall from the Scene dropdown",
            )
            visited.append("free_fall")
            page.get_by_text("angle of ω from the axis", exact=False).first.wait_for(timeout=30_000)
            scene_by_keyboard(page, app, "free_fall")
            assert sorted(visited) == sorted(
                ["inertia_explorer", "pendulum", "wobble", "tennis_racket", "heavy_top", "phone_toss", "free_fall"]
            )
            assert re.search(r"\S", live(page)[0])
        finally:
            page.close()
