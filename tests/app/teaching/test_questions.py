"""Class questions: the model, the lecture keys, the CSV, and the one-answer
rules with raw websocket clients standing in for browsers (tests/harness.py), whose received messages are
decoded to check what goes over the wire."""

from __future__ import annotations

import contextlib
import csv
import io
import math
import re
import urllib.request

import msgspec
import pytest
import viser
from websockets.sync.client import connect

from app.__main__ import main
from app.teaching.class_questions import parse_choices
from app.teaching.lectures import read_lecture
from app.teaching.question_panel import results_html
from app.teaching.questions import TRUTHS, Ask, Poll, VoteRefused, check_ask, histogram, true_value
from app.teaching.voters import COOKIE
from physics.heavy_top import HeavyTop
from tests.app.reading import received_until
from tests.harness import CAMERA_MESSAGE, drain, received, running_app, send_value, wait_for

PIN = "4321"
RACKET = 6  # the shipped lecture's steps (0-based) with a question
PENDULUM = 2
STEADY = 9
PHONE = 12


# ------------------------------------------------------------------ the model
@pytest.mark.parametrize(
    ("raw", "message"),
    [
        ({"question": "", "choices": ["a", "b"]}, "question: a text of 1 to 300 characters, got ''"),
        ({"question": "Q", "choices": ["a"]}, "choices: a list of 2 to 5 texts for a question, got ['a']"),
        ({"question": "Q", "choices": list("abcdef")}, "choices: a list of 2 to 5 texts"),
        ({"question": "Q"}, "choices: a list of 2 to 5 texts for a question, got None"),
        ({"question": "Q", "choices": ["a", 3]}, "choices[2]: a text of 1 to 120 characters, got 3"),
        (
            {"question": "Q", "choices": ["a", "b"], "answer": 3},
            "answer: the number of the right choice, 1 to 2, got 3",
        ),
        ({"question": "Q", "choices": ["a", "b"], "answer": True}, "answer: the number of the right choice"),
        ({"question": "Q", "range": [1, 0]}, "range: [low, high], two finite numbers with low < high, got [1, 0]"),
        ({"question": "Q", "range": [0, math.inf]}, "range: [low, high], two finite numbers"),
        ({"question": "Q", "range": [0, 1], "choices": ["a", "b"]}, "choices: a number question"),
        ({"question": "Q", "range": [0, 1], "answer": "x"}, "answer: the true value, a finite number, got 'x'"),
        ({"question": "Q", "range": [0, 1], "truth": "spin"}, "truth: one of precession_rate, centre_of_percussion"),
        (
            {"question": "Q", "range": [0, 1], "truth": "precession_rate", "answer": 0.5},
            "answer and truth: give the true value typed (answer) or from the physics (truth), not both",
        ),
        (
            {"question": "Q", "range": [0, 1], "truth": "precession_rate", "unit": "m"},
            "unit: 'precession_rate' is in rad/s",
        ),
    ],
)
def test_a_bad_question_is_refused_saying_what_was_expected_and_what_came(raw, message):
    with pytest.raises(ValueError) as caught:
        check_ask(raw, "heavy_top")
    assert str(caught.value).startswith(message)


def test_a_truth_belongs_to_its_scene():
    with pytest.raises(
        ValueError, match="'precession_rate' is a quantity of the scene 'heavy_top', the step shows 'pendulum'"
    ):
        check_ask({"question": "Q", "range": [0, 1], "truth": "precession_rate"}, "pendulum")


@pytest.mark.parametrize(
    ("body", "message"),
    [
        ('question = "Q"\nchoices = ["a"]', "step 1, choices: a list of 2 to 5 texts for a question, got ['a']"),
        ('choices = ["a", "b"]', "step 1, choices: belongs to a question; the step has no question"),
        ("answer = 2", "step 1, answer: belongs to a question"),
        (
            'question = "Q"\nrange = [0, 1]\ntruth = "centre_of_percussion"',
            "step 1, truth: 'centre_of_percussion' is a quantity of the scene 'pendulum'",
        ),
    ],
)
def test_a_lecture_with_a_bad_question_is_refused_naming_the_step_and_the_key(tmp_path, body, message):
    path = tmp_path / "q.toml"
    path.write_text(f'[[step]]\nscene = "heavy_top"\n{body}\n', encoding="utf-8")
    with pytest.raises(ValueError) as caught:
        read_lecture(str(path))
    assert message in str(caught.value)


def test_the_shipped_lecture_asks_the_precession_the_flip_and_the_centre_of_percussion():
    steps = read_lecture("rigid-body-motion").steps
    asked = {k: step.ask for k, step in enumerate(steps) if step.ask is not None}
    assert set(asked) == {PENDULUM, RACKET, 7, STEADY, PHONE}
    assert asked[RACKET].choices[asked[RACKET].answer - 1] == "flips over and back, again and again"
    assert asked[PHONE].choices[asked[PHONE].answer - 1].startswith("turns over") and asked[PHONE].about == ("flip",)
    assert "sense of the spin" in asked[7].choices[asked[7].answer - 1]
    assert (asked[PENDULUM].truth, asked[PENDULUM].unit, asked[PENDULUM].range) == (
        "centre_of_percussion",
        "m",
        (0.0, 1.0),
    )
    assert (asked[STEADY].truth, asked[STEADY].unit) == ("precession_rate", "rad/s")
    assert steps[RACKET].values == {"spin": 6.0, "log_eps": -3.0}  # the question kept the step's sliders


def test_one_answer_per_voter_changed_until_the_vote_closes():
    now = [100.0]
    poll = Poll(clock=lambda: now[0])
    with pytest.raises(VoteRefused, match="there is no question to answer"):
        poll.vote("a", "A")
    poll.ask(Ask("Q", ("x", "y", "z"), 2), "step 1")
    assert poll.vote("a", "A") == "A"
    assert poll.vote("a", 3) == "C"  # changed, by number: still one answer
    assert poll.vote("b", "B") == "B"
    assert poll.count() == 2 and poll.current.counts() == [0, 1, 1]
    for bad in ("D", "AB", 0, 4, True, None, 1.0, "a"):
        with pytest.raises(VoteRefused, match="there is no choice"):
            poll.vote("c", bad)
    now[0] = 160.0
    poll.reveal()
    with pytest.raises(VoteRefused, match="the vote on this question is closed"):
        poll.vote("a", "B")
    assert poll.answer_of("a") == "C" and poll.current.counts() == [0, 1, 1]
    assert (poll.current.closed_at, poll.current.revealed_at) == (160.0, 160.0)


def test_a_number_answer_is_a_finite_number_in_the_range():
    poll = Poll()
    poll.ask(Ask("Rate?", unit="rad/s", range=(0.0, 2.0)), "step 10")
    for bad, why in (
        ("fast", "the answer is a number, got 'fast'"),
        ("nan", "the answer is a finite number, got nan"),
        (math.inf, "the answer is a finite number, got inf"),
        (1e300, "the answer is between 0 and 2 rad/s, got 1e+300"),
        ("-0.1", "the answer is between 0 and 2 rad/s, got -0.1"),
        (None, "the answer is a finite number, got None"),
        (True, "the answer is a finite number, got True"),
    ):
        with pytest.raises(VoteRefused) as caught:
            poll.vote("a", bad)
        assert str(caught.value) == why
    assert poll.vote("a", " 0.5 ") == 0.5 and poll.vote("b", 2) == 2.0 and poll.vote("c", "−0") == 0.0
    assert poll.current.counts() == [1, 0, 1, 0, 0, 0, 0, 0, 0, 1]


def test_the_histogram_bins_are_half_open_and_the_last_is_closed():
    assert histogram([0.0, 0.1, 0.0999, 0.95, 1.0, 0.5], 0.0, 1.0, 10) == [2, 1, 0, 0, 0, 1, 0, 0, 0, 2]
    assert histogram([], -1.0, 1.0, 4) == [0, 0, 0, 0]


def test_the_true_values_come_from_the_physics_api():
    lecture = read_lecture("rigid-body-motion")
    with running_app(start_loop=False) as app:
        app.simulation.load_lecture(lecture)
        app.go_to_step(STEADY)
        top = HeavyTop(0.4, 0.2, 1.0)  # the preset: I₁ = 0.4, I₃ = 0.2 kg m², M g ℓ = 1 N m
        theta, L3 = math.radians(60.0), 0.2 * 10.0  # θ₀ = 60°, ω₃ = 10 rad/s
        # The preset starts at φ̇₀ = 0.528 rad/s, ψ̇₀ = ω₃ − φ̇₀ cos θ₀ = 9.736 rad/s: the motion the class watches.
        shown = top.precession_rate(theta, 0.0, 0.528, 10.0 - 0.528 * 0.5)
        assert true_value(lecture.steps[STEADY].ask, app.scene) == pytest.approx(shown, rel=1e-12)
        # The slow root of I₁ cos θ φ̇² − L₃ φ̇ + M g ℓ = 0; the preset's φ̇₀ is it to three decimals, and
        # the mean rate of the (barely nutating) motion is within 3e-6 of it.
        slow = (L3 - math.sqrt(L3 * L3 - 4 * 0.4 * math.cos(theta) * 1.0)) / (2 * 0.4 * math.cos(theta))
        assert top.steady_precession_rates(theta, L3)[0] == pytest.approx(slow, rel=1e-12)
        assert shown == pytest.approx(slow, rel=3e-6)
        app.go_to_step(PENDULUM)
        model = app.scene.model
        cop = float(((model.center_of_percussion() - model.pivot) ** 2).sum() ** 0.5)
        assert true_value(lecture.steps[PENDULUM].ask, app.scene) == pytest.approx(cop, rel=1e-12)
        assert true_value(lecture.steps[STEADY].ask, app.scene) is None  # not its scene: no value
    assert set(TRUTHS) == {"precession_rate", "centre_of_percussion"}
    assert true_value(Ask("Q", range=(0, 1), answer=0.25), None) == 0.25


def test_the_csv_has_every_questions_counts_and_times():
    now = [1_800_000_000.0]
    poll = Poll(clock=lambda: now[0])
    poll.ask(Ask("Flip?", ("steady", "wobble", "flips"), 3), "step 7")
    poll.vote("a", "C")
    poll.vote("b", "C")
    poll.vote("c", "A")
    now[0] += 65.0
    poll.reveal()
    poll.ask(Ask("Rate?", unit="rad/s", range=(0.0, 2.0)), "step 10", true=0.5278654505337458)
    poll.vote("a", 0.5)
    rows = list(csv.reader(io.StringIO(poll.csv())))
    assert rows[0][:3] == ["question", "asked_utc", "closed_utc"]
    assert rows[1] == [
        "1",
        "2027-01-15T08:00:00+00:00",
        "2027-01-15T08:01:05+00:00",
        "2027-01-15T08:01:05+00:00",
        "step 7",
        "Flip?",
        "A: steady",
        "1",
        "3",
        "no",
        "",
    ]
    assert [r[7] for r in rows[1:4]] == ["1", "0", "2"] and rows[3][9] == "yes"
    numbers = rows[4:]
    assert len(numbers) == 10 and numbers[0][2] == "" and numbers[0][3] == ""  # still open
    assert [r[6] for r in numbers[:3]] == ["[0, 0.2)", "[0.2, 0.4)", "[0.4, 0.6)"] and numbers[-1][6] == "[1.8, 2]"
    assert [r[7] for r in numbers] == ["0", "0", "1"] + ["0"] * 7
    assert numbers[0][9:] == ["0.527865", "rad/s"]


def test_the_presenters_own_question_is_checked():
    assert parse_choices(" Which? ", "yes\n\n no \n") == Ask("Which?", ("yes", "no"))
    for text, choices, why in (
        ("", "a\nb", "type a question"),
        ("Q", "a", "type 2 to 5 choices, one a line (got 1)"),
        ("Q", "a\nb\nc\nd\ne\nf", "(got 6)"),
        ("Q", "a\n" + "b" * 121, "at most 120 characters"),
    ):
        with pytest.raises(ValueError, match=re.escape(why)):
            parse_choices(text, choices)


# ------------------------------------------------------------------ raw clients in presenter mode
@pytest.fixture(scope="module")
def lecture_app(tmp_path_factory):
    path = tmp_path_factory.mktemp("answers") / "answers.csv"
    with running_app(presenter=True, pin=PIN, start_loop=False, lecture="rigid-body-motion", answers=str(path)) as app:
        app.export_path = path
        yield app


@contextlib.contextmanager
def _browser(app, cookie: str | None = None):
    """A raw client (with a voter cookie if given): (websocket, client id, its question panel)."""
    before = set(app.server.get_clients())
    headers = {"Cookie": f"{COOKIE}={cookie}"} if cookie else None
    ws = connect(
        f"ws://127.0.0.1:{app.port}",
        subprotocols=[f"viser-v{viser.__version__}"],
        max_size=None,
        additional_headers=headers,
        close_timeout=1,
    )
    try:
        ws.send(CAMERA_MESSAGE)
        cid = wait_for(lambda: set(app.server.get_clients()) - before, what="the client").pop()
        wait_for(lambda: cid in app.questions._panels and app.questions._panels[cid].folder, what="its question panel")
        yield ws, cid, app.questions._panels[cid]
    finally:
        ws.close()


def _cookie(app) -> str:
    """What a browser loading the page receives: its voter token."""
    with urllib.request.urlopen(app.url, timeout=10) as response:
        header = response.headers["Set-Cookie"]
    assert "HttpOnly" in header and header.startswith(f"{COOKIE}=")
    return header.split(";")[0].split("=", 1)[1]


def _notes(messages):
    return [m["props"]["body"] for m in messages if m.get("type") == "NotificationShowMessage"]


def _note_in(messages, text: str) -> bool:
    """A notification among ``messages`` says ``text``."""
    return any(text in n for n in _notes(messages))


def _text(messages) -> str:
    return msgspec.json.encode(messages).decode()


def test_a_question_step_waits_and_every_follower_answers_once(lecture_app):
    app, questions = lecture_app, lecture_app.questions
    assert questions.voters.installed
    app.go_to_step(RACKET)
    assert not app.simulation.playing and app.time == 0.0
    assert (
        "**Question.**" in app.simulation.following.text.content
        and "flips" not in app.simulation.following.text.content
    )
    question = questions.poll.current
    assert question.source == "step 7" and question.open
    with _browser(app) as (a, a_id, a_panel), _browser(app) as (b, b_id, b_panel), _browser(app) as (p, p_id, _):
        app.classroom.present(app.server.get_clients()[p_id], PIN)
        wait_for(lambda: questions._panels[p_id].presenter, what="the presenter's panel")
        p_panel = questions._panels[p_id]
        drain(a), drain(b)
        send_value(a, a_panel.choice._impl.uuid, "C")
        wait_for(lambda: questions.poll.count() == 1, what="a's answer")
        wait_for(lambda: p_panel.count.content.startswith("**1 answer**"), what="the presenter's count")
        send_value(a, a_panel.choice._impl.uuid, "A")  # changed: still one answer
        wait_for(lambda: question.votes == {f"connection {a_id}": "A"}, what="the changed answer")
        send_value(a, a_panel.choice._impl.uuid, "Z")  # no such choice
        assert _note_in(received_until(a, lambda ms: _note_in(ms, "no option 'Z'")), "no option 'Z'"), "a's refusal"
        send_value(b, b_panel.choice._impl.uuid, "C")
        wait_for(lambda: questions.poll.count() == 2, what="b's answer")
        seen_by_b = received(b, 0.5)
        assert not any("no option" in n for n in _notes(seen_by_b))  # a's refusal went to a alone
        questions.vote(app.server.get_clients()[p_id], "B")
        assert questions.poll.count() == 2  # the presenter does not vote
        # Nothing a follower received so far tells how many answered or what: no count, no chart.
        before = _text(received(a, 0.3)) + _text(seen_by_b)
        assert "answers" not in before and "so far" not in before and "histogram" not in before
        assert question.counts() == [1, 0, 1]
        send_value(p, p_panel.reveal._impl.uuid, True)
        wait_for(lambda: question.revealed_at is not None, what="the reveal")
        after = _text(received_until(b, lambda ms: "2 answers" in _text(ms) and "✓" in _text(ms)))
        assert "2 answers" in after and "✓" in after  # the chart, with the right choice marked
        assert "again and again" in app.simulation.following.text.content  # the caption with the answers
        send_value(a, a_panel.choice._impl.uuid, "B")  # after the close (a raw client ignores disabled)
        closed = received_until(a, lambda ms: _note_in(ms, "closed") or _note_in(ms, "cannot be changed"))
        assert any("closed" in n or "cannot be changed" in n for n in _notes(closed))
        assert question.counts() == [1, 0, 1]
    rows = list(csv.reader(io.StringIO(app.export_path.read_text(encoding="utf-8"))))
    assert [r[7] for r in rows if r[4] == "step 7"][-3:] == ["1", "0", "1"]


def test_a_raw_client_cannot_vote_twice_and_a_reconnect_keeps_the_browsers_vote(lecture_app):
    app, questions = lecture_app, lecture_app.questions
    app.go_to_step(PENDULUM)
    question = questions.poll.current
    assert question.ask.range == (0.0, 1.0) and question.true == pytest.approx(app.scene.model.effective_length)
    assert not app.scene.cop_marker.visible and not app.scene.cop_label.visible  # the answer's marker waits
    token = _cookie(app)
    with _browser(app, token) as (ws, _, panel):
        for bad in ("abc", "nan", "inf", "1e308"):
            send_value(ws, panel.number._impl.uuid, bad)
            wait_for(lambda b=bad: panel.number.value == b, what="the text")
            send_value(ws, panel.send._impl.uuid, True)
            refused = received_until(ws, lambda ms: _note_in(ms, "the answer is"))
            assert any("the answer is" in n for n in _notes(refused)), f"{bad} refused"
        send_value(ws, panel.number._impl.uuid, 0.4)  # a number where text belongs
        assert any("must be text" in n for n in _notes(received_until(ws, lambda ms: _note_in(ms, "must be text"))))
        assert questions.poll.count() == 0
        send_value(ws, panel.number._impl.uuid, "0.58")
        wait_for(lambda: panel.number.value == "0.58", what="the text")
        for _ in range(3):  # pressed again and again: one answer
            send_value(ws, panel.send._impl.uuid, True)
        wait_for(lambda: questions.poll.count() == 1, what="the answer")
    with _browser(app, token) as (ws, _, panel):  # the same browser again: its answer is still there
        assert "0.58" in panel.mine.content and questions.poll.count() == 1
        send_value(ws, panel.number._impl.uuid, "0.6")
        wait_for(lambda: panel.number.value == "0.6", what="the text")
        send_value(ws, panel.send._impl.uuid, True)
        wait_for(lambda: question.votes == {f"browser {token}": 0.6}, what="the changed answer")
    with _browser(app, "forged-token") as (ws, cid, panel):  # a token the server never issued: one connection
        assert questions._identity[cid] == f"connection {cid}"
    questions.reveal(None)
    assert question.counts()[6] == 1
    assert app.scene.cop_marker.visible and app.scene.cop_label.visible  # shown with the answers


def test_export_answers_needs_presenter_mode(tmp_path, monkeypatch):
    out = tmp_path / "a.csv"
    with pytest.raises(SystemExit):
        main(["--shared", "--export-answers", str(out)])
    with pytest.raises(SystemExit):
        main(["--presenter", "--export-answers", str(tmp_path / "missing" / "a.csv")])
    assert not out.exists()


def test_the_presenter_asks_from_the_panel_and_saves_the_csv_a_follower_cannot(lecture_app):
    app, questions = lecture_app, lecture_app.questions
    with _browser(app) as (f, f_id, f_panel), _browser(app) as (p, p_id, _):
        app.classroom.present(app.server.get_clients()[p_id], PIN)
        wait_for(lambda: questions._panels[p_id].presenter, what="the presenter's panel")
        panel = questions._panels[p_id]
        send_value(p, panel.ask_text._impl.uuid, "Which way does L point?")
        send_value(p, panel.ask_choices._impl.uuid, "up\ndown\n")
        wait_for(lambda: panel.ask_choices.value == "up\ndown\n", what="the choices")
        drain(p)
        send_value(p, panel.ask_button._impl.uuid, True)
        wait_for(lambda: getattr(questions.poll.current, "source", None) == "asked from the panel", what="asked")
        assert questions.poll.current.ask == Ask("Which way does L point?", ("up", "down"))
        wait_for(lambda: questions._panels[f_id].choice is not None, what="the follower's buttons")
        assert questions._panels[f_id].choice.options == ("A", "B")
        # The panels are rebuilt one after another, the follower's first: wait for the presenter's whole folder.
        wait_for(lambda: panel.reveal is not None and panel.folder is not None, what="the presenter's rebuilt panel")
        assert panel.ask_text.value == ""  # the panel was rebuilt for the question: its boxes are empty
        send_value(p, panel.ask_text._impl.uuid, "Again?")
        send_value(p, panel.ask_choices._impl.uuid, "only one")
        wait_for(lambda: panel.ask_choices.value == "only one", what="the choices")
        send_value(p, panel.ask_button._impl.uuid, True)
        told = received_until(p, lambda ms: _note_in(ms, "type 2 to 5 choices, one a line (got 1)"))
        assert any("type 2 to 5 choices, one a line (got 1)" in n for n in _notes(told))
        questions.ask_from_panel(app.server.get_clients()[f_id], "Mine?", "a\nb")  # a follower has no Ask button
        assert questions.poll.current.source == "asked from the panel" and questions.poll.current.ask.text != "Mine?"
        drain(f)
        questions.save_for(app.server.get_clients()[f_id])
        assert not any(m.get("type") == "FileTransferStartDownload" for m in received(f, 0.5))
        send_value(p, questions._panels[p_id].save_button._impl.uuid, True)
        sent = received_until(p, lambda ms: any(m.get("type") == "FileTransferStartDownload" for m in ms))
        download = [m for m in sent if m.get("type") == "FileTransferStartDownload"]
        assert download and download[0]["filename"] == "answers.csv"


def test_the_chart_says_its_counts_to_a_screen_reader():
    poll = Poll()
    poll.ask(Ask("Flip?", ("steady", "flips"), 2), "step 7")
    poll.vote("a", "B")
    chart = results_html(poll.current)
    assert 'aria-label="1 answer: A: 0, B: 1; the right answer is B"' in chart and "<small>1 answer</small>" in chart
    poll.ask(Ask("Rate?", unit="rad/s", range=(0.0, 2.0)), "step 10", true=0.5278654505337458)
    poll.vote("a", 0.5)
    poll.vote("b", 0.55)
    chart = results_html(poll.current)
    assert 'aria-label="2 answers (rad/s) 0.4 to 0.6: 2; the true value is 0.5279 rad/s"' in chart
    assert "left:26.4%" in chart  # the red line at (0.52787 − 0) / 2 of the width


def test_a_scene_states_its_own_true_values_and_refuses_a_quantity_it_has_not():
    """The contract a truth is read through (Scene.truth): the heavy top's mean precession rate is the
    physics API's for the scene's start, the pendulum's centre of percussion its effective length."""
    with running_app("heavy_top", start_loop=False) as app:
        scene = app.scene
        assert scene.truth("precession_rate") == scene.top.precession_rate(*scene.start)
        with pytest.raises(ValueError, match="heavy_top gives no true value for 'centre_of_percussion'"):
            scene.truth("centre_of_percussion")
        app.switch_scene("pendulum")
        assert app.scene.truth("centre_of_percussion") == app.scene.model.effective_length


def test_a_number_answer_may_be_typed_with_a_decimal_comma():
    """A German or Spanish reader writes 0,5: taken as 0.5. A comma before three digits (1,500: a thousand
    and a half, or one and a half?) is refused as before."""
    poll = Poll()
    poll.ask(Ask("Rate?", unit="rad/s", range=(-2.0, 2.0)), "step 10")
    assert poll.vote("a", "0,5") == 0.5
    assert poll.vote("b", " −1,25 ") == -1.25
    with pytest.raises(VoteRefused, match="the answer is a number, got '1,500'"):
        poll.vote("c", "1,500")
    with pytest.raises(VoteRefused, match="the answer is a number"):
        poll.vote("c", "1,2,3")
