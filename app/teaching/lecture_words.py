"""A lecture file's own words in other languages: each step may carry its caption, question and choices per
language, and the lecture its title, which every reader of that language then reads.

A step writes them as a table named after the language (docs/lectures.md)::

    [[step]]
    caption = "**1. The inertia tensor.** ..."
    [step.de]
    caption = "**1. Der Trägheitstensor.** ..."

No catalog holds a lecturer's text: reading the file teaches the app its translations
(:func:`app.language.words.learn`), which the wire then uses as it uses the catalogs'.
"""

from __future__ import annotations

from typing import Any

from app.guards.text import lecturer_markdown
from app.language.catalogs import LANGUAGES, SOURCE
from app.language.words import learn

__all__ = ["LANGUAGE_KEYS", "STEP_WORDS", "check_lecture_words", "check_step_words", "learn_words"]

LANGUAGE_KEYS = tuple(lang for lang in LANGUAGES if lang != SOURCE)
"""The tables a step (and the lecture) may have: one per language the app speaks besides English."""
STEP_WORDS = ("caption", "question", "choices")
"""What of a step a language's table may give."""


def check_step_words(
    raw: dict[str, Any], where: str, question: str | None, choices: tuple[str, ...]
) -> dict[str, dict[str, Any]]:
    """A step's words per language, checked: ``{lang: {"caption": str, "question": str, "choices": [str]}}``.

    Parameters
    ----------
    raw : dict
        The step's table as read from the file.
    where : str
        Names the step in a message (``"lecture.toml, step 3"``).
    question, choices :
        The step's question and its choices in English (None, (): the step asks nothing).

    Raises
    ------
    ValueError
        A language's table is not a table, gives a key it may not, a text that is not text, a question to a
        step that asks none, or another number of choices than the English.
    """
    out: dict[str, dict[str, Any]] = {}
    for lang in LANGUAGE_KEYS:
        table = raw.get(lang)
        if table is None:
            continue
        here = f"{where}, {lang}"
        if not isinstance(table, dict):
            raise ValueError(f'{here}: a table of the step\'s words in that language, e.g. [step.{lang}] caption = "…"')
        for key, value in table.items():
            if key not in STEP_WORDS:
                raise ValueError(f"{here}: unknown key {key!r} (a language's table gives {', '.join(STEP_WORDS)})")
            if key == "choices":
                if not choices:
                    raise ValueError(f"{here}, choices: the step's question has no choices to translate")
                if not isinstance(value, list) or not all(isinstance(c, str) and c for c in value):
                    raise ValueError(f"{here}, choices: a list of texts, got {value!r}")
                if len(value) != len(choices):
                    raise ValueError(f"{here}, choices: {len(choices)} texts, as in English, got {len(value)}")
            elif not isinstance(value, str):
                raise ValueError(f"{here}, {key}: text, got {type(value).__name__}")
            if key == "question" and question is None:
                raise ValueError(f"{here}, question: the step asks no question")
        out[lang] = dict(table)
    return out


def check_lecture_words(document: dict[str, Any], where: str) -> dict[str, str]:
    """The lecture's title per language (``[de] title = "…"``), checked."""
    titles: dict[str, str] = {}
    for lang in LANGUAGE_KEYS:
        table = document.get(lang)
        if table is None:
            continue
        if not isinstance(table, dict) or set(table) - {"title"} or not isinstance(table.get("title", ""), str):
            raise ValueError(
                f'{where}, {lang}: a table with the lecture\'s title in that language, [{lang}] title = "…"'
            )
        if "title" in table:
            titles[lang] = table["title"]
    return titles


def learn_words(english: dict[str, Any], words: dict[str, dict[str, Any]]) -> None:
    """Teach the app a step's (or a lecture's) translations: each text as given, and as the panel shows it
    (the lecturer's Markdown sanitized, :func:`app.guards.text.lecturer_markdown`).

    ``english`` holds the English of each key given (``choices``: a tuple of texts)."""
    for lang, table in words.items():
        for key, text in table.items():
            pairs = zip(english[key], text, strict=True) if key == "choices" else [(english[key], text)]
            for source, translated in pairs:
                learn(source, lang, translated)
                learn(lecturer_markdown(source), lang, lecturer_markdown(translated))
