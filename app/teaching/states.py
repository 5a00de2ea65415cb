"""A simulation's state as a short text, and back: what "Copy state" shows and ``--state TEXT`` opens.

More in docs/app-notes.md (``app.teaching.states``).
"""

from __future__ import annotations

import base64
import binascii
import json
import math
import zlib
from typing import Any

from app.guards.inputs import MAX_TEXT  # the longest text the panel's text box takes: a state text fits it
from app.language.words import mark, say
from app.scenes import scene_names

PREFIX = "rbl1:"
"""Version 1 of the state text."""

MAX_JSON = 16_384
"""Most bytes a state text may decompress to (a state is a few hundred)."""

__all__ = ["MAX_TEXT", "PREFIX", "parse_state", "state_text"]


def state_text(snapshot: dict[str, Any], camera: dict[str, list[float]] | None = None) -> str:
    """The text of a :meth:`app.serving.simulation.Simulation.snapshot` (and optionally a camera).

    Raises
    ------
    ValueError
        If the scene holds a body handed over from another scene, or an uploaded file (neither has a short text).
    """
    if snapshot.get("payload") is not None:
        raise ValueError(
            mark(
                "this scene shows a body handed over from another scene; a state text cannot carry a mesh "
                "(copy the state of the scene it came from instead)"
            )
        )
    if "uploaded" in (snapshot.get("motion") or {}):
        raise ValueError(
            mark(
                "this scene shows an uploaded mesh or recording; a state text cannot carry a file (upload the "
                "file again where the state is opened)"
            )
        )
    state = {
        "scene": snapshot["scene"],
        "controls": [[name, value] for name, value in snapshot["controls"]],
        "motion": {key: _plain(value) for key, value in (snapshot.get("motion") or {}).items()},
        "time": float(snapshot["time"]),
        "speed": float(snapshot["speed"]),
        "playing": bool(snapshot["playing"]),
    }
    if camera is not None:
        state["camera"] = {key: [float(x) for x in camera[key]] for key in ("position", "look_at")}
    raw = json.dumps(state, separators=(",", ":"), ensure_ascii=False).encode()
    return PREFIX + base64.urlsafe_b64encode(zlib.compress(raw, 9)).decode().rstrip("=")


def parse_state(text: Any, scenes: list[str] | None = None) -> dict[str, Any]:
    """The state a text describes, checked: keys ``scene``, ``controls`` (list of ``(name, value)``),
    ``motion`` (dict of number lists), ``time``, ``speed``, ``playing`` and optionally ``camera``.

    Parameters
    ----------
    text : str
        A text made by :func:`state_text`.
    scenes : list of str, optional
        The scene names accepted (default: every registered scene).

    Raises
    ------
    ValueError
        Naming what is wrong: not text, too long, not a state text (prefix), damaged, too large
        unpacked, or a field of the wrong type, not finite, or an unknown scene.
    """
    if not isinstance(text, str):
        raise ValueError(say("a state text is text, got {kind!s}", kind=type(text).__name__))
    text = text.strip()
    if len(text) > MAX_TEXT:
        raise ValueError(
            say("a state text has at most {most} characters, this one has {length}", most=MAX_TEXT, length=len(text))
        )
    if not text.startswith(PREFIX):
        raise ValueError(say("not a Rigid Body Lab state: a state text starts with “{prefix!s}”", prefix=PREFIX))
    body = text[len(PREFIX) :]
    try:
        packed = base64.urlsafe_b64decode(body + "=" * (-len(body) % 4))
        inflater = zlib.decompressobj()
        raw = inflater.decompress(packed, MAX_JSON + 1)
        if len(raw) > MAX_JSON or inflater.unconsumed_tail:
            raise ValueError(say("this state text unpacks to more than {most} bytes: it is not a state", most=MAX_JSON))
        if not inflater.eof:
            raise ValueError(mark("this state text is cut short (copy all of it)"))
        state = json.loads(raw.decode())
    except binascii.Error:  # (a ValueError: first)
        raise ValueError(_damaged(mark("it has a character a state text never has, or one too few"))) from None
    except zlib.error:
        raise ValueError(_damaged(mark("some of its characters were changed or lost"))) from None
    except ValueError as exc:  # the JSON's, or a UnicodeDecodeError
        if "state text" in str(exc):
            raise
        raise ValueError(_damaged(mark("it does not unpack to a state"))) from None
    return _checked(state, scenes)


def _damaged(what: str) -> str:
    """:data:`DAMAGED` saying ``what`` (a marked text), translatable."""
    return say("this state text is damaged ({what}): copy it again, all of it, from “Copy state”", what=what)


DAMAGED = "this state text is damaged ({what}): copy it again, all of it, from “Copy state”"
"""The message for a state text that does not unpack (never the decoder's own words: they mean nothing to a
lecturer)."""


def _checked(state: Any, scenes: list[str] | None) -> dict[str, Any]:
    if not isinstance(state, dict):
        raise ValueError(mark("this state text does not hold a state"))
    if scenes is None:
        scenes = scene_names()
    scene = state.get("scene")
    if scene not in scenes:
        raise ValueError(say("this state is of a scene this app does not have: {scene!r}", scene=str(scene)[:40]))
    controls = state.get("controls")
    if not isinstance(controls, list) or not all(
        isinstance(c, list) and len(c) == 2 and isinstance(c[0], str) and _value(c[1]) for c in controls
    ):
        raise ValueError(mark("this state's controls are not (name, value) pairs of numbers, text or on/off"))
    motion = state.get("motion", {})
    if not isinstance(motion, dict) or not all(_numbers(v) for v in motion.values()):
        raise ValueError(mark("this state's motion is not lists of finite numbers"))
    out: dict[str, Any] = {
        "scene": scene,
        "payload": None,
        "controls": [(name, tuple(value) if isinstance(value, list) else value) for name, value in controls],
        "motion": motion,
    }
    for key, low, high in (("time", -1e12, 1e12), ("speed", 0.0, 1e3)):
        value = state.get(key)
        if isinstance(value, bool) or not isinstance(value, (int, float)) or not low <= value <= high:
            raise ValueError(
                say(
                    "this state's {key!s} must be a number between {low:g} and {high:g}, got {value!r}",
                    key=key,
                    low=low,
                    high=high,
                    value=value,
                )
            )
        out[key] = float(value)
    if not isinstance(state.get("playing"), bool):
        raise ValueError(mark("this state's clock must be running or paused (true or false)"))
    out["playing"] = state["playing"]
    camera = state.get("camera")
    if camera is not None:
        if not isinstance(camera, dict) or not all(
            _numbers(camera.get(key)) and len(camera[key]) == 3 for key in ("position", "look_at")
        ):
            raise ValueError(mark("this state's camera must be a position and a look-at point, three numbers each"))
        out["camera"] = {key: [float(x) for x in camera[key]] for key in ("position", "look_at")}
    return out


def _value(value: Any) -> bool:
    if isinstance(value, (bool, str)):
        return len(value) <= MAX_TEXT if isinstance(value, str) else True
    if isinstance(value, list):
        return _numbers(value)
    return isinstance(value, (int, float)) and math.isfinite(value) and abs(value) <= 2**53


def _numbers(value: Any) -> bool:
    """A (nested) list of finite numbers, at most 64 of them."""
    flat: list[Any] = []

    def walk(v: Any) -> bool:
        if isinstance(v, list):
            return all(walk(x) for x in v)
        flat.append(v)
        return not isinstance(v, bool) and isinstance(v, (int, float)) and math.isfinite(v)

    return isinstance(value, list) and walk(value) and len(flat) <= 64


def _plain(value: Any) -> Any:
    """numpy arrays and scalars as JSON lists and floats."""
    if hasattr(value, "tolist"):
        return value.tolist()
    return value
