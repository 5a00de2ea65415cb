"""Toss your phone: a gyroscope recording of a phone tossed about its intermediate axis, fitted with the free
body (with air drag), the measured ω beside the model's, and the fitted motion replayed slowly.

More in docs/app-notes.md (``app.scenes.phone_toss``).
"""

from __future__ import annotations

import functools
import threading
from types import SimpleNamespace
from typing import Any

import numpy as np
import viser

from app import controls, draw
from app.language.words import joined, mark, say
from app.panel.look import plot_axes, plot_colour
from app.recording.columns import euler_columns, vector_columns
from app.scenes.base import Answer, Scene, register
from app.scenes.tennis_racket import box_for_moments
from app.scenes.wording import amount
from app.uploads.gyro import EXAMPLE_NAME, TossFit, example_csv, fit_toss_upload
from app.uploads.worker import toss_fit_in_worker

__all__ = ["PhoneToss", "SLOW", "ALL_TOSSES", "example_fit", "ratios_text"]

SLOW = 0.2
"""The replay's pace: a second of flight takes five (a flip lasts a few tenths of a second)."""
ALL_TOSSES = mark("all tosses together")
PHONE_LENGTH = 1.2
"""m: the drawn phone's long side (its other sides from the fitted moments)."""
COMPONENTS = (("x", "vermillion"), ("y", "bluish_green"), ("z", "blue"))
AXIS_NAMES = {"x": mark("x, across the screen"), "y": mark("y, along the phone"), "z": mark("z, out of the screen")}


@functools.cache
def example_fit() -> TossFit:
    """The bundled example (:func:`app.uploads.gyro.example_csv`, the project's own model) fitted, all tosses:
    what the scene shows before any upload. The project's own file, fitted once per process."""
    return fit_toss_upload(EXAMPLE_NAME + ".csv", example_csv(), None)


def ratios_text(result: TossFit) -> str:
    """The fitted moments along x, y, z with their standard deviations, e.g. ``0.7998 ± 0.0001 : … : 1``."""
    parts = []
    for value, sigma in zip(result.fit.moments, result.fit.moments_sigma, strict=True):
        parts.append(
            "1" if sigma == 0.0 and value == 1.0 else say("{value:.4f} ± {sigma:.4f}", value=value, sigma=sigma)
        )
    return joined(parts, " : ")


def _toss_label(k: int, window: tuple[float, float]) -> str:
    return say("toss {number}: {start:.2f} to {end:.2f} s", number=k + 1, start=window[0], end=window[1])


@register
class PhoneToss(Scene):
    name = "phone_toss"
    title = mark("Toss your phone: a measured flip")
    order = 65  # after the tennis racket: the theory, then the measurement
    quantities = ("L", "omega")
    caption = mark(
        "**A measured flip.** A phone's gyroscope records ω in the phone's axes while it flies (phyphox, "
        '"Gyroscope (rotation rate)"). Tossed spinning about the axis across its screen, the intermediate one, '
        "it turns over in the air. The points are the samples, the lines the torque-free body with air drag "
        "fitted to them: the moments' ratios (largest 1; the scale cannot be seen in ω), each toss's ω at the "
        "release and the drag. The phone (a box of the fitted moments) replays the fitted motion at 0.2×, with "
        "L and ω. Before you upload, a toss made by the project's own model is shown."
    )
    camera = ((2.4, -2.6, 2.4), (0.0, 0.0, 1.0))
    view = (1.9, 1.9)  # the phone (1.2 m long) turning about its centre, and its arrows
    key_plot = "plot"  # ω measured and fitted: the flips, one component changing sign
    # Whether it flips: the axis and the half turns in the panel, the plot that shows them, the caption.
    answers = (
        Answer(
            "flip",
            readouts=("flip_axis_readout", "half_turns_readout"),
            hidden=("plot", "caption_markdown"),
        ),
    )
    centre = np.array([0.0, 0.0, 1.0])

    def build(self) -> None:
        self.screen = draw.screen_axes(type(self).camera)
        server, root, gui = self.ctx.server, self.ctx.root, self.ctx.server.gui
        self.upload_refusals = 0
        self.last_upload_message = ""
        self.closed = False  # set by teardown: a fit finished after a scene switch is dropped
        self._request = 0  # the newest fit asked for: an older one finishing later is dropped
        self._request_lock = threading.Lock()
        self._adopting = False  # adopt is setting the Toss dropdown
        self.body = draw.BodyMesh(server, root + "/body", box_for_moments(np.array([0.8, 0.2, 1.0])))
        self.L_arrow = draw.Arrow(server, root + "/L", "L", label="L")
        self.omega_arrow = draw.Arrow(server, root + "/omega", "omega", label="ω")
        self.upload = gui.add_upload_button(
            mark("Upload a phyphox recording (CSV, ZIP)"),
            icon=None,
            hint=mark("phyphox's Gyroscope (rotation rate): its Raw Data.csv or the .zip it shares; at most 20 MB"),
            mime_type=".csv,.zip",
        )
        # Not guarded: the file is read and fitted in a worker outside the simulation lock.
        controls.take_uploads(self.ctx, self.upload, self.load_upload, self._refuse)
        self.toss = gui.add_dropdown(mark("Toss"), options=(ALL_TOSSES,), initial_value=ALL_TOSSES)
        self.toss.on_update(self._on_toss)
        self.ratios_readout = controls.Readout(
            self.ctx, mark("fitted moments I_x : I_y : I_z (largest 1, ± σ)"), fmt="{}"
        )
        self.flip_axis_readout = controls.Readout(self.ctx, mark("it flips about (the intermediate axis)"), fmt="{}")
        self.residual_readout = controls.Readout(self.ctx, mark("residual, rms of measured − fitted (rad/s)"), fmt="{}")
        self.half_turns_readout = controls.Readout(
            self.ctx, mark("half turns, fitted / measured (first toss)"), fmt="{}"
        )
        self.drag_readout = controls.Readout(self.ctx, mark("|L| taken by air drag (first toss)"), fmt="{}")
        self.note = gui.add_markdown("")
        self.plot = gui.add_uplot(
            data=(np.zeros(2), *(np.zeros(2) for _ in range(6))),
            series=(
                viser.uplot.Series(label=mark("t (s)")),
                *(
                    viser.uplot.Series(
                        label=say("ω_{axis} measured", axis=axis),
                        stroke=plot_colour(draw.hex_colour(colour), self.ctx.dark),
                        width=0,
                        points=viser.uplot.Series_Points(
                            show=True, size=4, fill=plot_colour(draw.hex_colour(colour), self.ctx.dark)
                        ),
                    )
                    for axis, colour in COMPONENTS
                ),
                *(
                    viser.uplot.Series(
                        label=say("ω_{axis} fitted", axis=axis),
                        stroke=plot_colour(draw.hex_colour(colour), self.ctx.dark),
                        width=2,
                        points=viser.uplot.Series_Points(show=False),
                    )
                    for axis, colour in COMPONENTS
                ),
            ),
            title=mark("ω in the phone's axes (rad/s): points measured, lines fitted"),
            axes=plot_axes(),
            scales={"x": viser.uplot.Scale(time=False, auto=True), "y": viser.uplot.Scale(auto=True)},
            aspect=1.6,
        )
        self.source_name = EXAMPLE_NAME + ".csv"
        self.source_content = example_csv()
        self.adopt(example_fit())

    # -- showing a fit ------------------------------------------------------------------------------
    def adopt(self, result: TossFit, content: bytes | None = None) -> None:
        """Show a fitted recording: the phone of its moments, the plot, the readouts; the replay restarts.
        ``content``: the file's bytes, kept to fit another toss of it (None: the same file as before)."""
        fit = result.fit
        self.result = result
        if content is not None:
            self.source_name, self.source_content = result.source, content
        mesh = box_for_moments(fit.moments)
        # The box's principal axes are the phone's x, y, z; the fitted ones are turned from them by
        # fit.rotation (a few degrees at most), which the replay's attitudes already include.
        mesh.apply_transform(np.block([[fit.rotation, np.zeros((3, 1))], [np.zeros((1, 3)), np.ones((1, 1))]]))
        mesh.apply_scale(PHONE_LENGTH / float(np.max(np.ptp(mesh.vertices, axis=0))))  # type: ignore[no-untyped-call]  # trimesh does not annotate it
        self.body.set_mesh(mesh)
        self.L_scale = 0.55 * PHONE_LENGTH / float(np.max(np.linalg.norm(result.l_space, axis=1)))
        self.omega_scale = 0.55 * PHONE_LENGTH / float(np.max(np.linalg.norm(result.omega_space, axis=1)))
        labels = (ALL_TOSSES, *(_toss_label(k, w) for k, w in enumerate(result.windows)))
        self._shown_choice = ALL_TOSSES if result.chosen is None else labels[result.chosen + 1]
        # viser sets a dropdown's value to its first option when the old one is gone, and runs its callback:
        # not a student's choice, nothing to fit.
        self._adopting = True
        try:
            self.toss.options = labels
            self.toss.value = self._shown_choice  # type: ignore[misc]  # viser 1.1.1 types this setter read-only
        finally:
            self._adopting = False
        self.ratios_readout.set(ratios_text(result))
        self.flip_axis_readout.set(AXIS_NAMES[fit.axes[1]])
        relative = float(np.median(fit.relative_residuals))
        self.residual_readout.set(
            say("{residual:.3g} ({percent:.1f}% of |ω|)", residual=fit.residual, percent=100 * relative)
        )
        halves = fit.half_turn_times[0]
        self.half_turns_readout.set(
            say("{fitted} / {measured}", fitted=halves.predicted.size, measured=halves.measured.size)
        )
        self.drag_readout.set(say("{percent:.1f}%", percent=100 * fit.momentum_loss(0)))
        self.plot.data = (result.plot_times, *result.measured.T, *result.model.T)
        source = controls.markdown_text(result.source)
        if result.device:
            source = say("{file}, {device}", file=source, device=controls.markdown_text(result.device))
        note = say(
            "**{source}**: {found} toss(es) found, {fitted} fitted.",
            source=source,
            found=len(result.windows),
            fitted=len(result.fitted),
        )
        if result.left_out:
            left_out = joined([controls.markdown_text(reason) for reason in result.left_out], "; ")
            note = say("{note} Left out: {reasons}.", note=note, reasons=left_out)
        self.note.content = note
        self.ctx.restart()

    # -- uploads and the toss chosen (read and fitted in a worker, adopted under the lock) ------------
    def load_upload(self, filename: str, content: bytes, client: viser.ClientHandle | None = None) -> bool:
        """Read and fit an uploaded recording (all its tosses) in a worker; on success show it, on refusal keep
        what is shown and tell only the browser that sent it why."""
        return self._fit_and_adopt(filename, content, None, client)

    def _on_toss(self, event: Any) -> None:
        choice = self.toss.value
        if self._adopting or choice == self._shown_choice:
            return  # set by adopt, or nothing changed
        client = getattr(event, "client", None)
        reason = self.ctx.refusal(client.client_id) if client is not None else None
        options = tuple(self.toss.options)
        if reason is not None or choice not in options:
            with self.ctx.lock:
                self._refuse(reason or say("there is no {choice} in this recording", choice=repr(choice)), client)
                self.toss.value = self._shown_choice  # type: ignore[misc]  # viser 1.1.1 types this setter read-only
            return
        chosen = None if choice == ALL_TOSSES else options.index(choice) - 1
        if not self._fit_and_adopt(self.source_name, self.source_content, chosen, client, keep=True):
            with self.ctx.lock:
                if not self.closed:
                    self.toss.value = self._shown_choice  # type: ignore[misc]  # viser 1.1.1 types this setter read-only

    def _fit_and_adopt(
        self, filename: str, content: bytes, chosen: int | None, client: viser.ClientHandle | None, keep: bool = False
    ) -> bool:
        with self._request_lock:
            self._request += 1
            request = self._request
        try:
            result: TossFit | Exception = toss_fit_in_worker(filename, content, chosen)
        except Exception as exc:  # noqa: BLE001 - shown to the browser that sent it by the guarded swap below
            result = exc
        # Guarded: under the lock, any surprise shown to the user who acted, then a redraw.
        swap = self.ctx.guarded(lambda _event: self._swap_in(result, None if keep else content, client, request))
        return bool(swap(SimpleNamespace(client=client)))

    def _swap_in(
        self, result: TossFit | Exception, content: bytes | None, client: viser.ClientHandle | None, request: int
    ) -> bool:
        if self.closed or request != self._request:  # the user left the scene, or asked for another fit since
            return False
        if isinstance(result, ValueError):
            return self._refuse(str(result), client)
        if isinstance(result, Exception):
            raise result
        self.adopt(result, content)
        self.last_upload_message = say(
            "{file}: {fitted} toss(es) fitted", file=result.source, fitted=len(result.fitted)
        )
        self.ctx.notify(
            mark("Recording fitted"),
            say("{fitted}; moments {ratios}", fitted=self.last_upload_message, ratios=ratios_text(result)),
            client=client,
        )
        return True

    def _refuse(self, message: str, client: viser.ClientHandle | None) -> bool:
        self.upload_refusals += 1
        self.last_upload_message = message
        self.ctx.notify(mark("Recording refused — the previous one stays"), message, client=client, error=True)
        return False

    # -- copies (presenter mode's "Explore on my own") ------------------------------------------------
    def snapshot(self) -> dict[str, Any]:
        # An uploaded recording is not in the controls: a copy needs the fit and the file (a state text refuses
        # it). The bundled one is every scene's: the Toss dropdown says which of its tosses is fitted.
        if self.result.source == EXAMPLE_NAME + ".csv":
            return {}
        return {"uploaded": (self.result, self.source_content)}

    def prepare(self, motion: dict[str, Any]) -> None:
        shown = motion.get("uploaded")
        if isinstance(shown, tuple) and len(shown) == 2 and isinstance(shown[0], TossFit):
            self.adopt(shown[0], shown[1])

    def teardown(self) -> None:
        with self.ctx.lock:
            self.closed = True

    # -- the state --------------------------------------------------------------------------------
    def compute(self, t: float, dt: float) -> dict[str, Any]:
        # The fitted flights replayed one after the other, again and again, at SLOW× the real pace.
        times = self.result.replay_times
        flight = (SLOW * t) % (self.result.duration + float(times[1] - times[0]))
        k = min(int(np.searchsorted(times, flight)), times.size - 1)
        return {
            "R": self.result.attitudes[k],
            "omega": self.result.omega_space[k],
            "L": self.result.l_space[k],
            "flight_time": float(times[k]),
            "t": t,
        }

    def draw(self, state: dict[str, Any]) -> None:
        c = self.centre
        self.body.set_pose(state["R"], c)
        self.L_arrow.set(state["L"] * self.L_scale, c)
        self.omega_arrow.set(state["omega"] * self.omega_scale, c, apart_from=self.L_arrow, screen=self.screen)

    def columns(self, state: dict[str, Any]) -> dict[str, float]:
        R = state["R"]
        return {
            "flight time (s)": state["flight_time"],
            **euler_columns(R),
            **vector_columns("omega_phone", R.T @ state["omega"], "rad/s"),
            **vector_columns("L_per_Imax", state["L"], "rad/s"),
        }

    def describe(self, state: dict[str, Any]) -> str:
        fit = self.result.fit
        if "flip" in self.held:  # a class question asks what the phone does in the air
            return say(
                "Phone toss, {file}: {count} toss(es) recorded; what the phone does in the air is the class question.",
                file=self.result.source,
                count=len(self.result.fitted),
            )
        moments = joined([say("{moment:.3g}", moment=float(m)) for m in fit.moments], " : ")
        return say(
            "Phone toss, {file}: {count} toss(es) fitted, moments I_x : I_y : I_z = {moments}; it flips about its "
            "{axis} axis ({axis_name}); the fit is off by {residual} rms; replayed at {slow:g}× the real pace.",
            file=self.result.source,
            count=len(self.result.fitted),
            moments=moments,
            axis=fit.axes[1],
            axis_name=AXIS_NAMES[fit.axes[1]],
            residual=amount(fit.residual, "rad/s"),
            slow=SLOW,
        )
