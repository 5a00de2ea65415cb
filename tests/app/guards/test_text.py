"""Text is text: the payload corpus through each escaping function, rendered by a Markdown parser with raw
HTML on (as viser's page renders it), and through each path of the app that writes untrusted text.

``markdown-it`` stands in for the page's renderer here (CommonMark with raw HTML, links checked as the page's
``defaultUrlTransform`` checks them); the browser test (tests/browser/test_hostile_text.py) runs the same
corpus in Chromium.
"""

from __future__ import annotations

import csv
import io
import re
from html.parser import HTMLParser
from typing import Any

import pytest
import trimesh
from markdown_it import MarkdownIt

from app.guards.text import csv_cell, csv_row, html_text, lecturer_markdown, markdown_text
from app.scenes import REGISTRY, load_all
from app.serving.app import export
from app.teaching.question_panel import mine_text, results_html
from app.teaching.questions import Poll, Question, check_ask
from app.teaching.states import state_text
from tests.app.payloads import PAYLOADS
from tests.app.reading import received_until
from tests.harness import click_button, open_scene, raw_client, running_app, send_upload, send_value, wait_for

_render = MarkdownIt("commonmark", {"html": True}).render

SAFE_TAGS = {"p", "strong", "em", "code", "pre", "a", "ul", "ol", "li", "blockquote", "br", "hr", "h1", "h2", "h3"}
"""What the lecturer's Markdown may become: formatting, never a tag of its own."""


class _Tags(HTMLParser):
    def __init__(self) -> None:
        super().__init__(convert_charrefs=True)
        self.tags: list[tuple[str, list[tuple[str, str | None]]]] = []
        self.text: list[str] = []

    def handle_starttag(self, tag: str, attrs: list[tuple[str, str | None]]) -> None:
        self.tags.append((tag, attrs))

    def handle_data(self, data: str) -> None:
        self.text.append(data)


def _parsed(html: str) -> _Tags:
    parser = _Tags()
    parser.feed(html)
    parser.close()
    return parser


def _dangerous(parsed: _Tags, allowed: set[str], styled: bool = False) -> list[Any]:
    """Tags not in ``allowed``, event handlers, ``srcdoc``, script links (and ``style`` unless ``styled``)."""
    bad = []
    for tag, attrs in parsed.tags:
        if tag not in allowed:
            bad.append(tag)
        for name, value in attrs:
            if name.startswith("on") or name == "srcdoc" or (name == "style" and not styled):
                bad.append((tag, name))
            if name in {"href", "src"} and re.sub(r"\s", "", value or "").lower().startswith(("javascript:", "data:")):
                bad.append((tag, name, value))
    return bad


@pytest.mark.parametrize("payload", PAYLOADS)
def test_markdown_text_is_only_text(payload: str) -> None:
    """In a Markdown element: one paragraph holding exactly the payload's characters, no image for viser's
    server to read."""
    escaped = markdown_text(payload)
    parsed = _parsed(_render(escaped))
    assert [tag for tag, _ in parsed.tags] == ["p"]
    assert "".join(parsed.text).strip() == payload.strip()
    assert "![" not in escaped


@pytest.mark.parametrize("payload", PAYLOADS)
def test_html_text_is_only_text(payload: str) -> None:
    parsed = _parsed(html_text(payload))
    assert parsed.tags == []
    assert "".join(parsed.text) == payload


@pytest.mark.parametrize("payload", PAYLOADS)
def test_lecturer_markdown_keeps_no_html(payload: str) -> None:
    parsed = _parsed(_render(lecturer_markdown(f"> a quotation\n\n**Step.** {payload}")))
    assert _dangerous(parsed, SAFE_TAGS) == []
    assert ("strong", []) in parsed.tags and ("blockquote", []) in parsed.tags  # formatting kept


def test_new_lines_and_controls_are_spaces() -> None:
    assert markdown_text("a\nb\r\n# c\u2028d") == "a b  \\# c d"
    assert html_text("a\nb") == "a b"
    assert markdown_text(3.5) == "3.5"
    assert markdown_text("- a (b). 2. c -5") == "\\- a (b). 2. c -5"
    assert markdown_text(" 12) x") == " 12\\) x"


def test_lecturer_markdown_refuses_what_is_not_text() -> None:
    with pytest.raises(ValueError, match="must be text, got bytes"):
        lecturer_markdown(b"x")  # type: ignore[arg-type]


def test_captions_keep_their_formatting() -> None:
    """The scenes' captions lose nothing but entities for ``<`` (shown as ``<`` all the same)."""
    load_all()
    for cls in REGISTRY.values():
        caption = cls.caption
        assert _parsed(_render(lecturer_markdown(caption))).text == _parsed(_render(caption)).text, cls.name


# ------------------------------------------------------------------ the paths that write untrusted text
def _only_formatting(markdown: str) -> bool:
    return _dangerous(_parsed(_render(markdown)), {"p", "strong", "em"}) == []


HOSTILE = PAYLOADS[7]  # the iframe srcdoc of a mesh's file name


def test_an_uploaded_file_name_is_text_in_the_note() -> None:
    stl = trimesh.creation.box(extents=(0.3, 0.2, 0.1)).export(file_type="stl")
    with running_app("inertia_explorer", start_loop=False) as app:
        scene = open_scene(app, "inertia_explorer")
        with raw_client(app) as ws:
            send_upload(ws, scene.upload._impl.uuid, HOSTILE, stl)
            wait_for(lambda: "Uploaded" in scene.choice.value, 60, what="the upload to be read")
            wait_for(lambda: "iframe" in scene.note.content, 30, what="the note")
        assert _only_formatting(scene.note.content)
        assert "<" not in scene.note.content


def test_a_state_text_with_a_hostile_label_is_text_in_the_status_line() -> None:
    """The status line of a browser's own session quotes the label of the control the state names."""
    snapshot = {"scene": "heavy_top", "controls": [[PAYLOADS[1], 1.0]], "time": 0.0, "speed": 1.0, "playing": False}
    with running_app("heavy_top", start_loop=False, private=True) as app:
        with raw_client(app) as ws:
            session = wait_for(lambda: next(iter(app.sessions.values()), None), 60, what="the session")
            send_value(ws, session.state_box._impl.uuid, state_text(snapshot))
            click_button(ws, session.panel.open_state_button._impl.uuid)
            received_until(ws, lambda _: session.status.content, 30)
        assert "OnErRoR" in session.status.content  # the label is quoted: shown, as text
        assert _only_formatting(session.status.content)


def test_questions_choices_and_answers_are_text() -> None:
    ask = check_ask({"question": PAYLOADS[0], "choices": [PAYLOADS[2], PAYLOADS[12]], "answer": 1})
    question = Question(ask, "panel", 0.0)
    assert _dangerous(_parsed(results_html(question)), {"div", "b", "small", "span"}, styled=True) == []
    assert _only_formatting(mine_text(question, PAYLOADS[5]))
    number = Question(check_ask({"question": "How fast?", "range": [0, 10], "unit": "<b>"}), "panel", 0.0)
    assert _dangerous(_parsed(results_html(number)), {"div", "b", "small", "span"}, styled=True) == []
    assert _only_formatting(mine_text(number, 3.0))


# ------------------------------------------------------------------ CSV cells
@pytest.mark.parametrize(
    "cell",
    ["=1+1", "+SUM(A1:A2)", "-2+3", "@cmd", "\t=1", "\r=1", '  =HYPERLINK("http://x")', "-1_0", "=cmd|' /C calc'!A0"],
)
def test_a_formula_is_neutralised(cell: str) -> None:
    assert csv_cell(cell) == "'" + cell


@pytest.mark.parametrize("cell", ["-0.5", "+1e3", "-inf", "text", "", "a=b", 3, -2.5, None])
def test_numbers_and_plain_text_stay(cell: Any) -> None:
    assert csv_cell(cell) == cell


def test_the_answers_csv_neutralises_what_was_typed() -> None:
    """The answers CSV (the only CSV with typed text): question, choices and unit as a presenter typed them."""
    poll = Poll()
    poll.ask(check_ask({"question": '=HYPERLINK("http://evil","x")', "choices": ["@SUM(1)", "-1+2"]}), "panel")
    poll.ask(check_ask({"question": "+A1*2", "range": [0, 1], "unit": "-x"}), "panel")
    rows = list(csv.reader(io.StringIO(poll.csv())))
    cells = [cell for row in rows[1:] for cell in row]
    assert '\'=HYPERLINK("http://evil","x")' in cells and "'+A1*2" in cells and "'-x" in cells
    assert not any(cell.lstrip(" ").startswith(("=", "+", "@", "\t", "\r")) for cell in cells)
    assert all(not cell.startswith("-") or cell == "'" or float(cell) < 0 for cell in cells if cell)


def test_the_export_csv_header_is_neutralised(tmp_path: Any) -> None:
    """The export's CSV: names of columns through the same check; its numbers stay numbers."""
    written = export("free_fall", tmp_path, 1 / 30)
    rows = list(csv.reader(written.csv.open(encoding="utf-8")))
    assert rows[0] == csv_row(rows[0])
    assert all(float(cell) == float(cell) for cell in rows[1])
