"""The pseudo-locale: every letter accented, placeholders and markup kept, bracketed, 40% longer."""

from __future__ import annotations

import re

import pytest

from app.language.pseudo import CLOSE, GROWTH, OPEN, pseudo

EXAMPLES = [
    "Play",
    "Spin {omega:.3f} rad/s",
    "**Heavy top**: <b>L</b> precesses &amp; nutates",
    "The energy $E = \\tfrac12 \\omega \\cdot L$ is kept: `code`",
    "See https://phyphox.org/ for the app",
]


@pytest.mark.parametrize("text", EXAMPLES)
def test_no_ascii_letter_survives_outside_what_is_kept(text: str) -> None:
    out = pseudo(text)
    assert out.startswith(OPEN) and out.endswith(CLOSE)
    kept = re.compile(r"\{[^{}]*\}|<[^<>]*>|&[#\w]+;|`[^`]*`|\$[^$]*\$|https?://\S+")
    assert not re.search(r"[A-Za-z]", kept.sub("", out))


@pytest.mark.parametrize("text", EXAMPLES)
def test_placeholders_and_markup_are_kept_in_order(text: str) -> None:
    kept = re.compile(r"\{[^{}]*\}|<[^<>]*>|&[#\w]+;|`[^`]*`|\$[^$]*\$|https?://\S+")
    assert kept.findall(pseudo(text)) == kept.findall(text)


@pytest.mark.parametrize("text", EXAMPLES)
def test_a_pseudo_text_is_at_least_forty_percent_longer(text: str) -> None:
    assert len(pseudo(text)) >= (1 + GROWTH) * len(text)


def test_blank_text_and_surrounding_whitespace_stay() -> None:
    assert pseudo("   ") == "   "
    assert pseudo("\nPlay  ").startswith("\n" + OPEN) and pseudo("\nPlay  ").endswith(CLOSE + "  ")
