"""The teacher's view of private sessions (``rigid-body-lab --private --pin PIN``): the table, Spotlight,
and what is refused.

Real websocket clients on 127.0.0.1 stand in for browsers (tests/harness.py's raw_client); the loop does
not run (``start_loop=False``), so every session's clock moves only when a test calls ``frame`` and the
table only when a test calls ``refresh``.
"""

from __future__ import annotations

import contextlib
import gc
import re
import time
import weakref

import numpy as np
import pytest

from app.teaching import presenter
from app.teaching.pin_gate import PinGate
from app.teaching.teacher import MAX_NAME, Row, clean_name, table_html
from app.teaching.teacher_panel import WATCHED
from tests.app.reading import received_until
from tests.app.serving.test_serving_modes import command
from tests.harness import (
    FRAME,
    click_button,
    raw_client,
    received,
    running_app,
    send_value,
    still_connected,
    wait_for,
)

PIN = "Lab2026"


@pytest.fixture()
def lab():
    with running_app("heavy_top", private=True, pin=PIN, start_loop=False) as app:
        yield app


def _join(app, stack):
    """A browser joins; returns (websocket, client id) once its session and its number are there."""
    before = set(app.server.get_clients())
    ws = stack.enter_context(raw_client(app, wait=False))
    # Polled finely: a browser is registered and its session made within tens of ms (35 joins a module).
    (cid,) = wait_for(lambda: set(app.server.get_clients()) - before, interval=0.005, what="the browser")
    wait_for(
        lambda: app.teacher.panel_of(cid) is not None and cid in app.sessions,
        interval=0.005,
        what="the session and its number",
    )
    return ws, cid


def _teach(app, ws, cid, pin=PIN):
    """Type ``pin`` in the browser's Teacher PIN box and press Open teacher's view."""
    panel = app.teacher.panel_of(cid)
    send_value(ws, panel.pin._impl.uuid, pin)
    wait_for(lambda: panel.pin.value == pin, what="the PIN to arrive")
    click_button(ws, panel.open._impl.uuid)


def _teacher(app, stack):
    ws, cid = _join(app, stack)
    _teach(app, ws, cid)
    wait_for(lambda: app.teacher.panel_of(cid).teaching, what="the teacher's view to open")
    return ws, cid


def _table_rows(content):
    """(session cell, scene cell, parameters cell, time cell, activity cell) of each row of the table."""
    return re.findall(
        r'<tr><th scope="row">(.*?)</th><td>(.*?)</td><td>(.*?)</td><td>(.*?)</td><td>(.*?)</td></tr>', content
    )


def _seconds(text):
    """The seconds of a "Last activity" cell ("40 s ago")."""
    found = re.fullmatch(r"(\d+) s ago", text)
    assert found, text
    return int(found.group(1))


def _messages_of(app, cid):
    return [title for title, _ in app.sessions[cid].messages]


# ---------------------------------------------------------------------------------------------- pieces
def test_a_name_is_cleaned_to_letters_digits_and_a_few_marks():
    assert clean_name("  Zoë   Müller ") == "Zoë Müller"
    assert clean_name("<b>Ann</b>") == "b Ann b"
    assert clean_name("<img src=x onerror=alert(1)>") == "img src x onerror alert 1"
    assert clean_name("O'Brien-Smith_2.") == "O'Brien-Smith_2."
    assert clean_name("\u202eevil\u200b\x00me") == "evil me"  # direction override, zero width, NUL
    assert clean_name("x" * 5000) == "x" * MAX_NAME
    assert clean_name(12) == clean_name(None) == clean_name(["Ann"]) == ""
    assert clean_name("ｆｕｌｌ") == "full"  # NFKC: full-width letters are letters


def test_the_table_escapes_every_text_it_shows():
    row = Row(7, '<script>x</script>"', "<i>scene</i>", (("<b>a</b>", "1 & 2"),), 3.25, False, 75.0)
    content = table_html([row])
    assert "<script>" not in content and "<i>" not in content and "<b>" not in content
    assert "&lt;script&gt;x&lt;/script&gt;&quot;" in content and "1 &amp; 2" in content
    ((who, scene, params, clock, idle),) = _table_rows(content)
    assert who.startswith("7 · ") and clock == "3.2 s (paused)" and idle == "75 s ago"
    assert "No student is connected yet" in table_html([])


def test_the_pin_gate_limits_one_browser_and_the_room():
    gate = PinGate("4321", "where")
    for i in range(presenter.ATTEMPTS):
        assert gate.refusal("a", "0000", now=100.0 + i) == ("Wrong PIN", "where")
    assert gate.refusal("a", "4321", now=110.0) == ("Too many wrong PINs", "Try again in 54 s.")
    assert gate.refusal("a", "4321", now=104.0 + presenter.LOCKOUT + 0.5) is None
    assert gate.refusal("b", 4321, now=200.0) == ("Wrong PIN", "where")  # not text: wrong, never an error
    assert gate.refusal("b", " 4321 ", now=201.0) is None  # spaces around it are forgiven, as the presenter's
    # The room's budget stops the addresses that guessed, never the right PIN from one that did not.
    room = PinGate("4321", "where", identify=lambda cid: (cid, cid.split("/")[0]))
    for i in range(presenter.CLASS_ATTEMPTS):
        assert room.refusal(f"10.0.0.{i % 10}/c{i}", "0000", now=300.0)[0] == "Wrong PIN"
    assert room.refusal("10.0.0.1/fresh", "4321", now=330.0) == ("Too many wrong PINs", "Try again in 30 s.")
    assert room.refusal("10.0.0.1/fresh", "4321", now=360.5) is None
    assert room.refusal("10.0.0.99/lecturer", "4321", now=330.0) is None


# ---------------------------------------------------------------------------------------------- the table
def test_the_command_says_how_to_open_the_teachers_view():
    with command("--private", "--pin", PIN) as (_, next_line):
        printed = []
        while not printed or not printed[-1].startswith("Teacher's view"):
            line = next_line()
            assert line is not None, f"the command stopped printing: {printed}"
            printed.append(line.rstrip("\n"))
    assert "Mode: private (every browser has its own simulation)" in printed
    assert (
        printed[-1] == "Teacher's view: type the --pin in the panel's “Teacher PIN” box to open the table of sessions"
    )


def test_every_student_is_told_the_teacher_can_see_the_session(lab):
    with raw_client(lab):
        wait_for(lambda: lab.sessions and lab.teacher.panel_of(next(iter(lab.sessions))), what="the session")
        (cid,) = lab.sessions
        assert lab.teacher.panel_of(cid).number.content == f"**Session 1** · {WATCHED}"


def test_without_a_pin_private_mode_has_no_teachers_view():
    with running_app("heavy_top", private=True, start_loop=False) as app, raw_client(app):
        assert app.teacher is None
        wait_for(lambda: len(app.sessions) == 1, what="the session")
        (session,) = app.sessions.values()
        labels = {str(getattr(h, "label", "")) for h in session.server.gui._gui_input_handle_from_uuid.values()}
        assert "Teacher PIN" not in labels and "Your name" not in labels


def test_the_table_of_five_sessions(lab):
    app = lab
    with contextlib.ExitStack() as stack:
        teacher_ws, teacher = _teacher(app, stack)
        students = [_join(app, stack) for _ in range(5)]
        (ws0, s0), (ws1, s1), (ws2, s2), _, (ws4, s4) = students
        numbers = {cid: app.teacher.number_of(cid) for _, cid in students}
        assert sorted(numbers.values()) == list(range(2, 7))  # the teacher joined first: number 1
        # Two students give names (one with markup), one picks another scene, one changes a parameter.
        send_value(ws0, app.teacher.panel_of(s0).name._impl.uuid, "Ada Lovelace")
        send_value(ws1, app.teacher.panel_of(s1).name._impl.uuid, "<b>Bob</b>")
        picker = app.sessions[s2].scene_picker
        send_value(ws2, picker._impl.uuid, "Tennis racket: the intermediate axis")
        spin = app.sessions[s4].scene.params.sliders["spin"]
        send_value(ws4, spin._impl.uuid, 12.5)
        wait_for(lambda: getattr(app.sessions[s2].scene, "name", None) == "tennis_racket", what="the scene switch")
        wait_for(lambda: app.sessions[s4].scene.params.values["spin"] == 12.5, what="the new spin")
        wait_for(lambda: app.teacher.name_of(s1) == "b Bob b", what="the names")
        for _ in range(30):  # half a second of student 0's clock; student 3 is paused at 0
            app.sessions[s0].frame(FRAME)
        app.sessions[students[3][1]].set_playing(False)
        now = time.time()
        app.teacher.refresh(now)
        panel = app.teacher.panel_of(teacher)
        rows = _table_rows(panel.table.content)
        assert [who for who, *_ in rows] == ["2 · Ada Lovelace", "3 · b Bob b", "4", "5", "6"]
        by_number = {int(who.split(" ")[0]): (scene, params, clock) for who, scene, params, clock, _ in rows}
        assert set(by_number) == set(numbers.values())  # every student, and not the teacher
        assert by_number[numbers[s2]][0] == "Tennis racket: the intermediate axis"
        assert all(by_number[numbers[c]][0] == "Heavy top" for _, c in students if c != s2)
        assert "spin ω₃ (rad/s) = 12.5" in by_number[numbers[s4]][1]
        assert "spin ω₃ (rad/s) = 10" in by_number[numbers[s0]][1]
        assert by_number[numbers[s0]][2] == "0.5 s"
        assert by_number[numbers[students[3][1]]][2] == "0.0 s (paused)"
        assert panel.choice.options == tuple(str(n) for n in sorted(numbers.values()))
        # The table is what the teacher's page receives; no student's page receives any of it.
        table_uuid = panel.table._impl.uuid
        received(teacher_ws, 0.2)
        drained = [received(ws, 0.0) for ws, _ in students]
        assert all(not any("rbl-teacher" in str(m) for m in got) for got in drained)
        app.sessions[s0].frame(FRAME * 6)
        app.teacher.refresh(now + 1.0)
        updates = [m for m in received(teacher_ws, 0.5) if m.get("uuid") == table_uuid]
        assert len(updates) == 1 and set(updates[0]["updates"]) == {"content"}  # one element, one message
        assert "0.6 s" in updates[0]["updates"]["content"]
        # Last activity: nothing happens for 40 s (more since each joined or typed), then student 4 moves a slider.
        app.teacher.refresh(now + 40.0)
        idle = {who.split(" ")[0]: activity for who, _, _, _, activity in _table_rows(panel.table.content)}
        assert all(40 <= _seconds(text) < 100 for text in idle.values()), idle
        send_value(ws4, spin._impl.uuid, 11.0)
        wait_for(lambda: app.sessions[s4].scene.params.values["spin"] == 11.0, what="the change")
        app.teacher.refresh(now + 41.0)
        idle = {who.split(" ")[0]: activity for who, _, _, _, activity in _table_rows(panel.table.content)}
        assert idle.pop(str(numbers[s4])) == "now" and all(41 <= _seconds(text) < 100 for text in idle.values())
    wait_for(lambda: not app.sessions, what="every session to be freed")


def test_the_table_of_thirty_sessions_one_that_leaves_and_a_spotlight(lab):
    app = lab
    with contextlib.ExitStack() as stack:
        teacher_ws, teacher = _teacher(app, stack)
        students = [_join(app, stack) for _ in range(30)]
        panel = app.teacher.panel_of(teacher)
        now = time.time()
        rows = app.teacher.refresh(now)
        assert len(rows) == 30 and len(_table_rows(panel.table.content)) == 30
        assert {r.scene for r in rows} == {"Heavy top"}
        assert len(panel.choice.options) == 30
        # A refresh that finds nothing new sends the teacher nothing: neither the table nor the dropdown.
        table = panel.table._impl.uuid
        current = panel.table.content

        def has_current(ms: list) -> bool:  # this refresh's table, not an earlier 1 Hz one's of fewer students
            return any(m.get("uuid") == table and m.get("updates", {}).get("content") == current for m in ms)

        shown = received_until(teacher_ws, has_current)
        assert has_current(shown)  # this refresh's table has come
        assert app.teacher.refresh(now) == rows
        quiet = [
            m for m in received(teacher_ws, 0.3) if m.get("uuid") in (panel.table._impl.uuid, panel.choice._impl.uuid)
        ]
        assert not quiet, quiet
        # One leaves: gone from the table and from the dropdown at the next refresh.
        ws, leaving = students[7]
        number = app.teacher.number_of(leaving)
        ws.close()
        wait_for(lambda: leaving not in app.sessions and app.teacher.number_of(leaving) is None, what="it to leave")
        app.teacher.refresh()
        assert str(number) not in panel.choice.options and len(_table_rows(panel.table.content)) == 29
        # Spotlight the last of the thirty, which has picked the pendulum and paused 0.75 s in.
        _, last = students[-1]
        app.sessions[last].switch_scene("pendulum")
        for _ in range(45):
            app.sessions[last].frame(FRAME)
        app.sessions[last].set_playing(False)
        assert app.teacher.spotlight(app.server.get_clients()[teacher], str(app.teacher.number_of(last)))
        own = app.sessions[teacher]
        assert own.scene.name == "pendulum" and own.time == app.sessions[last].time == pytest.approx(0.75, abs=1e-12)
        assert own.snapshot()["controls"] == app.sessions[last].snapshot()["controls"] and not own.playing
        assert still_connected(teacher_ws, app=own)


def test_a_departed_students_session_is_collected_although_a_teacher_watched_it(lab):
    # The desk keeps a browser's number, name and controls, never its Simulation: once the browser has
    # left and the table has been rewritten, nothing of the desk holds the session alive.
    app = lab
    with contextlib.ExitStack() as stack:
        _teacher(app, stack)
        with raw_client(app) as ws:
            (cid,) = wait_for(lambda: set(app.sessions) - set(app.teacher.teachers), what="the student's session")
            wait_for(lambda: app.teacher.number_of(cid), what="its number")
            session, scene = weakref.ref(app.sessions[cid]), weakref.ref(app.sessions[cid].scene)
            assert len(app.teacher.refresh()) == 1
            assert app.teacher.spotlight(
                app.server.get_clients()[next(iter(app.teacher.teachers))], str(app.teacher.number_of(cid))
            )
            ws.close()
        wait_for(lambda: cid not in app.sessions and app.teacher.number_of(cid) is None, what="it to leave")
        assert app.teacher.refresh() == []
        wait_for(lambda: _collected(session) and _collected(scene), timeout=10, what="the session to be collected")


def _collected(ref) -> bool:
    gc.collect()
    return ref() is None


# ---------------------------------------------------------------------------------------------- Spotlight
def test_spotlight_copies_the_state_and_leaves_the_students_session_untouched(lab):
    app = lab
    with contextlib.ExitStack() as stack:
        _, teacher = _teacher(app, stack)
        _, student = _join(app, stack)
        session = app.sessions[student]
        # A friction top (stepped: its attitude is state, not a formula of t) 1.2 s into its motion.
        sliders = session.scene.params.sliders
        sliders["friction"].value, sliders["spin"].value, sliders["theta0"].value = 0.02, 14.0, 20.0
        assert session.scene.params.values["friction"] == 0.02 and session.scene.params.values["theta0"] == 20.0
        session.set_speed(1.0)
        session.set_playing(True)
        for _ in range(72):
            session.frame(FRAME)
        before = session.snapshot()
        clock, frames, scene = session.time, session.frames, session.scene
        attitude = session.scene.R.copy()
        assert clock == pytest.approx(1.2, abs=1e-12) and before["motion"] and not scene.landed  # still spinning

        own = app.sessions[teacher]
        client = app.server.get_clients()[teacher]
        assert app.teacher.spotlight(client, str(app.teacher.number_of(student)))
        assert own.messages[-1][0] == "Spotlight"
        # The teacher's view is the student's state.
        copied = own.snapshot()
        assert copied["scene"] == "heavy_top" and copied["controls"] == before["controls"]
        assert copied["time"] == clock and copied["playing"] is True and copied["speed"] == 1.0
        np.testing.assert_array_equal(own.scene.R, attitude)
        np.testing.assert_array_equal(own.scene.L_body, before["motion"]["L_body"])
        # The student's session is untouched: the same scene object, state, clock and frame count.
        after = session.snapshot()
        assert session.scene is scene and session.time == clock and session.frames == frames
        assert after["controls"] == before["controls"] and after["playing"] == before["playing"]
        np.testing.assert_array_equal(after["motion"]["R"], before["motion"]["R"])
        np.testing.assert_array_equal(after["motion"]["L_body"], before["motion"]["L_body"])
        assert "Spotlight" not in [t for t, _ in session.messages]
        # Nothing is shared: the copy runs on, the student's stays; then both run the same motion.
        own.frame(FRAME * 30)
        assert session.time == clock and np.array_equal(session.scene.R, attitude)
        assert not np.array_equal(own.scene.R, attitude)
        session.frame(FRAME * 30)
        np.testing.assert_allclose(session.scene.R, own.scene.R, rtol=0, atol=1e-12)


def test_spotlight_of_another_scene_switches_the_teachers_view_and_takes_the_camera(lab):
    app = lab
    with contextlib.ExitStack() as stack:
        _, teacher = _teacher(app, stack)
        _, student = _join(app, stack)
        session = app.sessions[student]
        session.switch_scene("tennis_racket")
        session.set_time(2.5)
        client = app.server.get_clients()[teacher]
        assert app.teacher.spotlight(client, str(app.teacher.number_of(student)))
        own = app.sessions[teacher]
        assert own.scene.name == "tennis_racket" and own.time == 2.5
        student_camera = app.server.get_clients()[student].camera
        np.testing.assert_array_equal(own.view[0], student_camera.position)
        np.testing.assert_array_equal(own.view[1], student_camera.look_at)


# ---------------------------------------------------------------------------------------------- refusals
def test_wrong_pins_are_refused_to_that_browser_and_limited(lab):
    app = lab
    with contextlib.ExitStack() as stack:
        ws, cid = _join(app, stack)
        other_ws, other = _join(app, stack)
        _teach(app, ws, cid, "0000")
        wait_for(lambda: "Wrong PIN" in _messages_of(app, cid), what="the wrong PIN to be refused")
        assert not app.teacher.panel_of(cid).teaching and cid not in app.teacher.teachers
        # Not text, and far too long: refused by the input checks before the desk sees them.
        pin_box = app.teacher.panel_of(cid).pin
        send_value(ws, pin_box._impl.uuid, 1e308)
        send_value(ws, pin_box._impl.uuid, "9" * 100_000)
        wait_for(lambda: "takes at most" in app.sessions[cid].status.content, what="the refusals")
        assert "must be text" in " ".join(body for _, body in app.sessions[cid].messages)
        client = app.server.get_clients()[cid]
        for _ in range(presenter.ATTEMPTS - 1):
            assert not app.teacher.open_view(client, "1111")
        assert not app.teacher.open_view(client, PIN)  # locked out: even the right PIN waits
        assert "Too many wrong PINs" in _messages_of(app, cid)
        assert not any(t in _messages_of(app, other) for t in ("Wrong PIN", "Too many wrong PINs"))
        assert still_connected(ws, app=app.sessions[cid]) and still_connected(other_ws, app=app.sessions[other])


def test_bad_spotlights_are_refused_to_the_teacher_only(lab):
    app = lab
    with contextlib.ExitStack() as stack:
        teacher_ws, teacher = _teacher(app, stack)
        student_ws, student = _join(app, stack)
        leaving_ws, leaving = _join(app, stack)
        own, client = app.sessions[teacher], app.server.get_clients()[teacher]
        before = own.snapshot()
        told = len(app.sessions[student].messages)
        # A student cannot spotlight: it has no such control, and the desk refuses it anyway.
        assert not app.teacher.spotlight(app.server.get_clients()[student], str(app.teacher.number_of(leaving)))
        assert app.sessions[student].messages[-1] == ("Refused", "Only the teacher's view can spotlight a session.")
        told += 1
        # Numbers that are not numbers, huge ones, and the teacher's own.
        for bad in ("abc", "1e308", "-1", "99999999999", 10**30, None, str(app.teacher.number_of(teacher))):
            assert not app.teacher.spotlight(client, bad)
            assert own.messages[-1][0] == "Refused"
        assert own.messages[-1] == (
            "Refused",
            f"Session {app.teacher.number_of(teacher)} is a teacher's view, not a student's.",
        )
        # A session that has just left.
        number = str(app.teacher.number_of(leaving))
        leaving_ws.close()
        wait_for(lambda: leaving not in app.sessions, what="it to leave")
        assert not app.teacher.spotlight(client, number)
        assert own.messages[-1] == ("Refused", f"Session {number} is not connected (it may just have left).")
        # The same through the page's controls: a value the dropdown does not offer is refused by the checks.
        app.teacher.refresh()  # the dropdown now offers the one student left
        panel = app.teacher.panel_of(teacher)
        assert panel.choice.options == (str(app.teacher.number_of(student)),)
        send_value(teacher_ws, panel.choice._impl.uuid, "<script>")
        wait_for(lambda: "has no option" in own.status.content, what="the dropdown's refusal")
        click_button(teacher_ws, panel.spotlight._impl.uuid)  # the choice is still a live session: it works
        wait_for(lambda: own.messages[-1][0] == "Spotlight", what="the spotlight")
        assert own.snapshot()["scene"] == before["scene"]
        assert len(app.sessions[student].messages) == told  # the teacher's refusals went to the teacher only
        assert still_connected(teacher_ws, app=own) and still_connected(student_ws, app=app.sessions[student])


def test_a_pool_process_numbers_its_own_and_says_when_the_pools_table_is_unreachable(monkeypatch):
    """Process 2 of a pool of 3 whose Redis does not answer (nothing listens on port 1): it numbers its
    sessions 2, 5, 8, shows its own sessions under a notice, and refuses a Spotlight of another process's
    number with the reason; its own sessions are spotlighted as ever."""
    monkeypatch.setenv("RBL_REDIS", "127.0.0.1:1")
    monkeypatch.setenv("RBL_POOL", "homework 2 3")
    with running_app("heavy_top", private=True, pin=PIN, start_loop=False) as app, contextlib.ExitStack() as stack:
        assert app.teacher.place is not None and app.teacher.pool is not None
        teacher_ws, teacher = _teacher(app, stack)
        _, student = _join(app, stack)
        assert (app.teacher.number_of(teacher), app.teacher.number_of(student)) == (2, 5)
        app.teacher.pool.start()  # the loop does not run here: the pool's thread alone
        wait_for(lambda: app.teacher.pool.failures >= 1, what="a cycle that Redis did not answer")
        assert app.teacher.pool.writes == 0 and not app.teacher.pool.available
        rows = app.teacher.refresh()
        table = app.teacher.panel_of(teacher).table.content
        assert [row.number for row in rows] == [5] and "Redis at 127.0.0.1:1" in table and "cannot be reached" in table
        client, own = app.server.get_clients()[teacher], app.sessions[teacher]
        assert not app.teacher.spotlight(client, "3")  # process 3's number
        title, body = own.messages[-1]
        assert title == "Refused" and body.startswith("Session 3: the pool's shared table (Redis at 127.0.0.1:1)")
        assert app.teacher.spotlight(client, "5") and own.messages[-1][0] == "Spotlight"
        # A request from the pool for a session here is answered with its state text, read only.
        assert app.teacher.answer(5).startswith("rbl") and app.teacher.answer(5) == app.teacher.answer(5)
        with pytest.raises(ValueError, match="teacher's view"):
            app.teacher.answer(2)
        with pytest.raises(ValueError, match="not connected"):
            app.teacher.answer(8)
