"""A message viser sends to many browsers is turned into its wire form once, not once per browser.

More in docs/app-notes.md (``app.guards.serialize``).
"""

from __future__ import annotations

from typing import Any

from viser.infra import _messages

__all__ = ["serialize_once"]

_KEPT = "_rbl_wire"
"""The attribute a message keeps its wire form in (False: it carries binary buffers, never kept)."""

_viser_form = _messages.Message.as_serializable_dict


def _once(message: Any, binary_buffers: list[memoryview] | None = None) -> dict[str, Any]:
    """viser's ``Message.as_serializable_dict``, kept on the message when it adds no binary buffer.

    A message with arrays (points, meshes) puts them into ``binary_buffers`` at indices that depend on the
    window it is sent in: it is serialized anew each time, as viser does.
    """
    kept = message.__dict__.get(_KEPT)
    if kept:
        return kept  # type: ignore[no-any-return]
    if kept is False or binary_buffers is None:
        return _viser_form(message, binary_buffers)
    before = len(binary_buffers)
    form = _viser_form(message, binary_buffers)
    message.__dict__[_KEPT] = form if len(binary_buffers) == before else False
    return form


def serialize_once() -> None:
    """Let every viser message keep its wire form (process-wide; calling it again changes nothing)."""
    _messages.Message.as_serializable_dict = _once  # type: ignore[method-assign,assignment]
