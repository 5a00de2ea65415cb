"""The rules for a transfer (app.uploads.transfers), without viser or a browser: what a declared start may be,
how many may be in flight, when one has stalled. tests/app/guards/test_upload_guard.py sends the same
through a real websocket."""

from __future__ import annotations

import pytest

from app.uploads import limits
from app.uploads.transfers import Declared, InFlight, Transfers, overrun_refusal, start_refusal, well_formed_count

NONE_IN_FLIGHT = InFlight(0, 0, 0)


def test_a_well_formed_start_with_nothing_in_flight_may_start() -> None:
    assert start_refusal(Declared("box.stl", "t1", 684, 1), NONE_IN_FLIGHT) is None
    assert start_refusal(Declared("empty.stl", "t1", 0, 0), NONE_IN_FLIGHT) is None
    assert start_refusal(Declared("big.stl", "t1", limits.MAX_BYTES, limits.MAX_PARTS), NONE_IN_FLIGHT) is None


@pytest.mark.parametrize(
    ("declared", "expected"),
    [
        (Declared(None, "t1", 10, 1), "a file name is at most 255 characters of text"),
        (Declared("x" * (limits.MAX_NAME + 1), "t1", 10, 1), "a file name is at most 255 characters"),
        (Declared("box.stl", 7, 10, 1), "a file name is at most 255 characters"),
        (
            Declared("box.stl", "t1", True, 1),
            "box.stl was sent in a form this server does not take (size True, 1 parts)",
        ),
        (Declared("box.stl", "t1", -1, 1), "(size -1, 1 parts)"),
        (Declared("box.stl", "t1", 2**53 + 1, 1), "(size 9007199254740993, 1 parts)"),
        (Declared("box.stl", "t1", 10, 1.0), "(size 10, 1.0 parts)"),
        (Declared("box.stl", "t1", 10, limits.MAX_PARTS + 1), "(size 10, 1025 parts)"),
        (Declared("box.stl", "t1", 10, 0), "(size 10, 0 parts)"),
        (Declared("box.stl", "t1", 0, 1), "(size 0, 1 parts)"),
        (Declared("../../etc/box.stl", "t1", limits.MAX_BYTES + 1, 1), "box.stl is 20.0 MB; the limit is 20.0 MB"),
    ],
)
def test_a_malformed_or_oversized_start_is_refused_with_its_reason(declared: Declared, expected: str) -> None:
    reason = start_refusal(declared, NONE_IN_FLIGHT)
    assert reason is not None and reason.startswith("Upload refused: ") and expected in reason
    assert "../" not in reason  # the folder a browser put before the name is never echoed


def test_transfers_in_flight_are_limited_per_browser_per_address_and_for_the_server() -> None:
    box = Declared("box.stl", "t9", 684, 1)
    assert "your previous file is still arriving" in str(start_refusal(box, InFlight(limits.PER_CLIENT, 1, 0)))
    assert "from your address is arriving" in str(start_refusal(box, InFlight(0, 1, limits.PER_ADDRESS)))
    assert "receiving 8 other files" in str(start_refusal(box, InFlight(0, limits.MAX_TRANSFERS, 0)))
    assert start_refusal(box, InFlight(0, limits.MAX_TRANSFERS - 1, 0)) is None


def test_the_overrun_refusal_names_the_file_and_its_declared_size() -> None:
    assert overrun_refusal("dir/liar.stl", 1234567) == (
        "Upload refused: liar.stl sent more bytes than it declared (1,234,567)."
    )


def test_a_count_is_an_int_from_zero_to_two_to_the_53() -> None:
    assert [well_formed_count(v) for v in (0, 2**53, 5)] == [True, True, True]
    assert [well_formed_count(v) for v in (-1, 2**53 + 1, False, 1.0, "3", None)] == [False] * 6


def test_a_transfer_stalls_after_its_idle_or_its_total_time_and_not_before() -> None:
    transfers = Transfers()
    transfers.accepted("t1", "127.0.0.2", now=100.0)
    assert transfers.address("t1") == "127.0.0.2" and transfers.address("t2") == ""
    assert not transfers.stalled("t1", 100.0 + limits.IDLE_SECONDS)
    assert transfers.stalled("t1", 100.0 + limits.IDLE_SECONDS + 0.001)
    # Parts keep a transfer alive, but not past its total time.
    step = limits.IDLE_SECONDS / 2
    now = 100.0
    while now + step <= 100.0 + limits.STALL_SECONDS:
        now += step
        transfers.sent_part("t1", now)
        assert not transfers.stalled("t1", now)
    transfers.sent_part("t1", 100.0 + limits.STALL_SECONDS + 0.001)
    assert transfers.stalled("t1", 100.0 + limits.STALL_SECONDS + 0.001)


def test_a_transfer_first_met_counts_from_then_and_ended_ones_are_forgotten() -> None:
    transfers = Transfers()
    assert not transfers.stalled("unseen", 50.0)  # met now: counts from now
    assert transfers.stalled("unseen", 50.0 + limits.IDLE_SECONDS + 1.0)
    transfers.accepted("a", "127.0.0.3", 0.0)
    transfers.accepted("b", "127.0.0.4", 0.0)
    transfers.keep_only({"b"})
    assert transfers.address("a") == "" and transfers.address("b") == "127.0.0.4"
    transfers.forget("b")
    transfers.sent_part("b", 1.0)  # a part after the end keeps nothing
    assert transfers.address("b") == ""
