"""Every value a browser sends is checked on the server (app.guards.inputs) before viser or a scene sees it.

The unit tests call :func:`app.guards.inputs.check_update` with viser's own props objects; the websocket tests
connect real clients to a running server on 127.0.0.1 and send the messages a browser (or a hostile
script) could send: the server keeps running, every other client stays connected, the values in force
stay, and only the sender hears of the refusal.
"""

from __future__ import annotations

import math
from typing import Any

import pytest

from app.guards.inputs import MAX_INT, MAX_TEXT, InputRefused, check_update
from tests.harness import raw_client, running_app, send_value, still_connected, wait_for


@pytest.fixture(scope="module")
def gui_app():
    with running_app("heavy_top", start_loop=True) as app:
        yield app


def props_of(handle: Any) -> Any:
    return handle._impl.props


# --------------------------------------------------------------------------------------------------
# check_update
# --------------------------------------------------------------------------------------------------
def test_numbers_are_clamped_to_the_slider_range_and_keep_the_controls_type(gui_app):
    gui = gui_app.server.gui
    real = gui.add_slider("real", min=0.0, max=2.0, step=0.1, initial_value=1.0)
    whole = gui.add_slider("whole", min=0, max=10, step=1, initial_value=5)
    try:
        assert check_update(1.0, props_of(real), "real", {"value": 1e23}) == {"value": 2.0}
        assert check_update(1.0, props_of(real), "real", {"value": -7}) == {"value": 0.0}
        assert check_update(1.0, props_of(real), "real", {"value": 0.5}) == {"value": 0.5}
        # int(1e23) would not fit msgpack's 64 bits: this is the value that closed every browser.
        out = check_update(5, props_of(whole), "whole", {"value": 1e23})
        assert out == {"value": 10} and isinstance(out["value"], int)
    finally:
        real.remove()
        whole.remove()


def test_an_integer_control_without_a_range_refuses_a_float_that_rounds_past_2_to_the_53(gui_app):
    gui = gui_app.server.gui
    count = gui.add_number("count", initial_value=5)  # an int number box with no min or max
    try:
        assert count._impl.props.min is None and count._impl.props.max is None
        for huge in (1e23, -1e23, float(2**60), 2.0**53 + 2**11):
            with pytest.raises(InputRefused, match="between −2⁵³ and 2⁵³"):
                check_update(5, props_of(count), "count", {"value": huge})
            # The same for an integer component of a vector control without a range.
            with pytest.raises(InputRefused, match="between −2⁵³ and 2⁵³"):
                check_update((1, 2), props_of(count), "pair", {"value": [huge, 1.0]})
        out = check_update(5, props_of(count), "count", {"value": 2.0**53})  # the largest exact integer
        assert out == {"value": MAX_INT} and isinstance(out["value"], int)
        assert check_update((1, 2), props_of(count), "pair", {"value": [3.4, -7.6]}) == {"value": (3, -8)}
    finally:
        count.remove()


def test_a_huge_float_sent_to_an_integer_box_without_a_range_leaves_other_clients_connected(gui_app):
    app = gui_app
    count = app.server.gui.add_number("count (test)", initial_value=5)
    try:
        with raw_client(app) as sender, raw_client(app) as other:
            before = len(app.messages)
            send_value(sender, count._impl.uuid, 1e23)
            wait_for(lambda: any("2⁵³" in body for _, body in app.messages[before:]), what="the refusal")
            assert count.value == 5
            assert still_connected(other, app=app) and still_connected(sender, app=app)
            with raw_client(app) as late:  # the value in force encodes for a browser that joins later
                assert still_connected(late, app=app)
    finally:
        count.remove()


@pytest.mark.parametrize(
    ("value", "message"),
    [
        (math.nan, "finite"),
        (math.inf, "finite"),
        (-math.inf, "finite"),
        (99999999999999999999999, "between −2⁵³ and 2⁵³"),
        (MAX_INT + 1, "between −2⁵³ and 2⁵³"),
        ("1.5", "must be a number"),
        (True, "must be a number"),
        (None, "must be a number"),
        ([1.0], "must be a number"),
    ],
)
def test_bad_numbers_are_refused_with_a_reason(gui_app, value, message):
    handle = gui_app.server.gui.add_slider("x", min=0.0, max=1.0, step=0.1, initial_value=0.5)
    try:
        with pytest.raises(InputRefused, match=message):
            check_update(0.5, props_of(handle), "x", {"value": value})
    finally:
        handle.remove()


def test_text_dropdowns_checkboxes_disabled_controls_and_other_properties(gui_app):
    gui = gui_app.server.gui
    text = gui.add_text("name", initial_value="")
    shown = gui.add_text("shown", initial_value="0", disabled=True)
    choice = gui.add_dropdown("body", options=("rod", "box"), initial_value="rod")
    box = gui.add_checkbox("on", initial_value=False)
    try:
        assert check_update("", props_of(text), "name", {"value": "ok"}) == {"value": "ok"}
        with pytest.raises(InputRefused, match=f"at most {MAX_TEXT} characters"):
            check_update("", props_of(text), "name", {"value": "x" * (MAX_TEXT + 1)})
        with pytest.raises(InputRefused, match="only shows a value"):
            check_update("0", props_of(shown), "shown", {"value": "1"})
        with pytest.raises(InputRefused, match="has no option"):
            check_update("rod", props_of(choice), "body", {"value": "<script>"})
        with pytest.raises(InputRefused, match="on or off"):
            check_update(False, props_of(box), "on", {"value": 1})
        with pytest.raises(InputRefused, match="only a control's value"):
            check_update("rod", props_of(choice), "body", {"options": ["a"], "value": "rod"})
    finally:
        for h in (text, shown, choice, box):
            h.remove()


# --------------------------------------------------------------------------------------------------
# Real websocket clients
# --------------------------------------------------------------------------------------------------
def test_absurd_values_from_one_client_leave_every_other_client_connected(gui_app):
    app = gui_app
    whole = app.server.gui.add_slider("whole (test)", min=0, max=10, step=1, initial_value=5)
    speed_uuid = app.simulation.speed_slider._impl.uuid
    try:
        with raw_client(app) as sender, raw_client(app) as other:
            refusals = sum(1 for title, _ in app.messages if title == "Refused")
            send_value(sender, whole._impl.uuid, 1e23)  # int(1e23) does not fit in 64 bits
            send_value(sender, speed_uuid, "fast")
            send_value(sender, speed_uuid, None)
            send_value(sender, app.simulation.time_text._impl.uuid, "999")  # a read-only display
            wait_for(lambda: whole.value == 10, what="the clamped value")
            wait_for(
                lambda: sum(1 for title, _ in app.messages if title == "Refused") >= refusals + 3,
                what="three refusals",
            )
            assert app.simulation.speed == 1.0 and app.simulation.speed_slider.value == 0.0  # 1× sits in the middle
            assert still_connected(other, app=app) and still_connected(sender, app=app)
            assert len(app.server.get_clients()) >= 2
            # A later browser gets the state in force, which encodes: it connects and hears the server.
            with raw_client(app) as late:
                assert still_connected(late, app=app)
    finally:
        whole.remove()


def test_a_value_a_slider_accepts_still_reaches_the_scene(gui_app):
    app = gui_app
    app.switch_scene("heavy_top")
    slider = app.scene.params.sliders["spin"]
    target = slider.min + 0.5 * (slider.max - slider.min)
    with raw_client(app) as ws:
        send_value(ws, slider._impl.uuid, target)
        wait_for(lambda: app.scene.params.values["spin"] == pytest.approx(target), what="the scene to take it")
        send_value(ws, slider._impl.uuid, 1e300)  # clamped to the slider's maximum, then offered
        wait_for(lambda: app.scene.params.values["spin"] == pytest.approx(slider.max), what="the clamped spin")


def test_a_flood_of_changes_from_one_browser_is_limited(gui_app):
    app = gui_app
    speed_uuid = app.simulation.speed_slider._impl.uuid
    with raw_client(app) as flooder, raw_client(app) as other:
        before = len(app.messages)
        for k in range(400):  # far more than a person can send: about 2,000 a second
            send_value(flooder, speed_uuid, 0.5 + 0.001 * (k % 7))
        wait_for(
            lambda: any("changes a second" in body for _, body in app.messages[before:]),
            what="the flood to be limited",
        )
        assert still_connected(other, app=app) and still_connected(flooder, app=app)


def _notifications(messages):
    return [m["props"]["body"] for m in messages if m.get("type") == "NotificationShowMessage"]


def test_a_refusal_goes_to_its_browser_only_and_not_into_the_shared_status_line(gui_app):
    from tests.app.reading import received_until
    from tests.harness import drain, received

    app = gui_app
    app.simulation.clear_status()
    with raw_client(app) as sender, raw_client(app) as other:
        drain(other)
        send_value(sender, app.simulation.speed_slider._impl.uuid, "fast (status)")
        wait_for(lambda: any("fast (status)" in body for _, body in app.messages), what="the refusal")
        told = received_until(sender, lambda ms: any("fast (status)" in body for body in _notifications(ms)))
        assert any("fast (status)" in body for body in _notifications(told))
        assert not _notifications(received(other, 0.5))  # the other browser hears nothing of it
        assert app.simulation.status.content == ""  # the status line everyone shares is not told either
        # A failure of the scene is everyone's: it is in the status line, until the clock runs again.
        app.simulation.pause("a numerical failure (test)")
        assert "a numerical failure (test)" in app.simulation.status.content
        failure = received_until(other, lambda ms: any("a numerical failure (test)" in b for b in _notifications(ms)))
        assert any("a numerical failure (test)" in body for body in _notifications(failure))
        app.set_playing(True)
        assert app.simulation.status.content == ""


def test_a_refusal_on_viser_s_event_loop_waits_for_the_notice_lock(gui_app):
    """The refusal runs on viser's event loop, not under the simulation's lock: it must take the lock
    that guards the messages and the status line (and nothing else, so it never waits for a frame)."""
    import time

    app = gui_app

    def told(text):
        return any(text in body for _, body in app.messages)

    with raw_client(app) as sender:
        with app.simulation.lock:  # a frame or a scene switch in progress does not hold the refusal up ...
            send_value(sender, app.simulation.speed_slider._impl.uuid, "fast (locked)")
            wait_for(lambda: told("fast (locked)"), what="the refusal while the simulation is locked")
        with app.simulation.notices.lock:  # ... but the notice lock does: nothing is written while another holds it
            send_value(sender, app.simulation.speed_slider._impl.uuid, "fast (notice)")
            deadline = time.monotonic() + 0.5
            while time.monotonic() < deadline:
                assert not told("fast (notice)")
                time.sleep(0.02)
        wait_for(lambda: told("fast (notice)"), what="the refusal once the lock is free")
