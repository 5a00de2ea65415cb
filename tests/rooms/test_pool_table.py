"""The pool's shared teacher's table (app.teaching.pool_table) against a real redis-server on loopback.

Two or three :class:`PoolTable` objects stand in for the processes of a pool; most tests turn their
cycles by hand (``cycle()``), so what each one has read is known exactly; the tests of expiry,
Spotlight requests and a Redis that dies run their threads and poll.
"""

from __future__ import annotations

import json
import time
from collections.abc import Iterator
from pathlib import Path

import pytest
import redis

from app.rooms.redis_server import redis_conf
from app.teaching.pool_table import (
    MAX_REQUESTS,
    MAX_ROWS,
    MAX_VALUE,
    TTL,
    PoolPlace,
    PoolRow,
    PoolTable,
    decode_rows,
    encode_rows,
    place_from_environment,
)
from app.teaching.teacher import Row, table_html
from tests.harness import wait_for
from tests.rooms.running import RedisServer, redis_server


def _row(number: int, name: str = "", scene: str = "Heavy top") -> PoolRow:
    return PoolRow(number, name, scene, (("Spin", "120"), ("Tilt", "0.3")), 1.25, True, 1_700_000_000.0)


class Process:
    """One process's part of the table: its rows, whether a teacher is here, what it answers."""

    def __init__(self, place: PoolPlace, rows: list[PoolRow]) -> None:
        self.rows = rows
        self.watching = True
        self.changes = 0
        self.table = PoolTable(place, lambda: list(self.rows), self.answer, lambda: self.watching, self.changed)

    def answer(self, number: int) -> str:
        if number not in {row.number for row in self.rows}:
            raise ValueError("it is not connected (it may just have left)")
        return f"rbl1:state-of-{number}"

    def changed(self) -> None:
        self.changes += 1


@pytest.fixture()
def server() -> Iterator[RedisServer]:
    with redis_server() as running:
        yield running


def _place(server: RedisServer, index: int, size: int = 2) -> PoolPlace:
    return PoolPlace("127.0.0.1", server.port, "homework", index, size)


def _numbers(table: PoolTable) -> list[int]:
    return sorted(row.number for row in table.remote_rows())


# ---------------------------------------------------------------------------------------------- pieces
def test_the_place_comes_from_the_environment_or_a_precise_refusal() -> None:
    env = {"RBL_REDIS": "127.0.0.1:6390", "RBL_POOL": "homework 2 3"}
    place = place_from_environment(env)
    assert place == PoolPlace("127.0.0.1", 6390, "homework", 2, 3)
    assert place_from_environment(env | {"RBL_REDIS_PASSWORD": "pw"}).password == "pw"  # type: ignore[union-attr]
    # Process 2 of 3 numbers its sessions 2, 5, 8, ...: every number names its process.
    assert [place.owner(n) for n in (1, 2, 3, 4, 5, 8)] == [1, 2, 3, 1, 2, 2]
    assert place_from_environment({}) is None and place_from_environment({"RBL_REDIS": "h:1"}) is None
    for bad, said in [
        ({"RBL_REDIS": "nohost", "RBL_POOL": "a 1 2"}, '"host:port"'),
        ({"RBL_REDIS": "h:99999", "RBL_POOL": "a 1 2"}, '"host:port"'),
        ({"RBL_REDIS": "h:1", "RBL_POOL": "a 1"}, "NAME INDEX SIZE"),
        ({"RBL_REDIS": "h:1", "RBL_POOL": "A<b> 1 2"}, "NAME INDEX SIZE"),
        ({"RBL_REDIS": "h:1", "RBL_POOL": "a 3 2"}, "got 3 of 2"),
    ]:
        with pytest.raises(ValueError, match=said):
            place_from_environment(bad)


def test_rows_go_through_json_and_back_and_bad_rows_are_left_out() -> None:
    place = PoolPlace("127.0.0.1", 1, "homework", 1, 2)
    rows = [_row(2, "Zoë"), _row(4, "<b>x</b>")]
    assert decode_rows(encode_rows(rows), place, 2) == [
        PoolRow(2, "Zoë", "Heavy top", (("Spin", "120"), ("Tilt", "0.3")), 1.2, True, 1_700_000_000.0),
        PoolRow(4, "<b>x</b>", "Heavy top", (("Spin", "120"), ("Tilt", "0.3")), 1.2, True, 1_700_000_000.0),
    ]  # the time to 0.1 s: a row that changes only there is not written again before the keep-alive
    good = [2, "a", "Pendulum", [["L", "1"]], 0.5, 0, 10.0]
    value = json.dumps(
        [
            good,
            [3, "b", "s", [], 0.0, 1, 1.0],  # an odd number is process 1's, not process 2's
            [4, 7, "s", [], 0.0, 1, 1.0],  # a name that is not text
            [6, "c", "s", [], float("nan"), 1, 1.0],  # a time that is not finite
            [8, "d", "s", [["a", "b"]] * 4, 0.0, 1, 1.0],  # more than three parameters
            [True, "e", "s", [], 0.0, 1, 1.0],
            [10, "x" * 500, "s", [], 0.0, 1, 1.0],  # cut to 64 characters
            "not a row",
        ]
    )
    decoded = decode_rows(value.encode(), place, 2)
    assert [r.number for r in decoded] == [2, 10] and decoded[1].name == "x" * 64
    assert decode_rows(b"not json", place, 2) == [] and decode_rows(b'{"a": 1}', place, 2) == []
    assert decode_rows(b"[" + b" " * MAX_VALUE + b"]", place, 2) == []  # too long: refused whole
    many = encode_rows([_row(2 * i) for i in range(1, 2 * MAX_ROWS)])
    assert len(json.loads(many)) == MAX_ROWS and len(decode_rows(many, place, 2)) == MAX_ROWS


def test_a_row_from_another_process_is_escaped_in_the_table() -> None:
    evil = PoolRow(2, '<img src=x onerror="alert(1)">', "<script>", (("<b>", "&amp;"),), 0.0, False, 0.0)
    row = Row(evil.number, evil.name, evil.scene, evil.parameters, evil.time, evil.playing, 5.0)
    page = table_html([row], notice="<i>down</i>")
    assert "<img" not in page and "<script>" not in page and "<b>" not in page and "<i>" not in page
    assert "&lt;img src=x onerror=&quot;alert(1)&quot;&gt;" in page and "&lt;i&gt;down&lt;/i&gt;" in page


# ---------------------------------------------------------------------------------------------- with Redis
def test_each_process_reads_the_others_rows_only_while_a_teacher_is_there(server: RedisServer) -> None:
    one = Process(_place(server, 1), [_row(1), _row(3)])
    two = Process(_place(server, 2), [_row(2, "Ann"), _row(4)])
    two.watching = False
    try:
        two.table.cycle()
        one.table.cycle()
        two.table.cycle()
        assert one.table.available and _numbers(one.table) == [2, 4] and one.changes == 1
        assert _numbers(two.table) == []  # no teacher on process 2: it only publishes
        # A change is written at the next look; an unchanged table is not written again before the keep-alive.
        writes = two.table.writes
        two.table.cycle()
        assert two.table.writes == writes
        two.rows[0] = _row(2, "Ann B")
        two.table.cycle()
        one.table.cycle()
        assert two.table.writes == writes + 1 and one.changes == 2
        assert [r.name for r in one.table.remote_rows()] == ["Ann B", ""]
        # Every key has a time to live: a dead process's rows cannot stay.
        client = redis.Redis(port=server.port)
        assert 0 < client.pttl("rbl:homework:r:2") <= TTL * 1000
        client.close()
    finally:
        one.table.stop()
        two.table.stop()


def test_a_dead_process_leaves_the_table_within_five_seconds(server: RedisServer) -> None:
    one = Process(_place(server, 1), [_row(1)])
    two = Process(_place(server, 2), [_row(2), _row(4)])
    one.table.start()
    two.table.start()
    try:
        wait_for(lambda: _numbers(one.table) == [2, 4], what="process 2's rows", timeout=10)
        # Process 2 dies without a word: its thread stops writing, nothing deletes its key.
        two.table._stop.set()
        stopped = time.monotonic()
        two.table._thread.join(timeout=10)
        wait_for(lambda: _numbers(one.table) == [], what="process 2's rows to expire", interval=0.05, timeout=10)
        assert time.monotonic() - stopped < 5.0  # the bound: TTL 2.5 s plus one 0.1 s read
    finally:
        one.table.stop()


def test_spotlight_asks_the_process_that_has_the_session(server: RedisServer) -> None:
    one = Process(_place(server, 1), [_row(1)])
    two = Process(_place(server, 2), [_row(2)])
    two.table.start()
    try:
        assert one.table.ask(2) == "rbl1:state-of-2"
        with pytest.raises(ValueError, match="not connected"):
            one.table.ask(4)  # process 2's number, but no such session there
        two.table.stop()
        with pytest.raises(ValueError, match="process 2 of the pool did not answer within 0.3 s"):
            one.table.ask(2, timeout=0.3)
        client = redis.Redis(port=server.port)
        queue = "rbl:homework:q:2"
        assert 0 < client.ttl(queue) <= 10  # the unanswered request goes by itself
        for _ in range(3 * MAX_REQUESTS):
            client.rpush(queue, b"junk")
        client.ltrim(queue, -MAX_REQUESTS, -1)
        two = Process(_place(server, 2), [_row(2)])
        two.table.start()  # junk in its queue is dropped; the next true request is answered
        assert one.table.ask(2, timeout=5) == "rbl1:state-of-2"
        client.close()
    finally:
        one.table.stop()
        two.table.stop()


def test_redis_killed_and_restarted_the_table_comes_back(server: RedisServer) -> None:
    one = Process(_place(server, 1), [_row(1)])
    two = Process(_place(server, 2), [_row(2)])
    one.table.start()
    two.table.start()
    try:
        wait_for(lambda: _numbers(one.table) == [2], what="process 2's rows", timeout=10)
        server.kill()
        wait_for(lambda: not one.table.available and _numbers(one.table) == [], what="Redis to be missed")
        with pytest.raises(ValueError, match="unreachable"):
            one.table.ask(2, timeout=0.5)
        server.start()  # the same port, empty: every process writes its rows again
        wait_for(lambda: one.table.available and _numbers(one.table) == [2], what="the table back", timeout=20)
        assert one.table.ask(2, timeout=5) == "rbl1:state-of-2"
    finally:
        one.table.stop()
        two.table.stop()


def test_a_server_with_a_password_takes_only_the_pools_processes(tmp_path: Path) -> None:
    config = tmp_path / "redis.conf"
    config.write_text(redis_conf("s3cret-of-the-pool"))
    with redis_server(config, "s3cret-of-the-pool") as server:
        right = PoolPlace("127.0.0.1", server.port, "homework", 1, 2, "s3cret-of-the-pool")
        assert "s3cret" not in repr(right)  # never in a log line
        one = Process(right, [_row(1)])
        two = Process(PoolPlace("127.0.0.1", server.port, "homework", 2, 2), [_row(2)])  # no password
        with pytest.raises(redis.AuthenticationError):
            two.table.cycle()
        one.table.cycle()
        assert one.table.available and one.table.writes == 1
        with pytest.raises(redis.AuthenticationError):
            redis.Redis(port=server.port).get("rbl:homework:r:1")
        one.table.stop()
        two.table.stop()
