"""The Rigid Body Lab server: one viser server, its simulations (one shared, or one per browser), a clock.

Threads. viser runs GUI callbacks in a thread pool; our loop thread advances every simulation's clock.
Each :class:`Simulation` has one re-entrant lock (:attr:`Simulation.lock`) guarding its state: callbacks
only change parameters (through :meth:`Simulation.guarded`), and the loop is the only place that asks
the scene's model for the state and moves the kept handles (inside ``atomic()``, so a browser applies a
frame's updates together). Values from browsers are checked on viser's event loop before any of this
(:mod:`app.inputs`). viser's own asyncio objects are changed only on its event loop (:mod:`app.event_loop`);
we hold none. Notifications (:meth:`Simulation.notify`) are sent from callback threads, the loop and
viser's event loop (a refused input or upload): the list of messages, the notifications shown and the
status line are guarded by a second, plain lock (``Simulation._notice_lock``), always the innermost of
ours (no other lock of ours is taken while it is held) and held for microseconds, so viser's event loop
never waits for a frame or a scene switch.

Presenter mode (:mod:`app.presenter`): the App is the lecture; browsers follow it read-only
(:meth:`Simulation.refusal`), and an explorer gets a :class:`Simulation` of its own, copied with
:meth:`Simulation.snapshot` / :meth:`Simulation.restore`.

Robustness. An exception in a callback is shown to the user who caused it (a notification), not
swallowed. An exception or a non-finite number in a frame pauses the clock with a message to everyone;
the last valid picture stays (a frame's state is computed and checked completely before any handle is
touched). The loop catches everything, so the server never dies of a scene.
"""

from __future__ import annotations

import functools
import math
import threading
import time
import traceback
from collections.abc import Callable
from pathlib import Path
from typing import Any

import numpy as np
import viser

from app import draw, look
from app.addresses import is_loopback
from app.event_loop import confine_events
from app.export_button import ExportFolder
from app.framing import framed
from app.inputs import check_update, guard_inputs
from app.lectures import Lecture, Step, read_lecture
from app.presenter import Classroom, check_pin, new_pin
from app.scenes import REGISTRY, Scene, load_all, scene_names
from app.speed import POSITION_MARKS, POSITION_STEP, SPEED_MAX, SPEED_MIN, position_of, speed_at, speed_label
from app.states import parse_state, state_text
from app.tunnel import guard_tunnel
from app.wire import departed as _departed
from app.wire import resend_poses

__all__ = ["App", "Simulation", "NumericalFailure", "check_finite"]

FPS = 60.0
FRAMING_GRACE = 10.0
"""Seconds after a camera is framed for a page during which a new page size always re-frames it: the page
reports its settled size as it loads, possibly before it has eased to the framed camera (seen as a timeout
of the look test on a loaded machine)."""
NOTIFY_SECONDS = 6.0  # a notification closes by itself after this long; an identical one is not stacked
FOV = math.radians(50.0)  # vertical field of view (viser's default 75° makes the scene look far away)
LAST_ORDER = 1e6  # viser's panel order of what comes after the scene's folder (legend, state, export)
MAX_FRAME_DT = 0.1  # s of wall time: a stalled frame does not make the simulation jump


NETWORK_SHARE = 0.3
"""Under load, the loop rests this fraction of its busy time between ticks: viser's event loop thread
serializes and sends the frames meanwhile (one GIL between them). Measured by benchmarks/serve.py."""


class NumericalFailure(ValueError):
    """A scene produced NaN or inf."""


def check_finite(state: dict[str, Any], where: str = "") -> None:
    """Raise :class:`NumericalFailure` naming the first non-finite number in a state dict (recursing
    into nested dicts, lists and tuples of numbers/arrays; other values are ignored)."""
    for key, value in state.items():
        name = f"{where}{key}"
        if isinstance(value, dict):
            check_finite(value, name + ".")
        elif isinstance(value, (float, int, np.floating, np.integer)) and not isinstance(value, bool):
            if not math.isfinite(float(value)):
                raise NumericalFailure(f"{name} = {value} is not a finite number")
        elif isinstance(value, np.ndarray) and value.dtype.kind in "fc":
            if not np.all(np.isfinite(value)):
                raise NumericalFailure(f"{name} contains NaN or inf")
        elif isinstance(value, (list, tuple)) and value and all(isinstance(v, (float, int, np.ndarray)) for v in value):
            check_finite({str(i): v for i, v in enumerate(value)}, name + "[")


def _first_scene(scene: str | None) -> tuple[str, list[str]]:
    """The scene to open first and the picker's list; refuses an unknown name."""
    load_all()
    names = scene_names()
    if not names:
        raise RuntimeError("no scenes are registered")
    if scene is not None and scene not in REGISTRY:
        raise ValueError(f"unknown scene {scene!r}; choose one of: {', '.join(names)}")
    return scene or names[0], names


class Simulation:
    """One simulation: a scene, its clock, its panel and its scene nodes, drawn for its browsers.

    Parameters
    ----------
    target : viser.ViserServer or viser.ClientHandle
        Where it is drawn: the server (every browser sees and drives the same simulation) or one
        browser's own client handle (a private session, ``rigid-body-lab --private``). Scenes reach it as
        ``ctx.server`` and use only its ``scene`` and ``gui``.
    scene : str, optional
        Name of the first scene (default: the first in the picker).
    fps : float
        Frames per second of the loop that drives it.
    share : bool
        Show viser's share button (a public tunnel).
    dark : bool
        The dark look (:mod:`app.look`), for a dark lecture room.
    """

    root = "/scene"
    _closed = False  # close() was called: callbacks still queued are dropped

    def __init__(
        self,
        target: viser.ViserServer | viser.ClientHandle,
        scene: str | None = None,
        *,
        fps: float = FPS,
        share: bool = False,
        dark: bool = False,
    ) -> None:
        first, names = _first_scene(scene)
        self.lock = threading.RLock()
        self.fps = float(fps)
        self.server: Any = target
        self.scene: Scene | None = None
        self.messages: list[tuple[str, str]] = []  # every notification sent (title, body), newest last
        self.frames = 0  # frames drawn
        self.last_state: dict[str, Any] = {}  # the state the last frame drew
        self.view: tuple[Any, Any] = ((3.0, -3.0, 2.0), (0.0, 0.0, 0.0))  # camera asked for, before framing
        self._t = 0.0
        self._playing = True
        self._speed = 1.0
        self._steps = 0
        self._dirty = True
        self._folder: Any = None
        self._switching = False
        self._last_time_text = 0.0
        self._shown: dict[tuple[Any, str, str], float] = {}  # (client id, title, body) -> when it was sent
        # notify runs on callback threads, the loop and viser's event loop (a refused input): the messages,
        # the notifications shown and the status line have a lock of their own, innermost (module docstring).
        self._notice_lock = threading.Lock()
        self._building: Scene | None = None  # the scene whose build() is running (see guarded)
        self._scene_inputs: list[Any] = []  # the scene's own controls, in the order it made them
        self._payload: Any = None  # what the current scene was handed by another (see switch_to)
        self.lecture: Lecture | None = None  # the lecture followed (load_lecture), its step and when it began
        self.step_index = 0
        self._step_started = 0.0
        self._lecture_gui: Any = None

        self.server.scene.set_up_direction("+z")
        draw.light(self.server.scene, dark=dark)
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
        self.dark = bool(dark)
        self._style = look.configure(self.server.gui, share=share, dark=dark)
        self._build_global_gui(names)
        guard_inputs(self.server.gui, self._refuse_input, self.refusal)
        if isinstance(self.server, viser.ViserServer):
            self.server.on_client_connect(self._on_connect)
        self.switch_scene(first)

    def _clients(self) -> list[Any]:
        """The browsers this simulation is drawn for."""
        if isinstance(self.server, viser.ViserServer):
            return list(self.server.get_clients().values())
        return [self.server]

    def _gone(self) -> bool:
        """True once the browser of a per-browser simulation has disconnected (nothing to draw for)."""
        return isinstance(self.server, viser.ClientHandle) and _departed(self.server)

    def _client(self, client_id: Any) -> Any:
        return next((c for c in self._clients() if c.client_id == client_id), None)

    # ------------------------------------------------------------------ GUI shared by all scenes
    def refusal(self, client_id: Any) -> str | None:
        """Why this browser may not drive this simulation, or None if it may (presenter mode overrides)."""
        return None

    def _build_global_gui(self, names: list[str]) -> None:
        gui = self.server.gui
        self._title = gui.add_markdown("**Rigid Body Lab**")
        titles = {REGISTRY[n].title: n for n in names}
        self._title_to_name = titles
        self.scene_picker = gui.add_dropdown("Scene", options=tuple(titles), initial_value=REGISTRY[names[0]].title)
        self.scene_picker.on_update(self.guarded(self._on_pick))
        with gui.add_folder("Clock") as clock:
            self.play_button = gui.add_button("Pause", icon=viser.Icon.PLAYER_PAUSE)
            self.step_button = gui.add_button("Step", icon=viser.Icon.PLAYER_TRACK_NEXT)
            self.reset_button = gui.add_button("Reset", icon=viser.Icon.REFRESH)
            # Logarithmic (app.speed): the value is a position in [−1, 1], the label shows the speed.
            self.speed_slider = gui.add_slider(
                speed_label(1.0), min=-1.0, max=1.0, step=POSITION_STEP, initial_value=0.0, marks=POSITION_MARKS
            )
            self.time_text = gui.add_text("Time (s)", initial_value="0.00", disabled=True)
        self.play_button.on_click(self.guarded(lambda _: self.set_playing(not self._playing)))
        self.step_button.on_click(self.guarded(lambda _: self.step()))
        self.reset_button.on_click(self.guarded(lambda _: self.restart()))
        self.speed_slider.on_update(self.guarded(lambda _: self.set_speed(speed_at(self.speed_slider.value))))
        self._style.content = look.STYLE + look.hide_number_box(self.speed_slider._impl.uuid)
        # Below the scene's own folder (LAST_ORDER): the scene's controls stay above the fold at 1280×800.
        with gui.add_folder("State", expand_by_default=False, order=LAST_ORDER + 1) as state:
            self.state_box = gui.add_text("State text", initial_value="", hint="Copy state writes it here")
            self.copy_state_button = gui.add_button("Copy state", icon=viser.Icon.COPY)
            self.open_state_button = gui.add_button("Open state", icon=viser.Icon.PLAYER_PLAY)
        self.copy_state_button.on_click(self.guarded(self._on_copy_state))
        self.open_state_button.on_click(self.guarded(self._on_open_state))
        self.export_folder = ExportFolder(self, order=LAST_ORDER + 2)
        self.status = gui.add_markdown("")
        self.legend = gui.add_html("", order=LAST_ORDER)
        self._clock = clock
        self._global_gui = [
            self._style,
            self._title,
            self.scene_picker,
            clock,
            state,
            self.export_folder.folder,
            self.status,
            self.legend,
        ]

    # ------------------------------------------------------------------ lectures
    def load_lecture(self, lecture: Lecture, *, check: bool = True) -> None:
        """Follow a lecture (:mod:`app.lectures`): its steps in the panel with Previous and Next.

        With ``check`` every step is applied once first, so that what only a scene can check (a preset's
        name, a slider's range, a possible body) is checked before the lecture starts at step 1.

        Raises
        ------
        ValueError
            Naming the step (1-based) and what was wrong with it; the simulation is left at its first scene.
        """
        with self.lock:
            if check:
                for k, step in enumerate(lecture.steps, start=1):
                    try:
                        self._apply_step(step)
                    except ValueError as exc:
                        raise ValueError(f"{Path(lecture.source).name or lecture.title}, step {k}: {exc}") from None
            self.lecture = lecture
            if self._lecture_gui is None:
                gui = self.server.gui
                with gui.add_folder("Lecture", order=-1.0) as folder:
                    self._lecture_text = gui.add_markdown("")
                    previous = gui.add_button("Previous", icon=viser.Icon.CHEVRON_LEFT)
                    following = gui.add_button("Next", icon=viser.Icon.CHEVRON_RIGHT)
                previous.on_click(self.guarded(lambda _: self.go_to_step(self.step_index - 1)))
                following.on_click(self.guarded(lambda _: self.go_to_step(self.step_index + 1)))
                self._lecture_gui = folder
                self._global_gui.append(folder)
            self.go_to_step(0)

    def go_to_step(self, index: int) -> None:
        """Show step ``index`` (0-based, clamped to the lecture) of the lecture being followed."""
        lecture = self.lecture
        if lecture is None:
            return
        with self.lock:
            index = min(max(index, 0), len(lecture.steps) - 1)
            step = lecture.steps[index]
            self.step_index = index
            self._step_started = time.monotonic()
            try:
                self._apply_step(step)
            except ValueError as exc:  # checked when loaded; a body handed over since may refuse it
                self.notify(f"Step {index + 1} could not be shown", str(exc), error=True)
            self._lecture_text.content = (
                f"**{lecture.title}** — step {index + 1} of {len(lecture.steps)}\n\n{step.caption}".rstrip()
            )

    def _auto_advance(self) -> None:
        """Go to the next step when the current one has ``seconds`` and they have passed (the last stays)."""
        lecture = self.lecture
        if lecture is None or self._closed or self.step_index + 1 >= len(lecture.steps):
            return
        seconds = lecture.steps[self.step_index].seconds
        if seconds is not None and time.monotonic() - self._step_started >= seconds:
            self.go_to_step(self.step_index + 1)

    def _apply_step(self, step: Step) -> None:
        """Put the simulation at a step: its state or its scene from the defaults, then its dropdown choices,
        preset, values, camera."""
        if step.state is not None:
            self.open_state(step.state)
            if step.scene is not None and self.scene is not None and self.scene.name != step.scene:
                raise ValueError(f"scene: the state is of {self.scene.name!r}, the step says {step.scene!r}")
        else:
            assert step.scene is not None  # read_lecture: a step has a scene or a state
            self.switch_scene(step.scene)
        scene = self.scene
        assert scene is not None
        for label, choice in step.choices.items():  # a dropdown (the body, the axis) before the sliders
            handle = next((h for h in self._scene_inputs if str(h.label) == label and hasattr(h, "options")), None)
            if handle is None:
                names = [str(h.label) for h in self._scene_inputs if hasattr(h, "options")]
                raise ValueError(f"choices.{label}: {scene.name} has no dropdown {label!r}; its dropdowns are {names}")
            if choice not in handle.options:
                raise ValueError(f"choices.{label}: no choice {choice!r}; the choices are {list(handle.options)}")
            handle.value = choice  # runs the dropdown's callback now: the scene adopts it or snaps back
            if handle.value != choice:
                why = self.messages[-1][1] if self.messages else "the scene refused it"
                raise ValueError(f"choices.{label}: {choice!r} was refused: {why}")
        if step.preset is not None:
            presets = getattr(scene, "presets", None)
            names = list(presets.presets) if presets is not None else []
            if presets is None or presets.resolve(step.preset) is None:
                raise ValueError(f"preset: {scene.name} has no preset {step.preset!r}; its presets are {names}")
            if not presets.choose(step.preset):
                raise ValueError(f"preset {step.preset!r} was refused: {presets.panel.last_refusal}")
        if step.values:
            params = getattr(scene, "params", None)
            if params is None:
                raise ValueError(f"values: {scene.name} has no sliders")
            for key, value in step.values.items():
                try:
                    params._number(key, value)
                except ValueError as exc:
                    raise ValueError(f"values.{key}: {exc}") from None
            if not params.offer(step.values):
                raise ValueError(f"values were refused: {params.last_refusal}")
        if step.camera is not None:
            self._set_camera(step.camera["position"], step.camera["look_at"])

    # ------------------------------------------------------------------ states as text
    def state_text(self, client: Any = None) -> str:
        """This simulation's state as a short text (:mod:`app.states`), with ``client``'s camera if given."""
        camera = None
        if client is not None:
            camera = {"position": list(client.camera.position), "look_at": list(client.camera.look_at)}
        return state_text(self.snapshot(), camera)

    def open_state(self, text: str) -> None:
        """Go to the state a text describes: all of it or, if any part is refused, none of it.

        Raises
        ------
        ValueError
            What is wrong with the text, or which control refused its value (the previous state stays).
        """
        state = parse_state(text)
        with self.lock:
            before = self.snapshot() if self.scene is not None else None
            try:
                if self.scene is None or self.scene.name != state["scene"]:
                    self.switch_scene(state["scene"])
                inputs = {str(h.label): h for h in self._scene_inputs if not h._impl.removed}
                checked = []
                for label, value in state["controls"]:
                    handle = inputs.get(label)
                    if handle is None:
                        raise ValueError(f"this state sets “{label}”, which the scene does not have")
                    checked.append(
                        (label, check_update(handle.value, handle._impl.props, label, {"value": value})["value"])
                    )
                self.restore(
                    {
                        **state,
                        "controls": [
                            (str(h.label), dict(checked).get(str(h.label), h.value)) for h in self._scene_inputs
                        ],
                    }
                )
            except Exception:
                if before is not None:
                    self.restore(before)
                raise
            camera = state.get("camera")
        if camera is not None:
            self._set_camera(camera["position"], camera["look_at"])

    def _set_camera(self, position: list[float], look_at: list[float]) -> None:
        eye, target = np.array(position, dtype=float), np.array(look_at, dtype=float)
        self.view = (eye, target)
        for client in self._clients():
            with client.atomic():
                client.camera.position = eye
                client.camera.look_at = target
        if isinstance(self.server, viser.ViserServer):
            self.server.initial_camera.position = eye
            self.server.initial_camera.look_at = target

    def _on_copy_state(self, event: Any) -> None:
        client = getattr(event, "client", None)
        try:
            self.state_box.value = self.state_text(client)
        except ValueError as exc:
            self.notify("No state text", str(exc), client=client, error=True)

    def _on_open_state(self, event: Any) -> None:
        client = getattr(event, "client", None)
        try:
            self.open_state(self.state_box.value)
        except ValueError as exc:
            self.notify("State refused", str(exc), client=client, error=True)

    def _on_pick(self, event: Any) -> None:
        if self._switching:
            return
        name = self._title_to_name[self.scene_picker.value]
        if self.scene is None or name != self.scene.name:
            self.switch_scene(name, client=getattr(event, "client", None))

    def _on_connect(self, client: viser.ClientHandle) -> None:
        if self.scene is not None:
            self._show_scene_to(client, *self.scene.camera)

    @staticmethod
    def _show_scene_to(client: Any, position: Any, look_at: Any) -> None:
        """Point a browser's camera at a scene, framed clear of the panel for its view (app.framing).

        A page reports its real size only after its layout settles (and again when the window or a
        phone's orientation changes): until the viewer moves the camera, a new size re-frames it, and
        always within :data:`FRAMING_GRACE` of the last framing (the page may report its settled size
        before it has eased to the camera it was sent, which would look like a viewer's move).
        """
        size = (client.camera.image_width, client.camera.image_height)
        eye, target = framed(position, look_at, size[0], size[1], FOV)
        first = getattr(client, "_rbl_framing", None) is None
        client._rbl_framing = (size, eye, position, look_at, time.monotonic())
        with client.atomic():
            client.camera.fov = FOV
            client.camera.position = eye
            client.camera.look_at = target
        if first:
            client.camera.on_update(Simulation._reframe)

    @staticmethod
    def _reframe(camera: Any) -> None:
        client = camera.client
        size, eye, position, look_at, when = client._rbl_framing
        if (camera.image_width, camera.image_height) == size:
            return
        # The page echoes the position in float32 and after its own easing: "unmoved" is to 1e-3 of the
        # distance (an orbit by a person moves it by far more).
        moved = np.linalg.norm(np.asarray(camera.position) - eye) > 1e-3 * max(1.0, float(np.linalg.norm(eye)))
        if moved and time.monotonic() - when > FRAMING_GRACE:
            return  # the viewer has moved the camera: theirs now
        Simulation._show_scene_to(client, position, look_at)

    # ------------------------------------------------------------------ the context scenes use
    @property
    def time(self) -> float:
        """Simulation time, s."""
        return self._t

    @property
    def playing(self) -> bool:
        return self._playing

    @property
    def speed(self) -> float:
        return self._speed

    def guarded(self, fn: Callable[..., Any]) -> Callable[..., Any]:
        """Wrap a callback: run it under the lock, show an exception to the user, ask for a redraw.

        A callback wrapped while a scene is being built belongs to that scene: once the scene is gone (a
        browser's message can arrive just after a switch), it is dropped instead of acting on removed
        controls.
        """
        owner = self._building

        @functools.wraps(fn)
        def wrapper(*args: Any, **kwargs: Any) -> Any:
            client = getattr(args[0], "client", None) if args else None
            reason = self.refusal(client.client_id) if client is not None else None
            if reason is not None:  # an upload or a click that did not pass through the input checks
                self.notify("Refused", reason, client=client, error=True)
                return None
            try:
                with self.lock:
                    if self._closed or self._gone():
                        return None  # it arrived after its simulation was closed or its browser left
                    if owner is not None and owner is not self.scene:
                        return None
                    out = fn(*args, **kwargs)
                    self._dirty = True
                    return out
            except Exception as exc:  # noqa: BLE001 - shown to the user, never swallowed
                traceback.print_exc()
                self.notify("Something went wrong", f"{type(exc).__name__}: {exc}", client=client, error=True)
                return None

        return wrapper

    def notify(self, title: str, body: str, client: Any = None, error: bool = False) -> None:
        """A notification to one client (the one who acted) or, without one, to every connected client.

        It closes by itself after :data:`NOTIFY_SECONDS`; the same notification is not sent to the same
        browser again while the first is still showing. An error for everyone (a numerical failure, a
        lecture step) also goes to the scene's status line (cleared on a scene switch and on the next
        accepted change); an error for one browser (a refused input or upload) goes to the status line
        only of a simulation that browser has to itself: the one the server draws for everyone (shared,
        presenter) is not told of it.
        """
        with self._notice_lock:
            self.messages.append((title, body))
            del self.messages[:-50]
        clients = [client] if client is not None else self._clients()
        now = time.monotonic()
        for c in clients:
            key = (getattr(c, "client_id", None), title, body)
            with self._notice_lock:
                self._shown = {k: v for k, v in self._shown.items() if now - v < NOTIFY_SECONDS}
                if key in self._shown:
                    continue
                self._shown[key] = now
            try:
                c.add_notification(title, body, color="red" if error else "blue", auto_close_seconds=NOTIFY_SECONDS)
            except Exception:  # noqa: BLE001 - a client that just left must not break the caller
                pass
        if error and (client is None or not isinstance(self.server, viser.ViserServer)):
            with self._notice_lock:
                self.status.content = f"⚠ **{title}**: {body}"

    def clear_status(self) -> None:
        """Empty the scene's status line (a change was accepted, or the scene changed)."""
        with self._notice_lock:
            if self.status.content:
                self.status.content = ""

    def _refuse_input(self, client_id: Any, message: str) -> None:
        """A value a browser sent was refused by :func:`app.inputs.guard_inputs`: tell that browser."""
        client = self._client(client_id)
        if client is not None:
            self.notify("Refused", message, client=client, error=True)

    def request_redraw(self) -> None:
        self._dirty = True

    def set_time(self, t: float) -> None:
        """Put the clock at ``t`` (s), the scene untouched (a refused change puts the time back)."""
        with self.lock:
            self._t = float(t)
            self._dirty = True

    def restart(self) -> None:
        """t = 0 with the current parameters (the Reset button; scenes call it after a parameter change)."""
        with self.lock:
            self._t = 0.0
            if self.scene is not None:
                self.scene.reset()
            self._dirty = True

    def pause(self, reason: str | None = None) -> None:
        """Stop the clock; with a reason, tell everyone why."""
        with self.lock:
            self.set_playing(False)
            if reason:
                self.notify("Paused", reason, error=True)

    def set_playing(self, playing: bool) -> None:
        with self.lock:
            self._playing = bool(playing)
            self.play_button.label = "Pause" if self._playing else "Play"
            self.play_button.icon = viser.Icon.PLAYER_PAUSE if self._playing else viser.Icon.PLAYER_PLAY
            if self._playing:
                self.clear_status()

    def step(self) -> None:
        """Pause and advance one frame's worth of simulation time (1/60 s × speed)."""
        with self.lock:
            self.set_playing(False)
            self._steps += 1

    def set_speed(self, speed: float) -> None:
        speed = float(speed)
        if not (math.isfinite(speed) and SPEED_MIN - 1e-9 <= speed <= SPEED_MAX + 1e-9):
            raise ValueError(f"speed must be between {SPEED_MIN}× and {SPEED_MAX}×, got {speed}")
        with self.lock:
            self._speed = speed
            position = position_of(speed)
            if abs(self.speed_slider.value - position) > 1e-9:
                self.speed_slider.value = position  # type: ignore[misc]  # viser 1.1.1 types this setter read-only
            if self.speed_slider.label != speed_label(speed):
                self.speed_slider.label = speed_label(speed)

    def switch_to(self, name: str, payload: Any = None) -> None:
        """For scenes: switch to another scene and hand it a payload (see Scene.accept)."""
        self.switch_scene(name, payload=payload)

    # ------------------------------------------------------------------ the state, to copy or restore
    def snapshot(self) -> dict[str, Any]:
        """Everything needed to start another simulation where this one is now.

        The scene, what it was handed (a body from another scene), the values of its controls (by
        label, in order), its own motion state (:meth:`Scene.snapshot`), the time, speed and whether the
        clock runs.
        """
        with self.lock:
            if self.scene is None:
                raise ValueError("there is no scene to copy (it failed to build)")
            return {
                "scene": self.scene.name,
                "payload": self._payload,
                "controls": [(str(h.label), h.value) for h in self._scene_inputs if not h._impl.removed],
                "motion": self.scene.snapshot(),
                "time": self._t,
                "speed": self._speed,
                "playing": self._playing,
            }

    def restore(self, snapshot: dict[str, Any]) -> None:
        """Go to the state :meth:`snapshot` gave (a control whose label differs is left as it is)."""
        with self.lock:
            if self.scene is None or self.scene.name != snapshot["scene"] or snapshot.get("payload") is not None:
                self.switch_scene(snapshot["scene"], payload=snapshot.get("payload"))
            assert self.scene is not None
            self.scene.prepare(snapshot["motion"])
            # Twice: a control that re-applies others (a preset) must not override what followed it.
            for _ in range(2):
                for handle, (label, value) in zip(list(self._scene_inputs), snapshot["controls"], strict=False):
                    if str(handle.label) == label and handle.value != value:
                        handle.value = value  # runs the control's callback: the scene adopts it
            assert self.scene is not None
            self.scene.restore(snapshot["motion"])
            self.set_speed(snapshot["speed"])
            self._t = float(snapshot["time"])
            self.set_playing(snapshot["playing"])
            self._dirty = True

    def close(self) -> None:
        """Remove this simulation's scene, nodes and panel (a browser stops exploring on its own)."""
        with self.lock:
            self._closed = True
            self._teardown()
            for handle in [*self._global_gui, self._grid]:
                try:
                    handle.remove()
                except Exception:  # noqa: BLE001 - its browser may have gone already
                    pass
            self._global_gui = []

    # ------------------------------------------------------------------ scenes
    def switch_scene(self, name: str, payload: Any = None, client: Any = None) -> None:
        """Tear the current scene down and build ``name``; on failure go back to the previous one."""
        if name not in REGISTRY:
            raise ValueError(f"unknown scene {name!r}; choose one of: {', '.join(scene_names())}")
        with self.lock:
            previous = type(self.scene) if self.scene is not None else None
            self._teardown()
            try:
                scene = self._build(REGISTRY[name])
                if payload is not None:
                    scene.accept(payload)
                self._payload = payload
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
            self._switching = True
            try:
                self.scene_picker.value = cls.title  # type: ignore[misc]  # viser 1.1.1 types this setter read-only
            finally:
                self._switching = False
            self.legend.content = draw.legend_html(cls.quantities)
            self.clear_status()  # the status line belongs to the scene
            self.view = cls.camera
            for c in self._clients():
                self._show_scene_to(c, *cls.camera)
            if isinstance(self.server, viser.ViserServer):  # a browser's first view, before it reports its size
                position, look_at = framed(*cls.camera, 1280, 800, FOV)
                self.server.initial_camera.fov = FOV
                self.server.initial_camera.position = position
                self.server.initial_camera.look_at = look_at
            self._t = 0.0
            self._dirty = True

    def _build(self, cls: type[Scene]) -> Scene:
        self.server.scene.add_frame(self.root, show_axes=False)
        self._folder = self.server.gui.add_folder(cls.title)
        scene = cls(self)
        self._building = scene
        inputs = self.server.gui._gui_input_handle_from_uuid
        before = set(inputs)
        try:
            with self._folder:
                if cls.caption:
                    self.server.gui.add_markdown(cls.caption)
                scene.build()
        finally:
            self._building = None
        resend_poses(self.server.scene, self.root)  # browsers keep a replaced node's pose (app.wire)
        # The scene's own adjustable controls (not buttons, not read-only readouts), for snapshot().
        self._scene_inputs = [
            h
            for uuid, h in list(inputs.items())
            if uuid not in before
            and not isinstance(h, (viser.GuiButtonHandle, viser.GuiUploadButtonHandle))
            and hasattr(h._impl.props, "label")  # a control, not a progress bar
            and not getattr(h._impl.props, "disabled", False)
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

    # ------------------------------------------------------------------ the loop
    def frame(self, wall_dt: float = 1.0 / FPS) -> bool:
        """Advance the clock by ``wall_dt`` × speed (if playing) and redraw; True if a frame was drawn."""
        with self.lock:
            self._auto_advance()
            scene = self.scene
            if scene is None or self._closed or self._gone():
                return False
            if self._playing:
                advance = min(max(wall_dt, 0.0), MAX_FRAME_DT) * self._speed
            elif self._steps:
                advance = self._steps * self._speed / self.fps
                self._steps = 0
            else:
                advance = 0.0
            if advance == 0.0 and not self._dirty:
                return False
            t_new = self._t + advance
            try:
                state = scene.compute(t_new, advance)
                check_finite(state)
            except Exception as exc:  # noqa: BLE001 - pause with a message; keep the last valid picture
                self._failed(exc)
                return False
            self._t = t_new
            try:
                with self.server.atomic():
                    scene.draw(state)
                    now = time.monotonic()
                    if now - self._last_time_text > 0.1 or not self._playing:
                        self._last_time_text = now
                        self.time_text.value = f"{self._t:.2f}"  # type: ignore[misc]  # viser 1.1.1 typing
            except Exception as exc:  # noqa: BLE001
                self._failed(exc)
                return False
            self._dirty = False
            self.frames += 1
            self.last_state = state  # what was drawn (the export writes its columns)
            return True

    def _failed(self, exc: Exception) -> None:
        if self._gone():
            return  # its browser left during the frame (viser removed the handles): nothing to report
        traceback.print_exc()
        self._dirty = False
        what = (
            "a numerical failure"
            if isinstance(exc, (NumericalFailure, FloatingPointError, ArithmeticError))
            else "an error"
        )
        self.pause(
            f"{what} at t = {self._t:.3f} s — {type(exc).__name__}: {exc}. The last valid state is shown; "
            "change a parameter or press Reset."
        )


class App(Simulation):
    """The app: the viser server, its simulations and the real-time loop that drives them.

    Three ways to serve. By default every browser sees and drives one shared simulation (the app is that
    simulation: ``app.scene``, ``app.frame(dt)``, ...). In presenter mode (the default on a non-loopback
    host) the app is the lecture: every browser follows it read-only until it enters the PIN, and may
    explore a copy of its own (:mod:`app.presenter`; the copies are in ``app.sessions``). With
    ``private=True`` every browser gets its own :class:`Simulation` when it connects (``app.sessions``,
    by client id), freed when it leaves; the app itself then has no scene.

    Parameters
    ----------
    host, port : str, int
        Where to serve (default http://127.0.0.1:8080).
    scene : str, optional
        Name of the first scene (default: the first in the picker).
    start_loop : bool
        Start the real-time loop thread (tests and the benchmark drive :meth:`frame` themselves).
    verbose : bool
        Let viser print its banner.
    fps : float
        Frames per second of the loop.
    share : bool
        Show viser's share button, which can publish the server on a public tunnel (off by default).
    dark : bool
        The dark look (``--dark``), for a dark lecture room.
    private : bool
        One simulation per browser instead of one for all.
    presenter : bool, optional
        Presenter mode; default: on when ``host`` is not a loopback address and ``private`` is off.
    pin : str, optional
        The presenter PIN (4 to 32 letters or digits); default: six random digits, in ``app.pin``.
    state : str, optional
        A state text (:mod:`app.states`, the panel's "Copy state") to start from; in private mode every
        browser's session starts from it. A bad text raises ValueError before the server starts.
    lecture : str, optional
        A lecture file, by path or by name in ``lectures/`` (:mod:`app.lectures`); every step is checked
        before the server serves (ValueError naming the step and the key). In private mode every browser
        follows it on its own.
    """

    def __init__(
        self,
        host: str = "127.0.0.1",
        port: int = 8080,
        scene: str | None = None,
        *,
        start_loop: bool = True,
        verbose: bool = False,
        fps: float = FPS,
        share: bool = False,
        dark: bool = False,
        private: bool = False,
        presenter: bool | None = None,
        pin: str | None = None,
        state: str | None = None,
        lecture: str | None = None,
    ) -> None:
        if state is not None:
            scene = parse_state(state)["scene"]  # refused here, before anything starts
        self._state_text = state
        self._lecture = read_lecture(lecture) if lecture is not None else None
        first, _ = _first_scene(scene)
        if presenter is None:
            presenter = not private and not is_loopback(host)
        if presenter and private:
            raise ValueError("choose presenter mode or private sessions, not both")
        self.pin = check_pin(pin) if pin is not None else new_pin()
        server = viser.ViserServer(host=host, port=port, verbose=verbose)
        confine_events(server)
        self.host, self.port = host, server.get_port()
        self.private = bool(private)
        self.sessions: dict[Any, Simulation] = {}
        self._sessions_lock = threading.Lock()
        self._stop = threading.Event()
        self._thread: threading.Thread | None = None
        self.classroom: Classroom | None = None
        if presenter:
            self.server = server
            self._share = share
            self.classroom = Classroom(self, self.pin, self._copy_for)
        guard_tunnel(server, share=share, permit=self.refusal)
        if self.private:
            self.server = server
            self.fps, self._first, self._share, self.dark = float(fps), first, share, bool(dark)
            self.lock = threading.RLock()
            self.scene = None
            look.configure(server.gui, share=share, dark=dark)
            if self._lecture is not None:  # checked once, on a simulation nobody sees, before serving
                probe = Simulation(server, first, fps=fps, share=share, dark=dark)
                try:
                    probe.load_lecture(self._lecture)
                except ValueError:
                    server.stop()
                    raise
                finally:
                    probe.close()
            server.on_client_connect(self._open_session)
            server.on_client_disconnect(self._close_session)
        else:
            super().__init__(server, first, fps=fps, share=share, dark=dark)
            try:
                if state is not None:
                    self.open_state(state)
                if self._lecture is not None:
                    self.load_lecture(self._lecture)
            except ValueError:
                server.stop()
                raise
        if start_loop:
            self.start()

    # ------------------------------------------------------------------ presenter mode
    @property
    def mode(self) -> str:
        """ "shared", "presenter" or "private"."""
        return "private" if self.private else ("presenter" if self.classroom is not None else "shared")

    def refusal(self, client_id: Any) -> str | None:
        return self.classroom.refusal(client_id) if self.classroom is not None else None

    def _clients(self) -> list[Any]:
        clients = super()._clients()
        if self.classroom is None:
            return clients
        return [c for c in clients if not self.classroom.exploring(c.client_id)]  # explorers see their copy

    def _copy_for(self, client: viser.ClientHandle) -> Simulation:
        """A browser's own copy of the lecture, at the lecture's current state (presenter mode)."""
        snapshot = self.snapshot()
        copy = Simulation(client, snapshot["scene"], fps=self.fps, share=self._share, dark=self.dark)
        copy.restore(snapshot)
        return copy

    # ------------------------------------------------------------------ private sessions
    def _open_session(self, client: viser.ClientHandle) -> None:
        try:
            session = Simulation(client, self._first, fps=self.fps, share=self._share, dark=self.dark)
            if self._state_text is not None:
                session.open_state(self._state_text)
            if self._lecture is not None:
                session.load_lecture(self._lecture, check=False)
        except Exception:
            if _departed(client):
                return  # it left while its session was being built
            raise
        with self._sessions_lock:
            self.sessions[client.client_id] = session
        if _departed(client):  # it left just now: its disconnect may have come before the line above
            self._close_session(client)

    def _close_session(self, client: viser.ClientHandle) -> None:
        # The browser has gone: its panel and nodes went with its connection; drop the simulation.
        with self._sessions_lock:
            self.sessions.pop(client.client_id, None)

    def simulations(self) -> list[Simulation]:
        """The simulations the loop drives: the shared one, or one per connected browser."""
        with self._sessions_lock:
            own = list(self.sessions.values())
        return own if self.private else [self, *own]

    # ------------------------------------------------------------------ the loop
    def start(self) -> None:
        """Start the real-time loop thread (daemon), and compile the integrators' kernels beside it."""
        if self._thread is not None:
            return
        from physics.integrators.warm import warm

        # numba compiles (or loads from its cache) in the background: a scene's first step never waits.
        threading.Thread(target=warm, name="rbl-warm-kernels", daemon=True).start()
        self._stop.clear()
        self._thread = threading.Thread(target=self._run, name="rbl-loop", daemon=True)
        self._thread.start()

    def _run(self) -> None:
        period = 1.0 / self.fps
        last = time.perf_counter()
        while not self._stop.is_set():
            now = time.perf_counter()
            dt, last = now - last, now
            self._tick(dt)
            busy = time.perf_counter() - now
            # Under load (many private sessions) a tick takes longer than a frame: each session then
            # advances by the real elapsed time (the physics is exact at any step), and the loop leaves
            # the GIL to the network thread for a share of its own time, so that what was drawn is sent.
            self._stop.wait(max(period - busy, NETWORK_SHARE * busy))

    def _tick(self, dt: float) -> None:
        """One frame of every simulation. A function of its own so that its loop variable dies with it: in
        ``_run`` it outlived the tick and kept the last session of a departed browser alive (never collected)
        until another browser came."""
        for simulation in self.simulations():
            try:
                simulation.frame(dt)
            except Exception:  # noqa: BLE001 - the loop never dies, and one session cannot stop another
                traceback.print_exc()

    def stop(self) -> None:
        """Stop the loop and the server."""
        self._stop.set()
        if self._thread is not None:
            self._thread.join(timeout=2.0)
            self._thread = None
        self.server.stop()

    @property
    def url(self) -> str:
        return f"http://{self.host}:{self.port}"
