"""The timeline in real browsers: the racket paused after its first flip and dragged back before it shows the
exact model's attitude at the server's time; the friction top dragged back and forward again shows the same
states bit for bit; a replay at 0.1× runs the last seconds in ten times their length; a follower's view
follows the lecturer's scrubbing; the keys ←, Shift+← and Shift+→ move the clock back and on."""

from __future__ import annotations

import contextlib
import math
import re
from collections.abc import Iterator
from typing import Any

import numpy as np
import pytest

from app.panel.timeline_panel import TIMELINE
from physics.events import flip_events
from physics.free_body import FreeBody
from tests.harness import click, click_until, control_id, open_page, running_app, slider_value, wait_for

pytestmark = pytest.mark.browser

VIEW = {"width": 1280, "height": 800}
NOTHING_FOCUSED = "() => { if (document.activeElement) document.activeElement.blur(); }"
READY = "() => window.rblAccess === true && [...document.querySelectorAll('button')].some(b => b.textContent.trim() === 'Step back')"


@contextlib.contextmanager
def scene_page(chromium: Any, scene: str) -> Iterator[tuple[Any, Any]]:
    """An app showing ``scene`` and a page of it whose keyboard patch and Step back button are there."""
    with running_app(scene) as app:
        page, _ = open_page(chromium, app, viewport=VIEW)
        try:
            page.wait_for_function(READY, timeout=30_000)
            yield app, page
        finally:
            page.close()


def drag_time(page: Any, fraction: float) -> None:
    """Drag the timeline's thumb with the mouse to ``fraction`` (0-1) of its track, as a user does."""
    box_id = control_id(page, TIMELINE)
    track = page.locator(f"[id='{box_id}'] .mantine-Slider-track").first
    thumb = page.locator(f"[id='{box_id}'] [role=slider]").first
    track.scroll_into_view_if_needed()
    t, h = track.bounding_box(), thumb.bounding_box()
    assert t is not None and h is not None
    page.mouse.move(h["x"] + h["width"] / 2, h["y"] + h["height"] / 2)
    page.mouse.down()
    page.mouse.move(t["x"] + fraction * t["width"], t["y"] + t["height"] / 2, steps=8)
    page.mouse.up()


def fraction_of(page: Any, t: float) -> float:
    """Where time ``t`` (s) is on the timeline's track as the page shows it (its min and max)."""
    thumb = page.locator(f"[id='{control_id(page, TIMELINE)}'] [role=slider]").first
    low, high = (float(thumb.get_attribute(a) or "nan") for a in ("aria-valuemin", "aria-valuemax"))
    return (t - low) / (high - low)


def drag_and_wait(page: Any, app: Any, fraction: float) -> float:
    """Drag the timeline to ``fraction`` of its track and wait until the server shows the instant the page's
    slider came to rest at (not one it passed on the way); returns the server's time, s."""
    drag_time(page, fraction)
    # The page draws (and its slider takes the mouse's last moves) a few times a second: two of its frames
    # after the mouse is up, its slider shows where the drag ended.
    drawn = page.evaluate("() => window.rblFrames")
    wait_for(lambda: page.evaluate("() => window.rblFrames") >= drawn + 2, 30, what="the page to draw the drag")
    shown = slider_value(page, TIMELINE)
    wait_for(lambda: settled(app, shown), 30, what="the instant dragged to")
    assert slider_value(page, TIMELINE) == shown
    return app.time


def paused_in_page(page: Any, app: Any) -> None:
    """Wait until the page's timeline shows the paused time and the span the server gives it (a drag is
    read against the span the page shows)."""
    slider = app.simulation.panel.timeline.slider
    thumb = f"[id='{control_id(page, TIMELINE)}'] [role=slider]"

    def shown() -> bool:
        high = page.evaluate(f"() => document.querySelector(\"{thumb}\").getAttribute('aria-valuemax')")
        return settled(app, slider_value(page, TIMELINE)) and float(high) == slider.max

    wait_for(shown, 30, what="the page's timeline at the paused time")


def settled(app: Any, t_page: str | None) -> bool:
    """The server paused at the time the page's slider shows (to its two decimals) and has drawn it."""
    sim = app.simulation
    with sim.lock:
        return (
            t_page is not None
            and not sim.playing
            and abs(sim.time - float(t_page)) < 0.0051
            and not sim._dirty
            and sim.last_state.get("t", sim.time) == sim.time
        )


def test_the_racket_dragged_back_before_its_flip_shows_the_exact_attitude_there(chromium) -> None:
    with scene_page(chromium, "tennis_racket") as (app, page):
        scene = app.scene
        flip = flip_events(scene.motion, 0.0, 10.0)[0].time  # the first half-turn (1.42 s)
        wait_for(lambda: app.time > flip + 0.3, 60, what="the racket to flip")
        click(page.get_by_role("button", name="Pause"))
        wait_for(lambda: not app.simulation.playing, 20, what="the click to pause")
        paused_in_page(page, app)
        drag_and_wait(page, app, fraction_of(page, flip - 0.6))
        with app.simulation.lock:
            t, R = app.time, app.simulation.last_state["R"].copy()
        assert 0.0 < t < flip
        # The exact model made afresh from the scene's start (L along +z, ω0 from the sliders).
        exact = FreeBody(scene.moments).trajectory(scene.omega0, scene.attitude0).at(t).attitude
        angle = 2.0 * math.asin(min(1.0, float(np.linalg.norm(R - exact)) / math.sqrt(8.0)))
        assert angle < 1e-9


def test_the_friction_top_dragged_back_and_forward_repeats_its_states_bit_for_bit(chromium) -> None:
    with scene_page(chromium, "heavy_top") as (app, page):
        assert app.scene.presets.choose("sleeping top with friction: falls")
        app.set_speed(10.0)
        wait_for(lambda: app.time > 12.0, 120, what="the top to spin down and fall")
        click(page.get_by_role("button", name="Pause"))
        wait_for(lambda: not app.simulation.playing, 20, what="the click to pause")
        paused_in_page(page, app)
        seen: dict[float, tuple[np.ndarray, np.ndarray]] = {}
        again = 0
        for fraction in (0.8, 0.5, 0.2, 0.5, 0.8):  # back, then forward again over the same instants
            drag_and_wait(page, app, fraction)
            with app.simulation.lock:
                t = app.time
                state = app.simulation.last_state
                R, L = state["R"].copy(), state["L_body"].copy()
            if t in seen:
                again += 1
                assert np.array_equal(R, seen[t][0]) and np.array_equal(L, seen[t][1]), t
            seen[t] = (R, L)
        # The mouse reached the same instants going forward again.
        assert again >= 2 and len(seen) >= 3, sorted(seen)


def test_a_replay_at_a_tenth_takes_ten_times_the_span(chromium) -> None:
    with scene_page(chromium, "tennis_racket") as (app, page):
        flip = flip_events(app.scene.motion, 0.0, 10.0)[0].time
        wait_for(lambda: app.time > flip + 0.3, 60, what="the racket to flip")
        # Paused just after the flip (the page opens seconds after the clock starts on a loaded machine).
        end = app.simulation.timeline.seek(flip + 0.7)
        # A click lost to a panel that re-laid itself out (a loaded machine) is made again, as a user would.
        button = page.locator("button").filter(has_text=re.compile(r"^\s*Replay\s*$"))
        folder = page.locator(".rbl-folder", has_text="Replay")
        click_until(folder, lambda: button.first.is_visible(), "the Replay folder to open")
        timeline = app.simulation.timeline
        click_until(button, lambda: timeline.replay or timeline.last_replay, "the replay to start")
        wait_for(lambda: app.simulation.timeline.last_replay is not None, 120, what="the replay to end")
        replay = app.simulation.timeline.last_replay
        assert replay.start == pytest.approx(end - 2.0) and replay.end == end and replay.start < flip < end
        # 2 s of simulated time at the clock's 0.1×: 20 s of its wall time (to round-off), over many frames.
        assert replay.speed == 0.1 and replay.wall == pytest.approx(20.0, rel=1e-9) and replay.frames > 20
        assert app.simulation.speed == 1.0 and not app.simulation.playing and app.time == end


def test_the_arrow_keys_step_back_and_jump_a_second(chromium) -> None:
    with scene_page(chromium, "heavy_top") as (app, page):
        wait_for(lambda: app.time > 2.5, 60, what="the clock to run")
        page.evaluate(NOTHING_FOCUSED)
        page.keyboard.press("Space")
        wait_for(lambda: not app.simulation.playing, 10, what="Space to pause")
        paused = app.time
        page.keyboard.press("ArrowLeft")
        wait_for(lambda: app.time < paused, 10, what="← to step back")
        assert app.time == pytest.approx(paused - 1.0 / 60.0, abs=1e-12)
        back = app.time
        page.keyboard.press("Shift+ArrowLeft")
        wait_for(lambda: app.time < back - 0.5, 10, what="Shift+← to jump back")
        assert app.time == pytest.approx(back - 1.0, abs=1e-12)
        page.keyboard.press("Shift+ArrowRight")
        wait_for(lambda: app.time > back - 0.5, 10, what="Shift+→ to jump on")
        assert app.time == pytest.approx(back, abs=1e-12) and not app.simulation.playing


PIN = "2718"
READOUT = """(text) => { for (const el of document.querySelectorAll('label[for]')) {
        if (el.textContent.trim() !== text) continue;
        const input = el.closest('.mantine-Flex-root').querySelector('input');
        return input ? input.value : null; }
    return null; }"""
"""The value of the read-only text box labelled ``text`` (the time readout)."""
SLIDER_DISABLED = "(id) => document.querySelector(`[id='${id}'] [role=slider]`).getAttribute('aria-disabled')"


def test_a_follower_follows_the_lecturers_scrubbing(chromium) -> None:
    with running_app("tennis_racket", presenter=True, pin=PIN) as app:
        small = {"width": 1024, "height": 720}
        lecturer, lecturer_client = open_page(chromium, app, viewport=small)
        try:
            pin_box = "xpath=//label[text()='Presenter PIN']/ancestor::div[contains(@class,'Flex-root')][1]//input"
            lecturer.locator(pin_box).first.fill(PIN)
            wait_for(lambda: app.classroom._panels[lecturer_client.client_id].pin.value == PIN, what="the PIN")
            click(lecturer.get_by_role("button", name="Present"))
            wait_for(lambda: lecturer_client.client_id in app.classroom.presenters, what="the page to present")
            follower, _ = open_page(chromium, app, viewport=small)
            try:
                wait_for(lambda: app.time > 2.2, 60, what="the clock to run")
                click(lecturer.get_by_role("button", name="Pause"))
                wait_for(lambda: not app.simulation.playing, 20, what="the lecturer's pause")
                paused_in_page(lecturer, app)
                for fraction in (0.25, 0.6):
                    drag_and_wait(lecturer, app, fraction)
                    shown = slider_value(lecturer, TIMELINE)
                    # The follower's slider and its time readout show the instant the lecturer chose.
                    wait_for(lambda s=shown: slider_value(follower, TIMELINE) == s, 30, what="the follower's slider")
                    wait_for(
                        lambda: follower.evaluate(READOUT, "Time (s)") == f"{app.time:.2f}",
                        30,
                        what="the follower's time",
                    )
                # A follower's own drag is refused: the lecture's time stays.
                t = app.time
                assert follower.evaluate(SLIDER_DISABLED, control_id(follower, TIMELINE)) == "true"
                track = follower.locator(f"[id='{control_id(follower, TIMELINE)}'] .mantine-Slider-track").first
                box = track.bounding_box()
                follower.mouse.click(box["x"] + 0.9 * box["width"], box["y"] + box["height"] / 2)
                follower.wait_for_timeout(500)  # what is not sent cannot be waited for
                assert app.time == t
            finally:
                follower.close()
        finally:
            lecturer.close()


EVENTS = """() => { const list = [...document.querySelectorAll('li')].map(li => li.textContent)
    .filter(t => t.includes('half-turn')); return list; }"""


def test_the_event_list_in_the_page_times_the_half_turns_half_a_period_apart(chromium) -> None:
    with scene_page(chromium, "tennis_racket") as (app, page):
        scene = app.scene
        app.simulation.timeline.seek(6.0)  # paused with half-turns before and after
        click(page.locator(".rbl-folder", has_text="Measure"))
        lines = wait_for(lambda: len(page.evaluate(EVENTS)) >= 3 and page.evaluate(EVENTS), 30, what="the events")
        times = [float(re.search(r"([0-9.]+) s:", line).group(1)) for line in lines]
        period = FreeBody(scene.moments).period(scene.omega0)  # the physics API's, from the scene's start
        assert np.allclose(np.diff(times), period / 2.0, atol=1e-4)  # shown to 0.1 ms
        first = flip_events(scene.motion, 0.0, 10.0)[0].time
        assert any(abs(t - first) < 5e-5 for t in times)
