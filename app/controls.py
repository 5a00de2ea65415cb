"""Shared GUI pieces: labelled sliders with a validation hook, readouts, a presets dropdown, a gauge.

All of them are made inside a scene's ``build()`` so they land in the scene's folder, and all of their
callbacks run through ``ctx.guarded`` (under the simulation lock; an exception is shown to the user).

:class:`ParameterPanel` is the heart of "bad input is refused": a slider change is offered to the
scene's ``apply(values)`` as a *candidate* set of values; if ``apply`` raises (``ValueError`` for an
impossible body, or any other exception) the slider snaps back to the last accepted value, the user who
moved it gets a notification saying why, and the model, the clock and the panel stay exactly as they
were (:class:`Rollback`: what ``apply`` assigned, the scene's motion state, every control and text of
the scene's folder, the time; side effects beyond those are redone by applying the accepted values again).
"""

from __future__ import annotations

import math
from collections.abc import Callable
from dataclasses import dataclass
from typing import Any

import numpy as np
import viser
from viser import _messages

__all__ = [
    "SliderSpec",
    "ParameterPanel",
    "Readout",
    "Presets",
    "Gauge",
    "refusable_dropdown",
    "InvariantDrift",
    "Rollback",
]


@dataclass(frozen=True)
class SliderSpec:
    """One parameter slider: key in the values dict, label with units, range, step and initial value."""

    key: str
    label: str
    min: float
    max: float
    step: float
    initial: float
    hint: str | None = None


class ParameterPanel:
    """A group of sliders whose values are accepted or refused together by ``apply(values)``.

    Parameters
    ----------
    ctx : SceneContext
    specs : list of SliderSpec
    apply : callable(dict[str, float]) -> None
        Adopts a candidate set of values; raises ``ValueError`` to refuse it (the message is shown).
    """

    def __init__(self, ctx: Any, specs: list[SliderSpec], apply: Callable[[dict[str, float]], None]) -> None:
        self.ctx = ctx
        self._apply = apply
        self.values: dict[str, float] = {s.key: float(s.initial) for s in specs}
        self.last_refusal: Exception | None = None  # why the last offer was refused (a lecture step reports it)
        self.sliders: dict[str, Any] = {}
        self._syncing = False
        self.refusals = 0  # how many changes were refused (tests and the status line read it)
        self.listeners: list[Callable[[dict[str, float]], None]] = []  # told of every accepted change
        for spec in specs:
            handle = ctx.server.gui.add_slider(
                spec.label, min=spec.min, max=spec.max, step=spec.step, initial_value=spec.initial, hint=spec.hint
            )
            handle.on_update(ctx.guarded(self._on_slider(spec.key)))
            self.sliders[spec.key] = handle

    def _on_slider(self, key: str) -> Callable[[Any], None]:
        def on_update(event: Any) -> None:
            if self._syncing:
                return
            value = float(self.sliders[key].value)
            if value == self.values[key]:
                return
            self.offer({key: value}, client=getattr(event, "client", None))

        return on_update

    def offer(self, changes: dict[str, float], client: Any = None) -> bool:
        """Offer new values (some keys); returns True if accepted. Refused: notify, snap sliders back.

        Transactional: whatever ``apply`` raises, of any type, everything is put back as it was
        (:class:`Rollback`): the scene's attributes, its motion state, the controls and texts of its
        folder, the clock's time; the sliders show the last accepted values, and Reset still works.
        """
        with self.ctx.lock:
            try:
                candidate = {**self.values, **{k: self._number(k, v) for k, v in changes.items()}}
            except Exception as exc:  # noqa: BLE001 - a value that is no number of the range: refused
                self.refuse(exc, client)
                return False
            rollback = Rollback(self.ctx, getattr(self._apply, "__self__", None), self._folder(), self._accepted())
            try:
                self._apply(candidate)
            except Exception as exc:  # noqa: BLE001 - any failure refuses the change, none escapes
                rollback.restore(lambda: self._apply(dict(self.values)))
                self.refuse(exc, client)
                return False
            self.values = candidate
            self._sync(candidate)
            for listener in self.listeners:
                listener(candidate)
            self.ctx.request_redraw()
            clear = getattr(self.ctx, "clear_status", None)
            if clear is not None:
                clear()
            return True

    def _folder(self) -> Any:
        """The container the sliders are in (the scene's folder): what a refused change restores."""
        first = next(iter(self.sliders.values()), None)
        if first is None:
            return None
        gui = first._impl.gui_api
        return gui._container_handle_from_uuid.get(first._impl.parent_container_id)

    def _accepted(self) -> dict[str, Any]:
        """The values in force of the controls a browser may have changed just now (uuid -> value): the
        sliders' accepted values and the accepted choices of refusable dropdowns."""
        accepted = {h._impl.uuid: self.values[key] for key, h in self.sliders.items()}
        folder = self._folder()
        for uuid, value in getattr(folder, "_rbl_choices", {}).items():
            accepted[uuid] = value["value"]
        return accepted

    def refuse(self, exc: Exception, client: Any = None) -> None:
        """Tell the browser that asked why its change was refused, and show the values in force."""
        self.refusals += 1
        self.last_refusal = exc
        if isinstance(exc, ValueError):
            title, text = "Refused: that is not a possible body", str(exc)
        else:
            title, text = "Refused: the scene could not take these values", f"{type(exc).__name__}: {exc}"
        self.ctx.notify(title, text, client=client, error=True)
        self._sync(self.values)

    def _number(self, key: str, value: Any) -> float:
        """A candidate value for slider ``key``: a finite number (its slider's range is the browser's limit)."""
        if key not in self.sliders:
            raise ValueError(f"there is no parameter {key!r}; the parameters are {', '.join(self.sliders)}")
        if isinstance(value, bool) or not isinstance(value, (int, float)):
            raise ValueError(f"{key} must be a number, got {type(value).__name__}")
        try:
            number = float(value)
        except OverflowError:
            raise ValueError(f"{key} must be a finite number, got an integer of {len(str(value))} digits") from None
        if not math.isfinite(number):
            raise ValueError(f"{key} must be a finite number, got {value}")
        slider = self.sliders[key]
        low, high = float(slider.min), float(slider.max)
        slack = 1e-9 * (high - low)
        if not low - slack <= number <= high + slack:
            raise ValueError(f"{key} must be between {low:g} and {high:g}, got {number:g}")
        return number

    def _sync(self, values: dict[str, float]) -> None:
        # Setting .value from Python runs the callbacks synchronously: suppress them while syncing.
        self._syncing = True
        try:
            for key, handle in self.sliders.items():
                if handle.value != values[key]:
                    handle.value = values[key]
        finally:
            self._syncing = False


class Readout:
    """A read-only number with a label and units, rewritten only when its text changes.

    Every number in the panel has four significant digits (``fmt``'s default) and its unit in the label.
    """

    def __init__(self, ctx: Any, label: str, fmt: str = "{:.4g}", hint: str | None = None) -> None:
        self.fmt = fmt
        self.handle = ctx.server.gui.add_text(label, initial_value="—", disabled=True, hint=hint)

    @property
    def text(self) -> str:
        return self.handle.value

    def set(self, value: float | str) -> None:
        if isinstance(value, str):
            text = value
        elif not math.isfinite(value):
            text = "∞" if value > 0 else ("−∞" if value < 0 else "—")
        else:
            text = self.fmt.format(value)
        if self.handle.value != text:
            self.handle.value = text


class Presets:
    """A dropdown of named presets; choosing one offers its values to a :class:`ParameterPanel`.

    ``presets`` maps a name to a dict of values or to a callable returning one (computed from the
    current values, e.g. a steady-precession rate). The first entry, ``"—"``, does nothing.
    ``renamed`` maps a preset's former names to its name now, so lectures, state texts and export
    commands written with an old name keep working.
    """

    NONE = "— choose a preset —"

    def __init__(
        self,
        ctx: Any,
        panel: ParameterPanel,
        presets: dict[str, dict[str, float] | Callable[[dict[str, float]], dict[str, float]]],
        label: str = "Preset",
        renamed: dict[str, str] | None = None,
    ) -> None:
        self.panel = panel
        self.presets = presets
        self.renamed = dict(renamed or {})
        self.handle = ctx.server.gui.add_dropdown(label, options=(self.NONE, *presets.keys()), initial_value=self.NONE)
        self.handle.on_update(ctx.guarded(self._chosen))
        self.last: str | None = None
        self._chosen_values: dict[str, float] = {}
        self._choosing = False
        panel.listeners.append(self._values_changed)

    def _values_changed(self, values: dict[str, float]) -> None:
        """A slider moved away from the chosen preset: the dropdown no longer names it."""
        if self._choosing or self.last is None or values == self._chosen_values:
            return
        self.last = None
        self._show(self.NONE)

    def _show(self, name: str) -> None:
        """Set the dropdown without choosing (setting a value from Python runs its callbacks at once)."""
        if self.handle.value != name:
            self._choosing = True
            try:
                self.handle.value = name
            finally:
                self._choosing = False

    def _chosen(self, event: Any) -> None:
        name = self.handle.value
        if name == self.NONE or self._choosing:
            return
        self.choose(name, client=getattr(event, "client", None))

    def resolve(self, name: str) -> str | None:
        """The preset's name now (a former name is taken too), or None if there is no such preset."""
        name = self.renamed.get(name, name)
        return name if name in self.presets else None

    def choose(self, name: str, client: Any = None) -> bool:
        """Apply a preset by name (or a former name); returns True if accepted."""
        name = self.renamed.get(name, name)
        preset = self.presets[name]
        try:
            # A computed preset (e.g. a steady-precession rate) may not exist for the current body.
            values = preset(dict(self.panel.values)) if callable(preset) else preset
        except Exception as exc:  # noqa: BLE001 - of any type: refused, the dropdown shows the last one
            self.panel.refuse(exc, client)
            self._show(self.last or self.NONE)
            return False
        self._choosing = True
        try:
            ok = self.panel.offer(values, client=client)
        finally:
            self._choosing = False
        if ok:
            self.last, self._chosen_values = name, dict(self.panel.values)
        self._show(name if ok else (self.last or self.NONE))  # a refused preset is not shown as chosen
        return ok


class Gauge:
    """A value against a threshold: a bar filled to ``value / (2 threshold)`` (the threshold at half),
    blue above the threshold and orange below, with a line of text."""

    def __init__(self, ctx: Any, label: str) -> None:
        self.text = ctx.server.gui.add_markdown(label)
        self.label = label
        self.bar = ctx.server.gui.add_progress_bar(0.0, color="orange")
        self._last: tuple[float, str] | None = None

    def set(self, value: float, threshold: float, text: str) -> None:
        fill = 100.0 * min(max(value / (2.0 * threshold), 0.0), 1.0) if threshold > 0 else 0.0
        colour = "blue" if value > threshold else "orange"  # not green/red: told apart by every eye
        key = (round(fill, 1), colour + text)
        if key == self._last:
            return
        self._last = key
        self.bar.value = fill
        self.bar.color = colour
        self.text.content = f"{self.label}  \n{text}"


def refusable_dropdown(
    ctx: Any,
    label: str,
    options: tuple[str, ...],
    initial: str,
    *,
    apply: Callable[[], bool | None],
) -> Any:
    """A dropdown whose choice is offered to ``apply()`` (which reads the dropdown's new value).

    ``apply`` refuses the choice by returning ``False`` (e.g. :meth:`ParameterPanel.offer`, which has
    already told the browser why and put everything back) or by raising any exception (the browser that
    chose is told here). A refused choice snaps back to the last accepted one. Returns the viser handle.
    """
    handle = ctx.server.gui.add_dropdown(label, options=options, initial_value=initial)
    accepted = {"value": initial}
    # The accepted choice, for a ParameterPanel.offer of the same folder that is refused while the
    # dropdown already shows the new one (its Rollback puts the accepted one back before re-applying).
    gui = handle._impl.gui_api
    folder = gui._container_handle_from_uuid.get(handle._impl.parent_container_id)
    if folder is not None:
        if not hasattr(folder, "_rbl_choices"):
            folder._rbl_choices = {}
        folder._rbl_choices[handle._impl.uuid] = accepted

    def on_update(event: Any) -> None:
        value = handle.value
        if value == accepted["value"]:
            return  # includes the snap-back below, which runs this callback again
        try:
            ok = apply()
        except Exception as exc:  # noqa: BLE001 - of any type: refused, the dropdown snaps back
            text = str(exc) if isinstance(exc, ValueError) else f"{type(exc).__name__}: {exc}"
            ctx.notify("Refused", text, client=getattr(event, "client", None), error=True)
            ok = False
        if ok is False:
            handle.value = accepted["value"]
        else:
            accepted["value"] = value

    handle.on_update(ctx.guarded(on_update))
    return handle


class Rollback:
    """What a scene's ``apply`` may change, taken before it runs, and put back if it raises.

    Parameters
    ----------
    ctx : SceneContext
        Its clock (``time``, ``playing``; ``set_time``, ``set_playing``) is put back.
    owner : object or None
        The scene whose ``apply`` runs: its attributes (by reference) and its motion state
        (``snapshot()``/``restore()``).
    folder : viser container or None
        Every control and text in it (and in folders within it): their properties and values.
    accepted : dict
        uuid -> the value in force, for the controls a browser has just changed (what they show back).

    :meth:`restore` puts all of it back. If ``apply`` had changed anything before it raised, the accepted
    values are applied again first (``reapply``), so that side effects beyond the attributes and the
    panel (a mesh sent, a ghost restarted) match them too; then the attributes, motion, panel and clock
    are put back exactly. The trail drawn so far may be restarted; the state is not.
    """

    def __init__(self, ctx: Any, owner: Any, folder: Any, accepted: dict[str, Any]) -> None:
        self.ctx, self.owner = ctx, owner
        self.attributes = dict(vars(owner)) if owner is not None else {}
        self.motion = _call(owner, "snapshot")
        self.clock = (getattr(ctx, "time", None), getattr(ctx, "playing", None))
        self.accepted = accepted
        self.panel = [(h, _props(h), accepted.get(h._impl.uuid, _value(h))) for h in _handles(folder)]

    def changed(self) -> bool:
        """Whether anything taken was changed (a control a browser set just now aside)."""
        if self.owner is not None:
            now = vars(self.owner)
            if now.keys() != self.attributes.keys() or any(now[k] is not v for k, v in self.attributes.items()):
                return True
        if (getattr(self.ctx, "time", None), getattr(self.ctx, "playing", None)) != self.clock:
            return True
        for handle, props, value in self.panel:
            if handle._impl.removed:
                continue
            if any(_differs(getattr(handle._impl.props, k), v) for k, v in props.items()):
                return True
            if handle._impl.uuid not in self.accepted and _differs(_value(handle), value):
                return True
        return False

    def restore(self, reapply: Callable[[], object]) -> None:
        """Put everything back; ``reapply`` applies the accepted values (run only if something changed)."""
        changed = self.changed()
        self._attributes()
        self._panel()
        if changed:
            try:
                reapply()
            except Exception:  # noqa: BLE001 - it may fail as the candidate did: what follows puts it back
                pass
            self._attributes()
            if self.motion is not None:
                _call(self.owner, "restore", self.motion)
            self._panel()
        time, playing = self.clock
        if time is not None and getattr(self.ctx, "time", time) != time and hasattr(self.ctx, "set_time"):
            self.ctx.set_time(time)
        if (
            playing is not None
            and getattr(self.ctx, "playing", playing) != playing
            and hasattr(self.ctx, "set_playing")
        ):
            self.ctx.set_playing(playing)

    def _attributes(self) -> None:
        if self.owner is not None:
            vars(self.owner).clear()
            vars(self.owner).update(self.attributes)

    def _panel(self) -> None:
        """Every control and text as taken, without running a control's callbacks."""
        for handle, props, value in self.panel:
            if handle._impl.removed:
                continue
            for name, old in props.items():
                if _differs(getattr(handle._impl.props, name), old):
                    setattr(handle, name, old)  # viser sends the property to every browser
            if value is not _NO_VALUE and _differs(_value(handle), value):
                handle._impl.value = value
                handle._impl.gui_api._websock_interface.queue_message(
                    _messages.GuiUpdateMessage(handle._impl.uuid, {"value": value})
                )


_NO_VALUE = object()


def _handles(container: Any) -> list[Any]:
    """The GUI handles in a container and in the containers within it."""
    found: list[Any] = []
    for child in list(getattr(container, "_children", {}).values()):
        if getattr(getattr(child, "_impl", None), "props", None) is not None:
            found.append(child)
        found.extend(_handles(child))
    return found


def _props(handle: Any) -> dict[str, Any]:
    return {k: v.copy() if isinstance(v, np.ndarray) else v for k, v in vars(handle._impl.props).items()}


def _value(handle: Any) -> Any:
    impl = handle._impl
    return _NO_VALUE if getattr(impl, "is_button", False) or not hasattr(impl, "value") else impl.value


def _differs(a: Any, b: Any) -> bool:
    if a is b:
        return False
    if isinstance(a, np.ndarray) or isinstance(b, np.ndarray):
        return not (isinstance(a, np.ndarray) and isinstance(b, np.ndarray) and np.array_equal(a, b))
    try:
        return not bool(a == b)
    except (TypeError, ValueError):  # tuples of arrays (a plot's data): not the same object, so changed
        return True


def _call(owner: Any, name: str, *args: Any) -> Any:
    """``owner.name(*args)`` if the owner has it (a Scene's snapshot/restore), else None."""
    method = getattr(owner, name, None)
    return method(*args) if callable(method) else None


DRIFT_EVERY = 15
"""The invariants are sampled (and the plot sent) every this many frames: 4 a second at 60 frames/s. A
frame of thirty private sessions should not pay for a plot nobody can read faster."""

DRIFT_POINTS = 80
"""Samples the invariant-drift plot keeps (the newest at the right)."""

DRIFT_FLOOR = 1e-17
"""A drift below this (exactly 0 included) is drawn at it: the plot is of log₁₀, and 0 has none."""


class InvariantDrift:
    """A small live plot of the relative drift of a scene's invariants (E, |L|, L_z, L₃ as they apply).

    ``add(t, values)`` takes a function returning each invariant's value and its scale (the size a drift is
    measured against: |L| for L_z, which may pass through 0), called only on the frames that sample; the
    first sample after :meth:`clear` is the reference. The plot
    shows log₁₀ |v − v₀| / scale against time: flat near −15 for an exact solution, rising for friction or
    an integrator. It is cleared with the scene's traces (Reset, a new parameter).
    """

    def __init__(
        self,
        ctx: Any,
        names: tuple[str, ...],
        colours: tuple[str, ...],
        title: str = "Invariants: log₁₀ relative drift",
    ) -> None:
        self.names = names
        self.handle = ctx.server.gui.add_uplot(
            data=(np.zeros(1), *(np.full(1, math.log10(DRIFT_FLOOR)) for _ in names)),
            series=(
                viser.uplot.Series(label="t (s)"),
                *(viser.uplot.Series(label=name, stroke=colour, width=2) for name, colour in zip(names, colours)),
            ),
            scales={
                "x": viser.uplot.Scale(time=False, auto=True),
                "y": viser.uplot.Scale(auto=False, range=(-17.0, 0.0)),
            },
            title=title,
            aspect=2.2,
        )
        self.clear()

    def clear(self) -> None:
        self.reference: dict[str, float] | None = None
        self.times: list[float] = []
        self.drifts: list[list[float]] = [[] for _ in self.names]
        self._calls = 0

    def add(self, t: float, values: Callable[[], dict[str, tuple[float, float]]]) -> None:
        """A frame at time ``t`` (s); every :data:`DRIFT_EVERY`-th one samples ``values()`` (``name`` →
        ``(value, scale)``) and sends the plot."""
        self._calls += 1
        if (self._calls - 1) % DRIFT_EVERY:
            return
        sample = values()  # evaluated only on the sampling frames
        if self.reference is None:
            self.reference = {name: sample[name][0] for name in self.names}
        for k, name in enumerate(self.names):
            value, scale = sample[name]
            drift = abs(value - self.reference[name]) / scale if scale > 0.0 else 0.0
            self.drifts[k].append(math.log10(max(drift, DRIFT_FLOOR)) if math.isfinite(drift) else 0.0)
            del self.drifts[k][:-DRIFT_POINTS]
        self.times.append(float(t))
        del self.times[:-DRIFT_POINTS]
        self.handle.data = (np.array(self.times), *(np.array(d) for d in self.drifts))

    def latest(self) -> dict[str, float]:
        """The newest log₁₀ drift of each invariant (what the plot shows at its right end)."""
        return {name: d[-1] for name, d in zip(self.names, self.drifts) if d}
