"""Hostile connections against a presenter room: do the followers keep their frame rate, does memory stay bounded?

``python -m benchmarks.hostile [--hostile 300] [--followers 30] [--seconds 20]`` starts a presenter room on
127.0.0.1 (the heavy top, playing) and, in two processes of their own, ``--followers`` raw clients that read
the lecture as pages do (each from its own 127.0.1.x address) and ``--hostile`` raw clients from ten addresses
127.0.2.x that, for ``--seconds``, keep doing what the server must shrug off: floods of a message type viser
relays (``GuiFormDirtyMessage``, 10 kB each), random other message types, floods of camera messages, and PIN
guessers that reconnect for every wrong PIN. It writes ``benchmarks/results/hostile.md``: the followers' frame
rate (pose messages per second of the top's body: one a frame), the server's resident memory, what the gate
dropped and the caps refused. Loopback only; it stops by itself.
"""

from __future__ import annotations

import argparse
import asyncio
import multiprocessing as mp
import random
import statistics
import time
from pathlib import Path
from typing import Any

import msgspec
import viser
import zstandard
from viser import _messages
from websockets.asyncio.client import connect

from benchmarks.serve_clients import WARMUP, read_clients
from benchmarks.soak import resident_mb
from tests.harness import CAMERA_MESSAGE, running_app

RESULTS = Path(__file__).resolve().parent / "results" / "hostile.md"
BODY = "/scene/top"  # the heavy top's body: its pose is sent once a frame
TARGET_FPS = 55.0
TARGET_MB = 1024.0
PIN = "Lab2718"
ADDRESSES = 10
"""The hostile clients' machines (a few students' laptops), 127.0.2.1 to 127.0.2.10."""
KINDS = ("relayed flood", "other types", "camera flood", "PIN guesser")
OTHER_TYPES = sorted(set(_messages.Message._subclass_from_type_string()) - {"GuiUpdateMessage", "ViewerCameraMessage"})


def _uuid_of(raw: bytes, kind: str, label: str) -> str | None:
    inner_size = int.from_bytes(raw[:8], "little")
    compressed = int.from_bytes(raw[8:16], "little")
    inner = zstandard.ZstdDecompressor().decompress(raw[16 : 16 + compressed], max_output_size=inner_size)
    for m in msgspec.msgpack.decode(inner)["messages"]:
        if m.get("type") == kind and (m.get("props") or {}).get("label") == label:
            return str(m["uuid"])
    return None


async def _one(port: int, k: int, deadline: float, tally: dict[str, int], kinds: tuple[str, ...] = KINDS) -> None:
    """Connection after connection from one hostile client until ``deadline``."""
    kind = kinds[k % len(kinds)]
    source = f"127.0.2.{k % ADDRESSES + 1}"
    rng = random.Random(k)
    while time.monotonic() < deadline:
        try:
            async with connect(
                f"ws://127.0.0.1:{port}",
                subprotocols=[f"viser-v{viser.__version__}"],  # type: ignore[list-item]
                local_addr=(source, 0),
                max_size=None,
                open_timeout=10,
                close_timeout=1,
            ) as ws:
                tally["connections"] += 1
                await ws.send(CAMERA_MESSAGE)
                if kind == "relayed flood":
                    dirty = msgspec.msgpack.encode({"type": "GuiFormDirtyMessage", "uuid": "x" * 10_000})
                    for _ in range(30):
                        await ws.send(dirty)
                elif kind == "other types":
                    for _ in range(30):
                        await ws.send(msgspec.msgpack.encode({"type": rng.choice(OTHER_TYPES), "uuid": "x"}))
                elif kind == "camera flood":
                    for _ in range(1_000):
                        await ws.send(CAMERA_MESSAGE)
                else:
                    box = button = None
                    async with asyncio.timeout(10):
                        while box is None or button is None:
                            raw = await ws.recv()
                            box = box or _uuid_of(raw, "GuiTextMessage", "Presenter PIN")  # type: ignore[arg-type]
                            button = button or _uuid_of(raw, "GuiButtonMessage", "Present")  # type: ignore[arg-type]
                    wrong = f"{rng.randrange(10**6):06d}"
                    await ws.send(
                        msgspec.msgpack.encode({"type": "GuiUpdateMessage", "uuid": box, "updates": {"value": wrong}})
                    )
                    await ws.send(
                        msgspec.msgpack.encode({"type": "GuiUpdateMessage", "uuid": button, "updates": {"value": True}})
                    )
                    tally["wrong PINs"] += 1
                try:
                    async with asyncio.timeout(2):  # read what comes (a page reads), then leave
                        while True:
                            await ws.recv()
                except TimeoutError:
                    tally["left by the client after 2 s"] += 1
        except (TimeoutError, OSError) as exc:
            tally[type(exc).__name__] += 1
        except Exception as exc:  # noqa: BLE001 - closed by the server: counted by its code
            code = getattr(getattr(exc, "rcvd", None), "code", None)
            tally[f"closed by the server ({code})" if code else type(exc).__name__] += 1
        await asyncio.sleep(0.05)


def attack(port: int, n: int, seconds: float, out: Any, kinds: tuple[str, ...] = KINDS) -> None:
    """In a child process: ``n`` hostile clients for ``seconds``; report what happened to them."""
    from collections import Counter

    tally: Counter[str] = Counter()

    async def main() -> None:
        deadline = time.monotonic() + seconds
        await asyncio.gather(*(_one(port, k, deadline, tally, kinds) for k in range(n)))

    asyncio.run(main())
    out.put(dict(tally))


def measure(n_hostile: int, n_followers: int, seconds: float, kinds: tuple[str, ...] = KINDS) -> dict[str, Any]:
    """One run: the followers' frame rates and the server's memory with ``n_hostile`` hostile clients."""
    with running_app("heavy_top", presenter=True, pin=PIN) as app:
        ctx = mp.get_context("spawn")
        follow_out, attack_out = ctx.Queue(), ctx.Queue()
        sources = [f"127.0.1.{i + 1}" for i in range(n_followers)]  # a machine each
        readers = ctx.Process(
            target=read_clients, args=(app.port, n_followers, seconds, follow_out, sources), daemon=True
        )
        readers.start()
        deadline = time.monotonic() + 60
        while len(app.server.get_clients()) < n_followers and time.monotonic() < deadline:
            time.sleep(0.05)
        attackers = ctx.Process(
            target=attack, args=(app.port, n_hostile, WARMUP + seconds, attack_out, kinds), daemon=True
        )
        attackers.start()
        rss = [resident_mb()]
        t0, cpu0, frames0 = time.monotonic(), time.process_time(), app.simulation.frames
        while time.monotonic() - t0 < WARMUP + seconds:
            time.sleep(0.25)
            rss.append(resident_mb())
        elapsed = time.monotonic() - t0
        cpu = (time.process_time() - cpu0) / elapsed  # the server's process: cores it used
        drawn = (app.simulation.frames - frames0) / elapsed  # frames the server drew a second
        per_client = follow_out.get(timeout=120)
        rates = [nodes.get(BODY, 0.0) for _, _, nodes, _ in per_client]
        lost = [why for _, _, _, why in per_client]
        tally = attack_out.get(timeout=120)
        readers.join(timeout=10)
        attackers.join(timeout=10)
        buffer = len(app.server._websock_server._broadcast_buffer.message_from_id)
        return {
            "rates": rates,
            "lost": [why for why in lost if why],
            "rss_max": max(rss),
            "rss_start": rss[0],
            "tally": tally,
            "dropped": dict(app.gate.dropped.most_common(6)),
            "dropped_total": sum(app.gate.dropped.values()),
            "gate_closed": app.gate.closed,
            "refused": dict(app.admission.refused),
            "buffer": buffer,
            "cpu": cpu,
            "drawn": drawn,
        }


def report(result: dict[str, Any], n_hostile: int, n_followers: int, seconds: float) -> str:
    rates = result["rates"]
    slowest = min(rates) if rates else 0.0
    ok_fps = slowest >= TARGET_FPS
    ok_mb = result["rss_max"] < TARGET_MB
    tally = ", ".join(f"{k}: {v}" for k, v in sorted(result["tally"].items()))
    dropped = ", ".join(f"{k}: {v}" for k, v in result["dropped"].items())
    lines = [
        "# Hostile connections against a presenter room",
        "",
        f"`python -m benchmarks.hostile --hostile {n_hostile} --followers {n_followers} --seconds {seconds:g}`: a presenter",
        f"room (heavy top, playing) on 127.0.0.1, {n_followers} followers reading as pages do, {n_hostile} hostile clients",
        f"from {ADDRESSES} addresses (relayed-type floods, other message types, camera floods, reconnecting PIN guessers;",
        "a quarter each), all on this machine's cores with the server.",
        "",
        "| quantity | measured | target |",
        "| --- | --- | --- |",
        f"| followers' frame rate, slowest (frames/s) | {slowest:.1f} | ≥ {TARGET_FPS:g} ({'met' if ok_fps else 'NOT met'}) |",
        f"| followers' frame rate, median (frames/s) | {statistics.median(rates) if rates else 0.0:.1f} | |",
        f"| frames the server drew (frames/s) | {result['drawn']:.1f} | |",
        f"| followers that lost their connection | {len(result['lost'])} | 0 |",
        f"| server's resident memory, peak (MB) | {result['rss_max']:.0f} (at start {result['rss_start']:.0f}) | < {TARGET_MB:g} ({'met' if ok_mb else 'NOT met'}) |",
        f"| replay buffer after the attack (messages) | {result['buffer']} | as before: no hostile message kept |",
        f"| messages the gate dropped | {result['dropped_total']} ({dropped}) | |",
        f"| connections the gate closed for offences | {result['gate_closed']} | |",
        f"| connections the caps refused | {result['refused'] or 0} | |",
        f"| the server's process during the attack (cores of 2) | {result['cpu']:.2f} | |",
        f"| the hostile clients' side | {tally} | |",
        "",
    ]
    return "\n".join(lines)


def main(argv: list[str] | None = None) -> None:
    parser = argparse.ArgumentParser(description=__doc__.splitlines()[0])
    parser.add_argument("--hostile", type=int, default=300)
    parser.add_argument("--followers", type=int, default=30)
    parser.add_argument("--seconds", type=float, default=20.0)
    parser.add_argument("--kind", choices=KINDS, action="append", help="only these attacks (default: all four)")
    args = parser.parse_args(argv)
    if not (1 <= args.hostile <= 1000 and 1 <= args.followers <= 200 and 1.0 <= args.seconds <= 300.0):
        parser.error("bounded: 1-1000 hostile, 1-200 followers, 1-300 s")
    result = measure(args.hostile, args.followers, args.seconds, tuple(args.kind or KINDS))
    text = report(result, args.hostile, args.followers, args.seconds)
    RESULTS.write_text(text)
    print(text)


if __name__ == "__main__":
    main()
