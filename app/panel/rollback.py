"""Rollback: a refused change undone completely, as if it had never been offered.

What ``apply`` assigned on the scene, the scene's motion state, every control and text of the scene's
folder and the time are put back; side effects beyond those are redone by applying the accepted values.
"""

from __future__ import annotations

from collections.abc import Callable
from typing import Any

import numpy as np

from app.contracts import SceneContext
from app.guards.handles import NO_VALUE, handles_in, is_removed, prop, props_of, show_value, uuid_of, value_of

__all__ = ["Rollback"]


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

    def __init__(self, ctx: SceneContext, owner: object | None, folder: Any, accepted: dict[str, Any]) -> None:
        self.ctx, self.owner = ctx, owner
        self.attributes = dict(vars(owner)) if owner is not None else {}
        self.motion = _call(owner, "snapshot")
        self.clock = (getattr(ctx, "time", None), getattr(ctx, "playing", None))
        self.accepted = accepted
        self.panel = [(h, props_of(h), accepted.get(uuid_of(h), value_of(h))) for h in handles_in(folder)]

    def changed(self) -> bool:
        """Whether anything taken was changed (a control a browser set just now aside)."""
        if self.owner is not None:
            now = vars(self.owner)
            if now.keys() != self.attributes.keys() or any(now[k] is not v for k, v in self.attributes.items()):
                return True
        if (getattr(self.ctx, "time", None), getattr(self.ctx, "playing", None)) != self.clock:
            return True
        for handle, props, value in self.panel:
            if is_removed(handle):
                continue
            if any(_differs(prop(handle, k), v) for k, v in props.items()):
                return True
            if uuid_of(handle) not in self.accepted and _differs(value_of(handle), value):
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
            if is_removed(handle):
                continue
            for name, old in props.items():
                if _differs(prop(handle, name), old):
                    setattr(handle, name, old)  # viser sends the property to every browser
            if value is not NO_VALUE and _differs(value_of(handle), value):
                show_value(handle, value)


def _differs(a: Any, b: Any) -> bool:
    if a is b:
        return False
    if isinstance(a, np.ndarray) or isinstance(b, np.ndarray):
        return not (isinstance(a, np.ndarray) and isinstance(b, np.ndarray) and np.array_equal(a, b))
    try:
        return not bool(a == b)
    except (TypeError, ValueError):  # tuples of arrays (a plot's data): not the same object, so changed
        return True


def _call(owner: object | None, name: str, *args: Any) -> Any:
    """``owner.name(*args)`` if the owner has it (a Scene's snapshot/restore), else None."""
    method = getattr(owner, name, None)
    return method(*args) if callable(method) else None
