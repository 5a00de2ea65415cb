"""Shared GUI pieces: labelled sliders with a validation hook, readouts, a presets dropdown, a gauge.

More in docs/app-notes.md (``app.panel.parameters``).
"""

from __future__ import annotations

import math
import re
import unicodedata
import weakref
from collections.abc import Callable
from dataclasses import dataclass
from typing import Any, Literal

import viser

from app.contracts import SceneContext
from app.guards.handles import container_of, uuid_of
from app.guards.wire import send_markdown
from app.language.words import mark, say
from app.panel.rollback import Rollback

__all__ = [
    "SliderSpec",
    "ParameterPanel",
    "Readout",
    "HELD",
    "Presets",
    "Gauge",
    "refusable_dropdown",
    "take_uploads",
    "folded",
]

_CHOICES: dict[int, dict[str, dict[str, Any]]] = {}
"""The accepted choice of every refusable dropdown, id(its folder) -> dropdown uuid -> {"value": …}: what a
refused ParameterPanel.offer of that folder puts back (see :func:`refusable_dropdown`)."""


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

    def __init__(self, ctx: SceneContext, specs: list[SliderSpec], apply: Callable[[dict[str, float]], None]) -> None:
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

    def offer(self, changes: dict[str, float], client: viser.ClientHandle | None = None) -> bool:
        """Offer new values (some keys); returns True if accepted. Refused: notify, snap sliders back.

        Transactional: whatever ``apply`` raises, of any type, everything is put back as it was
        (:class:`Rollback`): the scene's attributes, its motion state, the controls and texts of its
        folder, the clock's time; the sliders show the last accepted values, and Reset still works.
        """
        with self.ctx.lock:
            try:
                candidate = {**self.values, **{k: self.checked_number(k, v) for k, v in changes.items()}}
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
        return None if first is None else container_of(first)

    def _accepted(self) -> dict[str, Any]:
        """The values in force of the controls a browser may have changed just now (uuid -> value): the
        sliders' accepted values and the accepted choices of refusable dropdowns."""
        accepted = {uuid_of(h): self.values[key] for key, h in self.sliders.items()}
        folder = self._folder()
        for uuid, value in _CHOICES.get(id(folder), {}).items():
            accepted[uuid] = value["value"]
        return accepted

    def refuse(self, exc: Exception, client: viser.ClientHandle | None = None) -> None:
        """Tell the browser that asked why its change was refused, and show the values in force."""
        self.refusals += 1
        self.last_refusal = exc
        if isinstance(exc, ValueError):
            title, text = mark("Refused: that is not a possible body"), str(exc)
        else:
            title, text = mark("Refused: the scene could not take these values"), f"{type(exc).__name__}: {exc}"
        self.ctx.notify(title, text, client=client, error=True)
        self._sync(self.values)

    def checked_number(self, key: str, value: Any) -> float:
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


_ASCII = {
    "\u0307": "dot",
    "φ": "phi",
    "θ": "theta",
    "ω": "omega",
    "ψ": "psi",
    "Ω": "omega",
    "−": "-",
    "×": "x",
    "½": "1/2",
    "⁄": "/",
}


def folded(text: str) -> str:
    """A name as one might type it in ASCII: lower case, Greek letters spelt out (a dot above: ``dot``),
    accents dropped, subscripts as digits, spaces collapsed (``folded("φ̇0 = −1 × steady") ==
    "phidot0 = -1 x steady"``)."""
    spelt = "".join(_ASCII.get(c, c) for c in unicodedata.normalize("NFKD", text))
    return " ".join("".join(c for c in spelt if not unicodedata.combining(c)).lower().split())


HELD = mark("held back: shown with the answers")
"""What a readout says while a class question asks for its value."""


class Readout:
    """A read-only number with a label and units, rewritten only when its text changes.

    Every number in the panel has four significant digits (``fmt``'s default) and its unit in the label.
    """

    def __init__(self, ctx: SceneContext, label: str, fmt: str = "{:.4g}", hint: str | None = None) -> None:
        self.fmt = fmt
        self._said = re.sub(r"\{\d*", "{value", fmt, count=1)  # ``{:.4g}``, ``{0:.4g}``: one named field, for say()
        self.handle = ctx.server.gui.add_text(label, initial_value="—", disabled=True, hint=hint)
        self.value_text = "—"  # the text it states (shown unless held back)
        self.held = False

    @property
    def text(self) -> str:
        """The text shown in the panel (:data:`HELD` while held back)."""
        return self.handle.value

    def set(self, value: float | str) -> None:
        if isinstance(value, str):
            text = value
        elif not math.isfinite(value):
            text = "∞" if value > 0 else ("−∞" if value < 0 else "—")
        else:
            text = say(self._said, value=value)  # written as each reader's language writes numbers
        self.value_text = text
        self._show()

    def hold(self, held: bool) -> None:
        """Hold the value back (a class question asks for it) or show it again (the answers are shown)."""
        self.held = bool(held)
        self._show()

    def _show(self) -> None:
        text = HELD if self.held else self.value_text
        if self.handle.value != text:
            self.handle.value = text  # type: ignore[misc]  # viser 1.1.1 types this setter read-only


class Presets:
    """A dropdown of named presets; choosing one offers its values to a :class:`ParameterPanel`.

    ``presets`` maps a name to a dict of values or to a callable returning one (computed from the
    current values, e.g. a steady-precession rate). The first entry, ``"—"``, does nothing.
    ``renamed`` maps a preset's former names to its name now, so lectures, state texts and export
    commands written with an old name keep working.
    """

    NONE = mark("— choose a preset —")

    def __init__(
        self,
        ctx: SceneContext,
        panel: ParameterPanel,
        presets: dict[str, dict[str, float] | Callable[[dict[str, float]], dict[str, float]]],
        label: str = mark("Preset"),
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
                self.handle.value = name  # type: ignore[misc]  # viser 1.1.1 types this setter read-only
            finally:
                self._choosing = False

    def _chosen(self, event: Any) -> None:
        name = self.handle.value
        if name == self.NONE or self._choosing:
            return
        self.choose(name, client=getattr(event, "client", None))

    def resolve(self, name: str) -> str | None:
        """The preset's name now, or None if there is no such preset. Taken too: a former name, the name typed
        in ASCII and any case (``phidot0 = -1 x steady`` for ``φ̇0 = −1 × steady``), and the start of one name
        only (``loops``; ``sleeping top`` fits two and is refused)."""
        name = self.renamed.get(name, name)
        if name in self.presets:
            return name
        typed = folded(name)
        if not typed:
            return None
        same = [p for p in self.presets if folded(p) == typed]
        starting = [p for p in self.presets if folded(p).startswith(typed)]
        found = same or starting
        return found[0] if len(found) == 1 else None

    def choose(self, name: str, client: viser.ClientHandle | None = None) -> bool:
        """Apply a preset by name (or a former name, or a name :meth:`resolve` takes); returns True if
        accepted (KeyError for no such preset)."""
        name = self.resolve(name) or name
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

    def __init__(self, ctx: SceneContext, label: str) -> None:
        self.text = ctx.server.gui.add_markdown(label)
        self.label = label
        self.bar = ctx.server.gui.add_progress_bar(0.0, color="orange")
        self._fill, self._text = 0.0, ""
        self._colour: Literal["blue", "orange"] = "orange"

    def set(self, value: float, threshold: float, text: str) -> None:
        fill = 100.0 * min(max(value / (2.0 * threshold), 0.0), 1.0) if threshold > 0 else 0.0
        colour: Literal["blue", "orange"] = "blue" if value > threshold else "orange"  # told apart by every eye
        fill = round(fill, 1)
        if fill != self._fill:  # each part only when it changes: text, bar and colour are set every frame
            self._fill = self.bar.value = fill  # type: ignore[misc]  # viser 1.1.1 types this setter read-only
        if colour != self._colour:
            self._colour = self.bar.color = colour
        if text != self._text:
            self._text = text
            send_markdown(self.text, say(_GAUGE, label=self.label, text=text))


_GAUGE = "{label}  \n{text}"
"""A gauge's Markdown: its label over its line of text (markup alone: each part is translated as a value)."""


def refusable_dropdown(
    ctx: SceneContext,
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
    folder = container_of(handle)
    if folder is not None:
        if id(folder) not in _CHOICES:
            weakref.finalize(folder, _CHOICES.pop, id(folder), None)  # forgotten with its folder (or the root)
        _CHOICES.setdefault(id(folder), {})[uuid_of(handle)] = accepted

    def on_update(event: Any) -> None:
        value = handle.value
        if value == accepted["value"]:
            return  # includes the snap-back below, which runs this callback again
        try:
            ok = apply()
        except Exception as exc:  # noqa: BLE001 - of any type: refused, the dropdown snaps back
            text = str(exc) if isinstance(exc, ValueError) else f"{type(exc).__name__}: {exc}"
            ctx.notify(mark("Refused"), text, client=getattr(event, "client", None), error=True)
            ok = False
        if ok is False:
            handle.value = accepted["value"]  # type: ignore[misc]  # viser 1.1.1 types this setter read-only
        else:
            accepted["value"] = value

    handle.on_update(ctx.guarded(on_update))
    return handle


def take_uploads(
    ctx: SceneContext,
    button: Any,
    load: Callable[[str, bytes, viser.ClientHandle | None], object],
    refuse: Callable[[str, viser.ClientHandle | None], object],
) -> None:
    """Hand every file uploaded through ``button`` (a viser upload button) to ``load(name, content, client)``,
    outside the simulation's lock (it reads the file in a worker and takes the lock to adopt it). Who may drive
    is asked first: a follower's file is refused, ``refuse(reason, client)`` under the lock, before anything
    reads it."""

    def on_upload(event: Any) -> None:
        client = getattr(event, "client", None)
        reason = ctx.refusal(client.client_id) if client is not None else None
        if reason is not None:
            with ctx.lock:
                refuse(reason, client)
            return
        file = button.value
        load(file.name, file.content, client)

    button.on_upload(on_upload)
