"""The motion in words: each scene's live description, before and after a change of its
parameters, says the numbers the physics API gives (three significant digits, with units), and is sent
after a change and at most every DESCRIBE_SECONDS otherwise, not every frame."""

from __future__ import annotations

import html
import math
import re

import numpy as np

from app.scenes.free_fall import FLIGHT_TIME, RISE, VELOCITY
from app.scenes.heavy_top import PRESETS
from app.scenes.wording import tip_path
from app.serving.simulation import DESCRIBE_SECONDS
from physics import G
from physics.free_body import FreeBody
from physics.heavy_top import HeavyTop
from physics.pendulum import PhysicalPendulum
from tests.harness import FRAME, open_scene

NUMBER = r"(-?[0-9.e+-]+)"


def said(app) -> str:
    """The text of the page's live region, as a browser receives it (the Html element's content)."""
    content = app.shared.panel.words.content
    assert 'aria-live="polite"' in content
    return html.unescape(re.sub(r"<[^>]+>", "", content))


def g3(x: float) -> str:
    """A number as the description says it (three significant digits)."""
    return f"{x:.3g}"


def numbers(pattern: str, text: str) -> tuple[str, ...]:
    found = re.search(pattern, text)
    assert found, f"{pattern!r} not in {text!r}"
    return found.groups()


def heavy_top_says(text: str, v: dict[str, float]) -> None:
    top = HeavyTop(v["I1"], v["I3"], v["mgl"])
    theta0 = math.radians(v["theta0"])
    motion = top.trajectory(theta0, 0.0, v["phidot0"], v["spin"] - v["phidot0"] * math.cos(theta0))
    shape = tip_path(motion.Lz, motion.L3, motion.theta_min, motion.theta_max)
    rate, lo, hi, period, spin = numbers(
        rf"Heavy top, {shape}: precessing at {NUMBER} rad/s, nutating between {NUMBER}° and {NUMBER}° every "
        rf"{NUMBER} s; spin {NUMBER} rad/s, (above|below) the sleeping threshold\.",
        text,
    )[:5]
    assert rate == g3(motion.precession_rate)
    assert (lo, hi) == (g3(math.degrees(motion.theta_min)), g3(math.degrees(motion.theta_max)))
    assert period == g3(motion.nutation_period)
    assert spin == g3(v["spin"])
    above = v["I3"] * v["spin"] > 2.0 * math.sqrt(v["mgl"] * v["I1"])
    assert ("above the sleeping" in text) == above


def test_heavy_top_says_its_motion_before_and_after_a_change(app):
    scene = open_scene(app, "heavy_top")
    app.frame(FRAME)
    before = said(app)
    assert before.startswith("Heavy top, cusps: ")  # released at rest in θ: the tip draws cusps
    heavy_top_says(before, dict(scene.params.values))
    scene.params.sliders["spin"].value = 20.0  # as a browser would (callbacks run)
    app.frame(FRAME)
    after = said(app)
    assert after != before
    heavy_top_says(after, dict(scene.params.values))
    assert "spin 20 rad/s, above the sleeping threshold" in after


def test_heavy_top_names_waves_and_loops(app):
    scene = open_scene(app, "heavy_top")
    for preset, shape in (("waves (φ̇0 = ½ × steady)", "waves"), ("loops (φ̇0 = −1 × steady)", "loops")):
        values = PRESETS[preset]
        assert callable(values)
        assert scene.params.offer(values(dict(scene.params.values)))
        app.frame(FRAME)
        assert said(app).startswith(f"Heavy top, {shape}: ")
        heavy_top_says(said(app), dict(scene.params.values))


def test_heavy_top_with_friction_says_its_tilt_and_spin_now(app):
    scene = open_scene(app, "heavy_top")
    scene.params.sliders["friction"].value = 0.02
    for _ in range(3):
        app.frame(FRAME)
    state = app.shared.last_state
    tilt, spin = numbers(rf"friction 0.02 N m s: tilted {NUMBER}°; spin {NUMBER} rad/s", said(app))
    # Said when the change was drawn (two frames ago at most): the stepped top has moved little since.
    assert abs(float(tilt) - math.degrees(state["theta"])) < 0.01 * float(tilt)
    assert abs(float(spin) - state["L_body"][2] / scene.top.I3) < 0.01 * float(spin)


def wobble_says(text: str, scene) -> None:
    v, I1, I3 = scene.params.values, scene.moments[0], scene.moments[2]
    alpha = math.radians(v["tilt"])
    w_perp, w3 = v["spin"] * math.sin(alpha), v["spin"] * math.cos(alpha)
    space, cone, body = numbers(
        rf"the symmetry axis turns about the fixed L at {NUMBER} rad/s, {NUMBER}° from it; in the body, "
        rf"ω turns about the axis at {NUMBER} rad/s",
        text,
    )
    # Lecture, "the symmetric body": φ̇ = |L|/I₁, Ω = ω₃ (I₁ − I₃)/I₁, tan θ = I₁ ω⊥/(I₃ ω₃).
    assert space == g3(math.hypot(I1 * w_perp, I3 * w3) / I1)
    assert body == g3(w3 * (I1 - I3) / I1)
    assert cone == g3(math.degrees(math.atan2(I1 * w_perp, I3 * w3)))
    rates = FreeBody(scene.moments).precession_rates(scene.omega0)
    assert (space, body) == (g3(rates.space), g3(rates.body))


def test_wobble_and_free_fall_say_their_motion_before_and_after_a_change(app):
    for name in ("wobble", "free_fall"):
        scene = open_scene(app, name)
        app.frame(FRAME)
        before = said(app)
        wobble_says(before, scene)
        scene.params.sliders["tilt"].value = 40.0
        app.frame(FRAME)
        after = said(app)
        assert after != before
        wobble_says(after, scene)
    rise, flight = numbers(rf"rises {NUMBER} m and lands after {NUMBER} s", after)
    assert (rise, flight) == (g3(VELOCITY[2] ** 2 / (2 * G)), g3(2 * VELOCITY[2] / G))
    assert (rise, flight) == (g3(RISE), g3(FLIGHT_TIME))


def pendulum_says(text: str, scene) -> None:
    v = scene.params.values
    model = PhysicalPendulum(scene.props, scene.pivot, np.array([1.0, 0.0, 0.0]))
    amp = math.radians(v["amplitude"])
    swing, period, small, ell, strike = numbers(
        rf"swinging ±{NUMBER}° every {NUMBER} s \(small swings {NUMBER} s\); the centre of percussion is "
        rf"{NUMBER} m below the pivot, the strike point {NUMBER} m\.",
        text,
    )
    assert swing == g3(v["amplitude"])
    assert period == g3(float(model.period(amp)))
    assert small == g3(model.small_oscillation_period)
    assert ell == g3(model.effective_length)
    assert strike == g3(v["strike"])


def test_pendulum_says_its_swing_before_and_after_a_change(app):
    scene = open_scene(app, "pendulum")
    app.frame(FRAME)
    before = said(app)
    pendulum_says(before, scene)
    scene.params.sliders["amplitude"].value = 90.0
    app.frame(FRAME)
    assert said(app) != before
    pendulum_says(said(app), scene)
    assert "swinging ±90° every" in said(app)


def test_tennis_racket_says_it_flips_at_the_lecture_rate(app):
    scene = open_scene(app, "tennis_racket")
    app.frame(FRAME)
    for spin in (None, 9.0):
        if spin is not None:
            scene.params.sliders["spin"].value = spin
            app.frame(FRAME)
        text, moments = said(app), scene.moments
        I1, I2, I3 = moments
        w = scene.params.values["spin"]
        rate = numbers(
            rf"about axis 2, the intermediate one: it flips over and back every {NUMBER} s, growing at {NUMBER} 1/s",
            text,
        )
        # Lecture: λ² = Ω² (I₁ − I₂)(I₂ − I₃)/(I₁ I₃) about the intermediate axis.
        assert rate[1] == g3(w * math.sqrt((I1 - I2) * (I2 - I3) / (I1 * I3)))
        assert rate[1] == g3(FreeBody(moments).stability(1, w).rate)
        assert f"spun at {g3(w)} rad/s" in text


def test_inertia_explorer_says_the_principal_moments(app):
    scene = open_scene(app, "inertia_explorer")
    app.frame(FRAME)
    for px in (None, 0.2):
        if px is not None:
            scene.params.sliders["px"].value = px
            app.frame(FRAME)
        text = said(app)
        moments = scene.props.principal()[0]
        assert f"{g3(moments[0])}, {g3(moments[1])} and {g3(moments[2])} kg m² about the centre of mass" in text
        offset = np.array([scene.params.values[k] for k in ("px", "py", "pz")])
        about = np.sort(np.linalg.eigvalsh(scene.props.tensor_about(scene.props.center_of_mass + offset)))[::-1]
        assert (
            f"about the pivot {g3(float(np.linalg.norm(offset)))} m away, {g3(about[0])}, {g3(about[1])} and {g3(about[2])} kg m²"
            in text
        )


def test_the_words_are_sent_after_a_change_and_at_most_every_few_seconds(app):
    scene = open_scene(app, "heavy_top")
    sim = app.shared
    calls = []
    describe = scene.describe
    scene.describe = lambda state: calls.append(state) or describe(state)  # type: ignore[method-assign]
    app.frame(FRAME)
    calls.clear()
    for _ in range(30):  # half a second of frames, nothing changed: nothing said
        app.frame(FRAME)
    assert calls == []
    sim._described_at -= DESCRIBE_SECONDS  # as if the time had passed
    app.frame(FRAME)
    assert len(calls) == 1
    scene.params.sliders["theta0"].value = 45.0  # a change is said at once
    app.frame(FRAME)
    assert len(calls) == 2
    assert "nutating between 45° and" in said(app)
