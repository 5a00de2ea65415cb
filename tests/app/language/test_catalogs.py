"""The catalogs: every language complete, every placeholder and tag of a message kept in its translation,
the browser's preferred language found, the catalogs compiled into a built package."""

from __future__ import annotations

import gettext
import importlib.util
import re
import shutil
import string
from pathlib import Path

import pytest
from babel.messages.pofile import read_po

from app.language.catalogs import DOMAIN, LANGUAGES, LOCALE_DIR, PSEUDO, babel_locale, catalog, negotiate
from app.language.words import template_ids

ROOT = Path(__file__).resolve().parents[3]
TRANSLATED = [lang for lang in LANGUAGES if lang != "en"]
TAG = re.compile(r"</?\s*([a-zA-Z][\w-]*)")


def fields(text: str) -> set[str]:
    return {f"{name}:{spec}" for _, name, spec, _ in string.Formatter().parse(text) if name is not None}


def entries(lang: str) -> dict[str, str]:
    with (LOCALE_DIR / lang / "LC_MESSAGES" / f"{DOMAIN}.po").open("rb") as fp:
        return {str(m.id): str(m.string) for m in read_po(fp) if m.id}


@pytest.mark.parametrize("lang", TRANSLATED)
def test_every_message_is_translated(lang: str) -> None:
    found = entries(lang)
    missing = sorted(set(template_ids()) - {k for k, v in found.items() if v.strip()})
    assert missing == [], f"{lang}: {len(missing)} untranslated, e.g. {missing[:5]}"


@pytest.mark.parametrize("lang", TRANSLATED)
def test_every_placeholder_and_tag_survives_translation(lang: str) -> None:
    """A translation with a field missing, renamed or reformatted would fail to fill (the English form would
    be shown); one with a tag lost would break the markup: both are caught here, message by message."""
    wrong = []
    for english, translated in entries(lang).items():
        if not translated:
            continue
        if fields(english) != fields(translated):
            wrong.append((english, translated, "fields"))
        if sorted(TAG.findall(english)) != sorted(TAG.findall(translated)):
            wrong.append((english, translated, "tags"))
    assert wrong == []


def test_the_check_sees_a_lost_placeholder() -> None:
    assert fields("ω = {omega:.3f} rad/s") != fields("ω = {omega} rad/s")
    assert fields("{a} and {b}") == fields("{b} und {a}")


@pytest.mark.parametrize("lang", TRANSLATED)
def test_a_catalog_loads_and_translates(lang: str) -> None:
    assert catalog(lang).gettext("Play") not in ("", "Play")


@pytest.mark.parametrize(
    ("header", "default", "expected"),
    [
        ("de-DE,de;q=0.9,en;q=0.8", "en", "de"),
        ("fr-FR,fr;q=0.9,es;q=0.5", "en", "es"),  # the best we speak, not the first
        ("fr-FR,en;q=0.1,de;q=0.5", "es", "de"),  # ranked by quality, not by order
        ("zh-CN,zh;q=0.9", "en", "zh"),
        ("fr", "de", "de"),  # nothing we speak: the app's language
        (None, "es", "es"),
        ("", "es", "es"),
        ("de;q=0", "en", "en"),  # q=0: not acceptable
        ("de;q=abc,es", "en", "es"),  # an unreadable quality: that entry ignored
        ("x" * 5000, "en", "en"),  # an enormous header: the default, without parsing it
        ("<script>,de", "en", "de"),
    ],
)
def test_the_browsers_preferred_language_is_found(header: str | None, default: str, expected: str) -> None:
    assert negotiate(header, default) == expected


def test_numbers_follow_each_language() -> None:
    assert babel_locale("de").number_symbols["latn"]["decimal"] == ","
    assert babel_locale("es").number_symbols["latn"]["decimal"] == ","
    assert babel_locale("zh").number_symbols["latn"]["decimal"] == "."
    assert babel_locale(PSEUDO).number_symbols["latn"]["decimal"] == "."


def test_an_unknown_language_is_refused_with_the_choices() -> None:
    with pytest.raises(ValueError, match="expected a language among en, de, es, zh, en-XA, got 'xx'"):
        catalog("xx")


def test_the_build_step_compiles_every_catalog_to_what_the_app_reads(tmp_path: Path) -> None:
    """setup.py's build step (run by ``pip install`` and by a wheel's build) writes a ``.mo`` per language
    that gettext reads back to the same translations the app uses."""
    spec = importlib.util.spec_from_file_location("setup_for_test", ROOT / "setup.py")
    assert spec is not None and spec.loader is not None
    build = importlib.util.module_from_spec(spec)
    spec.loader.exec_module(build)
    shutil.copytree(LOCALE_DIR, tmp_path / "locale")
    written = build.compile_catalogs(tmp_path / "locale")
    assert sorted(p.parent.parent.name for p in written) == sorted(TRANSLATED)
    for mo in written:
        with mo.open("rb") as fp:
            compiled = gettext.GNUTranslations(fp)
        lang = mo.parent.parent.name
        for english, translated in entries(lang).items():
            assert compiled.gettext(english) == (translated or english) == catalog(lang).gettext(english)
