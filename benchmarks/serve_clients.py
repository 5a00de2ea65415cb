"""The serve benchmark's clients (:mod:`benchmarks.serve`): websocket readers in a process of their own.

A module of its own so that the child process :func:`benchmarks.serve.measure` spawns imports only what reading
needs (the harness's client, msgspec, zstandard), not the app, the scenes and the integrators: that import was
a second of every row's time before its clients connected.
"""

from __future__ import annotations

import contextlib
import threading
import time
from collections import Counter
from typing import Any

import msgspec
import zstandard

from tests.harness import raw_client

WARMUP = 1.5  # s: the first messages (meshes, the panel) are not a frame's cost
POSE_MESSAGES = frozenset({"SetOrientationMessage", "SetPositionMessage"})


class _Message(msgspec.Struct):
    type: str
    name: Any = None  # a scene node's name (other messages have none, or something else)


class _Window(msgspec.Struct):
    messages: list[_Message]


_WINDOW = msgspec.msgpack.Decoder(_Window)


def posed_nodes(raw: bytes, zstd: zstandard.ZstdDecompressor | None = None) -> set[str]:
    """The scene nodes whose pose one websocket message (a window of viser messages) sets.

    viser's wire format: the msgpack's size and the compressed size (8 bytes each, little-endian), the
    zstd-compressed msgpack of ``{"messages": [...], ...}``, then raw binary buffers (not read here).
    ``zstd``: a decompressor to reuse (a reader of many messages makes one, not one a message).
    """
    inner_size = int.from_bytes(raw[:8], "little")
    compressed = int.from_bytes(raw[8:16], "little")
    zstd = zstd or zstandard.ZstdDecompressor()
    inner = zstd.decompress(raw[16 : 16 + compressed], max_output_size=inner_size)
    return {str(m.name) for m in _WINDOW.decode(inner).messages if m.type in POSE_MESSAGES}


def read_clients(port: int, n: int, seconds: float, out: Any, sources: list[str] | None = None) -> None:
    """In a child process: connect ``n`` clients, read for WARMUP + ``seconds``, report per client its
    bytes/s, messages/s and, per scene node, the messages/s that set the node's pose (``sources``: the
    loopback address each client connects from, default 127.0.0.1)."""

    class _Port:  # raw_client needs .port and a server to ask for its clients: skip that wait here
        def __init__(self) -> None:
            self.port = port

    counts: list[list[int]] = [[0, 0] for _ in range(n)]  # bytes, messages after the warm-up
    posed: list[Counter[str]] = [Counter() for _ in range(n)]  # node -> messages setting its pose
    lost: list[str] = ["" for _ in range(n)]  # why a client stopped reading before the end ("": it did not)
    stop = threading.Event()
    measuring = threading.Event()

    def read(ws: Any, i: int) -> None:
        while not stop.is_set():
            try:
                message = ws.recv(timeout=0.1)
            except TimeoutError:
                continue
            except Exception as exc:  # noqa: BLE001 - a closed connection: the row says so
                lost[i] = f"{type(exc).__name__}: {exc}"
                return
            if measuring.is_set():
                counts[i][0] += len(message)
                counts[i][1] += 1
                posed[i].update(posed_nodes(message))

    with contextlib.ExitStack() as stack:
        where = sources or [None] * n
        sockets = [stack.enter_context(raw_client(_Port(), wait=False, source=where[i])) for i in range(n)]
        readers = [threading.Thread(target=read, args=(ws, i), daemon=True) for i, ws in enumerate(sockets)]
        for r in readers:
            r.start()
        time.sleep(WARMUP)
        measuring.set()
        t0 = time.monotonic()
        time.sleep(seconds)
        measuring.clear()
        elapsed = time.monotonic() - t0
        stop.set()
        for r in readers:
            r.join(timeout=2.0)
    out.put(
        [
            (b / elapsed, m / elapsed, {node: k / elapsed for node, k in p.items()}, why)
            for (b, m), p, why in zip(counts, posed, lost, strict=True)
        ]
    )
