"""viser's handles read and written where its public API has no word for it: the one door to their insides.

viser 1.1.1 keeps a GUI element's or scene node's state in the handle's private ``_impl`` (its uuid, its
properties, whether it was removed, the container it sits in), the GUI's lookup tables in
``GuiApi._gui_input_handle_from_uuid`` and ``_container_handle_from_uuid``, a container's elements in its
``_children`` and the scene's nodes in ``SceneApi._handle_from_node_name``. Everything of ours that needs
them calls the functions here; docs/viser-internals.md lists each with what breaks if viser changes it.
"""

from __future__ import annotations

from typing import Any

import numpy as np
import viser
from viser import _messages

__all__ = [
    "NO_VALUE",
    "container_of",
    "gui_inputs",
    "handles_in",
    "is_removed",
    "node_pose",
    "prop",
    "properties",
    "props_of",
    "scene_nodes",
    "show_value",
    "uuid_of",
    "value_of",
]

NO_VALUE = object()
"""What :func:`value_of` returns for an element that has no value (a button, a markdown text)."""


def uuid_of(handle: Any) -> str:
    """The element's id, as the browser knows it (viser's ``_impl.uuid``)."""
    return str(handle._impl.uuid)


def is_removed(handle: Any) -> bool:
    """Whether the element or node has been removed (``_impl.removed``)."""
    return bool(handle._impl.removed)


def prop(handle: Any, name: str, default: Any = None) -> Any:
    """One of the element's properties as the server holds it (``_impl.props.<name>``), else ``default``."""
    return getattr(handle._impl.props, name, default)


def properties(handle: Any) -> Any:
    """The element's or node's properties object itself (viser's ``…Props`` dataclass; read, never write)."""
    return handle._impl.props


def props_of(handle: Any) -> dict[str, Any]:
    """A copy of all the element's properties, name -> value (arrays copied)."""
    return {k: v.copy() if isinstance(v, np.ndarray) else v for k, v in vars(handle._impl.props).items()}


def value_of(handle: Any) -> Any:
    """The element's value as the server holds it, or :data:`NO_VALUE` (a button or an element without one)."""
    impl = handle._impl
    return NO_VALUE if getattr(impl, "is_button", False) or not hasattr(impl, "value") else impl.value


def show_value(handle: Any, value: Any) -> None:
    """Set the element's value and send it to every browser without running its update callbacks (a refused
    change put back: the callbacks would offer it again)."""
    handle._impl.value = value
    handle._impl.gui_api._websock_interface.queue_message(_messages.GuiUpdateMessage(uuid_of(handle), {"value": value}))


def container_of(handle: Any) -> Any:
    """The folder (or other container handle) the element sits in, or None (the panel's root)."""
    gui = handle._impl.gui_api
    return gui._container_handle_from_uuid.get(handle._impl.parent_container_id)


def handles_in(container: Any) -> list[Any]:
    """The GUI elements in a container and in the containers within it, in the order they were added."""
    found: list[Any] = []
    for child in list(getattr(container, "_children", {}).values()):
        if getattr(getattr(child, "_impl", None), "props", None) is not None:
            found.append(child)
        found.extend(handles_in(child))
    return found


def gui_inputs(gui: viser.GuiApi) -> dict[str, Any]:
    """The server's input elements, uuid -> handle: viser's own table (live; copy it to iterate)."""
    return gui._gui_input_handle_from_uuid


def scene_nodes(scene: viser.SceneApi) -> dict[str, Any]:
    """The server's scene nodes, name -> handle: viser's own table (live; copy it to iterate)."""
    return scene._handle_from_node_name


def node_pose(handle: Any) -> tuple[bool, Any, Any]:
    """A scene node's (visible, wxyz (4,), position (3,) in m) relative to its parent, as the server holds it."""
    impl = handle._impl
    return bool(impl.visible), impl.wxyz, impl.position
