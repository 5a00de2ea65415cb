"""Class questions in real browsers: a presenter and three followers in one Chromium
(each page its own context, so its own voter cookie); the followers vote and one changes its vote, a
follower's page shows no count before the reveal, "Show answers" puts the chart on every page; a raw
websocket client with a follower's cookie cannot add a vote, nor vote for a choice that does not exist."""

from __future__ import annotations

import pytest
import viser
from websockets.sync.client import connect

from app.teaching.voters import COOKIE
from tests.harness import CAMERA_MESSAGE, click, received, running_app, send_value, wait_for

pytestmark = pytest.mark.browser

PIN = "2718"
SMALL = {"width": 720, "height": 640}
# The shipped lecture's racket step (tests/app/teaching/test_questions.py checks the shipped questions): one step
# loads faster than twelve.
LECTURE = """title = "One question"
[[step]]
scene = "tennis_racket"
values = { spin = 6.0, log_eps = -3.0 }
caption = "The racket flips over and back, again and again."
question = "Spun about its middle axis with a tiny push off it: after a few seconds the racket..."
choices = ["keeps spinning steadily", "wobbles a little", "flips over and back, again and again"]
answer = 3
"""


def _panel_text(page) -> str:
    return page.evaluate("() => document.body.innerText")


def _client_of(app, page):
    """The server's handle of the page's connection: the one whose voter cookie is the page's."""
    cookie = next(c["value"] for c in page.context.cookies() if c["name"] == COOKIE)
    ids = [cid for cid, who in app.questions._identity.items() if who == f"browser {cookie}"]
    assert len(ids) == 1
    return app.server.get_clients()[ids[0]]


def test_three_followers_vote_change_and_see_the_answers_only_when_revealed(chromium, tmp_path):
    path = tmp_path / "one.toml"
    path.write_text(LECTURE, encoding="utf-8")
    with running_app(presenter=True, pin=PIN, lecture=str(path)) as app:
        questions = app.questions
        question = questions.poll.current  # the lecture waits at t = 0 with the question
        assert question.source == "step 1" and not app.simulation.playing and app.time == 0.0
        pages = [chromium.new_page(viewport=SMALL) for _ in range(4)]
        for page in pages:  # four pages load side by side
            page.goto(app.url, wait_until="commit")
        wait_for(lambda: len(app.server.get_clients()) == 4, 60, what="four pages to connect")
        try:
            for page in pages:
                page.wait_for_selector("canvas", timeout=60_000)
            identities = [questions._identity[cid] for cid in app.server.get_clients()]
            assert len(set(identities)) == 4 and all(who.startswith("browser ") for who in identities)  # cookies
            lecturer = pages[0]
            lecturer_client = _client_of(app, lecturer)
            assert app.classroom.present(lecturer_client, PIN)
            followers = [(page, None) for page in pages[1:]]
            for page, _ in followers:
                page.get_by_text("after a few seconds the racket").first.wait_for(timeout=30_000)
            for (page, _), letter in zip(followers, "CCA", strict=True):
                click(page.get_by_role("button", name=letter, exact=True))
            wait_for(lambda: questions.poll.count() == 3, 30, what="three answers")
            third = followers[2][0]
            click(third.get_by_role("button", name="C", exact=True))  # changes its mind
            wait_for(lambda: question.counts() == [0, 0, 3], 30, what="the changed vote")
            third.get_by_text("Your answer: C.").first.wait_for(timeout=30_000)
            lecturer.get_by_text("3 answers so far").first.wait_for(timeout=30_000)

            # A script with the first follower's cookie (the same browser): no second vote, no made-up choice.
            cookie = next(c["value"] for c in followers[0][0].context.cookies() if c["name"] == COOKIE)
            before = set(app.server.get_clients())
            ws = connect(
                f"ws://127.0.0.1:{app.port}",
                subprotocols=[f"viser-v{viser.__version__}"],
                additional_headers={"Cookie": f"{COOKIE}={cookie}"},
                max_size=None,
                close_timeout=1,
            )
            try:
                ws.send(CAMERA_MESSAGE)
                cid = wait_for(lambda: set(app.server.get_clients()) - before, what="the script").pop()
                wait_for(lambda: cid in questions._panels and questions._panels[cid].choice, what="its panel")
                uuid = questions._panels[cid].choice._impl.uuid
                send_value(ws, uuid, "B")
                wait_for(lambda: question.counts() == [0, 1, 2], 30, what="the browser's one vote, changed")
                send_value(ws, uuid, "F")
                refused = wait_for(lambda: [m for m in received(ws, 0.3) if "no option 'F'" in str(m)], what="refusal")
                assert refused and questions.poll.count() == 3 and question.counts() == [0, 1, 2]
            finally:
                ws.close()

            for page, _ in followers:  # no count and no chart on a follower's page before the reveal
                text = _panel_text(page)
                assert "answers so far" not in text and "3 answers" not in text
            click(lecturer.get_by_role("button", name="Show answers"))
            wait_for(lambda: question.revealed_at is not None, 30, what="the reveal")
            for page, _ in followers:
                page.get_by_text("3 answers", exact=True).first.wait_for(timeout=30_000)
                page.get_by_text("The vote is closed.", exact=False).first.wait_for(timeout=30_000)
            assert "again and again" in _panel_text(lecturer)  # the caption comes with the answers
        finally:
            for page in pages:
                page.close()
