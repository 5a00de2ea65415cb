"""Text is text: the one way untrusted text reaches viser's Markdown and Html elements, and the sanitizer of
the lecturer's Markdown.

viser 1.1.1 renders raw HTML inside its Markdown element (``rehypeRawDom``: tags, attributes and event
handlers as written) and sets its Html element's ``innerHTML``; its server also reads an image file for
every ``![..](path)`` in a Markdown element's content and sends it to the page. So anything that comes from
a browser or a file (mesh and file names, state texts, typed names, questions, choices, answers) goes in
through :func:`markdown_text` or :func:`html_text`, which leave nothing for either parser to act on; the
lecturer's Markdown (captions, lecture steps) keeps its formatting through :func:`lecturer_markdown`, which
removes every HTML tag with the maintained sanitizer ``nh3``. More in docs/security.md.
"""

from __future__ import annotations

import html
import re
import unicodedata
from collections.abc import Iterable
from typing import Any

import nh3

__all__ = ["csv_cell", "csv_row", "html_text", "lecturer_markdown", "markdown_text"]

_MARKDOWN_MARKS = frozenset("\\`*_[]!#|~{}")
"""The punctuation that opens Markdown's inline formatting, links and images, code, tables, strike-through
and headings: each gets a backslash (CommonMark makes any escaped ASCII punctuation literal). ``& < >``
become entities; other punctuation (``. , ( ) - : ;``) does nothing without these and stays as it is."""

_LEADING_MARK = re.compile(r"^(\s*)([-+*]|\d+[.)])(?=\s|$)")
"""A line that starts like a list item or a heading's underline."""


_FORMULA_START = ("=", "+", "-", "@", "\t", "\r")
"""What makes a spreadsheet read a cell as a formula (OWASP's CSV-injection list)."""


def _plain(text: object) -> str:
    """``text`` as one line: control characters (newlines included) become spaces."""
    return "".join(" " if unicodedata.category(c) in ("Cc", "Cf", "Zl", "Zp") else c for c in str(text))


def html_text(text: object) -> str:
    """``text`` (anything; ``str()`` of it) for an Html element, shown as the characters it has, on one line.

    Every ``& < > " '`` becomes its entity, so no tag, attribute or entity of the text is parsed.
    """
    return html.escape(_plain(text), quote=True)


def markdown_text(text: object) -> str:
    """``text`` (anything; ``str()`` of it) for a Markdown element, shown as the characters it has, on one
    line, with no formatting, link, image or HTML.

    ``& < >`` become entities (a Markdown parser turns an entity into a literal character, never into a
    tag) and the marks of :data:`_MARKDOWN_MARKS` get a backslash, so ``*``, ``[``, ``](``, ``!``, ``#``
    and the like stay literal; viser's image reader, which looks for ``![``, finds none. A leading list
    marker is escaped too.
    """
    out = []
    for c in _plain(text):
        if c in "&<>":
            out.append(html.escape(c, quote=False))
        elif c in _MARKDOWN_MARKS:
            out.append("\\" + c)
        else:
            out.append(c)
    return _LEADING_MARK.sub(lambda m: m.group(1) + m.group(2)[:-1] + "\\" + m.group(2)[-1], "".join(out))


def lecturer_markdown(text: str) -> str:
    """The lecturer's Markdown with every HTML tag removed and its formatting kept.

    ``nh3`` (the Rust ``ammonia`` sanitizer) is given no tag to keep: every tag goes, and the content of
    ``script`` and ``style`` goes with it; the text of others stays as text, its ``<`` and ``&`` as
    entities, which Markdown shows as the characters. ``>`` is given back as itself (it cannot open a tag;
    Markdown needs it for a quotation). Markdown's own links and images are left for the page, whose
    Markdown renderer drops ``javascript:`` and other unsafe link targets.
    """
    if not isinstance(text, str):
        raise ValueError(f"lecturer Markdown must be text, got {type(text).__name__}")
    cleaned = nh3.clean(text, tags=set(), attributes={}, clean_content_tags={"script", "style"}, strip_comments=True)
    return cleaned.replace("&gt;", ">")


def csv_cell(value: Any) -> Any:
    """A cell for a CSV file a spreadsheet may open: text that starts (after spaces) with ``= + - @``, a tab
    or a carriage return gets a leading ``'`` so that it is shown, never run as a formula (OWASP's advice
    on CSV injection); a signed number (``-0.5``, ``+1e3``) is a number, and stays; anything else as it is.
    """
    if not isinstance(value, str) or not value.lstrip(" ").startswith(_FORMULA_START):
        return value
    try:
        float(value.replace("_", "x"))  # Python's float takes "1_0"; a spreadsheet does not
    except ValueError:
        return "'" + value
    return value


def csv_row(row: Iterable[Any]) -> list[Any]:
    """Every cell of ``row`` through :func:`csv_cell`."""
    return [csv_cell(value) for value in row]
