"""A lecture file's own translations: a step's caption, question and choices per language, read, checked and
then translated for each reader as the catalogs' words are; every mistake refused with where it is."""

from __future__ import annotations

from pathlib import Path

import pytest

from app.guards.text import lecturer_markdown
from app.language.catalogs import PSEUDO
from app.language.words import translate
from app.teaching.lectures import read_lecture

LECTURE = """
title = "Spinning tops"
[de]
title = "Kreisel"

[[step]]
scene = "heavy_top"
caption = "**1. The heavy top.** It precesses at 0.517 rad/s & <b>nutates</b>."
[step.de]
caption = "**1. Der schwere Kreisel.** Er präzediert mit 0,517 rad/s & <b>nutiert</b>."
[step.zh]
caption = "**1. 重陀螺。** 它以 0.517 rad/s 进动。"

[[step]]
scene = "tennis_racket"
question = "What does the racket do about its intermediate axis?"
choices = ["It spins steadily", "It flips"]
answer = 2
caption = "It flips."
[step.es]
question = "¿Qué hace la raqueta alrededor de su eje intermedio?"
choices = ["Gira de forma estable", "Da la vuelta"]
"""


def write(tmp_path: Path, text: str) -> str:
    path = tmp_path / "tops.toml"
    path.write_text(text, encoding="utf-8")
    return str(path)


def test_a_steps_words_are_read_and_translated_for_each_reader(tmp_path: Path) -> None:
    lecture = read_lecture(write(tmp_path, LECTURE))
    first, second = lecture.steps
    assert lecture.titles == {"de": "Kreisel"}
    assert set(first.words) == {"de", "zh"} and set(second.words) == {"es"}
    assert translate(first.caption, "de").startswith("**1. Der schwere Kreisel.**")
    # As the panel shows it too (sanitized: the tag removed, & as an entity).
    shown = lecturer_markdown(first.caption)
    assert translate(shown, "de") == lecturer_markdown(first.words["de"]["caption"])
    assert translate(first.caption, "es") == first.caption  # no Spanish given: English
    assert second.ask is not None
    assert translate(second.ask.text, "es") == "¿Qué hace la raqueta alrededor de su eje intermedio?"
    assert [translate(c, "es") for c in second.ask.choices] == ["Gira de forma estable", "Da la vuelta"]
    assert translate("Spinning tops", "de") == "Kreisel"
    assert translate(first.caption, PSEUDO).startswith("⟦")  # the pseudo-locale sees it as a message too


@pytest.mark.parametrize(
    ("change", "message"),
    [
        ('[step.de]\ncaption = "x"\n[step.de.more]\nx = 1', r"step 1, de: unknown key 'more'"),
        ("[step.de]\ncaption = 3", r"step 1, de, caption: text, got int"),
        ('[step.de]\nquestion = "Wie?"', r"step 1, de, question: the step asks no question"),
        ('[step.de]\nchoices = ["a"]', r"step 1, de, choices: the step's question has no choices"),
        ('[step.fr]\ncaption = "x"', r"step 1: unknown key 'fr'"),
    ],
)
def test_a_wrong_translation_is_refused_with_where_it_is(tmp_path: Path, change: str, message: str) -> None:
    text = 'title = "t"\n[[step]]\nscene = "heavy_top"\ncaption = "c"\n' + change + "\n"
    with pytest.raises(ValueError, match=message):
        read_lecture(write(tmp_path, text))


def test_choices_must_match_the_englishs_count(tmp_path: Path) -> None:
    text = LECTURE.replace('choices = ["Gira de forma estable", "Da la vuelta"]', 'choices = ["Gira"]')
    with pytest.raises(ValueError, match=r"step 2, es, choices: 2 texts, as in English, got 1"):
        read_lecture(write(tmp_path, text))


def test_a_lectures_title_table_takes_a_title_only(tmp_path: Path) -> None:
    with pytest.raises(ValueError, match=r"de: a table with the lecture's title"):
        read_lecture(write(tmp_path, LECTURE.replace('[de]\ntitle = "Kreisel"', '[de]\ntitle = "K"\nother = 1')))
