"""What an upload costs the server: resident memory and time for the largest files a browser may send.

The targets: no upload of 20 MB or less takes the server's resident memory past 1 GB, and a
pathological file costs bounded time. Each case here is handed to the inertia explorer as the page's
upload does (``InertiaExplorer.load_upload``: read in a worker process with memory and time limits, the
body swapped in under the simulation's lock), in a fresh server process, and the server's resident
memory is sampled every 10 ms while it runs. Cases: a binary STL within 0.1 % of the 20 MiB limit that
is a valid body (a 104,800-sided cylinder, 419,200 triangles), a 16 MB icosphere, a GLB of 20,000
instanced nodes (1 MB that would expand to 240,000 triangles), 20 MiB of garbage under an STL name, and
a 6 MB ASCII STL.

Run: ``python -m benchmarks.upload_memory`` (about a minute); writes ``benchmarks/results/upload_memory.md``
(or ``--out``).
"""

from __future__ import annotations

import argparse
import json
import os
import subprocess
import sys
import tempfile
from pathlib import Path

from app.uploads.limits import MAX_BYTES
from tests.harness import glb_with_nodes

RESULTS = Path(__file__).resolve().parent / "results" / "upload_memory.md"
LIMIT_MB = 1000.0


def cases(folder: Path) -> list[tuple[str, Path]]:
    """Write each case's file into ``folder``; returns (description, path)."""
    import numpy as np
    import trimesh

    files = {
        "cylinder, 104,800 sides (binary STL)": (
            "cylinder.stl",
            trimesh.creation.cylinder(radius=0.1, height=0.5, sections=104_800).export(file_type="stl"),
        ),
        "icosphere, 327,680 triangles (binary STL)": (
            "sphere.stl",
            trimesh.creation.icosphere(subdivisions=7).export(file_type="stl"),
        ),
        "20,000 instanced nodes (GLB)": ("nodes.glb", glb_with_nodes(20_000)),
        "garbage bytes under an STL name": ("garbage.stl", np.random.default_rng(1).bytes(MAX_BYTES)),
        "icosphere, 20,480 triangles (ASCII STL)": (
            "ascii.stl",
            trimesh.creation.icosphere(subdivisions=5).export(file_type="stl_ascii").encode(),
        ),
    }
    out = []
    for description, (name, content) in files.items():
        path = folder / name
        path.write_bytes(content)
        out.append((description, path))
    return out


_MEASURE = r"""
import json, sys, threading, time
from pathlib import Path

def rss_mb():
    return int(Path("/proc/self/statm").read_text().split()[1]) * 4096 / 1e6

if __name__ == "__main__":
    from tests.harness import running_app
    path = Path(sys.argv[1])
    content = path.read_bytes()
    with running_app("inertia_explorer", start_loop=False) as app:
        before = rss_mb()
        peak = [before]
        done = threading.Event()
        def sample():
            while not done.is_set():
                peak[0] = max(peak[0], rss_mb())
                time.sleep(0.01)
        sampler = threading.Thread(target=sample, daemon=True)
        sampler.start()
        start = time.perf_counter()
        accepted = app.scene.load_upload(path.name, content)
        seconds = time.perf_counter() - start
        done.set()
        sampler.join()
        message = app.scene.last_upload_message if not accepted else app.scene.label
        print(json.dumps({"accepted": bool(accepted), "seconds": seconds, "before": before,
                          "peak": max(peak[0], rss_mb()), "message": message}))
"""


def measure(path: Path) -> dict:
    """Upload ``path`` to a fresh server process; its result as a dict."""
    root = Path(__file__).resolve().parent.parent
    with tempfile.NamedTemporaryFile("w", suffix=".py", delete=False) as script:
        script.write(_MEASURE)
    try:
        env = {**os.environ, "PYTHONPATH": str(root)}
        done = subprocess.run(
            [sys.executable, script.name, str(path)], capture_output=True, text=True, env=env, timeout=300, cwd=root
        )
    finally:
        os.unlink(script.name)
    lines = [line for line in done.stdout.splitlines() if line.startswith("{")]
    if not lines:
        raise RuntimeError(f"the measurement of {path.name} failed:\n{done.stderr[-2000:]}")
    result: dict = json.loads(lines[-1])
    return result


def main(argv: list[str] | None = None) -> str:
    parser = argparse.ArgumentParser(description=__doc__.splitlines()[0])
    parser.add_argument("--out", type=Path, default=RESULTS)
    args = parser.parse_args(argv)
    rows = []
    with tempfile.TemporaryDirectory() as folder:
        for description, path in cases(Path(folder)):
            size = path.stat().st_size / 1e6
            r = measure(path)
            said = " ".join(r["message"].replace("|", "/").split())
            verdict = "accepted" if r["accepted"] else "refused: " + (said if len(said) <= 90 else said[:87] + "...")
            rows.append(
                f"| {description} | {size:.1f} | {verdict} | {r['seconds']:.1f} | {r['before']:.0f} | {r['peak']:.0f} |"
            )
            print(rows[-1], flush=True)
    worst = max(float(row.split("|")[-2]) for row in rows)
    text = "\n".join(
        [
            "# Upload memory: the server's resident memory while it takes the largest uploads",
            "",
            "`python -m benchmarks.upload_memory`. Each file is handed to the inertia explorer as a page's upload "
            "is (read in a worker process with a 1 GiB address-space and 30 s limit, swapped in under the lock), "
            "in a fresh server process; RSS sampled every 10 ms. MB = 10⁶ bytes.",
            "",
            "| file | size (MB) | answer | seconds | server RSS before (MB) | server RSS peak (MB) |",
            "| --- | ---: | --- | ---: | ---: | ---: |",
            *rows,
            "",
            f"Largest server RSS: **{worst:.0f} MB** (target: at most {LIMIT_MB:.0f} MB for any upload of 20 MB or "
            f"less) — {'met' if worst <= LIMIT_MB else 'NOT met'}.",
            "",
        ]
    )
    args.out.parent.mkdir(parents=True, exist_ok=True)
    args.out.write_text(text)
    print(f"written {args.out}")
    return text


if __name__ == "__main__":
    main()
