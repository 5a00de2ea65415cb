"""The Scene base class, the context a scene is given, and the registry scenes join with ``@register``.

How to write a scene, with a complete example: docs/architecture.md ("Adding a scene").
"""

from __future__ import annotations

from collections.abc import Iterable
from dataclasses import dataclass
from typing import TYPE_CHECKING, Any, ClassVar

from app.contracts import SceneContext
from app.language.words import say
from physics.events import MotionEvent, events_between
from physics.free_body_trajectory import FreeBodyTrajectory
from physics.heavy_top import HeavyTopTrajectory
from physics.pendulum import PendulumTrajectory

if TYPE_CHECKING:
    from app.panel.parameters import ParameterPanel, Presets

__all__ = ["Answer", "Scene", "SceneContext", "register", "REGISTRY"]


@dataclass(frozen=True)
class Answer:
    """What of a scene states or shows one of its quantities: held back while a class question about that
    quantity is open (:meth:`Scene.hold`), shown again at the reveal.

    Each name is an attribute path of the scene (``"params.sliders.phidot0"``: attributes, then dict keys).

    Attributes
    ----------
    quantity : str
        The quantity a lecture's question asks about (a step's ``truth``, or its ``about``).
    readouts : tuple of str
        Readouts (anything with ``hold(bool)``, e.g. :class:`app.panel.parameters.Readout`) that state it:
        they say it is held back instead.
    hidden : tuple of str
        Scene nodes, labels, plots, sliders or markdown (anything with ``visible``) hidden meanwhile; the
        scene's caption in the panel is ``"caption_markdown"``.
    """

    quantity: str
    readouts: tuple[str, ...] = ()
    hidden: tuple[str, ...] = ()


def _resolve(scene: Scene, path: str) -> Any:
    """The object at an attribute path of ``scene`` (dots: attributes, then dict keys), or None."""
    obj: Any = scene
    for part in path.split("."):
        obj = obj.get(part) if isinstance(obj, dict) else getattr(obj, part, None)
        if obj is None:
            return None
    return obj


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
    view: ClassVar[tuple[float, float] | None] = None
    """Width and height (m), across the camera's look-at point, of what the scene must show: each browser's
    camera comes as close as lets it fill the part of the view the panel leaves free
    (:func:`app.serving.framing.framed`); None: the camera's own distance."""
    static: ClassVar[bool] = False
    """A still picture with nothing that moves in time (the inertia explorer): its clock stays paused at 0."""
    answers: ClassVar[tuple[Answer, ...]] = ()
    """The quantities a class question may ask about, and what of the scene states each (:class:`Answer`)."""
    key_plot: ClassVar[str] = ""
    """Attribute path of the scene's key plot (a viser uPlot handle; ``""``: none), shown large in projector
    mode (:mod:`app.panel.projector`): the evidence the class reads, e.g. the racket's ω₁ω₂ω₃."""
    params: ParameterPanel | None = None
    """The scene's parameter sliders, each under its stable key (``params.sliders["spin"]``), or None: what
    a lecture step's ``values`` set, and what names a slider in a state text."""
    presets: Presets | None = None
    """Its named presets of those sliders (a lecture step's ``preset``), or None."""

    def __init__(self, ctx: SceneContext) -> None:
        self.ctx = ctx
        self.traces: list[Any] = []  # app.draw.Trace objects cleared by reset()/restart()
        self.held: frozenset[str] = frozenset()  # quantities held back while a question about them is open
        self.caption_markdown: Any = None  # the caption in the panel (the simulation sets it)
        self._shown_before: dict[str, bool] = {}  # what a hidden element's visibility was before

    def truth(self, quantity: str) -> float:
        """The true value, in SI units, of one of its :attr:`answers` as the scene stands (a lecture's number
        question with ``truth = quantity``).

        Raises
        ------
        ValueError
            The scene gives no value for ``quantity``.
        """
        raise ValueError(f"{self.name} gives no true value for {quantity!r}")

    def control_key(self, control: object) -> str:
        """The name a state text gives one of the scene's controls: a parameter slider's stable key
        (``"spin"``), which rewording its label does not change; any other control's label."""
        if self.params is not None:
            for key, slider in self.params.sliders.items():
                if slider is control:
                    return key
        return str(getattr(control, "label", ""))

    def key_plot_handle(self) -> Any:
        """The scene's key plot (:attr:`key_plot`), or None."""
        return _resolve(self, self.key_plot) if self.key_plot else None

    def hold(self, quantities: Iterable[str]) -> None:
        """Hold back what states ``quantities`` (names of :attr:`answers`) and show again what states the
        others: readouts say they are held back, declared nodes are hidden; :meth:`describe` leaves them out.

        Raises
        ------
        ValueError
            A quantity the scene does not declare (the names it declares are listed).
        """
        wanted = frozenset(quantities)
        declared = {a.quantity for a in self.answers}
        if not wanted <= declared:
            unknown = sorted(wanted - declared)[0]
            raise ValueError(
                f"the scene {self.title!r} declares no answer {unknown!r}; it declares {sorted(declared) or 'none'}"
            )
        for answer in self.answers:
            held = answer.quantity in wanted
            for path in answer.readouts:
                readout = _resolve(self, path)
                if readout is not None:
                    readout.hold(held)
            for path in answer.hidden:
                node = _resolve(self, path)
                if node is None:
                    continue
                if held and path not in self._shown_before:
                    self._shown_before[path] = bool(node.visible)
                    node.visible = False
                elif not held and path in self._shown_before:
                    node.visible = self._shown_before.pop(path)
        self.held = wanted

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

    def earliest(self) -> float:
        """The earliest time the timeline can go back to, s (default 0: an exact motion from its start)."""
        return 0.0

    def rewind(self, t: float) -> None:
        """The clock jumped to ``t`` (s), back or ahead (the timeline): every piece that keeps a past forgets
        what it drew after ``t``. A piece with ``rewind(t)`` (a time plot, a trace, an integrator's ghost)
        keeps what came before ``t``; the other :attr:`traces` start again from ``t``."""
        pieces: dict[int, Any] = {id(p): p for p in self.traces}
        pieces.update((id(p), p) for p in vars(self).values() if callable(getattr(p, "rewind", None)))
        for piece in pieces.values():
            rewind = getattr(piece, "rewind", None)
            if callable(rewind):
                rewind(t)
            else:
                piece.clear()

    def events(self, t0: float, t1: float) -> list[MotionEvent]:
        """The motion's events in ``[t0, t1]`` (s of the clock), from its exact solution
        (:func:`physics.events.events_between`): the flip's half-turns, the nutation's turning points, the
        swing's. Default: those of the scene's ``motion`` when it is an exact trajectory; none otherwise."""
        motion = getattr(self, "motion", None)
        if isinstance(motion, (FreeBodyTrajectory, HeavyTopTrajectory, PendulumTrajectory)):
            return events_between(motion, t0, t1)
        return []

    def vectors(self, state: dict[str, Any]) -> dict[str, Any]:
        """The drawn directions at a state :meth:`compute` gave, by name (``"L"``, ``"ω"``,
        ``"symmetry axis"``; the vertical is added by the measure), each shape (3,) in space, for the angle
        between two of them. Default: from the state's ``L``, ``omega``/``omega_space`` and ``axis`` (or the
        attitude's third column); a scene with other names overrides it."""
        found: dict[str, Any] = {}
        R = state.get("R")
        L = state.get("L", getattr(self, "L_space", None))  # a torque-free body's L is fixed in space
        if L is not None:
            found["L"] = L
        omega = state.get("omega", state.get("omega_space"))
        if omega is not None:
            found["ω"] = omega
        if "axis" in state:
            found["symmetry axis"] = state["axis"]
        elif R is not None:
            found["symmetry axis"] = R[:, 2]
        return found

    def teardown(self) -> None:
        """Release what is not a node under ``ctx.root`` or GUI in the scene folder (default: nothing)."""

    def columns(self, state: dict[str, Any]) -> dict[str, float]:
        """The scene's quantities at a state :meth:`compute` gave, for the export's CSV: header (symbol and
        SI unit, e.g. ``"theta (rad)"``) to value, in column order (:mod:`app.recording.columns`). Default: none."""
        return {}

    def describe(self, state: dict[str, Any]) -> str:
        """The motion in one sentence with its numbers and units (:mod:`app.scenes.wording`), at a state
        :meth:`compute` gave: what a screen reader announces in place of the 3D view. Default: the title."""
        return say("{title}.", title=self.title)

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
