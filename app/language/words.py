"""The words the app shows: marked for the catalogs in English, translated for each reader.

A fixed text is marked with :func:`mark` where it is written (Babel's extractor finds it; gettext's ``N_``);
a text with values in it is made with :func:`say`, which returns the English and remembers how it was made,
so that :func:`translate` can make it again in another language with the values written as that
language writes numbers (``0,517 rad/s``). Texts that are neither (a student's name, a file's) pass
through :func:`translate` unchanged.
"""

from __future__ import annotations

import functools
import html
import string
import threading
from collections import OrderedDict
from collections.abc import Callable
from typing import NamedTuple

from babel.messages.pofile import read_po
from babel.numbers import get_decimal_symbol, get_group_symbol, get_minus_sign_symbol

from app.language.catalogs import DOMAIN, LANGUAGES, LOCALE_DIR, PSEUDO, SOURCE, babel_locale, catalog, check_language
from app.language.pseudo import pseudo

__all__ = [
    "PER_TEMPLATE",
    "REMEMBERED",
    "Said",
    "carried",
    "english_option",
    "escaped",
    "learn",
    "joined",
    "keep",
    "mark",
    "remembered_count",
    "say",
    "said_again",
    "template_ids",
    "transformed",
    "translate",
]

REMEMBERED = 20_000
"""How many texts made by :func:`say` are remembered (the newest; a readout makes a new one each frame, and
is translated as soon as it is sent)."""

PER_TEMPLATE = 1_000
"""How many of those one template may hold (its newest): a readout rewritten every frame (a friction top's
tilt, in every private session) forgets its own older texts, not the other templates' texts that are still
on screen (a stability readout set once, a session's number)."""

_FORMATTER = string.Formatter()
_SAID: OrderedDict[str, tuple[str, tuple[tuple[str, object], ...]]] = OrderedDict()
_BY_TEMPLATE: dict[str, OrderedDict[str, None]] = {}  # template -> its remembered texts, oldest first
_KEPT: dict[str, tuple[str, tuple[tuple[str, object], ...]]] = {}
_LOCK = threading.Lock()


def mark(text: str) -> str:
    """``text`` unchanged, marked for the catalogs (a label, a button, a caption)."""
    return text


def say(template: str, /, **values: object) -> str:
    """``template`` filled with ``values`` in English, remembered so it can be translated.

    Parameters
    ----------
    template : str
        English with ``{name}`` or ``{name:.3f}`` fields (Python's format syntax), the catalogs' message id.
    **values
        A number is written as each language writes it (decimal comma, group separator) with the field's
        format; a text is itself translated (a word made with :func:`mark` or :func:`say`).

    Returns
    -------
    str
        The English text.
    """
    text = template.format(**values)
    if values and text not in values.values():  # a text that is its own value would translate for ever
        with _LOCK:
            _remember(text, template, tuple(values.items()))
    return text


class Said(NamedTuple):
    """How a text was said (its template and values, a value said in turn carried likewise), as plain data:
    what a worker process sends back with a refusal, so the app can say it again and translate it."""

    template: str
    values: tuple[tuple[str, object], ...]


def carried(text: str) -> Said | None:
    """How ``text`` was made by :func:`say` in this process (None if it was not, or is forgotten)."""
    with _LOCK:
        made = _SAID.get(text)
    if made is None:
        return None
    template, values = made
    return Said(template, tuple((k, carried(v) or v if isinstance(v, str) else v) for k, v in values))


def said_again(said: Said) -> str:
    """The text ``said`` describes, made again with :func:`say` in this process (so it translates here)."""
    values = {k: said_again(v) if isinstance(v, Said) else v for k, v in said.values}
    return say(said.template, **values)


def _remember(text: str, template: str, values: tuple[tuple[str, object], ...]) -> None:
    """Remember ``text`` as the newest, forgetting the oldest of its template past :data:`PER_TEMPLATE` and
    the oldest of all past :data:`REMEMBERED` (the caller holds the lock)."""
    before = _SAID.get(text)
    if before is not None and before[0] != template:  # the same English made by another template now
        _forget(text)
    _SAID[text] = (template, values)
    _SAID.move_to_end(text)
    own = _BY_TEMPLATE.setdefault(template, OrderedDict())
    own[text] = None
    own.move_to_end(text)
    while len(own) > PER_TEMPLATE:
        _forget(next(iter(own)))
    while len(_SAID) > REMEMBERED:
        _forget(next(iter(_SAID)))


def _forget(text: str) -> None:
    made = _SAID.pop(text, None)
    if made is None:
        return
    own = _BY_TEMPLATE.get(made[0])
    if own is not None:
        own.pop(text, None)
        if not own:
            del _BY_TEMPLATE[made[0]]


_JOIN = "{before}{separator}{after}"
"""Two texts joined (markup alone, not a message of the catalogs): each part translated as a value."""


def joined(parts: list[str] | tuple[str, ...], separator: str = "") -> str:
    """``separator.join(parts)``, made with :func:`say` so that each part (a word made with :func:`mark` or
    :func:`say`) is still translated in the joined text: a list whose length varies (a legend's rows, a
    chart's bars). The separator is translated too if it is a word of the catalogs."""
    if not parts:
        return ""
    text = parts[0]
    for part in parts[1:]:
        text = say(_JOIN, before=text, separator=separator, after=part)
    return text


def keep(text: str) -> str:
    """``text``, made by :func:`say`, kept translatable as long as the process runs (not only among the
    :data:`REMEMBERED` newest): a text made once and shown for ever, such as a caption with a number in it.
    A text :func:`say` made without values (a message id itself) needs no keeping and is returned as it is.
    """
    with _LOCK:
        waiting = [text]
        while waiting:  # the text and every said text it was made of (a legend's rows)
            part = waiting.pop()
            made = _SAID.get(part)
            if made is not None and part not in _KEPT:
                _KEPT[part] = made
                waiting += [value for _, value in made[1] if isinstance(value, str)]
    return text


def remembered_count() -> int:
    """How many texts made by :func:`say` are remembered now (at most :data:`REMEMBERED`)."""
    with _LOCK:
        return len(_SAID)


@functools.cache
def template_ids() -> frozenset[str]:
    """Every message id of the catalogs' template (``locale/rigid_body_lab.pot``)."""
    with (LOCALE_DIR / f"{DOMAIN}.pot").open("rb") as fp:
        return frozenset(str(m.id) for m in read_po(fp) if m.id)


def _number(value: float | int, spec: str, lang: str) -> str:
    english = format(value, spec)
    locale = babel_locale(lang)
    symbols = {".": get_decimal_symbol(locale), ",": get_group_symbol(locale), "-": get_minus_sign_symbol(locale)}
    return "".join(symbols.get(c, c) for c in english)


def _fill(template: str, values: tuple[tuple[str, object], ...], lang: str) -> str:
    given = dict(values)
    out = []
    for literal, field, spec, conversion in _FORMATTER.parse(template):
        out.append(literal)
        if field is None:
            continue
        value = given[field]
        if isinstance(value, (int, float)) and not isinstance(value, bool) and conversion is None:
            out.append(_number(value, spec or "", lang))
        elif isinstance(value, str) and conversion is None:
            out.append(format(translate(value, lang), spec or ""))
        else:
            out.append(_FORMATTER.format_field(_FORMATTER.convert_field(value, conversion), spec or ""))
    return "".join(out)


def _template(english: str, lang: str) -> str:
    with _LOCK:
        learnt = _LEARNT.get((lang, english))
    if learnt is not None:
        return learnt
    if lang == PSEUDO:
        return pseudo(english) if english in template_ids() else english
    return catalog(lang).gettext(english)


_DERIVED: OrderedDict[str, tuple[Callable[[str], str], str]] = OrderedDict()
"""Texts made from a translatable text by a transformation (escaped, sanitized), newest last."""
_LEARNT: dict[tuple[str, str], str] = {}
"""Translations given at run time (a lecture file's own), by (language, English)."""


def transformed(text: str, transform: Callable[[str], str]) -> str:
    """``transform(text)``, still translatable: its translation is ``transform`` of the translation of
    ``text`` (a said text escaped for Html, a lecturer's Markdown sanitized). ``transform`` must be pure."""
    out = transform(text)
    if out != text:
        with _LOCK:
            _DERIVED[out] = (transform, text)
            _DERIVED.move_to_end(out)
            while len(_DERIVED) > REMEMBERED:
                _DERIVED.popitem(last=False)
    return out


def escaped(text: str) -> str:
    """``html.escape(text)``, still translatable (:func:`transformed`)."""
    return transformed(text, html.escape)


def learn(english: str, lang: str, text: str) -> None:
    """Translate ``english`` as ``text`` for readers of ``lang`` from now on (a lecture file's own captions
    and questions, which no catalog holds); the pseudo-locale then treats ``english`` as a message too."""
    check_language(lang)
    if not english:
        return
    with _LOCK:
        if len(_LEARNT) >= REMEMBERED and (lang, english) not in _LEARNT:
            raise ValueError(f"at most {REMEMBERED} texts may be given translations, got one more: {english[:40]!r}")
        _LEARNT[(lang, english)] = text
        _LEARNT[(PSEUDO, english)] = pseudo(english)


def translate(text: str, lang: str) -> str:
    """``text`` as a reader of ``lang`` reads it (unchanged in English, or if the app did not write it)."""
    if lang == SOURCE or not text:
        return text
    check_language(lang)
    with _LOCK:
        made = _SAID.get(text) or _KEPT.get(text)
        derived = _DERIVED.get(text) if made is None else None
        learnt = _LEARNT.get((lang, text))
    if learnt is not None:
        return learnt
    if derived is not None:
        transform, source = derived
        return transform(translate(source, lang))
    if made is None:
        return _template(text, lang)
    template, values = made
    try:
        return _fill(_template(template, lang), values, lang)
    except (KeyError, IndexError, ValueError):  # a translation whose fields do not match: the English form
        return _fill(template, values, lang)


def english_option(value: str, options: tuple[str, ...]) -> str:
    """The English option that ``value``, chosen in a browser reading a translated dropdown, stands for
    (``value`` itself if it is an option, or stands for none)."""
    if value in options:
        return value
    for lang in [*LANGUAGES, PSEUDO]:
        for option in options:
            if translate(option, lang) == value:
                return option
    return value
