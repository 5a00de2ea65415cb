"""Every value a browser sends is checked on the server before viser or a scene sees it.

More in docs/app-notes.md (``app.guards.inputs``).
"""

from __future__ import annotations

import math
import time
import weakref
from collections.abc import Callable
from typing import Any

import viser
from viser import _messages, infra

from app.contracts import ClientId
from app.guards.uploads import guard_uploads
from app.language.words import english_option, say

__all__ = ["MAX_TEXT", "MAX_INT", "InputRefused", "check_update", "guard_inputs"]

MAX_TEXT = 2000
"""Longest text a browser may send into a text control, characters."""

MAX_INT = 2**53
"""Largest integer magnitude taken (exact in a JavaScript number and in a float64)."""

RATE = 60.0
"""Changes a browser may send per second, sustained (a dragged slider sends at most one a frame)."""

BURST = 120.0
"""Changes a browser may send at once before :data:`RATE` applies."""


class InputRefused(ValueError):
    """A browser's value for a control was refused; the message says why, for that browser."""


def _number(value: Any, label: str) -> float | int:
    if isinstance(value, bool) or not isinstance(value, (int, float)):
        raise InputRefused(
            say(
                "“{label}” must be a number, got {kind!s} {value!s}",
                label=label,
                kind=type(value).__name__,
                value=_short(value),
            )
        )
    if isinstance(value, int) and abs(value) > MAX_INT:
        raise InputRefused(
            say("“{label}” must be between −2⁵³ and 2⁵³, got {value!s}", label=label, value=_short(value))
        )
    if not math.isfinite(float(value)):
        raise InputRefused(say("“{label}” must be a finite number, got {value!s}", label=label, value=value))
    return value


def _whole(number: float, label: str) -> int:
    """``number`` rounded for an integer control, refused if the rounded value is over 2⁵³ in magnitude
    (a float such as 1e23 passes the range check of a control without ``min``/``max`` but would give an
    integer msgpack cannot encode)."""
    whole = int(round(number))
    if abs(whole) > MAX_INT:
        raise InputRefused(
            say("“{label}” must be between −2⁵³ and 2⁵³, got {value!s}", label=label, value=_short(number))
        )
    return whole


def _short(value: Any) -> str:
    text = repr(value)
    return text if len(text) <= 40 else text[:37] + "…"


def _clamp(value: float, low: Any, high: Any) -> float:
    if low is not None and value < low:
        return float(low)
    if high is not None and value > high:
        return float(high)
    return value


def check_update(current: Any, props: Any, label: str, updates: dict[str, Any]) -> dict[str, Any]:
    """The checked (and clamped) updates for one control, or :class:`InputRefused`.

    Parameters
    ----------
    current : Any
        The control's current value (its type is the type the new value must have).
    props : viser's props of the control
        ``min``/``max``/``options``/``disabled`` are read where the control has them.
    label : str
        The control's label, for the message.
    updates : dict
        What the browser sent: property name to new value.
    """
    # Each message is said with the label as a value (a word of the catalogs, translated with it).
    if set(updates) != {"value"}:
        raise InputRefused(say("“{label}”: only a control's value can be changed", label=label))
    if getattr(props, "disabled", False):
        raise InputRefused(say("“{label}” cannot be changed (it only shows a value)", label=label))
    value = updates["value"]
    if isinstance(current, bool):
        if not isinstance(value, bool):
            raise InputRefused(say("“{label}” must be on or off, got {value!s}", label=label, value=_short(value)))
        return {"value": value}
    if isinstance(current, (int, float)):
        number = _number(value, label)
        clamped = _clamp(float(number), getattr(props, "min", None), getattr(props, "max", None))
        return {"value": _whole(clamped, label) if isinstance(current, int) else float(clamped)}
    if isinstance(current, str):
        if not isinstance(value, str):
            raise InputRefused(say("“{label}” must be text, got {kind!s}", label=label, kind=type(value).__name__))
        if len(value) > MAX_TEXT:
            raise InputRefused(
                say(
                    "“{label}” takes at most {most} characters, got {length}",
                    label=label,
                    most=MAX_TEXT,
                    length=len(value),
                )
            )
        options = getattr(props, "options", None)
        if options is not None:
            value = english_option(value, tuple(options))  # a translated dropdown's choice, read back
        if options is not None and value not in options:
            raise InputRefused(say("“{label}” has no option {value!s}", label=label, value=_short(value)))
        return {"value": value}
    if isinstance(current, tuple):
        if not isinstance(value, (list, tuple)) or len(value) != len(current):
            raise InputRefused(
                say(
                    "“{label}” must be {count} numbers, got {value!s}",
                    label=label,
                    count=len(current),
                    value=_short(value),
                )
            )
        low, high = getattr(props, "min", None), getattr(props, "max", None)
        out = []
        for i, (old, new) in enumerate(zip(current, value, strict=True)):
            number = float(_number(new, label))
            number = _clamp(number, None if low is None else low[i], None if high is None else high[i])
            out.append(_whole(number, label) if isinstance(old, int) else number)
        return {"value": tuple(out)}
    raise InputRefused(say("“{label}” cannot be changed from a browser", label=label))


_GUARDED: weakref.WeakSet[viser.GuiApi] = weakref.WeakSet()
"""The GUIs :func:`guard_inputs` has guarded (kept here, not on viser's objects; forgotten with them)."""


def guard_inputs(
    gui: viser.GuiApi, refuse: Callable[[Any, str], None], permit: Callable[[Any], str | None] | None = None
) -> None:
    """Check every ``GuiUpdateMessage`` that reaches ``gui`` before viser applies it.

    Parameters
    ----------
    gui : viser.GuiApi
        The server's GUI (``server.gui``) or one client's (``client.gui``).
    refuse : callable(client_id, message)
        Tells the browser that sent a refused value why (a notification); called on viser's event loop.
    permit : callable(client_id) -> str or None, optional
        Whether this browser may change these controls at all: None if it may, otherwise the reason it
        may not (presenter mode: a follower without the PIN).

    Uploads to ``gui`` are guarded with the same ``refuse`` and ``permit``
    (:func:`app.guards.uploads.guard_uploads`). A GUI is guarded once: later calls for the same ``gui`` do
    nothing.
    """
    guard_uploads(gui, refuse, permit)
    if gui in _GUARDED:
        return  # one check per GUI: a browser's panel and its own simulation share client.gui
    _GUARDED.add(gui)
    interface = gui._websock_interface
    handlers: list[Any] = interface._incoming_handlers[_messages.GuiUpdateMessage]
    original = gui._handle_gui_updates
    index = handlers.index(original)  # a ValueError here means viser changed: the pin test catches it
    allowance: dict[ClientId, tuple[float, float]] = {}  # client id -> (changes it may still send, when)

    async def checked(client_id: infra.ClientId, message: _messages.GuiUpdateMessage) -> None:
        handle = gui._gui_input_handle_from_uuid.get(message.uuid, None)
        if handle is None or handle._impl.removed:
            return
        state = handle._impl
        reason = permit(client_id) if permit is not None else None
        if reason is not None:
            _send_value(gui, client_id, message.uuid, state.value)
            refuse(client_id, reason)
            return
        now = time.monotonic()
        tokens, then = allowance.get(client_id, (BURST, now))
        tokens = min(BURST, tokens + RATE * (now - then))
        if tokens < 1.0:
            allowance[client_id] = (tokens, now)
            _send_value(gui, client_id, message.uuid, state.value)
            refuse(
                client_id,
                say("More than {rate:.0f} changes a second: some were ignored. Slow down a little.", rate=RATE),
            )
            return
        allowance[client_id] = (tokens - 1.0, now)
        if len(allowance) > 10_000:  # browsers come and go: forget the oldest
            for key in list(allowance)[:5_000]:
                del allowance[key]
        try:
            label = str(getattr(state.props, "label", ""))
            updates = check_update(state.value, state.props, label, message.updates)
        except InputRefused as exc:
            _send_value(gui, client_id, message.uuid, state.value)
            refuse(client_id, str(exc))
            return
        clamped = updates != message.updates
        message.updates = updates
        await original(client_id, message)
        if clamped:
            _send_value(gui, client_id, message.uuid, state.value)

    handlers[index] = checked


def _send_value(gui: viser.GuiApi, client_id: ClientId, uuid: str, value: Any) -> None:
    """Set one browser's control back to the value in force (nobody else is told)."""
    owner = gui._owner
    client = owner if isinstance(owner, viser.ClientHandle) else owner.get_clients().get(client_id)
    if client is not None:
        client._websock_connection.queue_message(_messages.GuiUpdateMessage(uuid, {"value": value}))
