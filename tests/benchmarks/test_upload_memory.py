"""The upload-memory benchmark measures the worst uploads a browser may send: its files are within the
20 MB limit and its largest valid body is near the limits (not a small file that proves nothing)."""

from __future__ import annotations

import trimesh

from app.uploads.limits import MAX_BYTES, MAX_FACES, MAX_NODES
from benchmarks import upload_memory


def test_the_cases_are_the_largest_a_browser_may_send(tmp_path):
    files = dict(upload_memory.cases(tmp_path))
    assert all(path.stat().st_size <= MAX_BYTES for path in files.values())
    cylinder = files["cylinder, 104,800 sides (binary STL)"]
    assert cylinder.stat().st_size > 0.999 * MAX_BYTES  # within 0.1 % of the size limit
    mesh = trimesh.load(cylinder, force="mesh")
    assert 0.75 * MAX_FACES < len(mesh.faces) <= MAX_FACES and mesh.is_watertight
    assert files["garbage bytes under an STL name"].stat().st_size == MAX_BYTES
    nodes = files["20,000 instanced nodes (GLB)"].read_bytes()
    assert b'"nodes"' in nodes and 20_000 > MAX_NODES
