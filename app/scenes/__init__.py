"""Scenes of Rigid Body Lab: the Scene base class, the context a scene gets, and the registry.

How to add a scene
==================
Write one short module in ``app/scenes/`` (it is found automatically: every module in this package is
imported by :func:`load_all`) that composes the shared pieces of :mod:`app.draw` and :mod:`app.controls`
with one physics model::

    import numpy as np
    import trimesh
    from app import controls, draw
    from app.scenes import Scene, register

    @register
    class Spinner(Scene):
        name = "spinner"                 # id for --scene and the registry
        title = "A spinning rod"         # shown in the scene picker
        order = 50                       # position in the picker (smaller first)
        quantities = ("L", "omega")      # legend entries (keys of app.draw.COLOURS)
        caption = "**A rod** spinning: L = I ω."   # markdown, Unicode maths (no LaTeX)
        camera = ((2.5, -2.5, 1.8), (0.0, 0.0, 0.3))   # initial camera position, look-at (m)

        def build(self) -> None:
            # 3D nodes: ALWAYS name them under self.ctx.root (removed together on a scene switch).
            server = self.ctx.server
            self.body = draw.BodyMesh(server, self.ctx.root + "/body", trimesh.creation.cylinder(0.05, 1))
            self.omega_arrow = draw.Arrow(server, self.ctx.root + "/omega", "omega", scale=0.1)
            # GUI: anything added inside build() lands in this scene's folder (removed on switch).
            self.params = controls.ParameterPanel(self.ctx, [
                controls.SliderSpec("rate", "spin ω (rad/s)", 0.0, 20.0, 0.1, 5.0),
            ], apply=self.apply)
            self.rate_readout = controls.Readout(self.ctx, "period (s)")
            self.apply(self.params.values)

        def apply(self, values: dict[str, float]) -> None:
            # Called with a candidate set of slider values. Raise ValueError (with a message a student
            # understands) to REFUSE it: the slider snaps back, the user gets a notification, and the
            # last valid state stays. Otherwise adopt it (build the model) and usually restart.
            self.model = make_model(values["rate"])      # may raise ValueError
            self.ctx.restart()                            # t = 0, traces cleared, redraw

        def compute(self, t: float, dt: float) -> dict:
            # The state at simulation time t (dt = time advanced since the last frame, 0 when paused).
            # Do NOT touch handles here. Every float/array in the returned dict is checked for NaN/inf
            # before draw(); a non-finite value (or an exception) pauses the scene with a message and
            # the last drawn state stays. A stepping model returns its new internal state here and
            # adopts it in draw().
            R = self.model.attitude(t)
            return {"R": R, "omega": R @ self.model.omega}

        def draw(self, state: dict) -> None:
            # Update the kept handles in place (the server wraps this in server.atomic()).
            self.body.set_pose(state["R"])
            self.omega_arrow.set(state["omega"])
            self.rate_readout.set(2 * np.pi / self.model.rate)

Hooks in :class:`Scene` (all optional except ``build``, ``compute`` and ``draw``): ``reset()`` (the
clock's reset: go back to t = 0 with the current parameters; the default clears ``self.traces``),
``teardown()`` (release anything that is not a scene node under ``ctx.root`` nor GUI in the folder),
``columns(state)`` (the quantities an export writes to its CSV), ``accept(payload)`` (another scene hands over a body: e.g. the inertia explorer's "Spin it" calls
``ctx.switch_to("wobble", payload=...)``), ``snapshot()`` / ``prepare(motion)`` / ``restore(motion)`` (copy the
scene into another simulation: what the time and the controls do not give, what the controls refer to,
then the stepped state).

Time. Closed-form models evaluate the state at the absolute time ``t`` (exact, no drift, any speed);
a stepping model (friction) advances its own state by ``dt`` and must not mutate it in ``compute``.
The clock's single step advances ``speed/60`` s; a parameter change usually calls ``ctx.restart()``.

Colours. Use the quantity keys of ``app.draw.COLOURS`` (Okabe–Ito: L orange, ω blue, τ reddish purple,
trace vermillion, body cone bluish green, space cone sky blue, principal axes black, ...) and list them in ``quantities`` for the legend;
add a new key to COLOURS/LABELS rather than a one-off colour.

Tests. ``tests/harness.py`` has ``running_app``, ``open_page``, ``nudge_slider``, ``wait_for``,
``image_stats``; ``tests/conftest.py`` has the module-scoped ``chromium`` and ``live_app`` fixtures.

Callbacks. Sliders made with :mod:`app.controls` are already guarded. For any raw viser callback use
``@self.ctx.guarded`` (or ``handle.on_click(self.ctx.guarded(fn))``): it runs under the simulation lock,
shows any exception to the user as a notification (viser would otherwise swallow it), and asks for a
redraw. Callbacks only change parameters; the server's loop is the only place that moves the handles.

What the context offers (:class:`SceneContext`): ``server`` (the viser server), ``root`` (scene-node
prefix), ``lock``, ``guarded``, ``notify(title, body, client=None, error=False)``, ``restart()``,
``request_redraw()``, ``time`` (simulation time, s), ``playing``, ``pause(reason)``, ``switch_to(name,
payload=None)``.
"""

from __future__ import annotations

import importlib
import pkgutil
import threading
from collections.abc import Callable
from typing import Any, ClassVar, Protocol

__all__ = ["Scene", "SceneContext", "register", "REGISTRY", "load_all", "scene_names"]


class SceneContext(Protocol):
    """What a scene may use from the server (implemented by :class:`app.server.App`'s context)."""

    server: Any  # viser.ViserServer
    root: str
    lock: threading.RLock

    @property
    def time(self) -> float: ...

    @property
    def playing(self) -> bool: ...

    def guarded(self, fn: Callable[..., Any]) -> Callable[..., Any]: ...

    def notify(self, title: str, body: str, client: Any = None, error: bool = False) -> None: ...

    def restart(self) -> None: ...

    def clear_status(self) -> None: ...

    def request_redraw(self) -> None: ...

    def pause(self, reason: str | None = None) -> None: ...

    def switch_to(self, name: str, payload: Any = None) -> None: ...

    def refusal(self, client_id: Any) -> str | None:
        """Why this browser may not drive the simulation (presenter mode's followers), or None."""
        ...

    def set_time(self, t: float) -> None: ...

    def set_playing(self, playing: bool) -> None: ...


class Scene:
    """Base class of a scene: one section of the lecture, one physics model, shared drawing pieces.

    Subclasses set the class attributes and implement :meth:`build`, :meth:`compute`, :meth:`draw`.
    See the module docstring for a complete example.
    """

    name: ClassVar[str] = ""
    title: ClassVar[str] = ""
    order: ClassVar[int] = 100
    quantities: ClassVar[tuple[str, ...]] = ()
    caption: ClassVar[str] = ""
    camera: ClassVar[tuple[tuple[float, float, float], tuple[float, float, float]]] = (
        (3.0, -3.0, 2.0),
        (0.0, 0.0, 0.5),
    )

    def __init__(self, ctx: SceneContext) -> None:
        self.ctx = ctx
        self.traces: list[Any] = []  # app.draw.Trace objects cleared by reset()/restart()

    def build(self) -> None:
        """Create the scene nodes (under ``ctx.root``) and the GUI (lands in the scene's folder)."""
        raise NotImplementedError

    def compute(self, t: float, dt: float) -> dict[str, Any]:
        """The state at simulation time ``t`` (s); ``dt`` (s) is the time advanced since the last frame."""
        raise NotImplementedError

    def draw(self, state: dict[str, Any]) -> None:
        """Update the kept handles from ``state`` (inside ``server.atomic()``)."""
        raise NotImplementedError

    def reset(self) -> None:
        """Back to t = 0 with the current parameters (the clock's reset and ``ctx.restart()``)."""
        for trace in self.traces:
            trace.clear()

    def teardown(self) -> None:
        """Release what is not a node under ``ctx.root`` or GUI in the scene folder (default: nothing)."""

    def columns(self, state: dict[str, Any]) -> dict[str, float]:
        """The scene's quantities at a state :meth:`compute` gave, for the export's CSV: header (symbol and
        SI unit, e.g. ``"theta (rad)"``) to value, in column order (:mod:`app.columns`). Default: none."""
        return {}

    def snapshot(self) -> dict[str, Any]:
        """The motion state that the time and the controls do not give (a stepping model's state), to copy
        the scene into another simulation (default: nothing; closed-form models need only the time)."""
        return {}

    def prepare(self, motion: dict[str, Any]) -> None:
        """Before a snapshot's controls are set: adopt what they refer to (an uploaded body the Body
        dropdown names), from the state :meth:`snapshot` gave (default: nothing)."""

    def restore(self, motion: dict[str, Any]) -> None:
        """Adopt a state :meth:`snapshot` gave, after its controls are set (default: nothing to adopt)."""

    def accept(self, payload: Any) -> None:
        """Take a body handed over by another scene (default: refuse)."""
        raise ValueError(f"the scene {self.title!r} cannot take a body from another scene")


REGISTRY: dict[str, type[Scene]] = {}


def register(cls: type[Scene]) -> type[Scene]:
    """Class decorator: add a scene to :data:`REGISTRY` under ``cls.name``."""
    if not cls.name or not cls.title:
        raise ValueError(f"{cls.__name__} needs a name and a title to be registered")
    if cls.name in REGISTRY and REGISTRY[cls.name] is not cls:
        raise ValueError(f"two scenes are named {cls.name!r}: {REGISTRY[cls.name].__name__} and {cls.__name__}")
    REGISTRY[cls.name] = cls
    return cls


def load_all() -> dict[str, type[Scene]]:
    """Import every module of this package (each registers its scenes) and return the registry."""
    for info in pkgutil.iter_modules(__path__):
        if not info.name.startswith("_"):
            importlib.import_module(f"{__name__}.{info.name}")
    return REGISTRY


def scene_names() -> list[str]:
    """Registered scene names in picker order."""
    load_all()
    return [c.name for c in sorted(REGISTRY.values(), key=lambda c: (c.order, c.title))]
