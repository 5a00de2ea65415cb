"""An export from request to files: a scene (or a state text) run frame by frame on a server nobody watches,
recorded as a web page that plays it, its numbers as CSV and a picture of its end (:func:`export_with`,
:func:`export_zip_with`; ``rigid-body-lab export`` and the panel's Export button through
:func:`app.serving.app.export`, which hands it the headless simulation to record).

More in docs/app-notes.md (``app.recording.export``).
"""

from __future__ import annotations

import csv
import io
import sys
import tempfile
import threading
import zipfile
from collections.abc import Callable, Iterator
from contextlib import AbstractContextManager, contextmanager
from dataclasses import dataclass
from pathlib import Path
from typing import TYPE_CHECKING, Any, Protocol

from app.guards.handles import scene_nodes
from app.guards.language import recording_in
from app.guards.text import csv_row
from app.language.catalogs import SOURCE, check_language
from app.language.words import mark, say
from app.recording.picture import render_png
from physics.validation import finite_scalar

if TYPE_CHECKING:  # annotations only: the simulation is above this package
    from app.serving.simulation import Simulation

__all__ = [
    "EXPORT_FPS",
    "MAX_SECONDS",
    "Export",
    "Headless",
    "export_with",
    "export_zip_with",
    "check_request",
    "one_at_a_time",
    "page_in",
    "record",
    "terminal_progress",
    "zipped",
]

EXPORT_FPS = 30.0
"""Frames recorded per simulated second: smooth playback at a tenth of the bytes of the app's 60."""
MAX_SECONDS = 600.0
"""The longest export (s of simulated time): 18,000 frames, a few minutes of work."""

_running = threading.Lock()  # an export is a whole extra server: at most one runs in a process


@dataclass(frozen=True)
class Export:
    """What an export wrote: the page, the table and the picture, and how many frames they hold."""

    html: Path
    csv: Path
    png: Path
    frames: int


@contextmanager
def one_at_a_time() -> Iterator[None]:
    """Hold the process's one export place, or refuse (ValueError) while another export runs."""
    if not _running.acquire(blocking=False):
        raise ValueError(mark("another export is running in this server; try again when it has finished"))
    try:
        yield
    finally:
        _running.release()


def terminal_progress(done: int, total: int) -> None:
    """A progress bar on stderr, redrawn in place (the CLI's)."""
    if done < total and done % max(1, total // 100):
        return  # a hundred redraws in all
    width = 40
    filled = width * done // max(total, 1)
    end = "\n" if done >= total else ""
    print(f"\rexporting [{'#' * filled}{'.' * (width - filled)}] {done}/{total} frames", end=end, file=sys.stderr)
    sys.stderr.flush()


def check_request(scene: str | None, seconds: Any, preset: str | None, state: str | None, fps: Any) -> None:
    """Refuse (ValueError) an export request that names no scene, both a preset and a state, or seconds or
    fps out of range."""
    if preset is not None and state is not None:
        raise ValueError("give a preset or a state, not both")
    if scene is None and state is None:
        raise ValueError("name a scene (or give a state, which names its scene)")
    for name, value, low, high in (("seconds", seconds, 1.0 / EXPORT_FPS, MAX_SECONDS), ("fps", fps, 1.0, 120.0)):
        if not low <= finite_scalar(value, name) <= high:
            raise ValueError(f"{name} must be between {low:g} and {high:g}, got {float(value):g}")


class Headless(Protocol):
    """What makes the simulation an export records: a scene (at one of its presets) or a state text, on a
    server on 127.0.0.1 that nobody watches and no loop drives, stopped when the export leaves it
    (:meth:`app.serving.app.App.headless`). ValueError for a bad scene, preset or state."""

    def __call__(
        self, scene: str | None, *, state: str | None, preset: str | None
    ) -> AbstractContextManager[Simulation]: ...


def export_with(
    headless: Headless,
    scene: str | None,
    out: str | Path,
    seconds: float,
    *,
    preset: str | None = None,
    state: str | None = None,
    fps: float = EXPORT_FPS,
    progress: Callable[[int, int], None] | None = None,
    lang: str = SOURCE,
) -> Export:
    """Run a scene for ``seconds`` of simulated time on the simulation ``headless`` makes and write the page,
    CSV and PNG; the arguments after ``headless`` are :func:`app.serving.app.export`'s, which documents them.
    One export runs at a time in a process (:func:`one_at_a_time`).

    Raises
    ------
    ValueError
        A bad scene, preset, state, number of seconds or language, a state of another scene than
        ``scene``, or a scene that failed while running (named with its time); nothing is written then.
    """
    check_request(scene, seconds, preset, state, fps)
    lang = check_language(lang)
    seconds, fps = float(seconds), float(fps)
    frames = max(1, round(seconds * fps))
    with one_at_a_time(), headless(scene, state=state, preset=preset) as simulation:
        named = simulation.scene.name if simulation.scene is not None else None
        if state is not None and scene is not None and scene != named:
            raise ValueError(f"the state is of the scene {named!r}, not {scene!r}")
        return record(simulation, Path(out), frames, fps, progress, lang)


def export_zip_with(
    headless: Headless,
    state: str,
    seconds: float,
    progress: Callable[[int, int], None] | None = None,
    lang: str = SOURCE,
) -> bytes:
    """The files :func:`export_with` writes for a state text, as one zip archive (the panel's Export button,
    in the language of the browser that pressed it)."""
    with tempfile.TemporaryDirectory(prefix="rbl-export-") as folder:
        return zipped(export_with(headless, None, folder, seconds, state=state, progress=progress, lang=lang))


def record(
    sim: Simulation,
    out: Path,
    frames: int,
    fps: float,
    progress: Callable[[int, int], None] | None,
    lang: str = SOURCE,
) -> Export:
    """Run ``sim`` (a built simulation on a server nobody watches) for ``frames`` frames and write the files;
    the page's words (its scene's labels, its ``<html lang>``) in ``lang``. The CSV's columns are symbols
    and SI units, the same in every language.

    Raises
    ------
    ValueError
        The scene stopped (a numerical failure), named with its time and message; nothing is written then.
    """
    lang = check_language(lang)
    scene = sim.scene
    if scene is None:
        raise ValueError("the simulation has no scene to record")
    sim.set_playing(False)
    sim.request_redraw()
    sim.frame(0.0)  # the start, drawn before the recording begins
    serializer = sim.server.get_scene_serializer()
    rows: list[dict[str, float]] = []
    sim.set_playing(True)
    for k in range(frames + 1):
        if k > 0:
            serializer.insert_sleep(1.0 / fps)
            if scene.static:  # a still scene (its clock stays at 0): each frame is the same picture, drawn
                sim.request_redraw()
            if not sim.frame(1.0 / fps):
                last = sim.messages[-1][1] if sim.messages else mark("no message")
                raise ValueError(say("the scene stopped at t = {time:.3f} s: {last}", time=sim.time, last=last))
        rows.append({"t (s)": sim.time, **scene.columns(sim.last_state)})
        if progress is not None and k > 0:
            progress(k, frames)
    position, look_at = sim.view  # the whole picture is the scene's: no panel to frame it clear of
    picture = render_png(scene_nodes(sim.server.scene), position, look_at)
    recording_in(serializer, lang)
    html = page_in(serializer.as_html(), lang)
    out.mkdir(parents=True, exist_ok=True)
    paths = Export(out / "index.html", out / f"{scene.name}.csv", out / f"{scene.name}.png", frames + 1)
    paths.html.write_text(html, encoding="utf-8")
    with paths.csv.open("w", newline="", encoding="utf-8") as handle:
        writer = csv.writer(handle)
        writer.writerow(csv_row(rows[0]))  # the columns' names; the cells below are numbers
        writer.writerows([[repr(float(v)) for v in row.values()] for row in rows])
    paths.png.write_bytes(picture)
    return paths


def page_in(page: str, lang: str) -> str:
    """An exported page (viser's client, ``<html lang="en">``) naming ``lang`` as its language, so a screen
    reader pronounces its labels right."""
    return page.replace('<html lang="en">', f'<html lang="{check_language(lang)}">', 1)


def zipped(written: Export) -> bytes:
    """The three files of an export as one zip archive (the panel's download)."""
    buffer = io.BytesIO()
    with zipfile.ZipFile(buffer, "w", zipfile.ZIP_DEFLATED) as archive:
        for path in (written.html, written.csv, written.png):
            archive.write(path, arcname=path.name)
    return buffer.getvalue()
