"""Presenter mode: followers read-only, presenters with the PIN, explorers with a copy of their own.

Real websocket clients on 127.0.0.1 stand in for browsers (tests/harness.py's raw_client); what they
receive is decoded from viser's wire format (``received``), so these tests see what a page would draw.
"""

from __future__ import annotations

import numpy as np
import pytest

from app.serving.simulation import Simulation
from app.teaching import presenter
from app.teaching.presenter import Classroom, check_pin, new_pin
from tests.app.reading import received_until
from tests.harness import click_button, drain, raw_client, received, running_app, send_value, still_connected, wait_for

PIN = "4321"


@pytest.fixture()
def lecture():
    with running_app("heavy_top", presenter=True, pin=PIN) as app:
        yield app


def _cid(app, before):
    new = set(app.server.get_clients()) - before
    assert len(new) == 1
    return new.pop()


def _join(app, stack):
    """A browser joins; returns (websocket, client id, its panel)."""
    before = set(app.server.get_clients())
    ws = stack.enter_context(raw_client(app))
    cid = _cid(app, before)
    wait_for(lambda: cid in app.classroom._panels, what="the browser's own panel")
    return ws, cid, app.classroom._panels[cid]


def _present(app, ws, panel, pin):
    send_value(ws, panel.pin._impl.uuid, pin)
    wait_for(lambda: panel.pin.value == pin, what="the PIN to arrive")
    click_button(ws, panel.present._impl.uuid)


def _shown_value(messages, uuid):
    """The value a page shows for a control after these messages (its creation, then its updates)."""
    value = None
    for m in messages:
        if m.get("uuid") == uuid:
            if "props" in m:
                value = m["value"]
            elif "value" in m.get("updates", {}):
                value = m["updates"]["value"]
    return value


def _created(messages, uuid):
    """The messages creating control ``uuid`` (with its props), in order."""
    return [m for m in messages if m.get("uuid") == uuid and "props" in m]


def _replayed(messages):
    """viser's end of the replay of the state a joining page is sent has come."""
    return any(m.get("type") == "ReplayDoneMessage" for m in messages)


def _enables(message, uuid):
    return message.get("uuid") == uuid and message.get("updates", {}).get("disabled") is False


def _lecture_removed(messages, spin, app):
    """An explorer's page was told to remove the lecture's slider, picker and scene root."""
    removed = {m["uuid"] for m in messages if m.get("type") == "GuiRemoveMessage"}
    return {spin._impl.uuid, app.simulation.scene_picker._impl.uuid} <= removed and any(
        m.get("type") == "RemoveSceneNodeMessage" and m["name"] == "/scene" for m in messages
    )


def _uuids(messages, key="uuid"):
    return {m.get(key) for m in messages if key in m}


def test_pin_is_six_random_digits_or_checked():
    pins = {new_pin() for _ in range(50)}
    assert all(len(p) == 6 and p.isdigit() for p in pins) and len(pins) > 40
    assert check_pin("Lecture7") == "Lecture7"
    for bad in ("123", "x" * 33, "12 34", "12;4", ""):
        with pytest.raises(ValueError, match="4 to 32 letters or digits"):
            check_pin(bad)


def test_a_non_loopback_host_means_presenter_mode_and_private_is_exclusive():
    from app.serving.app import App

    with pytest.raises(ValueError, match="not both"):
        App(port=0, private=True, presenter=True, start_loop=False)
    with pytest.raises(ValueError, match="PIN"):
        App(port=0, presenter=True, pin="no", start_loop=False)


def test_a_follower_sees_the_lecture_disabled_and_cannot_change_it(lecture):
    import contextlib

    app = lecture
    with contextlib.ExitStack() as stack:
        ws, cid, panel = _join(app, stack)
        spin = app.scene.params.sliders["spin"]
        # The state a page is sent on joining, to viser's end of its replay, and the slider in it.
        messages = received_until(ws, lambda ms: _replayed(ms) and _created(ms, spin._impl.uuid))
        created = _created(messages, spin._impl.uuid)
        assert created and created[-1]["props"]["disabled"] is True  # read-only in the follower's page
        assert spin._impl.props.disabled is False  # ... but not on the server: a presenter can use it
        before = app.scene.params.values["spin"]
        send_value(ws, spin._impl.uuid, before + 1.0)
        wait_for(lambda: any("following the lecturer" in b for _, b in app.messages), what="the refusal")
        assert app.scene.params.values["spin"] == before and spin.value == before
        # Uploads and clicks are refused too (the clock's Pause is a button).
        playing = app.simulation.playing
        click_button(ws, app.simulation.play_button._impl.uuid)
        assert still_connected(ws, app=app)
        assert app.simulation.playing == playing
        # The refusal went to that browser only: the lecture's status line stays clean.
        assert "following" not in app.simulation.status.content


def test_the_pin_makes_a_presenter_wrong_pins_are_limited(lecture, monkeypatch):
    import contextlib

    app = lecture
    with contextlib.ExitStack() as stack:
        ws, cid, panel = _join(app, stack)
        other, other_id, other_panel = _join(app, stack)
        _present(app, ws, panel, "9999")
        wait_for(lambda: any(t == "Wrong PIN" for t, _ in app.messages), what="the wrong PIN to be refused")
        assert cid not in app.classroom.presenters
        drain(ws)
        _present(app, ws, panel, PIN)
        wait_for(lambda: cid in app.classroom.presenters, what="the browser to become a presenter")
        # Its controls arrive enabled again, and its changes are the lecture's.
        spin = app.scene.params.sliders["spin"]
        unlocked = [
            m
            for m in received_until(ws, lambda ms: any(_enables(m, spin._impl.uuid) for m in ms))
            if m.get("uuid") == spin._impl.uuid and "updates" in m
        ]
        assert any(m["updates"].get("disabled") is False for m in unlocked)
        before = app.scene.params.values["spin"]
        send_value(ws, spin._impl.uuid, before + 1.0)
        wait_for(lambda: app.scene.params.values["spin"] == before + 1.0, what="the presenter's change")
        # The follower still cannot, and still sees the controls disabled.
        send_value(other, spin._impl.uuid, before + 2.0)
        assert still_connected(other, app=app)
        assert app.scene.params.values["spin"] == before + 1.0
        # Wrong PINs: after ATTEMPTS, even the right one waits.
        for _ in range(presenter.ATTEMPTS):
            assert not app.classroom.present(app.server.get_clients()[other_id], "0000")
        assert not app.classroom.present(app.server.get_clients()[other_id], PIN)
        assert other_id not in app.classroom.presenters
        assert any(t == "Too many wrong PINs" for t, _ in app.messages)


def test_exploring_gives_a_copy_from_the_current_state_and_following_brings_the_lecture_back(lecture):
    import contextlib

    app = lecture
    with contextlib.ExitStack() as stack:
        lecturer, lecturer_id, lecturer_panel = _join(app, stack)
        _present(app, lecturer, lecturer_panel, PIN)
        wait_for(lambda: lecturer_id in app.classroom.presenters, what="a presenter")
        spin = app.scene.params.sliders["spin"]
        changed = spin.value + 1.5
        send_value(lecturer, spin._impl.uuid, changed)
        wait_for(lambda: app.scene.params.values["spin"] == changed, what="the lecture to change")
        wait_for(lambda: app.time > 0.3, what="the lecture's clock to run")

        student, student_id, student_panel = _join(app, stack)
        drain(student)
        click_button(student, student_panel.explore._impl.uuid)
        wait_for(lambda: student_id in app.sessions, what="the student's own copy")
        copy = app.sessions[student_id]
        assert isinstance(copy, Simulation) and copy is not app
        assert copy.scene.name == app.scene.name and copy.scene.params.values["spin"] == changed
        assert copy.time > 0.3  # it starts where the lecture was, not at t = 0
        assert app.classroom.exploring(student_id)
        # The button is relabelled just after the copy is registered: wait for it rather than race it.
        wait_for(lambda: student_panel.explore.label == "Follow the lecturer", what="the button relabelled")
        # The student's page removes the lecture's panel and nodes, then hears nothing more of it.
        removal = received_until(student, lambda ms: _lecture_removed(ms, spin, app))
        removed = {m["uuid"] for m in removal if m.get("type") == "GuiRemoveMessage"}
        assert spin._impl.uuid in removed and app.simulation.scene_picker._impl.uuid in removed
        assert any(m.get("type") == "RemoveSceneNodeMessage" and m["name"] == "/scene" for m in removal)
        send_value(lecturer, spin._impl.uuid, changed + 1.0)
        wait_for(lambda: app.scene.params.values["spin"] == changed + 1.0, what="the lecturer's next change")
        later = received(student, 1.0)
        lecture_ids = set(app.server.gui._gui_input_handle_from_uuid)
        assert not (_uuids(later) & lecture_ids), "an explorer must not receive the lecture"
        assert not any(m.get("name", "").startswith("/scene") and m.get("owner") == "" for m in later)
        # The copy is the student's: it changes it, the lecture does not move.
        own = copy.scene.params.sliders["spin"]
        send_value(student, own._impl.uuid, own.value - 2.0)
        wait_for(lambda: copy.scene.params.values["spin"] == changed - 2.0, what="the student's change")
        assert app.scene.params.values["spin"] == changed + 1.0
        assert copy.frames > 0

        # Follow the lecturer: the copy is dropped and the lecture arrives as it is now, read-only.
        click_button(student, student_panel.explore._impl.uuid)
        wait_for(lambda: student_id not in app.sessions, what="the copy to be dropped")
        back = received_until(
            student,
            lambda ms: _created(ms, spin._impl.uuid) and _shown_value(ms, spin._impl.uuid) == changed + 1.0,
        )
        replayed = [m for m in back if m.get("uuid") == spin._impl.uuid and "props" in m]
        assert replayed and replayed[-1]["props"]["disabled"] is True
        assert _shown_value(back, spin._impl.uuid) == changed + 1.0
        assert student_panel.explore.label == "Explore on my own"
        assert still_connected(lecturer, app=app) and still_connected(student, app=app)


def test_explorers_are_freed_when_they_leave(lecture):
    import contextlib

    app = lecture
    for _ in range(5):
        with contextlib.ExitStack() as stack:
            ws, cid, panel = _join(app, stack)
            click_button(ws, panel.explore._impl.uuid)
            wait_for(lambda cid=cid: cid in app.sessions, what="a copy")
        wait_for(lambda: not app.sessions and not app.classroom._panels, what="the copy and panel to be freed")
    assert app.scene is not None and app.scene.name == "heavy_top"  # the lecture goes on
    assert isinstance(app.classroom, Classroom) and not app.classroom.presenters
    # Nothing kept per departed browser: no stream state, no lock, no connection in viser.
    wait_for(lambda: not app.classroom.view._clients, what="the stream state of departed browsers to go")
    assert not app.classroom._toggling and not app.server.get_clients()


def test_a_followers_upload_is_refused_before_anything_reads_it(lecture, monkeypatch):
    import contextlib
    from types import SimpleNamespace

    import trimesh

    from app.scenes import inertia_explorer
    from tests.harness import send_upload

    app = lecture
    app.switch_scene("inertia_explorer")
    parsed: list[str] = []

    def reader(filename, content, **_):
        parsed.append(filename)
        raise ValueError(f"{filename} was read (test)")

    monkeypatch.setattr(inertia_explorer, "body_in_worker", reader)
    content = trimesh.creation.box(extents=(0.3, 0.2, 0.1)).export(file_type="stl")
    scene = app.scene
    with contextlib.ExitStack() as stack:
        ws, cid, panel = _join(app, stack)
        # Through the websocket, as a page (or a script) would send it: refused when it starts.
        before = len(app.messages)
        send_upload(ws, scene.upload._impl.uuid, "brick.stl", content)
        wait_for(lambda: any("following the lecturer" in b for _, b in app.messages[before:]), what="the refusal")
        assert still_connected(ws, app=app)
        assert not parsed and scene.uploaded is None and not app.server.gui._current_file_upload_states
        assert "following" not in app.simulation.status.content  # to that browser only
        # The scene's own callback asks first too (a file viser completed before the browser lost the right).
        client = app.server.get_clients()[cid]
        refused = scene.upload_refusals
        for callback in scene.upload._impl.update_cb:  # the callback viser runs for the upload button
            callback(SimpleNamespace(client=client, target=scene.upload))
        assert not parsed and scene.uploaded is None
        assert scene.upload_refusals == refused + 1 and "following the lecturer" in scene.last_upload_message
        # A presenter's file is read.
        _present(app, ws, panel, PIN)
        wait_for(lambda: cid in app.classroom.presenters, what="a presenter")
        send_upload(ws, scene.upload._impl.uuid, "brick.stl", content)
        wait_for(lambda: parsed == ["brick.stl"], what="the presenter's file to reach the reader")


def test_exploring_copies_an_uploaded_body_and_its_state_text_is_refused_by_name():
    """The lecture shows an uploaded mesh: a student's own copy shows the same body (not a primitive), and
    Copy state says a state text cannot carry a mesh instead of failing."""
    import contextlib

    import trimesh

    from app.teaching.states import state_text

    with running_app("inertia_explorer", presenter=True, pin=PIN) as app:
        brick = trimesh.creation.box(extents=(0.3, 0.2, 0.1)).export(file_type="stl")
        assert app.scene.load_upload("brick.stl", brick)
        lecture_label, lecture_props = app.scene.label, app.scene.props
        assert lecture_label.startswith("brick.stl")
        with contextlib.ExitStack() as stack:
            student, student_id, student_panel = _join(app, stack)
            drain(student)
            click_button(student, student_panel.explore._impl.uuid)
            wait_for(lambda: student_id in app.sessions, what="the student's own copy")
            copy = app.sessions[student_id]
            wait_for(lambda: copy.scene is not None and copy.scene.label == lecture_label, what="the body copied")
            np.testing.assert_array_equal(copy.scene.props.tensor, lecture_props.tensor)
            assert copy.scene.choice.value == app.scene.choice.value
            assert not [b for t, b in copy.messages if t == "Refused"], copy.messages
        with pytest.raises(ValueError, match="uploaded mesh"):
            state_text(app.simulation.snapshot())
