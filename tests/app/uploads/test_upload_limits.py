"""Uploads are limited before and while they are parsed (app.uploads.limits, app.uploads.worker).

A file whose header declares more than the limits is refused before anything parses it; the parse runs
in a worker process whose memory and time are capped, so no upload can take the server's memory or
its frames; the body that comes back is the one the in-process reader gives.
"""

from __future__ import annotations

import gc
import struct
import time

import numpy as np
import pytest
import trimesh

from app.uploads.limits import MAX_BYTES, MAX_FACES, MAX_NODES, READERS, check_declared_size
from app.uploads.reading import NotWatertightError, body_from_upload
from app.uploads.worker import body_in_worker
from tests.harness import glb_with_nodes


def test_a_glb_of_20000_instanced_nodes_is_refused_before_parsing():
    content = glb_with_nodes(20_000)
    assert len(content) < 2 * 1024 * 1024  # about a megabyte: the size check alone lets it through
    gc.disable()  # a collection of the test process's heap would be counted as this thread's CPU
    try:
        start = time.thread_time()
        with pytest.raises(ValueError, match=f"declares 20,000 nodes; the limit is {MAX_NODES:,}"):
            check_declared_size("city.glb", content)
        spent = time.thread_time() - start
    finally:
        gc.enable()
    assert spent < 0.5  # the header only: this thread's CPU, not the app threads beside it
    with pytest.raises(ValueError, match="20,000 nodes"):
        body_in_worker("city.glb", content)


def test_a_glb_within_the_limits_but_heavy_in_instances_is_refused_by_its_geometry_total():
    sphere = trimesh.creation.icosphere(subdivisions=4)  # 5,120 triangles
    check_declared_size("few.glb", glb_with_nodes(3, sphere))  # 15,360 triangles drawn: fine
    with pytest.raises(ValueError, match="numbers of geometry shown by 900 nodes"):
        check_declared_size("many.glb", glb_with_nodes(900, sphere))  # 4.6 million: refused


@pytest.mark.parametrize(
    ("name", "content", "message"),
    [
        ("big.stl", b"\0" * 80 + struct.pack("<I", MAX_FACES + 1) + b"\0" * 50 * (MAX_FACES + 1), "triangles"),
        ("big.ply", b"ply\nformat ascii 1.0\nelement vertex 3\nelement face 600000\nend_header\n", "faces"),
        ("big.obj", b"v 0 0 0\n" + b"f 1 1 1\n" * (MAX_FACES + 1), "faces"),
        (
            "packed.glb",
            b"glTF" + struct.pack("<II", 2, 40) + struct.pack("<II", 12, 0x4E4F534A) + b'{"a": [1,2]}',
            None,
        ),
    ],
    ids=["big.stl", "big.ply", "big.obj", "packed.glb"],  # not the contents: an id of 25 MB took seconds
)
def test_declared_sizes_of_each_format(name, content, message):
    if message is None:
        check_declared_size(name, content)  # a small, well-formed header passes
        return
    with pytest.raises(ValueError, match=f"{name} declares .* {message}; the limit is"):
        check_declared_size(name, content)


def test_the_worker_returns_the_body_the_reader_gives():
    content = trimesh.creation.box(extents=(0.3, 0.2, 0.1)).export(file_type="stl")
    here = body_from_upload("box.stl", content)
    there = body_in_worker("box.stl", content)
    np.testing.assert_array_equal(there.mass_properties.tensor, here.mass_properties.tensor)
    assert there.mass_properties.mass == here.mass_properties.mass


def test_the_worker_passes_an_open_mesh_with_its_hull_and_refusals_with_their_reason():
    box = trimesh.creation.box(extents=(0.3, 0.2, 0.1))
    open_mesh = trimesh.Trimesh(box.vertices, box.faces[1:], process=False).export(file_type="stl")
    with pytest.raises(NotWatertightError) as caught:
        body_in_worker("open.stl", open_mesh)
    assert caught.value.hull is not None and caught.value.hull.is_watertight
    with pytest.raises(ValueError, match="is empty"):
        body_in_worker("empty.stl", b"")
    with pytest.raises(ValueError, match="the limit is 20.0 MB"):
        body_in_worker("huge.stl", b"\0" * (MAX_BYTES + 1))


def test_a_worker_out_of_memory_or_time_is_refused_and_the_server_goes_on():
    sphere = trimesh.creation.icosphere(subdivisions=6).export(file_type="stl")  # 81,920 triangles
    with pytest.raises(ValueError, match="needs more than"):
        body_in_worker("sphere.stl", sphere, memory_limit=64 * 1024 * 1024)
    with pytest.raises(ValueError, match="took more than"):
        body_in_worker("sphere.stl", sphere, time_limit=1e-3)
    assert body_in_worker("sphere.stl", sphere).mass_properties.mass > 0  # the next upload is read as usual


def test_an_upload_that_finds_every_reader_busy_is_refused_at_once_without_a_worker(monkeypatch):
    from app.uploads import worker as upload_worker

    def no_worker(*_args, **_kwargs):
        raise AssertionError("a worker was started while every reader was busy")

    content = trimesh.creation.box(extents=(0.3, 0.2, 0.1)).export(file_type="stl")
    taken = 0
    try:
        while upload_worker._readers.acquire(blocking=False):  # every reader busy with another upload
            taken += 1
        assert taken == READERS
        monkeypatch.setattr(upload_worker, "_read_in_worker", no_worker)
        start = time.monotonic()
        with pytest.raises(upload_worker.ReadersBusy, match=r"box\.stl was not read: .* Upload it again"):
            body_in_worker("box.stl", content)
        assert time.monotonic() - start < 0.5  # refused at once, not queued behind the others
    finally:
        for _ in range(taken):
            upload_worker._readers.release()
    monkeypatch.undo()
    assert body_in_worker("box.stl", content).mass_properties.mass > 0  # free again: read as usual


def test_concurrent_uploads_run_at_most_readers_workers_at_once(monkeypatch):
    import threading

    from app.uploads import worker as upload_worker

    real = upload_worker._read_in_worker
    running, peak, lock = [0], [0], threading.Lock()

    def counted(*args, **kwargs):
        with lock:
            running[0] += 1
            peak[0] = max(peak[0], running[0])
        try:
            return real(*args, **kwargs)
        finally:
            with lock:
                running[0] -= 1

    monkeypatch.setattr(upload_worker, "_read_in_worker", counted)
    content = trimesh.creation.box(extents=(0.3, 0.2, 0.1)).export(file_type="stl")
    outcomes: list[object] = []
    gate = threading.Barrier(8)

    def one() -> None:
        gate.wait()
        try:
            outcomes.append(body_in_worker("box.stl", content))
        except upload_worker.ReadersBusy as exc:
            outcomes.append(exc)

    threads = [threading.Thread(target=one) for _ in range(8)]  # eight browsers upload at once
    for thread in threads:
        thread.start()
    for thread in threads:
        thread.join(timeout=120)
    assert len(outcomes) == 8 and 1 <= peak[0] <= READERS
    bodies = [o for o in outcomes if not isinstance(o, Exception)]
    assert bodies and len(bodies) + sum(isinstance(o, upload_worker.ReadersBusy) for o in outcomes) == 8
