"""say, mark and translate: a text made in English is made again in another language, its numbers written as
that language writes them (CLDR's symbols through Babel), its text values translated in turn."""

from __future__ import annotations

import pytest

from app.language import words
from app.language.catalogs import PSEUDO
from app.language.words import english_option, mark, say, translate


def test_english_is_returned_unchanged_by_every_function() -> None:
    assert mark("Play") == "Play"
    assert say("t = {t:.2f} s", t=1.5) == "t = 1.50 s"
    assert translate("Play", "en") == "Play"
    assert translate("a student's own words", "de") == "a student's own words"


@pytest.mark.parametrize(
    ("lang", "decimal", "group"), [("en", ".", ","), ("de", ",", "."), ("es", ",", "."), ("zh", ".", ",")]
)
def test_a_number_keeps_its_format_and_takes_the_languages_symbols(lang: str, decimal: str, group: str) -> None:
    """The field's format spec fixes the digits; the language (CLDR, through Babel) the symbols: German and
    Spanish write a decimal comma and group with a point, Chinese as English."""
    text = say("−{a:.3f} and {b:,.1f}", a=0.517, b=1234.5)
    assert translate(text, lang) == f"−0{decimal}517 and 1{group}234{decimal}5"


def test_a_negative_number_takes_the_languages_minus_sign() -> None:
    from babel.numbers import get_minus_sign_symbol

    assert translate(say("{x:.1f}", x=-2.0), "de") == f"{get_minus_sign_symbol('de')}2,0"


def test_a_text_value_is_translated_in_turn() -> None:
    text = say("{action}: {t:.1f} s", action=mark("Step"), t=0.5)
    assert translate(text, "de") == "Schritt: 0,5 s"  # "{action}: {t:.1f} s" is no msgid: its form stays
    assert translate(text, "zh") == "单步: 0.5 s"


def test_the_pseudo_locale_wraps_only_what_the_catalogs_know() -> None:
    assert translate("Play", PSEUDO).startswith("⟦Ƥĺàý")
    assert translate("Jane Doe", PSEUDO) == "Jane Doe"  # not ours: shown as it is, so a test sees it


def test_the_remembered_texts_are_bounded(monkeypatch: pytest.MonkeyPatch) -> None:
    monkeypatch.setattr(words, "REMEMBERED", 10)
    for i in range(50):
        say("{i} frames", i=i)
    assert words.remembered_count() == 10
    assert translate(say("{i} frames", i=7), "de") == "7 frames"


def test_a_translated_choice_is_read_back_in_english() -> None:
    options = ("Play", "Step")
    assert english_option("Schritt", options) == "Step"
    assert english_option("单步", options) == "Step"
    assert english_option("Step", options) == "Step"
    assert english_option("Nonsense", options) == "Nonsense"  # the inputs guard then refuses it


def test_an_unknown_language_is_a_valueerror_naming_the_choices() -> None:
    with pytest.raises(ValueError, match=r"expected a language among en, de, es, zh, en-XA, got 'fr'"):
        translate("Play", "fr")


def test_an_escaped_text_is_translated_then_escaped() -> None:
    """A said text holding a file's name with an apostrophe, shown in Html: the reader gets its translation,
    escaped the same way (not the English, which no catalog would find once escaped)."""
    from app.language.words import escaped

    text = say("{action}: {file}", action=mark("Step"), file="the project's <file>")
    shown = escaped(text)
    assert shown == "Step: the project&#x27;s &lt;file&gt;"
    assert translate(shown, "de") == "Schritt: the project&#x27;s &lt;file&gt;"
    assert escaped("Step") == "Step" and translate(escaped("Step"), "zh") == "单步"
