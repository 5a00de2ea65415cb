"""Lectures: a TOML file of steps that the panel walks through with "Previous" and "Next".

More in docs/app-notes.md (``app.teaching.lectures``).
"""

from __future__ import annotations

import importlib.util
import math
import tomllib
from dataclasses import dataclass, field
from pathlib import Path
from typing import Any

from app.scenes import scene_names
from app.teaching.lecture_words import LANGUAGE_KEYS, check_lecture_words, check_step_words, learn_words
from app.teaching.questions import Ask, check_ask
from app.teaching.states import parse_state


def _shipped_folder() -> Path:
    """The folder of the lectures shipped with the app: the ``lectures`` package (its ``*.toml`` files are
    package data, installed by a wheel as by an editable install). A source tree whose editable install
    predates that package has it beside ``app/``."""
    spec = importlib.util.find_spec("lectures")
    if spec is not None and spec.submodule_search_locations:
        folder = Path(next(iter(spec.submodule_search_locations)))
        if (folder / "__init__.py").is_file() and (folder / "rigid-body-motion.toml").is_file():
            return folder
    return Path(__file__).resolve().parent.parent / "lectures"


LECTURES = _shipped_folder()
"""Where ``--lecture NAME`` looks for ``NAME.toml``: the installed ``lectures`` package."""

MAX_BYTES = 1_000_000
"""Largest lecture file read, bytes."""

KEYS = ("scene", "preset", "choices", "values", "caption", "camera", "seconds", "state", "time", "replay")
QUESTION_KEYS = ("question", "answer", "unit", "range", "truth", "about")
"""A step's question (:func:`app.teaching.questions.check_ask`); its ``choices`` are then a list of texts."""

MAX_STEP_TIME = 300.0
"""The latest time a step may open at, s (the friction top's history reaches 300 s ahead in one go)."""
MAX_REPLAY = 60.0
"""The longest span a step may replay, s (at 0.1× a minute takes ten)."""

__all__ = ["LECTURES", "MAX_REPLAY", "MAX_STEP_TIME", "Lecture", "Step", "find_lecture", "read_lecture"]


@dataclass(frozen=True)
class Step:
    """One step of a lecture (see the module docstring for the keys)."""

    scene: str | None = None
    preset: str | None = None
    choices: dict[str, str] = field(default_factory=dict)
    values: dict[str, float] = field(default_factory=dict)
    caption: str = ""
    camera: dict[str, list[float]] | None = None
    seconds: float | None = None
    state: str | None = None
    ask: Ask | None = None
    time: float | None = None
    replay: float | None = None
    words: dict[str, dict[str, Any]] = field(default_factory=dict)
    """The step's caption, question and choices in other languages (:mod:`app.teaching.lecture_words`)."""


@dataclass(frozen=True)
class Lecture:
    """A lecture: its title and its steps, in order."""

    title: str
    steps: tuple[Step, ...]
    source: str = ""
    titles: dict[str, str] = field(default_factory=dict)
    """The title in other languages."""


def find_lecture(name_or_path: str) -> Path:
    """The file of a lecture given by path or by name (``lectures/NAME.toml``).

    Raises
    ------
    ValueError
        If neither exists (the message lists the lectures shipped).
    """
    path = Path(name_or_path)
    if path.is_file():
        return path
    shipped = LECTURES / f"{name_or_path}.toml"
    if shipped.is_file():
        return shipped
    names = sorted(p.stem for p in LECTURES.glob("*.toml"))
    raise ValueError(f"no lecture file {name_or_path!r}; the lectures shipped are: {', '.join(names) or 'none'}")


def read_lecture(name_or_path: str, scenes: list[str] | None = None) -> Lecture:
    """Read and check a lecture file (by path or by name).

    Raises
    ------
    ValueError
        The file is missing, too large, not TOML, or a step has an unknown key, a value of the wrong type
        or an unknown scene; the message names the step (1-based) and the key.
    """
    path = find_lecture(name_or_path)
    if path.stat().st_size > MAX_BYTES:
        raise ValueError(f"{path}: a lecture file has at most {MAX_BYTES:,} bytes")
    try:
        document = tomllib.loads(path.read_text(encoding="utf-8"))
    except (tomllib.TOMLDecodeError, UnicodeDecodeError) as exc:
        raise ValueError(f"{path}: not a TOML file ({exc})") from None
    if scenes is None:
        scenes = scene_names()
    title = document.get("title", path.stem)
    if not isinstance(title, str):
        raise ValueError(f"{path}: title must be text")
    unknown = set(document) - {"title", "step", *LANGUAGE_KEYS}
    if unknown:
        raise ValueError(f"{path}: unknown key {sorted(unknown)[0]!r} (a lecture has a title and [[step]] tables)")
    titles = check_lecture_words(document, str(path))
    raw_steps = document.get("step")
    if not isinstance(raw_steps, list) or not raw_steps:
        raise ValueError(f"{path}: a lecture needs at least one [[step]]")
    steps = tuple(_step(raw, k, scenes, path) for k, raw in enumerate(raw_steps, start=1))
    # Read, its translations are known to the app (as the catalogs' are): any reader of a language gets them.
    learn_words({"title": title}, {lang: {"title": text} for lang, text in titles.items()})
    for step in steps:
        english: dict[str, Any] = {"caption": step.caption}
        if step.ask is not None:
            english |= {"question": step.ask.text, "choices": step.ask.choices}
        learn_words(english, step.words)
    return Lecture(title, steps, str(path), titles)


def _step(raw: Any, k: int, scenes: list[str], path: Path) -> Step:
    where = f"{path.name}, step {k}"
    if not isinstance(raw, dict):
        raise ValueError(f"{where}: a step is a table of keys")
    for key in raw:
        if key not in KEYS and key not in QUESTION_KEYS and key not in LANGUAGE_KEYS:
            raise ValueError(f"{where}: unknown key {key!r} (a step has {', '.join(KEYS + QUESTION_KEYS)})")
    ask = None
    if "question" in raw:
        try:
            ask = check_ask(raw, raw.get("scene"))
        except ValueError as exc:
            raise ValueError(f"{where}, {exc}") from None
    elif any(key in raw for key in QUESTION_KEYS) or isinstance(raw.get("choices"), list):
        given = [key for key in (*QUESTION_KEYS, "choices") if key in raw]
        raise ValueError(f'{where}, {given[0]}: belongs to a question; the step has no question = "..."')
    state = raw.get("state")
    if state is not None:
        if not isinstance(state, str):
            raise ValueError(f"{where}, state: a state text, as “Copy state” gives it")
        try:
            parse_state(state, scenes)
        except ValueError as exc:
            raise ValueError(f"{where}, state: {exc}") from None
    scene = raw.get("scene")
    if scene is None and state is None:
        raise ValueError(f"{where}: a step needs a scene (or a state)")
    if scene is not None and scene not in scenes:
        raise ValueError(f"{where}, scene: no scene {scene!r}; the scenes are {', '.join(scenes)}")
    preset = raw.get("preset")
    if preset is not None and not isinstance(preset, str):
        raise ValueError(f"{where}, preset: the name of one of the scene's presets")
    choices = raw.get("choices", {}) if ask is None or ask.numeric else {}
    if not isinstance(choices, dict):
        raise ValueError(f'{where}, choices: a table of dropdown choices, e.g. choices = {{ Body = "Solid cylinder" }}')
    for key, value in choices.items():
        if not isinstance(value, str) or not value:
            raise ValueError(f"{where}, choices.{key}: the text of one of the dropdown's choices, got {value!r}")
    values = raw.get("values", {})
    if not isinstance(values, dict):
        raise ValueError(f"{where}, values: a table of slider values, e.g. values = {{ spin = 3.0 }}")
    for key, value in values.items():
        if isinstance(value, bool) or not isinstance(value, (int, float)) or not math.isfinite(value):
            raise ValueError(f"{where}, values.{key}: a finite number, got {value!r}")
    caption = raw.get("caption", "")
    if not isinstance(caption, str):
        raise ValueError(f"{where}, caption: markdown text")
    camera = raw.get("camera")
    if camera is not None:
        ok = isinstance(camera, dict) and set(camera) == {"position", "look_at"}
        ok = ok and all(
            isinstance(v, list)
            and len(v) == 3
            and all(isinstance(x, (int, float)) and not isinstance(x, bool) and math.isfinite(x) for x in v)
            for v in camera.values()
        )
        if not ok:
            raise ValueError(f"{where}, camera: {{ position = [x, y, z], look_at = [x, y, z] }} in metres")
        camera = {key: [float(x) for x in value] for key, value in camera.items()}
    seconds = raw.get("seconds")
    if seconds is not None and (
        isinstance(seconds, bool) or not isinstance(seconds, (int, float)) or not 0.5 <= seconds <= 86_400
    ):
        raise ValueError(f"{where}, seconds: between 0.5 and 86400, got {seconds!r}")
    at = _seconds(raw, "time", where, 0.0, MAX_STEP_TIME)
    replay = _seconds(raw, "replay", where, 0.1, MAX_REPLAY)
    if replay is not None and at is None:
        raise ValueError(f"{where}, replay: replays the seconds before the step's `time`, which it lacks")
    return Step(
        scene=scene,
        preset=preset,
        choices=dict(choices),
        values={key: float(value) for key, value in values.items()},
        caption=caption,
        camera=camera,
        seconds=None if seconds is None else float(seconds),
        state=state,
        ask=ask,
        time=at,
        replay=replay,
        words=check_step_words(raw, where, None if ask is None else ask.text, () if ask is None else ask.choices),
    )


def _seconds(raw: dict[str, Any], key: str, where: str, low: float, high: float) -> float | None:
    """A step's number of seconds under ``key``, from ``low`` to ``high``, or None if not given."""
    value = raw.get(key)
    if value is None:
        return None
    if isinstance(value, bool) or not isinstance(value, (int, float)) or not low <= value <= high:
        raise ValueError(f"{where}, {key}: a number of seconds from {low:g} to {high:g}, got {value!r}")
    return float(value)
