"""A handle's property type hints looked up once per kind of handle, not once per handle.

More in docs/app-notes.md (``app.guards.prop_hints``).
"""

from __future__ import annotations

import functools
from typing import Any, get_type_hints

from viser import _assignable_props_api

__all__ = ["cache_prop_hints"]


_HINTS: dict[type, dict[str, Any]] = {}
"""The type hints of each props class met (a dict write is atomic: two threads at worst look one up twice)."""


def _prop_hints(self: Any) -> dict[str, Any]:
    """viser's ``_prop_hints``: the type hints of the handle's props dataclass, from one shared table."""
    kind = type(self._impl.props)
    hints = _HINTS.get(kind)
    if hints is None:
        hints = _HINTS[kind] = get_type_hints(kind)
    return hints


def cache_prop_hints() -> None:
    """Install :func:`_prop_hints` as every viser handle's ``_prop_hints`` (process-wide; calling it again
    changes nothing).

    viser 1.1.1 computes it per handle (a ``cached_property`` evaluating the string annotations of the
    props dataclass, about 0.1 ms), so a scene that makes 50 trace nodes spent 5-10 ms on it at every
    scene switch. The hints depend on the props class only and are never changed, so one table serves all
    handles of a class; it stays a ``cached_property``, so a handle still reads it from its own dict.
    """
    base = _assignable_props_api.AssignablePropsBase
    current = base.__dict__["_prop_hints"]
    if getattr(current, "func", None) is _prop_hints:
        return
    cached = functools.cached_property(_prop_hints)
    cached.__set_name__(base, "_prop_hints")
    base._prop_hints = cached  # type: ignore[assignment]
