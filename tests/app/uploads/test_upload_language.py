"""An upload's refusal reads in the reader's language, also when a worker process made it: the worker sends
back how it said the refusal (:func:`app.language.words.carried`), the app says it again
(:func:`app.language.words.said_again`), and the wire translates it like any other said text."""

from __future__ import annotations

import pickle

import pytest

from app.language.catalogs import PSEUDO
from app.language.pseudo import OPEN
from app.language.words import Said, carried, mark, said_again, say, translate
from app.uploads.limits import MAX_BYTES, check_upload
from app.uploads.reading import NotWatertightError
from app.uploads.worker import body_in_worker
from tests.app.uploads.test_upload import open_box_stl


def test_a_said_text_is_carried_as_plain_data_and_said_again_whole() -> None:
    inner = say("{name} is empty (0 bytes): there is no mesh in it.", name="a.stl")
    outer = say("{name}: {reason}", name="b.zip", reason=inner)
    sent = pickle.loads(pickle.dumps(carried(outer)))  # what crosses the pipe
    assert isinstance(sent, Said) and isinstance(dict(sent.values)["reason"], Said)
    assert said_again(sent) == outer
    german = translate(outer, "de")
    assert german == "b.zip: a.stl ist leer (0 Bytes): es enthält kein Mesh."
    assert carried("a text nobody said") is None and carried(mark("faces")) is None


def test_a_refusal_made_in_the_worker_reads_in_german_spanish_and_chinese() -> None:
    with pytest.raises(NotWatertightError) as refused:
        body_in_worker("open.stl", open_box_stl())
    text = str(refused.value)
    assert text.startswith("open.stl is not watertight: ")
    german, spanish, chinese = (translate(text, lang) for lang in ("de", "es", "zh"))
    assert german.startswith("open.stl ist nicht wasserdicht: ") and "konvexe Hülle" in german
    assert spanish.startswith("open.stl no es estanco: ") and "envolvente convexa" in spanish
    assert chinese.startswith("open.stl 不封闭") and "凸包" in chinese
    assert translate(text, PSEUDO).startswith(OPEN)  # nothing of it escapes the pseudo-locale
    with pytest.raises(ValueError) as garbage:
        body_in_worker("noise.obj", b"this is not a mesh at all\n" * 10)
    assert translate(str(garbage.value), "de") != str(garbage.value)
    assert translate(str(garbage.value), "de").startswith("noise.obj ")


def test_a_refusal_made_before_the_worker_reads_in_the_readers_language() -> None:
    with pytest.raises(ValueError) as refused:
        check_upload("big.stl", b"\0" * (MAX_BYTES + 1))
    text = str(refused.value)
    assert "the limit is" in text
    assert "die Grenze ist" in translate(text, "de") and "Vereinfachen Sie das Mesh" in translate(text, "de")
    assert "el límite es" in translate(text, "es")
