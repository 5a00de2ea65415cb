"""One simulation: a scene, its clock, its panel and its scene nodes, drawn for its browsers.

More in docs/app-notes.md (``app.serving.simulation``).
"""

from __future__ import annotations

import functools
import math
import threading
import time
import traceback
from collections.abc import Callable
from typing import Any

import numpy as np
import viser

from app.contracts import ClientId
from app.drawing.palette import legend_html, light
from app.guards.callbacks import event_client, shielded
from app.guards.handles import NO_VALUE, gui_inputs, prop
from app.guards.inputs import guard_inputs
from app.guards.text import lecturer_markdown
from app.guards.wire import departed, resend_poses, unsent
from app.language.words import joined, mark, say, transformed
from app.panel.projector import Projector
from app.panel.simulation_panel import EXPORT_ORDER, SimulationPanel
from app.panel.speed import SPEED_MAX, SPEED_MIN, position_of, speed_label
from app.recording.export_folder import ExportFolder, ExportRun
from app.scenes import REGISTRY, Scene, load_all, scene_names
from app.serving import snapshot as snapshots
from app.serving.clock import Clock
from app.serving.finite import NumericalFailure, check_finite
from app.serving.framing import FOV, first_view, show_scene_to
from app.serving.notices import NOTIFY_SECONDS, Notices
from app.serving.timeline import Timeline
from app.teaching.following import Following
from app.teaching.lectures import Lecture

__all__ = ["FPS", "Simulation", "first_scene"]

FPS = 60.0
DESCRIBE_SECONDS = 5.0
"""The motion in words is said again at most this often while it runs (s), and at once after a change."""


def first_scene(scene: str | None) -> tuple[str, list[str]]:
    """The scene to open first and the picker's list; refuses an unknown name (ValueError)."""
    load_all()
    names = scene_names()
    if not names:
        raise RuntimeError("no scenes are registered")
    if scene is not None and scene not in REGISTRY:
        raise ValueError(f"unknown scene {scene!r}; choose one of: {', '.join(names)}")
    return scene or names[0], names


class Simulation:
    """One simulation, drawn for the whole server or for one browser.

    Parameters
    ----------
    target : viser.ViserServer or viser.ClientHandle
        Where it is drawn: the server (every browser sees the same simulation) or one browser's own client
        handle (a private session or an explorer's copy). Scenes reach it as ``ctx.server``.
    scene : str, optional
        Name of the first scene (default: the first in the picker).
    export : callable
        What the panel's Export button runs (:data:`app.recording.export_folder.ExportRun`).
    fps : float
        Frames per second of the loop that drives it.
    share : bool
        Show viser's share button (a public tunnel).
    dark : bool
        The dark look (:mod:`app.panel.look`), for a dark lecture room.
    refusal : callable(client_id) -> str or None, optional
        Why a browser may not drive it (presenter mode's followers), or None if it may; default: everyone may.
    shown_to : callable(client) -> bool, optional
        Which of the server's browsers it is drawn for (presenter mode: not those exploring a copy).
    language : callable(client_id) -> str, optional
        The language a browser reads (its export is written in it); default: English.
    """

    root = "/scene"

    def __init__(
        self,
        target: viser.ViserServer | viser.ClientHandle,
        scene: str | None = None,
        *,
        export: ExportRun,
        fps: float = FPS,
        share: bool = False,
        dark: bool = False,
        refusal: Callable[[Any], str | None] | None = None,
        shown_to: Callable[[Any], bool] | None = None,
        language: Callable[[ClientId], str] | None = None,
    ) -> None:
        first, names = first_scene(scene)
        self.lock = threading.RLock()
        self.fps = float(fps)
        self.server: viser.ViserServer | viser.ClientHandle = target
        self.dark = bool(dark)
        self.scene: Scene | None = None
        self.scene_inputs: list[Any] = []  # the scene's own adjustable controls, in the order it made them
        self.payload: Any = None  # what the current scene was handed by another (see switch_to)
        self.frames = 0  # frames drawn
        self.last_state: dict[str, Any] = {}  # the state the last frame drew
        self.view: tuple[Any, Any] = ((3.0, -3.0, 2.0), (0.0, 0.0, 0.0))  # camera asked for, before framing
        self.closed = False  # close() was called: callbacks still queued are dropped
        self._refusal = refusal
        self._shown_to = shown_to
        self.clock = Clock(fps)
        self._dirty = True
        self._owed = 0.0  # wall time (s) of frames left undrawn while the browser was behind (see tick)
        self._folder: Any = None
        self._last_time_text = 0.0
        self._described_at = -math.inf  # monotonic time of the last description (DESCRIBE_SECONDS)
        self._building: Scene | None = None  # the scene whose build() is running (see guarded)
        self.following = Following(self)
        self.timeline = Timeline(self)  # the clock moved by hand, and replays (its controls are the panel's)

        # One window for its browsers, as a scene switch (see switch_scene): the grid, the panel and the first
        # scene arrive together.
        with self.server.atomic():
            self.server.scene.set_up_direction("+z")
            light(self.server.scene, dark=dark)
            # The floor recedes: light lines on white, dark ones on the dark look (the body stays 3:1 over it).
            cell, section = ((72, 74, 80), (96, 98, 104)) if dark else ((205, 205, 205), (175, 175, 175))
            self._grid = self.server.scene.add_grid(
                "/grid",
                width=6.0,
                height=6.0,
                cell_size=0.5,
                plane="xy",
                position=(0, 0, 0),
                cell_color=cell,
                section_color=section,
            )
            # No public tunnel unless asked for: viser's share button would publish this server to the world.
            titles = {REGISTRY[n].title: n for n in names}
            self.panel = SimulationPanel(self, titles, share=share, dark=dark)
            # The panel's handles, by the names scenes and tests use.
            self.scene_picker, self.play_button = self.panel.scene_picker, self.panel.play_button
            self.speed_slider, self.time_text = self.panel.speed_slider, self.panel.time_text
            self.state_box, self.status, self.legend = self.panel.state_box, self.panel.status, self.panel.legend
            # The Export folder is recording's, placed in the panel after its State folder.
            self.export_folder = ExportFolder(self, export, NOTIFY_SECONDS, order=EXPORT_ORDER, language=language)
            self.panel.handles.append(self.export_folder.folder)
            self.projector = Projector(self.server.gui, self.guarded(self._projector_press))
            self.panel.projector_button.on_click(self.guarded(lambda _: self.set_projector(not self.projector.on)))
            own = not isinstance(self.server, viser.ViserServer)
            self.notices = Notices(self.clients, self.status, own_browser=own)
            guard_inputs(self.server.gui, self._refuse_input, self.refusal)
            if not own:
                self.server.on_client_connect(self._on_connect)
            self.switch_scene(first)

    # ------------------------------------------------------------------ who it is drawn for
    def clients(self) -> list[viser.ClientHandle]:
        """The browsers this simulation is drawn for."""
        if not isinstance(self.server, viser.ViserServer):
            return [self.server]
        clients = list(self.server.get_clients().values())
        return clients if self._shown_to is None else [c for c in clients if self._shown_to(c)]

    def behind(self) -> bool:
        """True while the browser of a per-browser simulation has not been sent everything already drawn."""
        return isinstance(self.server, viser.ClientHandle) and unsent(self.server)

    def gone(self) -> bool:
        """True once the browser of a per-browser simulation has disconnected (nothing to draw for)."""
        return isinstance(self.server, viser.ClientHandle) and departed(self.server)

    def refusal(self, client_id: ClientId) -> str | None:
        """Why this browser may not drive this simulation, or None if it may."""
        return self._refusal(client_id) if self._refusal is not None else None

    def pick(self, name: str, client: viser.ClientHandle | None = None) -> None:
        """A browser chose scene ``name`` in the picker."""
        if self.scene is None or name != self.scene.name:
            self.switch_scene(name, client=client)

    def _on_connect(self, client: viser.ClientHandle) -> None:
        if self.scene is not None:
            self._frame_for(client, self.scene)

    def _frame_for(self, client: viser.ClientHandle, scene: Scene) -> None:
        """Frame ``client``'s camera on ``scene``, clear of the panel or of projector mode's caption and plot."""
        on = self.projector.on
        show_scene_to(client, *scene.camera, scene.view, projector=on, plot=on and bool(scene.key_plot))

    # ------------------------------------------------------------------ projector mode
    def set_projector(self, on: bool) -> None:
        """Projector mode on or off for every browser this simulation is drawn for (:mod:`app.panel.projector`):
        the panel a slim bar, the step's caption and the scene's key plot large, the body framed anew."""
        with self.lock, self.server.atomic():
            self.projector.show(bool(on))
            self.panel.show_projector(self.projector.on)
            self._sync_projector()
            if self.scene is not None:
                for client in self.clients():
                    self._frame_for(client, self.scene)
            self._dirty = True

    def projector_caption(self) -> str:
        """What projector mode shows as the caption (the lecturer's Markdown): the lecture step's text as
        the class may see it now, or outside a lecture the scene's caption unless a question holds it back."""
        if self.following.lecture is not None:
            return self.following.step_text()
        scene = self.scene
        if scene is None or scene.caption_markdown is None or not scene.caption_markdown.visible:
            return ""
        return scene.caption

    def _sync_projector(self) -> None:
        if self.projector.on:
            scene = self.scene
            plot = scene.key_plot_handle() if scene is not None else None
            clock = () if scene is None or scene.static else ("Pause" if self.playing else "Play", "Reset")
            steps = ("Previous", "Next") if self.following.lecture is not None else ()
            self.projector.sync(self.projector_caption(), plot, (*steps[:1], *clock, *steps[1:]))

    def _projector_press(self, event: Any) -> None:
        """A button of projector mode's row: what the panel's button of that name does."""
        name = event.target.value
        if name in ("Previous", "Next"):
            self.following.go_to(self.step_index + (1 if name == "Next" else -1))
        elif name in ("Play", "Pause"):
            self.set_playing(name == "Play")
        elif name == "Reset":
            self.restart()
        else:
            self.set_projector(False)

    # ------------------------------------------------------------------ lectures and states
    @property
    def lecture(self) -> Lecture | None:
        """The lecture followed (:meth:`load_lecture`), or None."""
        return self.following.lecture

    @property
    def step_index(self) -> int:
        """The lecture's step shown (0-based)."""
        return self.following.step_index

    def load_lecture(self, lecture: Lecture, *, check: bool = True) -> None:
        """Follow a lecture (:class:`app.teaching.following.Following`); ValueError names a bad step."""
        self.following.load(lecture, check=check)
        if self.following.folder not in self.panel.handles:
            self.panel.handles.append(self.following.folder)

    def go_to_step(self, index: int) -> None:
        """Show step ``index`` (0-based, clamped) of the lecture followed."""
        self.following.go_to(index)

    def snapshot(self) -> dict[str, Any]:
        """Everything needed to start another simulation where this one is now (:mod:`app.serving.snapshot`)."""
        return snapshots.snapshot(self)

    def restore(self, snapshot: dict[str, Any]) -> None:
        """Go to the state :meth:`snapshot` gave."""
        snapshots.restore(self, snapshot)

    def state_text(self, client: viser.ClientHandle | None = None) -> str:
        """This simulation's state as a short text, with ``client``'s camera if given."""
        return snapshots.state_text(self, client)

    def open_state(self, text: str) -> None:
        """Go to the state a text describes, all of it or none of it (ValueError says what was refused)."""
        snapshots.open_state(self, text)

    def set_camera(self, position: Any, look_at: Any) -> None:
        """Point every browser's camera (and a new browser's first one) at ``look_at`` from ``position`` (m)."""
        eye, target = np.array(position, dtype=float), np.array(look_at, dtype=float)
        self.view = (eye, target)
        for client in self.clients():
            with client.atomic():
                client.camera.position = eye
                client.camera.look_at = target
        if isinstance(self.server, viser.ViserServer):
            self.server.initial_camera.position = eye
            self.server.initial_camera.look_at = target

    def hold_back(self, quantities: Any) -> None:
        """Hold back what of the scene states ``quantities`` (a class question asks for them; empty: show
        everything again), and say the motion in words again at once (:meth:`app.scenes.base.Scene.hold`)."""
        with self.lock:
            if self.scene is not None and (self.scene.held or quantities):
                self.scene.hold(quantities)
                self._dirty = True

    # ------------------------------------------------------------------ the context scenes use
    @property
    def time(self) -> float:
        """Simulation time, s."""
        return self.clock.t

    @property
    def playing(self) -> bool:
        return self.clock.playing

    @property
    def speed(self) -> float:
        return self.clock.speed

    @property
    def messages(self) -> list[tuple[str, str]]:
        """Every notification sent (title, body), newest last (the last 50)."""
        return self.notices.messages

    def guarded(self, fn: Callable[..., Any]) -> Callable[..., Any]:
        """Wrap a callback: run it under the lock, show an exception to the user, ask for a redraw.

        A callback wrapped while a scene is being built belongs to that scene: once the scene is gone (a
        browser's message can arrive just after a switch), it is dropped instead of acting on removed
        controls.
        """
        owner = self._building

        @functools.wraps(fn)
        def wrapper(*args: Any, **kwargs: Any) -> Any:
            client = event_client(args)
            reason = self.refusal(client.client_id) if client is not None else None
            if reason is not None:  # an upload or a click that did not pass through the input checks
                self.notify(mark("Refused"), reason, client=client, error=True)
                return None
            with self.lock:
                if self.closed or self.gone():
                    return None  # it arrived after its simulation was closed or its browser left
                if owner is not None and owner is not self.scene:
                    return None
                out = fn(*args, **kwargs)
                self._dirty = True
                return out

        return shielded(wrapper, self._tell_error)

    def _tell_error(self, client: viser.ClientHandle | None, title: str, body: str) -> None:
        self.notify(title, body, client=client, error=True)

    def notify(self, title: str, body: str, client: viser.ClientHandle | None = None, error: bool = False) -> None:
        """A notification to one client or to every browser it is drawn for (:class:`Notices`)."""
        self.notices.notify(title, body, client=client, error=error)

    def clear_status(self) -> None:
        """Empty the scene's status line (a change was accepted, or the scene changed)."""
        self.notices.clear_status()

    def _refuse_input(self, client_id: ClientId, message: str) -> None:
        client = next((c for c in self.clients() if c.client_id == client_id), None)
        if client is not None:
            self.notify(mark("Refused"), message, client=client, error=True)

    def request_redraw(self) -> None:
        self._dirty = True

    # ------------------------------------------------------------------ the clock
    def set_time(self, t: float) -> None:
        """Put the clock at ``t`` (s), the scene untouched (a refused change puts the time back)."""
        with self.lock:
            self.clock.t = float(t)
            self._dirty = True

    def restart(self) -> None:
        """t = 0 with the current parameters (the Reset button; scenes call it after a parameter change)."""
        with self.lock:
            self.clock.t = 0.0
            self.timeline.restart()
            if self.scene is not None:
                self.scene.reset()
            self._dirty = True

    def pause(self, reason: str | None = None) -> None:
        """Stop the clock; with a reason, tell everyone why."""
        with self.lock:
            self.set_playing(False)
            if reason:
                self.notify(mark("Paused"), reason, error=True)

    def set_playing(self, playing: bool) -> None:
        """Play or pause; a still scene (``Scene.static``) stays paused at t = 0."""
        with self.lock:
            if self.scene is not None and self.scene.static:
                playing = False
            if self.clock.playing and not playing:
                self._dirty = True  # the paused frame shows the time it stopped at (the timeline's slider)
            self.clock.playing = bool(playing)
            self.panel.show_playing(self.clock.playing)
            if self.clock.playing:
                self.clear_status()

    def step(self) -> None:
        """Pause and advance one frame's worth of simulation time (1/60 s × speed); nothing in a still scene."""
        with self.lock:
            self.set_playing(False)
            if self.scene is None or not self.scene.static:
                self.clock.steps += 1

    def set_speed(self, speed: float) -> None:
        speed = float(speed)
        if not (math.isfinite(speed) and SPEED_MIN - 1e-9 <= speed <= SPEED_MAX + 1e-9):
            raise ValueError(f"speed must be between {SPEED_MIN}× and {SPEED_MAX}×, got {speed}")
        with self.lock:
            self.clock.speed = speed
            position = position_of(speed)
            if abs(self.speed_slider.value - position) > 1e-9:
                self.speed_slider.value = position  # type: ignore[misc]  # viser 1.1.1 types this setter read-only
            if self.speed_slider.label != speed_label(speed):
                self.speed_slider.label = speed_label(speed)

    # ------------------------------------------------------------------ scenes
    def switch_to(self, name: str, payload: Any = None) -> None:
        """For scenes: switch to another scene and hand it a payload (see Scene.accept)."""
        self.switch_scene(name, payload=payload)

    def switch_scene(self, name: str, payload: Any = None, client: viser.ClientHandle | None = None) -> None:
        """Tear the current scene down and build ``name``; on failure go back to the previous one."""
        if name not in REGISTRY:
            raise ValueError(f"unknown scene {name!r}; choose one of: {', '.join(scene_names())}")
        # One window for the browsers: the old scene's removal and the new one's nodes and controls arrive
        # together, and each message queued skips waking viser's event loop (about 70 µs a message).
        with self.lock, self.server.atomic():
            previous = type(self.scene) if self.scene is not None else None
            self._teardown()
            try:
                scene = self._build(REGISTRY[name])
                if payload is not None:
                    scene.accept(payload)
                self.payload = payload
            except Exception as exc:
                traceback.print_exc()
                self._teardown()
                self.notify(
                    f"Could not open {REGISTRY[name].title}", f"{type(exc).__name__}: {exc}", client=client, error=True
                )
                if previous is None or previous is REGISTRY[name]:
                    raise
                scene = self._build(previous)
            cls = type(scene)
            self.panel.show_scene(cls.title)
            self.legend.content = legend_html(cls.quantities, dark=self.dark)
            self.clear_status()  # the status line belongs to the scene
            self.view = cls.camera
            for c in self.clients():
                self._frame_for(c, scene)
            if isinstance(self.server, viser.ViserServer):  # a browser's first view, before it reports its size
                position, look_at = first_view(*cls.camera, cls.view)
                self.server.initial_camera.fov = FOV
                self.server.initial_camera.position = position
                self.server.initial_camera.look_at = look_at
            self.clock.t = 0.0
            self.timeline.restart()
            if cls.static or previous is None or previous.static:  # a still scene has no clock; after one, play
                self.set_playing(not cls.static)
            self.panel.show_clock(not cls.static)
            self._dirty = True

    def _build(self, cls: type[Scene]) -> Scene:
        self.server.scene.add_frame(self.root, show_axes=False)
        self._folder = self.server.gui.add_folder(cls.title)
        scene = cls(self)
        self._building = scene
        inputs = gui_inputs(self.server.gui)
        before = set(inputs)
        try:
            with self._folder:
                if cls.caption:
                    scene.caption_markdown = self.server.gui.add_markdown(transformed(cls.caption, lecturer_markdown))
                scene.build()
        finally:
            self._building = None
        resend_poses(self.server.scene, self.root)  # browsers keep a replaced node's pose (app.guards.wire)
        # The scene's own adjustable controls (not buttons, not read-only readouts), for snapshot().
        self.scene_inputs = [
            h
            for uuid, h in list(inputs.items())
            if uuid not in before
            and not isinstance(h, (viser.GuiButtonHandle, viser.GuiUploadButtonHandle))
            and prop(h, "label", NO_VALUE) is not NO_VALUE  # a control, not a progress bar
            and not prop(h, "disabled", False)
        ]
        self.scene = scene
        return scene

    def _teardown(self) -> None:
        if self.scene is not None:
            try:
                self.scene.teardown()
            except Exception:  # noqa: BLE001
                traceback.print_exc()
        self.scene = None
        for remove in (lambda: self.server.scene.remove_by_name(self.root), lambda: self._folder.remove()):
            try:
                remove()
            except Exception:  # noqa: BLE001 - nothing to remove yet
                pass
        self._folder = None

    def close(self) -> None:
        """Remove this simulation's scene, nodes and panel (a browser stops exploring on its own)."""
        with self.lock:
            self.closed = True
            self._teardown()
            self.projector.remove()
            self.panel.remove()
            try:
                self._grid.remove()
            except Exception:  # noqa: BLE001 - its browser may have gone already
                pass

    # ------------------------------------------------------------------ the frame
    def tick(self, wall_dt: float) -> bool:
        """The real-time loop's frame (:meth:`frame`), left out while this simulation's own browser has not
        been sent the last one: a frame drawn then would replace that one in viser's buffer unseen. The wall
        time left out is owed and drawn with the next frame its browser can take; a change is drawn at once."""
        if not self._dirty and self.behind():
            self._owed += wall_dt
            return False
        wall_dt, self._owed = wall_dt + self._owed, 0.0
        return self.frame(wall_dt)

    def frame(self, wall_dt: float = 1.0 / FPS) -> bool:
        """Advance the clock by ``wall_dt`` × speed (if playing) and redraw; True if a frame was drawn."""
        with self.lock:
            if not self.closed:
                self.following.advance_if_due()
            scene = self.scene
            if scene is None or self.closed or self.gone():
                return False
            self.timeline.glide_frame()  # a dragged slider's glide: this frame's instant
            advance = self.clock.advance(wall_dt)
            t_before = self.clock.t
            if advance == 0.0 and not self._dirty:
                return False
            t_new = self.timeline.clamp(self.clock.t + advance)  # a replay stops at its end
            changed = self._dirty  # a change of parameters, scene, time or clock: describe at once
            try:
                state = scene.compute(t_new, advance)
                check_finite(state)
            except Exception as exc:  # noqa: BLE001 - pause with a message; keep the last valid picture
                self.failed(exc)
                return False
            self.clock.t = t_new
            self.timeline.after_frame(wall_dt, t_new - t_before)
            try:
                with self.server.atomic():
                    scene.draw(state)
                    self._sync_projector()
                    now = time.monotonic()
                    if now - self._last_time_text > 0.1 or not self.clock.playing:
                        self._last_time_text = now
                        self.time_text.value = say("{t:.2f}", t=self.clock.t)  # type: ignore[misc]  # viser 1.1.1 typing
                        if self.timeline.glide is None:  # mid-glide the dragging page's slider is ahead
                            self.panel.timeline.show(self.clock.t, self.timeline.earliest(), self.timeline.reached)
                        self.panel.measure.update(self.clock.t, state)
                    if changed or now - self._described_at >= DESCRIBE_SECONDS:
                        self._described_at = now
                        said, event = scene.describe(state), self.panel.measure.event_words(self.clock.t)
                        self.panel.show_words(joined([said, event]) if event else said)
            except Exception as exc:  # noqa: BLE001
                self.failed(exc)
                return False
            self._dirty = False
            self.frames += 1
            self.last_state = state  # what was drawn (the export writes its columns)
            return True

    def failed(self, exc: Exception) -> None:
        """A frame failed: pause with a message to everyone (nothing if its browser has left)."""
        if self.gone():
            return  # its browser left during the frame (viser removed the handles): nothing to report
        traceback.print_exc()
        self._dirty = False
        what = (
            "a numerical failure"
            if isinstance(exc, (NumericalFailure, FloatingPointError, ArithmeticError))
            else "an error"
        )
        self.pause(
            f"{what} at t = {self.clock.t:.3f} s — {type(exc).__name__}: {exc}. The last valid state is shown; "
            "change a parameter or press Reset."
        )
