"""The languages the app speaks and their message catalogs (gettext, managed with Babel).

The catalogs live in this package (``locale/<lang>/LC_MESSAGES/rigid_body_lab.po``), compiled to ``.mo``
when the package is built (``setup.py``'s build step runs Babel's compiler), so a plain ``pip install`` has
them; a source checkout without a build compiles a catalog in memory the first time it is asked for.
How to add a language: docs/translating.md.
"""

from __future__ import annotations

import functools
import gettext
import io
import threading
from pathlib import Path

from babel import Locale, UnknownLocaleError
from babel.messages.mofile import write_mo
from babel.messages.pofile import read_po

__all__ = [
    "DOMAIN",
    "LANGUAGES",
    "LOCALE_DIR",
    "PSEUDO",
    "SOURCE",
    "babel_locale",
    "catalog",
    "check_language",
    "negotiate",
]

DOMAIN = "rigid_body_lab"
LOCALE_DIR = Path(__file__).parent / "locale"
SOURCE = "en"
"""The language the app is written in: its catalogs' message ids."""
PSEUDO = "en-XA"
"""The pseudo-locale (Chromium's and Android's tag for it): every translatable text accented, bracketed and
40% longer (:mod:`app.language.pseudo`), so English that escaped the catalogs stands out."""

LANGUAGES: dict[str, str] = {"en": "English", "de": "Deutsch", "es": "Español", "zh": "中文"}
"""The languages a browser may choose, each named in itself (the pseudo-locale is for tests and translators,
chosen with ``--lang en-XA`` only)."""

_BABEL = {"en": "en", "de": "de", "es": "es", "zh": "zh_Hans_CN", PSEUDO: "en"}
_LOCK = threading.Lock()


def check_language(lang: str) -> str:
    """``lang`` if the app speaks it (or it is :data:`PSEUDO`), else ValueError naming the choices."""
    if lang in LANGUAGES or lang == PSEUDO:
        return lang
    choices = ", ".join([*LANGUAGES, PSEUDO])
    raise ValueError(f"expected a language among {choices}, got {lang!r}")


@functools.cache
def babel_locale(lang: str) -> Locale:
    """Babel's locale for a language of the app: how it writes numbers (decimal comma, minus sign)."""
    return Locale.parse(_BABEL[check_language(lang)])


@functools.cache
def _compiled(lang: str) -> gettext.NullTranslations:
    mo = LOCALE_DIR / lang / "LC_MESSAGES" / f"{DOMAIN}.mo"
    po = mo.with_suffix(".po")
    if mo.exists() and (not po.exists() or mo.stat().st_mtime >= po.stat().st_mtime):
        with mo.open("rb") as fp:
            return gettext.GNUTranslations(fp)
    if not po.exists():
        raise FileNotFoundError(f"no catalog for {lang!r}: expected {po}")
    with po.open("rb") as fp:
        messages = read_po(fp, locale=_BABEL[lang])
    out = io.BytesIO()
    write_mo(out, messages)
    out.seek(0)
    return gettext.GNUTranslations(out)


def catalog(lang: str) -> gettext.NullTranslations:
    """The message catalog of ``lang`` (English and the pseudo-locale: an empty one, every text its own)."""
    check_language(lang)
    if lang in (SOURCE, PSEUDO):
        return gettext.NullTranslations()
    with _LOCK:  # the first load compiles; two threads need not do it twice
        return _compiled(lang)


def negotiate(accept_language: str | None, default: str) -> str:
    """The language a browser prefers among :data:`LANGUAGES`, from its ``Accept-Language`` header.

    Parameters
    ----------
    accept_language : str or None
        The header as the browser sent it (``"de-DE,de;q=0.9,en;q=0.8"``); None or unreadable: ``default``.
    default : str
        The app's language (``rigid-body-lab --lang``), taken when the browser prefers none we have.
    """
    check_language(default)
    if not accept_language or len(accept_language) > 1000:
        return default
    ranked: list[tuple[float, int, str]] = []
    for position, part in enumerate(accept_language.split(",")[:32]):
        tag, _, params = part.strip().partition(";")
        quality = 1.0
        if params.strip().startswith("q="):
            try:
                quality = float(params.strip()[2:])
            except ValueError:
                continue
        if tag and quality > 0:
            ranked.append((-quality, position, tag.strip()))
    for _, _, tag in sorted(ranked):
        try:
            language = Locale.parse(tag.replace("-", "_")).language
        except (ValueError, UnknownLocaleError):
            continue
        if language in LANGUAGES:
            return language
    return default
