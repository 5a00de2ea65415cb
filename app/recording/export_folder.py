"""The panel's Export folder: the current state recorded for some seconds and downloaded as a zip.

A click takes the browser's state text and hands it to the export it was given (a callable, run in a thread
of its own so the clock and the other browsers go on); a notification shows the progress, then the
download starts, and the final note closes by itself like every other notification.
"""

from __future__ import annotations

import threading
from collections.abc import Callable
from typing import TYPE_CHECKING, Any, Literal

import viser

from app.contracts import ClientId
from app.guards.wire import departed
from app.language.catalogs import SOURCE
from app.language.words import mark, say

if TYPE_CHECKING:  # annotations only: the simulation is above this package
    from app.serving.simulation import Simulation

__all__ = ["ExportFolder", "EXPORT_SECONDS", "ExportRun"]

EXPORT_SECONDS = (1.0, 60.0, 10.0)
"""The panel's choice of recording length (s): least, most, default (the CLI allows longer)."""

ExportRun = Callable[[str, float, Callable[[int, int], None], str], bytes]
"""What the folder is given: (state text, seconds, progress(done, total), language) -> the zip's bytes, its
page's words in that language (the pressing browser's)."""


class _Left(Exception):
    """The browser that asked for an export has left while it ran."""


class ExportFolder:
    """The "Export" folder of a simulation's panel (seconds, and the button).

    Parameters
    ----------
    simulation : Simulation
        Whose panel, state text and notifications it uses.
    export : ExportRun
        Records a state text for some seconds and returns the zip (ValueError: refused, with the reason).
    auto_close_seconds : float
        How long the final note stays (as every notification).
    order : float, optional
        The folder's place in the panel.
    language : callable(client_id) -> str, optional
        The language a browser reads (``app.guards.language.Languages.language``): its export is written in
        it. Default: English.
    """

    def __init__(
        self,
        simulation: Simulation,
        export: ExportRun,
        auto_close_seconds: float,
        order: float | None = None,
        language: Callable[[ClientId], str] | None = None,
    ) -> None:
        self.simulation = simulation
        self.export = export
        self.language: Callable[[ClientId], str] = language or (lambda _client_id: SOURCE)
        self.auto_close_seconds = auto_close_seconds
        gui = simulation.server.gui
        low, high, default = EXPORT_SECONDS
        with gui.add_folder(mark("Export a recording"), expand_by_default=False, order=order) as self.folder:
            self.seconds = gui.add_slider(mark("Seconds to record"), min=low, max=high, step=1.0, initial_value=default)
            self.button = gui.add_button(
                mark("Export"), icon=viser.Icon.DOWNLOAD, hint=mark("a web page, a CSV and a PNG")
            )
        self.button.on_click(simulation.guarded(self._on_click))
        self.running: threading.Thread | None = None

    def _on_click(self, event: Any) -> None:
        client = getattr(event, "client", None)
        if client is None:
            return
        if self.running is not None and self.running.is_alive():
            self.simulation.notify(
                mark("Export running"), mark("the previous export has not finished yet"), client=client
            )
            return
        try:
            text = self.simulation.state_text(client)  # under the simulation's lock: one consistent state
        except ValueError as exc:  # e.g. a body handed over from another scene: no text can carry it
            self.simulation.notify(mark("Export refused"), str(exc), client=client, error=True)
            return
        seconds = float(self.seconds.value)
        name = self.simulation.scene.name if self.simulation.scene is not None else "scene"
        self.running = threading.Thread(
            target=self._run, args=(client, text, seconds, name), name="rbl-export", daemon=True
        )
        self.running.start()

    def _run(self, client: viser.ClientHandle, text: str, seconds: float, name: str) -> None:
        if departed(client):
            return
        try:
            note = client.add_notification(
                mark("Exporting"), say("{seconds:g} s of {name}…", seconds=seconds, name=name), loading=True
            )
        except Exception:  # noqa: BLE001 - it left
            return
        last = [-1]

        def progress(done: int, total: int) -> None:
            if departed(client):  # nobody to send it to: stop now and free the process's one export place
                raise _Left
            percent = 100 * done // total
            if percent >= last[0] + 10:  # a tenth at a time, not a stream
                last[0] = percent
                note.body = say("{seconds:g} s of {name}: {percent} %", seconds=seconds, name=name, percent=percent)

        final: tuple[str, str, Literal["green", "red"]]
        try:
            archive = self.export(text, seconds, progress, self.language(client.client_id))
            if departed(client):
                return  # it left as the export ended: nobody to send it to
            file = f"rigid-body-lab-{name}.zip"
            client.send_file_download(file, archive, save_immediately=True)
            final = (
                mark("Exported"),
                say("{file!s} ({kilobytes} kB)", file=file, kilobytes=len(archive) // 1024),
                "green",
            )
        except _Left:
            return
        except ValueError as exc:
            final = (mark("Export refused"), str(exc), "red")
        except Exception as exc:  # noqa: BLE001 - the server stays up; the browser is told
            final = (mark("Export failed"), f"{type(exc).__name__}: {exc}", "red")
        if departed(client):
            return
        # Every update carries all the props (viser keeps the latest): the note stops loading, says how it
        # ended and closes by itself like every other notification.
        note.title, note.body, note.color, note.loading = final[0], final[1], final[2], False
        note.auto_close_seconds = self.auto_close_seconds
