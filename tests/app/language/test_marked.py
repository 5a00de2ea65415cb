"""The marked words: the catalogs' template holds exactly what the code marks, every ``say`` template is a
valid format, and what the panel of each scene shows reaches another language.

The template is re-extracted here as ``pybabel extract`` makes it (app/language/babel.cfg, keywords ``say``
and ``mark``); a text marked or said in the code but missing from the committed template, or left in the
template after the code dropped it, fails until the template is made again (docs/translating.md).
"""

from __future__ import annotations

import re
import string
from pathlib import Path

import pytest
import viser
from babel.messages.extract import extract_from_dir
from babel.messages.frontend import parse_mapping_cfg
from babel.messages.pofile import read_po
from viser import _messages

from app.contracts import ClientId
from app.drawing.palette import legend_html
from app.guards.gate import close_reason
from app.guards.language import Languages
from app.language.catalogs import DOMAIN, LANGUAGES, LOCALE_DIR, PSEUDO
from app.language.words import PER_TEMPLATE, REMEMBERED, joined, keep, mark, say, template_ids, translate
from app.rooms.config import Backend, Department, Room
from app.rooms.landing import landing_html
from app.scenes import scene_names
from app.teaching.question_panel import count_text, mine_text, results_html
from app.teaching.questions import Ask, Poll, VoteRefused
from tests.harness import free_port, open_scene, running_app

ROOT = Path(__file__).resolve().parents[3]
APP = ROOT / "app"


def _extracted(*keywords: str) -> set[str]:
    """The message ids ``pybabel extract`` finds in app/ with these keywords."""
    with (LOCALE_DIR.parent / "babel.cfg").open() as fp:
        method_map, options_map = parse_mapping_cfg(fp)
    found = extract_from_dir(
        str(APP), method_map, options_map, keywords={k: None for k in keywords}, strip_comment_tags=True
    )
    return {message for _, _, message, _, _ in found if isinstance(message, str) and message}


def _catalog_ids(path: Path) -> set[str]:
    with path.open("rb") as fp:
        return {str(m.id) for m in read_po(fp) if m.id}


def test_the_template_holds_exactly_the_marked_and_said_texts() -> None:
    code = _extracted("say", "mark")
    template = _catalog_ids(LOCALE_DIR / f"{DOMAIN}.pot")
    assert template_ids() == template
    missing, stale = sorted(code - template), sorted(template - code)
    assert not missing, f"marked in the code, not in the template (make it again): {missing[:5]}"
    assert not stale, f"in the template, no longer in the code (make it again): {stale[:5]}"
    assert len(template) > 300  # every scene's and panel's words, not a handful


@pytest.mark.parametrize("lang", [lang for lang in LANGUAGES if lang != "en"])
def test_every_catalog_has_the_templates_messages(lang: str) -> None:
    """``pybabel update`` has run: each language's catalog lists every message of the template."""
    template = _catalog_ids(LOCALE_DIR / f"{DOMAIN}.pot")
    assert _catalog_ids(LOCALE_DIR / lang / "LC_MESSAGES" / f"{DOMAIN}.po") == template


def _dummy(spec: str) -> object:
    """A value a field with this format spec takes: a number for a numeric presentation type, else text."""
    kind = spec[-1:] if spec else ""
    if kind in "eEfFgGn%" and kind or "," in spec:
        return 1234.5
    if kind in "dbcoxX" and kind:
        return 12
    return "x"


def test_every_said_template_is_a_format_with_named_fields() -> None:
    said = _extracted("say")
    assert len(said) > 80
    for template in said:
        values = {}
        for _, field, spec, conversion in string.Formatter().parse(template):
            if field is None:
                continue
            assert field.isidentifier(), f"{template!r}: the field {field!r} is not a keyword (say takes keywords)"
            assert conversion in (None, "r", "s"), f"{template!r}: conversion {conversion!r}"
            values[field] = _dummy(spec or "")
        template.format(**values)  # a spec that does not fit its value raises here


def test_marked_texts_have_no_fields() -> None:
    """A text marked with ``mark`` is shown as it is: a ``{field}`` in it would be shown, never filled."""
    for text in _extracted("mark"):
        fields = [f for _, f, _, _ in string.Formatter().parse(text) if f is not None]
        assert not fields, f"{text!r} is marked but has fields: make it with say()"


def _shown(app) -> list[str]:
    """Every word the shared panel holds: labels, hints, Markdown and Html, dropdown options, plot titles."""
    out: list[str] = []
    gui = app.server.gui
    handles: dict = {}
    for container in list(gui._container_handle_from_uuid.values()):
        handles.update(getattr(container, "_children", {}))
    for handle in handles.values():
        props = handle._impl.props
        for field in ("label", "hint", "content", "_markdown", "title"):
            value = getattr(props, field, None)
            if isinstance(value, str):
                out.append(value)
        out += [o for o in getattr(props, "options", None) or () if isinstance(o, str)]
        out += [s["label"] for s in getattr(props, "series", None) or () if isinstance(s.get("label"), str)]
    return out


# What the panel shows and nobody translates: symbols and numbers, one-letter names, the app's name.
_UNTRANSLATED = re.compile(r"^[^A-Za-z]*[A-Za-z]?[^A-Za-z]*$|^\*\*Rigid Body Lab\*\*$")

# Words of the shared panel's own files (app/panel/simulation_panel.py, app/panel/access.py), marked by the
# work on those files: until then they are the only ones let through. Remove them here once marked.
_MARKED_ELSEWHERE: set[str] = set()


@pytest.mark.parametrize("name", scene_names())
def test_every_word_of_a_scenes_panel_reaches_the_pseudo_locale(name: str) -> None:
    """In the pseudo-locale every marked word is accented: a text of the scene's panel that comes out as it
    went in escaped the catalogs (an f-string, a joined text, an unmarked label)."""
    with running_app(name, start_loop=False) as app:
        scene = open_scene(app, name)
        escaped = []
        for text in _shown(app):
            if _UNTRANSLATED.match(text) or text.startswith("<style") or text in _MARKED_ELSEWHERE:
                continue
            if translate(text, PSEUDO) == text and re.search(r"[A-Za-z]{3}", text):
                escaped.append(text)
        # The motion in words too, as the live region says it.
        words = scene.describe(app.shared.last_state)
        assert translate(words, PSEUDO) != words
    assert not escaped, f"{name}: shown in English to every language: {escaped[:6]}"


def test_a_kept_text_outlives_the_remembered_newest() -> None:
    template = "{title}: {wobble}."
    assert template in template_ids()
    kept = keep(say(template, title=mark("Heavy top"), wobble=say("tilted {tilt}", tilt="4°")))
    forgotten = say(template, title=mark("Heavy top"), wobble="never kept")
    for k in range(REMEMBERED + PER_TEMPLATE):  # each a text of its own, of more templates than fit
        say("{n} answers" + " " * (k // PER_TEMPLATE), n=k)
    assert translate(kept, PSEUDO) != kept
    assert "Ĥéàṽý" in translate(kept, PSEUDO) and "ţîĺţéđ" in translate(kept, PSEUDO)  # its parts too
    assert translate(forgotten, PSEUDO) == forgotten  # the newest are remembered, not every text ever made


def test_a_template_rewritten_every_frame_forgets_its_own_texts_only() -> None:
    """A friction top's tilt readout makes a text a frame in every session: the texts of other templates
    still on screen (a stability readout set once) stay translatable."""
    once = say("{kind} (flips)", kind=mark("unstable"))
    tilt = "{tilt:.4g}, lying on the table"
    for k in range(5 * PER_TEMPLATE):
        say(tilt, tilt=k / 7.0)
    assert translate(once, PSEUDO) != once
    newest = say(tilt, tilt=(5 * PER_TEMPLATE - 1) / 7.0)
    oldest = tilt.format(tilt=0.0)
    assert translate(newest, PSEUDO) != newest and translate(oldest, PSEUDO) == oldest


def test_a_joined_list_keeps_each_part_translatable() -> None:
    parts = [mark("Rod"), mark("Solid sphere"), say("Uploaded: {name}", name="bat.stl")]
    text = joined(parts, ", ")
    assert text == "Rod, Solid sphere, Uploaded: bat.stl"
    pseudo = translate(text, PSEUDO)
    assert pseudo.count("⟦") == 3 and "bat.stl" in pseudo
    assert joined([], ", ") == "" and joined(["Rod"]) == "Rod"


def test_a_said_text_that_is_its_own_value_is_not_remembered() -> None:
    """say("{a}{b}", a="", b=x) is x itself: remembered, x would translate into itself for ever."""
    assert translate(say("{before}{after}", before="", after="Rod"), PSEUDO) == translate("Rod", PSEUDO)


def test_the_legend_is_translated_name_by_name_and_keeps_its_markup() -> None:
    html = legend_html(["L", "omega", "ghost"])
    pseudo = translate(html, PSEUDO)
    assert pseudo.count("⟦") == 3
    assert re.sub(r"⟦[^⟧]*⟧", "", pseudo).count("<div") == html.count("<div")


def test_the_landing_page_writes_itself_in_a_language() -> None:
    room = Room(name="a101", mode="private", backends=(Backend("127.0.0.1", 9001),))
    department = Department(listen_host="127.0.0.1", listen_port=8080, rooms=(room,), title="Physics")
    english = landing_html(department)
    assert english == landing_html(department, "en") and '<html lang="en">' in english
    assert "Choose your room:" in english and "the first scene" in english
    pseudo = landing_html(department, PSEUDO)
    assert '<html lang="en-XA">' in pseudo and "Choose your room:" not in pseudo
    assert "the first scene" not in pseudo and "a101" in pseudo
    assert "'" not in pseudo and "$" not in pseudo  # one nginx string
    with pytest.raises(ValueError, match="expected a language"):
        landing_html(department, "xx")


def test_a_close_reason_fits_a_close_frame_in_any_script() -> None:
    chinese = "拒绝" * 100
    cut = close_reason(chinese)
    assert len(cut.encode()) <= 123 and chinese.startswith(cut) and len(cut) == 41
    english = "Refused: " + "x" * 200
    assert close_reason(english) == english[:120]


def test_a_label_in_the_3d_scene_reaches_its_readers_language() -> None:
    """The scene's labels ("centre of mass", "strike point") travel as a LabelMessage's ``text``: translated
    for a browser reading another language, as it is for one reading English."""
    server = viser.ViserServer(host="127.0.0.1", port=free_port(), verbose=False)
    try:
        languages = Languages(server)
        languages.choose(ClientId(5), PSEUDO)
        handle = server.scene.add_label("/label", mark("centre of mass"))
        message = _messages.LabelMessage("/label", handle._impl.props)
        assert languages.translated(message, ClientId(5)).props.text == translate("centre of mass", PSEUDO)
        assert languages.translated(message, ClientId(6)).props.text == "centre of mass"
        assert translate("centre of mass", PSEUDO) != "centre of mass"
    finally:
        server.stop()


def test_the_question_panels_words_and_chart_reach_another_language() -> None:
    """The count, a follower's own answer and the chart (its bars, its words for a screen reader) are said
    texts: every word in them is translated, the lecturer's question and the numbers stay."""
    poll = Poll()
    poll.ask(Ask("Flip?", ("steady", "flips"), 2), "step 7")
    poll.vote("a", "B")
    question = poll.current
    assert question is not None
    for text in (count_text(question, 1), mine_text(question, "B"), mine_text(question, None)):
        assert translate(text, PSEUDO) != text
    poll.reveal()
    chart = results_html(question)
    pseudo = translate(chart, PSEUDO)
    assert "ŕîĝĥţ àñšŵéŕ" in pseudo and "1 answer" not in pseudo
    assert "steady" in pseudo and "flips" in pseudo  # the lecturer's choices stay as they are written
    poll.ask(Ask("Rate?", unit="rad/s", range=(0.0, 2.0)), "step 10", true=0.5278654505337458)
    poll.vote("a", 0.5)
    poll.reveal()
    numbers = poll.current
    assert numbers is not None
    pseudo = translate(results_html(numbers), PSEUDO)
    assert "Ţŕûé ṽàĺûé" in pseudo and "0.5279" in pseudo and "rad/s" in pseudo
    assert pseudo.count("<div") == results_html(numbers).count("<div")
    with pytest.raises(VoteRefused) as refused:
        poll.ask(Ask("Rate?", unit="rad/s", range=(0.0, 2.0)), "step 11")
        poll.vote("b", 7.0)
    assert translate(str(refused.value), PSEUDO) != str(refused.value)


def marks_inside_marks(source: str) -> list[int]:
    """Lines where ``mark("…")`` or ``say("…")`` sits inside another ``mark``/``say`` call: Babel's extractor
    takes only the outer call's strings, so the inner text would never reach the catalogs."""
    import ast

    found: list[int] = []

    def walk(node: ast.AST, inside: bool) -> None:
        for child in ast.iter_child_nodes(node):
            words = (
                isinstance(child, ast.Call) and isinstance(child.func, ast.Name) and child.func.id in ("say", "mark")
            )
            if words and inside:
                found.append(child.lineno)
            walk(child, inside or words)

    walk(ast.parse(source), False)
    return found


def test_no_marked_text_hides_inside_another_so_the_extractor_finds_every_one() -> None:
    app = Path(__file__).resolve().parents[3] / "app"
    nested = {str(p.relative_to(app)): marks_inside_marks(p.read_text()) for p in sorted(app.rglob("*.py"))}
    assert {path: lines for path, lines in nested.items() if lines} == {}


def test_the_check_sees_a_text_inside_another() -> None:
    assert marks_inside_marks('say("{a}", a=mark("x"))\nmark("y")\n') == [1]
