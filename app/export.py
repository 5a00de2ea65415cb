"""Export a motion without a browser: a web page that plays it, its numbers as CSV, a picture of its end.

``rigid-body-lab export --scene NAME [--preset P | --state TEXT] --seconds S --out DIR`` (and the panel's
Export button, through :func:`export_zip`) builds the scene on a server nobody connects to, on 127.0.0.1,
and runs its clock frame by frame (``fps`` frames per simulated second, not in real time) while viser's
scene serializer records what a browser would have been sent. It writes

* ``DIR/index.html`` — viser's client build with the recording embedded (``StateSerializer.as_html``):
  one self-contained file that plays from any static web host or straight from the disk;
* ``DIR/NAME.csv`` — the column ``t (s)``, then the scene's quantities (:meth:`app.scenes.Scene.columns`)
  with their units in the header, one row per frame, every number to full precision (``repr``);
* ``DIR/NAME.png`` — the last frame drawn without a browser (:mod:`app.picture`).
"""

from __future__ import annotations

import csv
import io
import socket
import sys
import tempfile
import threading
import zipfile
from collections.abc import Callable
from dataclasses import dataclass
from pathlib import Path
from typing import Any

from app.picture import render_png
from physics.validation import finite_scalar

__all__ = ["EXPORT_FPS", "MAX_SECONDS", "Export", "export", "export_zip", "terminal_progress"]

EXPORT_FPS = 30.0
"""Frames recorded per simulated second: smooth playback at a tenth of the bytes of the app's 60."""
MAX_SECONDS = 600.0
"""The longest export (s of simulated time): 18,000 frames, a few minutes of work."""

_one_at_a_time = threading.Lock()  # an export is a whole extra server: at most one runs in a process


@dataclass(frozen=True)
class Export:
    """What an export wrote: the page, the table and the picture, and how many frames they hold."""

    html: Path
    csv: Path
    png: Path
    frames: int


def _free_port() -> int:
    with socket.socket(socket.AF_INET, socket.SOCK_STREAM) as s:
        s.bind(("127.0.0.1", 0))
        return int(s.getsockname()[1])


def terminal_progress(done: int, total: int) -> None:
    """A progress bar on stderr, redrawn in place (the CLI's)."""
    if done < total and done % max(1, total // 100):
        return  # a hundred redraws in all
    width = 40
    filled = width * done // max(total, 1)
    end = "\n" if done >= total else ""
    print(f"\rexporting [{'#' * filled}{'.' * (width - filled)}] {done}/{total} frames", end=end, file=sys.stderr)
    sys.stderr.flush()


def _check_request(scene: str | None, seconds: Any, preset: str | None, state: str | None, fps: Any) -> None:
    if preset is not None and state is not None:
        raise ValueError("give a preset or a state, not both")
    if scene is None and state is None:
        raise ValueError("name a scene (or give a state, which names its scene)")
    for name, value, low, high in (("seconds", seconds, 1.0 / EXPORT_FPS, MAX_SECONDS), ("fps", fps, 1.0, 120.0)):
        if not low <= finite_scalar(value, name) <= high:
            raise ValueError(f"{name} must be between {low:g} and {high:g}, got {float(value):g}")


def export(
    scene: str | None,
    out: str | Path,
    seconds: float,
    *,
    preset: str | None = None,
    state: str | None = None,
    fps: float = EXPORT_FPS,
    progress: Callable[[int, int], None] | None = None,
) -> Export:
    """Run a scene for ``seconds`` of simulated time without a browser and write the page, CSV and PNG.

    Parameters
    ----------
    scene : str or None
        A scene name (``rigid-body-lab --scene``); None takes the state's scene.
    out : str or Path
        The directory to write (created if missing; files of the same names are replaced).
    seconds : float
        Simulated time to record (s), from 1/30 s to :data:`MAX_SECONDS`.
    preset : str, optional
        One of the scene's presets, by its name in the panel.
    state : str, optional
        A state text (the panel's "Copy state"): its scene, controls, time and camera.
    fps : float
        Frames per simulated second (rows of the CSV, frames of the recording).
    progress : callable, optional
        Called as ``progress(frames done, frames in all)`` after every frame.

    Returns
    -------
    Export
        The paths written and the number of frames.

    Raises
    ------
    ValueError
        A bad scene, preset, state, number of seconds, or a scene that failed while running (named with
        its time); nothing is written then.
    """
    from app.lectures import Step
    from app.server import App
    from app.states import parse_state

    _check_request(scene, seconds, preset, state, fps)
    seconds, fps = float(seconds), float(fps)
    if state is not None:
        named = parse_state(state)["scene"]
        if scene is not None and scene != named:
            raise ValueError(f"the state is of the scene {named!r}, not {scene!r}")
        scene = named
    frames = max(1, round(seconds * fps))
    if not _one_at_a_time.acquire(blocking=False):
        raise ValueError("another export is running in this server; try again when it has finished")
    try:
        app = App(host="127.0.0.1", port=_free_port(), scene=scene, start_loop=False, state=state)
        try:
            if preset is not None:
                app._apply_step(Step(scene=scene, preset=preset))
            return _record(app, Path(out), frames, fps, progress)
        finally:
            app.stop()
    finally:
        _one_at_a_time.release()


def _record(app: Any, out: Path, frames: int, fps: float, progress: Callable[[int, int], None] | None) -> Export:
    scene = app.scene
    app.set_playing(False)
    app.request_redraw()
    app.frame(0.0)  # the start, drawn before the recording begins
    serializer = app.server.get_scene_serializer()
    rows: list[dict[str, float]] = []
    app.set_playing(True)
    for k in range(frames + 1):
        if k > 0:
            serializer.insert_sleep(1.0 / fps)
            if not app.frame(1.0 / fps):
                raise ValueError(f"the scene stopped at t = {app.time:.3f} s: {_last_message(app)}")
        rows.append({"t (s)": app.time, **scene.columns(app.last_state)})
        if progress is not None and k > 0:
            progress(k, frames)
    position, look_at = app.view  # the whole picture is the scene's: no panel to frame it clear of
    picture = render_png(app.server.scene._handle_from_node_name, position, look_at)
    html = serializer.as_html()
    out.mkdir(parents=True, exist_ok=True)
    paths = Export(out / "index.html", out / f"{scene.name}.csv", out / f"{scene.name}.png", frames + 1)
    paths.html.write_text(html, encoding="utf-8")
    with paths.csv.open("w", newline="", encoding="utf-8") as handle:
        writer = csv.writer(handle)
        writer.writerow(list(rows[0]))
        writer.writerows([[repr(float(v)) for v in row.values()] for row in rows])
    paths.png.write_bytes(picture)
    return paths


def _last_message(app: Any) -> str:
    return app.messages[-1][1] if app.messages else "no message"


def export_zip(
    state: str,
    seconds: float,
    progress: Callable[[int, int], None] | None = None,
) -> bytes:
    """The files :func:`export` writes for a state text, as one zip archive (the panel's Export button)."""
    with tempfile.TemporaryDirectory(prefix="rbl-export-") as folder:
        written = export(None, folder, seconds, state=state, progress=progress)
        buffer = io.BytesIO()
        with zipfile.ZipFile(buffer, "w", zipfile.ZIP_DEFLATED) as archive:
            for path in (written.html, written.csv, written.png):
                archive.write(path, arcname=path.name)
        return buffer.getvalue()
