"""The landing page at ``/``: the department's rooms (name, mode, scene), each a link to ``/NAME/``.

A student who types the bare address finds the room. The page is static (written into nginx's
configuration), small, readable on a phone, and says nothing secret (no PIN, no backend address).

Its words are the catalogs' (:mod:`app.language`): ``landing_html(department, lang)`` writes the page in one
language; the rooms' nginx configuration carries one per language and serves the one the browser asks for
first (:mod:`app.rooms.nginx`).
"""

from __future__ import annotations

import html

from app.language.catalogs import SOURCE, check_language
from app.language.words import mark, translate
from app.rooms.config import Department, Room

__all__ = ["MODE_WORDS", "landing_html"]

MODE_WORDS = {
    "presenter": mark("lecture: follow the lecturer (the PIN drives it)"),
    "private": mark("private: a simulation of your own"),
    "shared": mark("shared: one simulation for everyone"),
}
"""What each mode means to a student, as the page says it."""

STYLE = (
    "body{font-family:system-ui,sans-serif;max-width:44em;margin:2em auto;padding:0 1em;color:#222}"
    "table{border-collapse:collapse;width:100%}th,td{text-align:left;padding:.5em;border-bottom:1px solid #ddd}"
    "a{font-weight:600}"
)


def _words(text: str, lang: str) -> str:
    """A word of the page in ``lang``, escaped (a translation may hold a quote: the page is one nginx string)."""
    return html.escape(translate(text, lang), quote=True)


def _row(room: Room, lang: str = SOURCE) -> str:
    name = html.escape(room.name, quote=True)
    scene = html.escape(room.scene, quote=True) if room.scene else _words(mark("the first scene"), lang)
    mode = _words(MODE_WORDS[room.mode], lang)
    return f'<tr><td><a href="/{name}/">{name}</a></td><td>{mode}</td><td>{scene}</td></tr>'


def landing_html(department: Department, lang: str = SOURCE) -> str:
    """The landing page's HTML (no single quote, backslash or ``$``: it is written as one nginx string), its
    words in ``lang`` (a language of :data:`app.language.catalogs.LANGUAGES`; ValueError for another)."""
    lang = check_language(lang)
    title = html.escape(department.title, quote=True)
    rows = "".join(_row(room, lang) for room in department.rooms)
    choose, room, mode, scene = (
        _words(word, lang) for word in (mark("Choose your room:"), mark("Room"), mark("Mode"), mark("Scene"))
    )
    return (
        (
            "<!doctype html>"
            f'<html lang="{lang}"><head><meta charset="utf-8"><title>{title}</title>'
            '<meta name="viewport" content="width=device-width, initial-scale=1">'
            f"<style>{STYLE}</style></head><body>"
            f"<h1>{title}</h1><p>{choose}</p>"
            f"<table><thead><tr><th>{room}</th><th>{mode}</th><th>{scene}</th></tr></thead><tbody>{rows}</tbody></table>"
            "</body></html>"
        )
        .replace("$", "&#36;")
        .replace("\\", "&#92;")
    )
