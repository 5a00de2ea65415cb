"""A frame's scene-node updates, sent as viser's own messages without the setters' per-call checks.

More in docs/app-notes.md (``app.guards.wire``).
"""

from __future__ import annotations

from typing import Any

import numpy as np
import viser
from numpy.typing import NDArray
from viser import _messages

__all__ = ["departed", "resend_poses", "send_markdown", "send_orientation", "send_points", "send_position", "unsent"]


def departed(client: viser.ClientHandle) -> bool:
    """The browser has disconnected (viser closed its message buffer and removes its handles)."""
    return bool(client._websock_connection.get_message_buffer().done)


def unsent(client: viser.ClientHandle) -> bool:
    """Whether viser's sender has not yet taken everything queued for this browser's own connection (its
    last frame is still waiting: the network thread is behind, or the browser reads slowly)."""
    buffer = client._websock_connection.get_message_buffer()
    cursor = buffer.generator_cursors.get(client.client_id)  # the last message its sender took
    return cursor is not None and bool(cursor < buffer.message_counter - 1)


def _live(handle: Any) -> Any:
    """The handle's state, or None when its browser has left (a frame in flight as it disconnects: there is
    no one to send to, and viser would warn about a message queued on a closed connection)."""
    impl = handle._impl
    if impl.removed:
        # As viser's setters: an update to a removed node would re-create it as a ghost in the browsers.
        raise RuntimeError(f"cannot update the removed scene node {impl.name!r}")
    if impl.api._websock_interface.get_message_buffer().done:
        return None
    return impl


def send_orientation(handle: Any, wxyz: NDArray[np.float64]) -> None:
    """Set a scene node's orientation ``(w, x, y, z)`` (unit quaternion, shape (4,)), if it changed."""
    impl = _live(handle)
    if impl is None:
        return
    value = (float(wxyz[0]), float(wxyz[1]), float(wxyz[2]), float(wxyz[3]))
    current = impl.wxyz
    if value == (current[0], current[1], current[2], current[3]):
        return
    current[:] = value
    impl.api._queue_scene_message(_messages.SetOrientationMessage(impl.name, value))


def send_position(handle: Any, position: NDArray[np.float64] | tuple[float, float, float]) -> None:
    """Set a scene node's position (m, shape (3,), or three floats), if it changed."""
    impl = _live(handle)
    if impl is None:
        return
    value = (float(position[0]), float(position[1]), float(position[2]))
    current = impl.position
    if value == (current[0], current[1], current[2]):
        return
    current[:] = value
    impl.api._queue_scene_message(_messages.SetPositionMessage(impl.name, value))


def send_points(handle: Any, points: NDArray[Any]) -> None:
    """Replace the ``points`` of a line-segments or arrows node (the node's shape, sent as float32).

    A copy is sent: the caller may go on writing its buffer while the message waits to be serialized.
    """
    impl = _live(handle)
    if impl is None:
        return
    points = np.array(points, dtype=np.float32)
    impl.props.points = points
    impl.api._queue_scene_message(_messages.SceneNodeUpdateMessage(impl.name, {"points": points}))


def send_markdown(handle: Any, content: str) -> None:
    """Set a markdown element's ``content``, if it changed (a gauge's line of text, rewritten every frame).

    viser's setter parses the text for images (``![...](...)``) and runs the generic property path; text
    without an image is sent as it is, which is what the parse would give. Text with one goes through
    viser's setter, which reads the image.
    """
    impl = handle._impl
    if impl.removed:  # as viser's setter: an update would re-create a removed element in the browsers
        raise RuntimeError("cannot update a removed markdown element")
    if "![" in content:
        handle.content = content
        return
    if impl.gui_api._websock_interface.get_message_buffer().done:
        return  # its browser has left
    handle._content = content  # what ``handle.content`` reads back
    if impl.props._markdown == content:
        return
    impl.props._markdown = content
    impl.gui_api._websock_interface.queue_message(_messages.GuiUpdateMessage(impl.uuid, {"_markdown": content}))


def resend_poses(scene: viser.SceneApi, prefix: str) -> None:
    """Send the pose of every scene node under ``prefix`` (a scene's root) as it stands, changed or not.

    A scene switch removes the old scene's nodes and adds the new scene's, often under the same names
    (``/scene/body``, ``/scene/L``). viser coalesces a pending removal with a pending creation of the same
    name (they share a redundancy key), so a browser sees a same-name creation, which keeps the old
    node's pose; and a new node whose pose equals the default (identity, the origin) never sends one. The
    explorer's box then stood turned as the wobble's cylinder was, the heavy top's L arrow started 1 m above
    its tip. Called once a scene is built, this sends every node's own pose.
    """
    for name, handle in list(scene._handle_from_node_name.items()):
        if not (name == prefix or name.startswith(prefix + "/")):
            continue
        impl = handle._impl
        if impl.removed:
            continue
        w, x, y, z = (float(v) for v in impl.wxyz)
        px, py, pz = (float(v) for v in impl.position)
        impl.api._queue_scene_message(_messages.SetOrientationMessage(name, (w, x, y, z)))
        impl.api._queue_scene_message(_messages.SetPositionMessage(name, (px, py, pz)))
