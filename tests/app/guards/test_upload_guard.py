"""Uploads are checked when they start, before viser stores any part (app.guards.uploads).

Real websocket clients send the messages a page sends for an upload (tests/harness.py's
``send_upload``), truthfully or not. viser acknowledges every part it stores (``FileTransferPartAck``
with the bytes so far); a refused transfer gets one acknowledgement of its whole declared size, which
releases the page's upload button, and nothing else: so the acknowledgements a client receives say
whether any part of it was kept.
"""

from __future__ import annotations

import contextlib

import pytest
import trimesh

from app.uploads import limits
from tests.harness import (
    raw_client,
    received,
    running_app,
    send_part,
    send_upload,
    start_upload,
    still_connected,
    wait_for,
)


@pytest.fixture(scope="module")
def explorer():
    with running_app("inertia_explorer", start_loop=False) as app:
        yield app


@pytest.fixture()
def readers(explorer, monkeypatch):
    """Every file the scene hands to a reader (none is parsed in these tests unless asked)."""
    from app.scenes import inertia_explorer

    calls: list[str] = []

    def recorded(filename, content, **_):
        calls.append(filename)
        raise ValueError(f"{filename} was handed to the reader (test)")

    monkeypatch.setattr(inertia_explorer, "body_in_worker", recorded)
    return calls


def _button(app):
    return app.scene.upload._impl.uuid


def _acks(messages, transfer):
    return [
        (m["transferred_bytes"], m["total_bytes"])
        for m in messages
        if m.get("type") == "FileTransferPartAck" and m.get("transfer_uuid") == transfer
    ]


def _refusals(app, before):
    return [body for title, body in app.messages[before:] if title == "Refused"]


def _stored(app):
    return dict(app.server.gui._current_file_upload_states)


def test_an_oversized_declared_size_is_refused_before_any_part_is_stored(explorer, readers):
    app = explorer
    with raw_client(app) as sender, raw_client(app) as other:
        received(other, 0.2)
        before, refused = len(app.messages), app.scene.upload_refusals
        size = limits.MAX_BYTES + 1
        transfer = start_upload(sender, _button(app), "huge.stl", size, 41)
        for index in range(3):  # the page sends its parts without waiting for an answer
            send_part(sender, _button(app), transfer, index, b"\0" * 1024)
        wait_for(lambda: _refusals(app, before), what="the refusal")
        assert "huge.stl is 20.0 MB; the limit is 20.0 MB" in _refusals(app, before)[0]
        seen = received(sender, 0.5)
        assert still_connected(sender, app=app)  # every part sent before this has been handled
        assert transfer not in _stored(app) and not readers
        assert app.scene.upload_refusals == refused  # the scene never heard of it
        assert _acks(seen, transfer) == [(size, size)]  # the release only: no part was kept
        removed = [m["uuid"] for m in seen if m.get("type") == "RemoveNotificationMessage"]
        assert removed == [f"upload-{transfer}"]  # the page's "Uploading" spinner is taken away
        shown = [m for m in seen if m.get("type") == "NotificationShowMessage"]
        assert any("huge.stl" in m["props"]["body"] for m in shown)
        heard = received(other, 0.5)  # the other browser hears nothing of it
        assert not [m for m in heard if "Notification" in str(m.get("type"))]
        assert not _acks(heard, transfer)


@pytest.mark.parametrize(
    ("size", "parts", "name", "message"),
    [
        (-5, 1, "a.stl", "in a form this server does not take"),
        (2**64 - 1, 1, "a.stl", "in a form this server does not take"),
        (10, limits.MAX_PARTS + 1, "a.stl", "in a form this server does not take"),
        (10, 0, "a.stl", "in a form this server does not take"),
        (10, 1, "x" * (limits.MAX_NAME + 1), "file name is at most"),
    ],
)
def test_a_transfer_no_page_would_announce_is_refused(explorer, readers, size, parts, name, message):
    app = explorer
    with raw_client(app) as sender:
        before = len(app.messages)
        transfer = start_upload(sender, _button(app), name, size, parts)
        wait_for(lambda: _refusals(app, before), what="the refusal")
        assert message in _refusals(app, before)[0]
        assert transfer not in _stored(app) and not readers
        assert still_connected(sender, app=app)


def test_parts_adding_up_to_more_than_the_declared_size_drop_the_transfer(explorer, readers):
    app = explorer
    with raw_client(app) as sender:
        before = len(app.messages)
        transfer = start_upload(sender, _button(app), "liar.stl", 100, 3)
        send_part(sender, _button(app), transfer, 0, b"a" * 80)
        send_part(sender, _button(app), transfer, 1, b"b" * 80)  # 160 bytes of a declared 100
        send_part(sender, _button(app), transfer, 2, b"c" * 80)
        wait_for(lambda: _refusals(app, before), what="the refusal")
        assert "liar.stl sent more bytes than it declared (100)" in _refusals(app, before)[0]
        seen = received(sender, 0.5)
        assert still_connected(sender, app=app)
        assert transfer not in _stored(app) and not readers
        assert _acks(seen, transfer) == [(80, 100), (100, 100)]  # one part kept, then the release


def test_a_shared_panels_upload_is_acknowledged_to_its_browser_only(explorer, readers):
    """viser broadcasts the acknowledgements of a shared panel's upload; every other page took them as an
    upload of its own. They go to the uploading browser only, the last with the whole size."""
    app = explorer
    with raw_client(app) as sender, raw_client(app) as other:
        received(other, 0.2)
        content = b"solid x\nendsolid x\n" * 40
        transfer = send_upload(sender, _button(app), "box.stl", content)
        wait_for(lambda: readers, what="the file handed to the reader")
        seen = received(sender, 0.5)
        assert _acks(seen, transfer)[-1] == (len(content), len(content))
        assert not _acks(received(other, 0.5), transfer)


def test_uploads_in_flight_are_limited_per_browser_and_for_the_server(explorer, readers):
    app = explorer
    with contextlib.ExitStack() as stack:
        # Each from a machine of its own (one address sends one file at a time: the next test).
        clients = [stack.enter_context(raw_client(app, source=f"127.0.1.{k}")) for k in range(limits.MAX_TRANSFERS + 1)]
        first = clients[0]
        before = len(app.messages)
        held = start_upload(first, _button(app), "slow.stl", 2000, 2)
        send_part(first, _button(app), held, 0, b"\0" * 1000)  # half of it: still arriving
        wait_for(lambda: held in _stored(app), what="the first transfer")
        start_upload(first, _button(app), "second.stl", 10, 1)
        wait_for(lambda: _refusals(app, before), what="the second file from the same browser refused")
        assert "previous file is still arriving" in _refusals(app, before)[0]
        for ws in clients[1 : limits.MAX_TRANSFERS]:  # the server's other places
            start_upload(ws, _button(app), "slow.stl", 2000, 2)
        wait_for(lambda: len(_stored(app)) == limits.MAX_TRANSFERS, what="every place taken")
        before = len(app.messages)
        start_upload(clients[-1], _button(app), "late.stl", 10, 1)
        wait_for(lambda: _refusals(app, before), what="one transfer too many refused")
        assert f"receiving {limits.MAX_TRANSFERS} other files" in _refusals(app, before)[0]
        assert len(_stored(app)) == limits.MAX_TRANSFERS
    # The browsers left: viser dropped their transfers, and the places are free again.
    wait_for(lambda: not _stored(app), what="the transfers of departed browsers to be dropped")
    with raw_client(app) as ws:
        before = len(readers)
        send_upload(ws, _button(app), "after.stl", b"solid x\nendsolid x\n")
        wait_for(lambda: len(readers) > before, what="the next upload to reach the reader")


def test_one_address_sends_one_file_at_a_time_however_many_connections(explorer, readers):
    app = explorer
    with raw_client(app, source="127.0.2.1") as one, raw_client(app, source="127.0.2.1") as two:
        held = start_upload(one, _button(app), "slow.stl", 2000, 2)
        wait_for(lambda: held in _stored(app), what="the first transfer")
        before = len(app.messages)
        start_upload(two, _button(app), "second.stl", 10, 1)
        wait_for(lambda: _refusals(app, before), what="the second connection's file refused")
        assert "another file from your address is arriving" in _refusals(app, before)[0]
        with raw_client(app, source="127.0.2.2") as elsewhere:  # another machine may
            send_upload(elsewhere, _button(app), "other.stl", b"solid x\nendsolid x\n")
            wait_for(lambda: "other.stl" in readers, what="another address's upload")


def test_a_transfer_silent_too_long_gives_its_place_to_the_next(explorer, readers, monkeypatch):
    app = explorer
    with raw_client(app, source="127.0.2.3") as stalled, raw_client(app, source="127.0.2.4") as next_one:
        held = start_upload(stalled, _button(app), "silent.stl", 2000, 2)
        wait_for(lambda: held in _stored(app), what="the silent transfer")
        monkeypatch.setattr(limits, "IDLE_SECONDS", 0.0)  # no part for longer than that
        monkeypatch.setattr(limits, "MAX_TRANSFERS", 1)
        send_upload(next_one, _button(app), "next.stl", b"solid x\nendsolid x\n")
        wait_for(lambda: "next.stl" in readers, what="the next upload to take the place")
        assert held not in _stored(app)


def test_a_stalled_transfer_gives_its_place_to_the_next(explorer, readers, monkeypatch):
    app = explorer
    with raw_client(app) as stalled, raw_client(app) as next_one:
        held = start_upload(stalled, _button(app), "stalled.stl", 2000, 2)
        wait_for(lambda: held in _stored(app), what="the stalled transfer")
        monkeypatch.setattr(limits, "STALL_SECONDS", 0.0)  # it has waited long enough
        monkeypatch.setattr(limits, "MAX_TRANSFERS", 1)
        send_upload(next_one, _button(app), "next.stl", b"solid x\nendsolid x\n")
        wait_for(lambda: "next.stl" in readers, what="the next upload to take the place")
        assert held not in _stored(app)


def test_a_good_file_still_arrives_and_becomes_the_body(explorer):
    app = explorer
    content = trimesh.creation.box(extents=(0.3, 0.2, 0.1)).export(file_type="stl")
    with raw_client(app) as ws:
        before = len(app.messages)
        send_upload(ws, _button(app), "brick.stl", content)
        wait_for(lambda: any(title == "Mesh loaded" for title, _ in app.messages[before:]), 60, what="the body loaded")
        assert app.scene.uploaded is not None and app.scene.uploaded.name == "brick.stl"
        assert not _stored(app)
