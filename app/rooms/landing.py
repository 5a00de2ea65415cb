"""The landing page at ``/``: the department's rooms (name, mode, scene), each a link to ``/NAME/``.

A student who types the bare address finds the room. The page is static (written into nginx's
configuration), small, readable on a phone, and says nothing secret (no PIN, no backend address).
"""

from __future__ import annotations

import html

from app.rooms.config import Department, Room

__all__ = ["MODE_WORDS", "landing_html"]

MODE_WORDS = {
    "presenter": "lecture: follow the lecturer (the PIN drives it)",
    "private": "private: a simulation of your own",
    "shared": "shared: one simulation for everyone",
}
"""What each mode means to a student, as the page says it."""

STYLE = (
    "body{font-family:system-ui,sans-serif;max-width:44em;margin:2em auto;padding:0 1em;color:#222}"
    "table{border-collapse:collapse;width:100%}th,td{text-align:left;padding:.5em;border-bottom:1px solid #ddd}"
    "a{font-weight:600}"
)


def _row(room: Room) -> str:
    name = html.escape(room.name, quote=True)
    scene = html.escape(room.scene or "the first scene", quote=True)
    mode = html.escape(MODE_WORDS[room.mode], quote=True)
    return f'<tr><td><a href="/{name}/">{name}</a></td><td>{mode}</td><td>{scene}</td></tr>'


def landing_html(department: Department) -> str:
    """The landing page's HTML (no single quote, backslash or ``$``: it is written as one nginx string)."""
    title = html.escape(department.title, quote=True)
    rows = "".join(_row(room) for room in department.rooms)
    return (
        (
            "<!doctype html>"
            f'<html lang="en"><head><meta charset="utf-8"><title>{title}</title>'
            '<meta name="viewport" content="width=device-width, initial-scale=1">'
            f"<style>{STYLE}</style></head><body>"
            f"<h1>{title}</h1><p>Choose your room:</p>"
            f"<table><thead><tr><th>Room</th><th>Mode</th><th>Scene</th></tr></thead><tbody>{rows}</tbody></table>"
            "</body></html>"
        )
        .replace("$", "&#36;")
        .replace("\\", "&#92;")
    )
