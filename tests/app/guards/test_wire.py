"""app.wire sends a frame's node updates as the very messages viser's setters send, and nothing when
the value did not change; a removed node is refused as viser refuses it."""

from __future__ import annotations

import numpy as np
import pytest
import viser

from app.guards.wire import send_markdown, send_orientation, send_points, send_position


@pytest.fixture(scope="module")
def server():
    server = viser.ViserServer(host="127.0.0.1", port=0, verbose=False)
    yield server
    server.stop()


def _queued(handle):
    """Capture what a handle queues (the scene API's owner-stamping queue, as the setters use)."""
    sent: list = []
    api = handle._impl.api
    original = api._queue_scene_message
    api._queue_scene_message = lambda message: (sent.append(message), original(message))
    return sent, lambda: setattr(api, "_queue_scene_message", original)


def _plain(value):
    if isinstance(value, np.ndarray):
        return (str(value.dtype), value.tolist())
    if isinstance(value, dict):
        return {k: _plain(v) for k, v in value.items()}
    return value


def _fields(message):
    """A message's type and fields, without the node's name (and viser's cache of it)."""
    fields = {k: v for k, v in vars(message).items() if k not in ("name", "_cached_redundancy_key")}
    return type(message).__name__, _plain(fields)


def _pair(server, kind):
    if kind == "arrows":
        make = lambda name: server.scene.add_arrows(name, points=np.zeros((1, 2, 3)), colors=(1, 2, 3))  # noqa: E731
    else:
        make = lambda name: server.scene.add_frame(name, show_axes=False)  # noqa: E731
    return make(f"/setter_{kind}"), make(f"/wire_{kind}")


@pytest.mark.parametrize(
    "kind, attribute, send, value",
    [
        ("frame", "wxyz", send_orientation, np.array([0.5, 0.5, -0.5, 0.5])),
        ("frame", "position", send_position, np.array([0.25, -1.5, 3.0])),
        ("arrows", "points", send_points, np.array([[[0.0, 0.0, 0.0], [0.1, 0.2, 0.3]]])),
    ],
)
def test_the_same_message_as_the_setter_then_nothing_for_the_same_value(server, kind, attribute, send, value):
    by_setter, by_wire = _pair(server, kind)
    sent, restore = _queued(by_setter)  # both nodes queue through the same scene API
    try:
        setattr(by_setter, attribute, value)
        send(by_wire, value)
        if attribute != "points":  # viser's setters skip an unchanged pose, as send_* do
            setattr(by_setter, attribute, value)
            send(by_wire, value.copy())
    finally:
        restore()
    sent_setter = [m for m in sent if m.name == by_setter.name]
    sent_wire = [m for m in sent if m.name == by_wire.name]
    assert [_fields(m) for m in sent_wire] == [_fields(m) for m in sent_setter]
    assert len(sent_wire) == 1
    np.testing.assert_array_equal(getattr(by_wire, attribute), getattr(by_setter, attribute))


def test_the_points_sent_are_a_copy_of_the_callers_buffer(server):
    _, handle = _pair(server, "arrows")
    sent, restore = _queued(handle)
    buffer = np.array([[[0.0, 0.0, 0.0], [1.0, 1.0, 1.0]]])
    try:
        send_points(handle, buffer)
        buffer[:] = 7.0  # the caller goes on writing while the message waits for the network thread
    finally:
        restore()
    assert sent[0].updates["points"].max() == 1.0


def test_a_removed_node_is_refused(server):
    handle = server.scene.add_frame("/gone", show_axes=False)
    handle.remove()
    for send, value in ((send_orientation, np.array([1.0, 0, 0, 0])), (send_position, np.zeros(3))):
        with pytest.raises(RuntimeError, match="removed"):
            send(handle, value)


def test_a_node_of_a_browser_that_left_is_skipped_without_a_warning(server):
    import time
    import warnings

    from tests.harness import raw_client

    class _App:  # what raw_client needs: the server to ask for its clients, and the port
        def __init__(self, server):
            self.server, self.port = server, server.get_port()

    with raw_client(_App(server)):
        deadline = time.monotonic() + 10
        while not server.get_clients() and time.monotonic() < deadline:
            time.sleep(0.02)
        client = next(iter(server.get_clients().values()))
        handle = client.scene.add_frame("/mine", show_axes=False)
    deadline = time.monotonic() + 10
    while not client._websock_connection.get_message_buffer().done and time.monotonic() < deadline:
        time.sleep(0.02)
    with warnings.catch_warnings():
        warnings.simplefilter("error")  # viser warns on a message queued on a closed connection
        send_position(handle, np.array([1.0, 2.0, 3.0]))
        send_orientation(handle, np.array([0.0, 1.0, 0.0, 0.0]))


def _gui_queued(server):
    """Capture what the server's GUI queues (viser's setters and send_markdown queue through it)."""
    sent: list = []
    interface = server.gui._websock_interface
    original = interface.queue_message
    interface.queue_message = lambda message: (sent.append(message), original(message))
    return sent, lambda: setattr(interface, "queue_message", original)


def test_markdown_the_same_message_as_the_setter_then_nothing_for_the_same_text(server):
    by_setter, by_wire = server.gui.add_markdown("before"), server.gui.add_markdown("before")
    text = "**L₃ against the threshold**  \nL₃ = 0.4 kg m²/s: above it, tilted 12.5°"
    sent, restore = _gui_queued(server)
    try:
        by_setter.content = text
        send_markdown(by_wire, text)
        by_setter.content = text
        send_markdown(by_wire, text)
    finally:
        restore()
    to_setter = [m.updates for m in sent if m.uuid == by_setter._impl.uuid]
    to_wire = [m.updates for m in sent if m.uuid == by_wire._impl.uuid]
    assert to_wire == to_setter == [{"_markdown": text}]
    assert by_wire.content == by_setter.content == text
    assert by_wire._impl.props._markdown == by_setter._impl.props._markdown


def test_markdown_with_an_image_goes_through_viser_and_a_removed_element_is_refused(server):
    handle = server.gui.add_markdown("before")
    with pytest.warns(UserWarning, match="no-such-image"):  # viser's setter tried to read the image
        send_markdown(handle, "![missing](no-such-image.png)")
    assert handle.content == "![missing](no-such-image.png)"
    handle.remove()
    with pytest.raises(RuntimeError, match="removed"):
        send_markdown(handle, "after")
