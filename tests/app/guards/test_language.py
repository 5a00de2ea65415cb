"""Each browser reads the app in its own language, through a real websocket: two browsers of one server, one
German and one English, each get their own words; a browser that chooses Spanish gets its panel again in
Spanish; a translated message is made once per language and message; a frame's poses pass untouched."""

from __future__ import annotations

import json
from typing import Any

import pytest
from viser import _messages

from app.guards.language import LANG_MARKER, Languages, lang_marker
from app.panel.access import PAGE_WORDS
from app.teaching.voters import COOKIE
from tests.app.reading import received_until
from tests.harness import FRAME, raw_client, running_app, send_value


def labels(messages: list[dict[str, Any]]) -> set[str]:
    """Every control's label a browser has been sent (created or updated)."""
    out = set()
    for m in messages:
        props = m.get("props")
        if isinstance(props, dict) and isinstance(props.get("label"), str):
            out.add(props["label"])
        updates = m.get("updates")
        if isinstance(updates, dict) and isinstance(updates.get("label"), str):
            out.add(updates["label"])
    return out


def contents(messages: list[dict[str, Any]]) -> set[str]:
    """Every Html element's content a browser has been sent (created or updated)."""
    out = set()
    for m in messages:
        for part in (m.get("props"), m.get("updates")):
            if isinstance(part, dict) and isinstance(part.get("content"), str):
                out.add(part["content"])
    return out


def uuid_of(messages: list[dict[str, Any]], label: str) -> str:
    return next(m["uuid"] for m in messages if isinstance(m.get("props"), dict) and m["props"].get("label") == label)


@pytest.fixture(scope="module")
def app() -> Any:
    with running_app("heavy_top", start_loop=False) as served:
        yield served


def test_two_browsers_of_one_server_each_read_their_own_language(app: Any) -> None:
    with (
        raw_client(app, headers={"Accept-Language": "de-DE,de;q=0.9"}) as german,
        raw_client(app, headers={"Accept-Language": "en-GB"}) as english,
    ):
        seen_de = received_until(
            german, lambda ms: "Schritt" in labels(ms) and any('data-rbl-lang="de"' in c for c in contents(ms))
        )
        seen_en = received_until(english, lambda ms: "Step" in labels(ms) and LANG_MARKER in contents(ms))
        assert {"Schritt", "Uhr", "Sprache"} <= labels(seen_de)
        assert "Step" not in labels(seen_de) and "Clock" not in labels(seen_de)
        assert {"Step", "Clock", "Language"} <= labels(seen_en)
        assert "Schritt" not in labels(seen_en)
        # The page learns its language (for <html lang>) from its own hidden marker.
        marker_de = next(c for c in contents(seen_de) if 'data-rbl-lang="de"' in c)
        assert marker_de == lang_marker("de", PAGE_WORDS) and LANG_MARKER not in contents(seen_de)
        # The page's own script finds its buttons and names viser's by these, in German.
        assert "&quot;Step&quot;: &quot;Schritt&quot;" in marker_de
        assert LANG_MARKER in contents(seen_en)
    # The server's own state stays English: scripts and the other browsers see the same app as before.
    assert app.simulation.panel.step_button.label == "Step"


def test_a_browser_that_chooses_a_language_gets_its_panel_again_in_it(app: Any) -> None:
    with raw_client(app) as ws, raw_client(app) as other:
        seen = received_until(ws, lambda ms: "Language" in labels(ms))
        received_until(other, lambda ms: "Language" in labels(ms))
        send_value(ws, uuid_of(seen, "Language"), "Español")
        again = received_until(
            ws, lambda ms: "Paso" in labels(ms) and any('data-rbl-lang="es"' in c for c in contents(ms))
        )
        assert {"Paso", "Reloj", "Reiniciar", "Idioma"} <= labels(again)
        assert lang_marker("es", PAGE_WORDS) in contents(again)
        # Nobody else's panel changed.
        app.frame(FRAME)
        later = received_until(other, lambda ms: False, timeout=0.5)
        assert not {"Paso", "Reloj", "Idioma"} & labels(later)


def test_a_language_we_do_not_speak_is_refused_to_its_browser_only(app: Any) -> None:
    with raw_client(app) as ws:
        seen = received_until(ws, lambda ms: "Language" in labels(ms))
        send_value(ws, uuid_of(seen, "Language"), "Klingon")
        told = received_until(ws, lambda ms: any("no option" in json.dumps(m) for m in ms))
        assert any("no option" in json.dumps(m) for m in told)
        assert app.languages.language(max(app.server.get_clients())) == "en"


def test_a_translated_message_is_made_once_per_language_and_poses_pass_untouched(app: Any) -> None:
    languages: Languages = app.languages
    languages.choose(-1, "de")
    languages.choose(-2, "de")
    languages.choose(-3, "zh")
    update = _messages.GuiUpdateMessage("u", {"label": "Step"})
    first, second, chinese = (languages.translated(update, c) for c in (-1, -2, -3))
    assert first is second and first.updates == {"label": "Schritt"}
    assert chinese.updates == {"label": "单步"}
    assert update.updates == {"label": "Step"}  # the original, which English browsers get, is untouched
    pose = _messages.SetOrientationMessage("/body", (1.0, 0.0, 0.0, 0.0))
    assert languages.translated(pose, -1) is pose
    for c in (-1, -2, -3):
        languages.forget(c)


def test_a_browsers_choice_is_kept_when_its_page_is_loaded_again(app: Any) -> None:
    """The choice rides on the browser's cookie (the voter token): its next page opens in it, over what its
    Accept-Language prefers; another browser with the same preference is not affected."""
    cookie = {"Cookie": f"{COOKIE}={app.voters.issue()}", "Accept-Language": "de"}
    with raw_client(app, headers=cookie) as ws:
        seen = received_until(ws, lambda ms: "Sprache" in labels(ms))
        send_value(ws, uuid_of(seen, "Sprache"), "中文")
        received_until(ws, lambda ms: "单步" in labels(ms))
    with raw_client(app, headers=cookie) as again, raw_client(app, headers={"Accept-Language": "de"}) as other:
        assert "单步" in labels(received_until(again, lambda ms: "单步" in labels(ms)))
        assert "Schritt" in labels(received_until(other, lambda ms: "Schritt" in labels(ms)))


def test_a_readouts_value_is_words_and_a_students_text_is_not(app: Any) -> None:
    """A read-only text box (a readout, the clock's time) shows words and numbers: each reader gets them in
    their language; an editable one holds what someone typed: never changed."""
    from app.language.words import say

    languages: Languages = app.languages
    languages.choose(-4, "de")
    readout = _messages.GuiTextMessage(
        "r",
        "",
        "root",
        _messages.GuiTextProps(order=0, label="Time (s)", hint=None, visible=True, disabled=True, multiline=False),
    )
    typed = _messages.GuiTextMessage(
        "t",
        "",
        "root",
        _messages.GuiTextProps(order=1, label="Your name", hint=None, visible=True, disabled=False, multiline=False),
    )
    for message in (readout, typed):
        languages.translated(message, -4)
    time = say("{t:.2f}", t=12.5)
    assert languages.translated(_messages.GuiUpdateMessage("r", {"value": time}), -4).updates == {"value": "12,50"}
    assert languages.translated(_messages.GuiUpdateMessage("t", {"value": time}), -4).updates == {"value": "12.50"}
    languages.forget(-4)


def test_a_removed_readout_is_forgotten_in_every_language(app: Any) -> None:
    """An English browser's stream teaches the same as any: a readout removed (its uuid reused by nothing we
    made) no longer has its value translated."""
    from app.language.words import say

    languages: Languages = app.languages
    languages.choose(-5, "de")
    props = _messages.GuiTextProps(order=0, label="x", hint=None, visible=True, disabled=True, multiline=False)
    languages.translated(_messages.GuiTextMessage("gone", "", "root", props), -6)  # -6: an English browser
    time = say("{t:.2f}", t=3.5)
    assert languages.translated(_messages.GuiUpdateMessage("gone", {"value": time}), -5).updates == {"value": "3,50"}
    languages.translated(_messages.GuiRemoveMessage("gone"), -6)
    assert languages.translated(_messages.GuiUpdateMessage("gone", {"value": time}), -5).updates == {"value": "3.50"}
    languages.forget(-5)
