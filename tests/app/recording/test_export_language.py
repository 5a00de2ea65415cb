"""An export in the reader's language: ``rigid-body-lab export --lang de`` (and the panel's Export button in a
German browser) writes a page whose scene labels are German and whose ``<html lang>`` says so; the CSV is
the same in every language (symbols and SI units). The recording is read back as viser's client reads it:
base64, zstd, an 8-byte length, msgpack."""

from __future__ import annotations

import base64
import re
from pathlib import Path
from typing import Any

import msgspec
import pytest
import zstandard

from app.__main__ import main
from app.language.catalogs import PSEUDO
from app.language.words import translate
from app.serving.app import export

LABELS = ("centre of percussion", "strike point")
"""The pendulum's labels in its 3D scene (its CM label is a symbol, the same in every language)."""


def recorded_texts(html: str) -> list[str]:
    """Every label text the exported page's recording holds."""
    encoded = re.search(r'window.__VISER_EMBED_DATA__="([^"]+)"', html)
    assert encoded is not None, "no recording in the page"
    packed = base64.b64decode(encoded.group(1))
    inner = zstandard.ZstdDecompressor().decompress(packed[8:], max_output_size=int.from_bytes(packed[:8], "little"))
    length = int.from_bytes(inner[:8], "little")
    recording: dict[str, Any] = msgspec.msgpack.decode(inner[8 : 8 + length])
    texts = []
    for _moment, message in recording["messages"]:
        for fields in (message, message.get("props") or {}, message.get("updates") or {}):
            if isinstance(fields, dict) and isinstance(fields.get("text"), str):
                texts.append(fields["text"])
    return texts


@pytest.mark.parametrize("lang", ["de", "es", "zh", PSEUDO])
def test_an_export_is_written_in_its_language(tmp_path: Path, lang: str) -> None:
    written = export("pendulum", tmp_path / lang, 0.2, lang=lang)
    page = written.html.read_text(encoding="utf-8")
    assert f'<html lang="{lang}">' in page
    texts = recorded_texts(page)
    for label in LABELS:
        assert translate(label, lang) != label
        assert translate(label, lang) in texts and label not in texts, (label, texts)
    english = export("pendulum", tmp_path / "en", 0.2)
    assert set(LABELS) <= set(recorded_texts(english.html.read_text(encoding="utf-8")))
    assert '<html lang="en">' in english.html.read_text(encoding="utf-8")
    assert written.csv.read_text(encoding="utf-8") == english.csv.read_text(encoding="utf-8")


def test_the_command_line_takes_lang(tmp_path: Path, capsys: pytest.CaptureFixture[str]) -> None:
    main(["export", "--scene", "pendulum", "--seconds", "0.2", "--out", str(tmp_path), "--lang", "de"])
    page = (tmp_path / "index.html").read_text(encoding="utf-8")
    assert '<html lang="de">' in page and translate("strike point", "de") in recorded_texts(page)
    with pytest.raises(SystemExit):
        main(["export", "--scene", "pendulum", "--seconds", "0.2", "--out", str(tmp_path), "--lang", "fr"])
    assert "invalid choice: 'fr'" in capsys.readouterr().err


def test_a_bad_language_is_refused_before_anything_runs(tmp_path: Path) -> None:
    with pytest.raises(ValueError, match="fr"):
        export("pendulum", tmp_path, 0.2, lang="fr")
    assert not tmp_path.joinpath("index.html").exists()


def test_the_panels_export_is_in_the_pressing_browsers_language() -> None:
    """The Export folder asks the server's languages which one a browser reads (a browser nobody has heard
    of reads ``--lang``'s)."""
    from tests.harness import running_app

    with running_app("pendulum", start_loop=False, lang="es") as app:
        folder = app.simulation.export_folder
        assert folder.language(123_456) == "es" == app.languages.language(123_456)
