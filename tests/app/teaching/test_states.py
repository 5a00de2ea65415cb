"""States as text: "Copy state" gives a short text, ``open_state`` / ``--state TEXT``
reopen exactly that state; a bad or foreign text is refused with a message and nothing changes."""

from __future__ import annotations

import base64
import json
import zlib
from types import SimpleNamespace

import numpy as np
import pytest

from app.__main__ import main
from app.teaching.states import MAX_JSON, PREFIX, parse_state, state_text
from tests.harness import raw_client, running_app, wait_for

FRICTION = "sleeping top with friction: falls"


def _pack(obj) -> str:
    raw = json.dumps(obj).encode()
    return PREFIX + base64.urlsafe_b64encode(zlib.compress(raw)).decode()


def _same(a: dict, b: dict) -> None:
    assert a["scene"] == b["scene"] and a["controls"] == b["controls"]
    assert a["time"] == b["time"] and a["speed"] == b["speed"] and a["playing"] == b["playing"]
    assert a["motion"].keys() == b["motion"].keys()
    for key in a["motion"]:
        np.testing.assert_array_equal(a["motion"][key], b["motion"][key])


def test_a_state_round_trips_through_its_text_exactly():
    with running_app("heavy_top", start_loop=False) as app:
        assert app.scene.presets.choose(FRICTION)
        app.set_playing(True)
        app.set_speed(2.5)
        for _ in range(40):
            app.frame(1.0 / 60.0)
        before = app.simulation.snapshot()
        text = app.state_text()
        assert text.startswith(PREFIX) and len(text) < 1000
        with running_app("wobble", start_loop=False) as other:
            other.simulation.open_state(text)
            _same(other.simulation.snapshot(), before)
            # The stepped friction top goes on from the same attitude: the next frames agree too.
            app.frame(1.0 / 60.0)
            other.frame(1.0 / 60.0)
            np.testing.assert_array_equal(app.scene.R, other.scene.R)
        # The parsed text is the snapshot (state → text → state).
        _same(parse_state(text), before)


def test_the_copy_button_writes_the_text_and_open_brings_it_back_with_the_camera():
    with running_app("pendulum", start_loop=False) as app:
        camera = SimpleNamespace(position=np.array([1.0, -2.0, 0.5]), look_at=np.array([0.0, 0.0, 0.3]))
        client = SimpleNamespace(camera=camera, client_id="someone")
        app.simulation.panel.on_copy_state(SimpleNamespace(client=client))
        text = app.simulation.state_box.value
        assert parse_state(text)["camera"] == {"position": [1.0, -2.0, 0.5], "look_at": [0.0, 0.0, 0.3]}
        app.switch_scene("wobble")
        app.simulation.open_state(text)
        assert app.scene.name == "pendulum"
        np.testing.assert_allclose(app.server.initial_camera.position, [1.0, -2.0, 0.5])


def test_a_state_text_opens_the_app_there_and_every_private_session():
    with running_app("heavy_top", start_loop=False) as source:
        source.set_speed(3.0)
        text = source.state_text()
    with running_app(state=text, start_loop=False) as app:
        assert app.scene.name == "heavy_top" and app.simulation.speed == 3.0
    with running_app(private=True, state=text) as app, raw_client(app):
        session = wait_for(lambda: next(iter(app.sessions.values()), None), what="the session")
        wait_for(lambda: session.scene is not None and session.speed == 3.0, what="the session at the state")


BAD = {
    "not text": (12, "is text"),
    "foreign": ("https://example.org/?s=1", "starts with"),
    "too long": (PREFIX + "A" * 3000, "at most 2000"),
    "cut short": (PREFIX + base64.urlsafe_b64encode(zlib.compress(b'{"scene": "wobble"}')[:-4]).decode(), "cut short"),
    "not json": (PREFIX + base64.urlsafe_b64encode(zlib.compress(b"hello")).decode(), "damaged"),
    "bomb": (PREFIX + base64.urlsafe_b64encode(zlib.compress(b"0" * (4 * MAX_JSON), 9)).decode(), "more than"),
    "not a state": (_pack([1, 2, 3]), "does not hold a state"),
    "unknown scene": (_pack({"scene": "orrery"}), "does not have"),
    "bad controls": (_pack({"scene": "wobble", "controls": [["spin", {"x": 1}]]}), "controls"),
    "nan time": (
        _pack({"scene": "wobble", "controls": [], "time": float("nan"), "speed": 1, "playing": True}),
        "time",
    ),
    "absurd speed": (_pack({"scene": "wobble", "controls": [], "time": 0, "speed": 1e9, "playing": True}), "speed"),
    "bad camera": (
        _pack({"scene": "wobble", "controls": [], "time": 0, "speed": 1, "playing": True, "camera": {"position": [1]}}),
        "camera",
    ),
}


@pytest.mark.parametrize("name", list(BAD))
def test_a_bad_text_is_refused_with_a_message(name):
    text, message = BAD[name]
    with pytest.raises(ValueError, match=message):
        parse_state(text)


def test_a_refused_control_leaves_the_previous_state_whole():
    with running_app("pendulum", start_loop=False) as app:
        app.set_speed(4.0)
        before = app.simulation.snapshot()
        good = parse_state(state_text({**before, "scene": "wobble", "controls": [], "motion": {}}))
        text = state_text({**good, "controls": [("no such slider", 1.0)]})
        with pytest.raises(ValueError, match="no such slider"):
            app.simulation.open_state(text)
        _same(app.simulation.snapshot(), before)
        # A value beyond a slider's range is clamped to it, as a browser's would be.
        wobble = state_text({**good, "controls": [("|ω| (rad/s)", 1e9)]})
        app.simulation.open_state(wobble)
        assert app.scene.params.values["spin"] == 10.0


def test_the_command_refuses_a_bad_state_before_starting(capsys):
    with pytest.raises(SystemExit) as info:
        main(["--state", "not-a-state", "--port", "0"])
    assert info.value.code == 2
    assert "--state: not a Rigid Body Lab state" in capsys.readouterr().err


OLD_STATE = (
    "rbl1:eNptks1Kw0AUhV_lMqsIsaY_SdpuXSkq4raUMk3HZDCZCTNTtZRCbUVxrQ8irlx3LfoOeRLvJKlUMatwz8m535zJnOiICUb6JGH0ejYy"
    "MicuiaQwSqaa9AcDonMu4OupWK3BUXRyoPeI22w1_KE7IIanBj7fi9USnM0rCh2v4VmBC244TSFXLGJac4kRDx-PpXEbUluPitUd0LGcGjAJA8Nz"
    "cK5iyDZvpadTe9Y7HnrL9S9Ty5pOIYbi_hmcY0tYhZfwl4pHxiJE4JxBBjvLzxXTzOCRi-ULRImUGtMtNU4BZ6Q8paIRg5SJ2CTg5JILU5bge2XG"
    "ocxyqhjccJRRY7GiRioMFRKrrerYTkEblgPG1BD-cOiSTFo80p-TC1s5srv7qNWQ1VsYBF4Hn3az2e2F3aZ1BJ1W2A0Drxd0A7_da_-Y_wr_fG_3"
    "nozGcjLDlfUyt7xWklIxYZNqPFy4eMsZ_iEY4btYKLOSRSR5SmdcxKRv1JQtvgEMC7YG"
)
"""A state text the app wrote before its sliders were named by key (by label): the heavy top, spin 12.5 rad/s,
tilt 40°, at t = 0.75 s."""


def test_sliders_are_named_by_their_keys_and_a_state_written_by_labels_still_opens():
    old = parse_state(OLD_STATE)
    assert ["spin ω₃ (rad/s)", 12.5] in [list(c) for c in old["controls"]]  # the old text names sliders by label
    with running_app("heavy_top", start_loop=False) as app:
        app.simulation.open_state(OLD_STATE)
        assert app.scene.params.values["spin"] == 12.5 and app.scene.params.values["theta0"] == 40.0
        assert app.time == 0.75
        written = parse_state(app.state_text())
        names = [name for name, _ in written["controls"]]
        assert names[:7] == ["spin", "theta0", "phidot0", "I1", "I3", "mgl", "friction"]
        assert ("spin", 12.5) in written["controls"]


def test_a_state_survives_a_slider_relabelled():
    """A slider's label is wording; its key is its name: a state saved before the label changed still opens."""
    with running_app("heavy_top", start_loop=False) as app:
        assert app.scene.params.offer({"spin": 17.0})
        text = app.state_text()
        app.scene.params.sliders["spin"].label = "rate of spin ω₃ (rad/s)"
        assert app.scene.params.offer({"spin": 3.0})
        app.simulation.open_state(text)
        assert app.scene.params.values["spin"] == 17.0
        with pytest.raises(ValueError, match="“no such control”, which the scene does not have"):
            app.simulation.open_state(
                _pack(
                    {
                        "scene": "heavy_top",
                        "controls": [["no such control", 1.0]],
                        "motion": {},
                        "time": 0.0,
                        "speed": 1.0,
                        "playing": False,
                    }
                )
            )
        assert app.scene.params.values["spin"] == 17.0  # refused: the last good state kept
