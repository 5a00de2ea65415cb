"""The pseudo-locale: a text accented, bracketed and made 40% longer, its placeholders and markup kept.

Under it a page shows at a glance any English that did not pass through the catalogs (it stays plain ASCII),
and whether the panel holds a language that writes longer than English (German runs about 30% longer).
"""

from __future__ import annotations

import math
import re

__all__ = ["GROWTH", "OPEN", "CLOSE", "pseudo"]

OPEN, CLOSE = "⟦", "⟧"
"""The brackets around a pseudo-translated text (not ``[ ]``, which Markdown reads as a link)."""
GROWTH = 0.4
"""How much longer a pseudo-translated text is than its English, at least."""

_ACCENTED = str.maketrans(
    "abcdefghijklmnopqrstuvwxyzABCDEFGHIJKLMNOPQRSTUVWXYZ",
    "àƀçđéƒĝĥîĵķĺɱñöƥǫŕšţûṽŵẋýžÀƁÇĐÉƑĜĤÎĴĶĹṀÑÖƤǪŔŠŢÛṼŴẊÝŽ",
)
_KEPT = re.compile(r"\{[^{}]*\}|<[^<>]*>|&[#\w]+;|`[^`]*`|\$[^$]*\$|https?://\S+")
"""What a translation keeps as it is: ``{placeholders}``, HTML tags and entities, code and math spans, links."""


def pseudo(text: str) -> str:
    """``text`` in the pseudo-locale: letters accented, outside placeholders and markup; bracketed; padded.

    >>> pseudo("Spin {omega} rad/s")
    '⟦Šƥîñ {omega} ŕàđ/š······⟧'
    """
    if not text.strip():
        return text
    pieces, last = [], 0
    for kept in _KEPT.finditer(text):
        pieces.append(text[last : kept.start()].translate(_ACCENTED))
        pieces.append(kept.group())
        last = kept.end()
    pieces.append(text[last:].translate(_ACCENTED))
    body = "".join(pieces)
    # Whitespace at the ends stays outside (a Markdown line break, an indented line).
    stripped = body.strip()
    lead = body[: len(body) - len(body.lstrip())]
    trail = body[len(body.rstrip()) :]
    padding = "·" * max(1, math.ceil(GROWTH * len(text)) - len(OPEN + CLOSE))
    return f"{lead}{OPEN}{stripped}{padding}{CLOSE}{trail}"
