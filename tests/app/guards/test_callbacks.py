"""The one wrapper every browser callback runs in (app.guards.callbacks.shielded): an exception reaches the
browser that acted as one notification and never the caller; a browser that left is not told, and what was
being made for it can be dropped; a result passes through."""

from __future__ import annotations

from types import SimpleNamespace

from app.contracts import Sessions
from app.guards.callbacks import SOMETHING_WENT_WRONG, first_argument, shielded, shielded_handler


def _client(gone: bool) -> SimpleNamespace:
    """A stand-in for a viser client: what ``departed`` reads of it (its message buffer done or not)."""
    buffer = SimpleNamespace(done=gone)
    return SimpleNamespace(client_id=7, _websock_connection=SimpleNamespace(get_message_buffer=lambda: buffer))


def _fails(_event: object) -> int:
    raise ZeroDivisionError("division by zero")


def test_an_exception_is_told_to_the_browser_that_acted_and_goes_no_further() -> None:
    told: list[tuple[object, str, str]] = []
    client = _client(gone=False)
    run = shielded(_fails, lambda c, title, body: told.append((c, title, body)))
    assert run(SimpleNamespace(client=client)) is None
    assert told == [(client, SOMETHING_WENT_WRONG, "ZeroDivisionError: division by zero")]


def test_a_browser_that_left_is_not_told_and_what_was_made_for_it_is_dropped() -> None:
    told: list[object] = []
    dropped: list[object] = []
    client = _client(gone=True)
    run = shielded_handler(_fails, lambda *a: told.append(a), left=dropped.append)
    run(SimpleNamespace(client=client))
    assert told == [] and dropped == [client]


def test_a_result_passes_through_and_the_client_may_be_the_first_argument() -> None:
    told: list[tuple[object, str, str]] = []
    client = _client(gone=False)
    assert shielded(lambda c, x: x * 2, lambda *a: told.append(a), client_of=first_argument)(client, 21) == 42
    shielded(lambda c: 1 / 0, lambda *a: told.append(a), client_of=first_argument)(client)
    assert told == [(client, SOMETHING_WENT_WRONG, "ZeroDivisionError: division by zero")]


def test_the_sessions_table_reads_like_a_dict_and_changes_only_through_its_methods() -> None:
    sessions: Sessions[str] = Sessions()
    sessions.put(1, "first")
    assert sessions.put_new(1, "other") == "first" and sessions.put_new(2, "second") == "second"
    assert dict(sessions) == {1: "first", 2: "second"} and len(sessions) == 2 and 1 in sessions
    assert sessions.get(3) is None and sessions.values() == ["first", "second"]
    for cid in sessions:  # iterating over a copy: a browser leaving meanwhile breaks nothing
        sessions.pop(cid)
    assert sessions.pop(1) is None and not sessions
