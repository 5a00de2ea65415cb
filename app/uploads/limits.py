"""Every limit on an upload, and the check a file's bytes must pass before anything parses them.

:func:`check_upload` reads only the size (:func:`check_size`) and each format's header (a 1 MB GLB of 20,000 instanced nodes
expands to gigabytes once parsed), so it costs microseconds and bounded memory. The transfer limits are
applied when a transfer starts (:mod:`app.uploads.transfers`, through :mod:`app.guards.uploads`), the
worker's by :mod:`app.uploads.worker`.
"""

from __future__ import annotations

import io
import json
import re
import struct
import zipfile
from pathlib import PurePath

from app.language.words import mark, say

__all__ = [
    "MAX_BYTES",
    "MAX_FACES",
    "MAX_NODES",
    "MAX_MESHES",
    "MAX_ACCESSORS",
    "MAX_ELEMENTS",
    "MAX_TRANSFERS",
    "PER_CLIENT",
    "PER_ADDRESS",
    "IDLE_SECONDS",
    "MAX_PARTS",
    "MAX_NAME",
    "STALL_SECONDS",
    "MEMORY_LIMIT",
    "TIME_LIMIT",
    "READERS",
    "MAX_MESSAGE",
    "MAX_ZIP_ENTRIES",
    "MAX_UNPACKED",
    "MAX_ZIP_RATIO",
    "RECORDING_FORMATS",
    "size_refusal",
    "check_size",
    "check_upload",
    "check_declared_size",
]

MAX_BYTES = 20 * 1024 * 1024
"""Largest upload accepted, bytes (20 MB)."""
MAX_FACES = 500_000
"""Most triangles a file may declare."""
MAX_NODES = 1_000
"""Most scene nodes a GLB may have (each instance of a mesh is a node)."""
MAX_MESHES = 1_000
"""Most meshes (and primitives) a GLB may have."""
MAX_ACCESSORS = 4_000
"""Most accessors (typed views of its buffers) a GLB may have."""
MAX_ELEMENTS = 3 * MAX_FACES * 3
"""Most numbers a GLB's accessors may hold together (vertices and indices, components counted)."""

# A gyroscope recording: phyphox's CSV, or the zip it shares (a CSV and a few small meta files).
RECORDING_FORMATS = ("csv", "zip")
"""Extensions of a recording (the phone-toss scene): the size limit's advice is then about the recording."""
MAX_ZIP_ENTRIES = 64
"""Most files a zip may hold (phyphox's export: Raw Data.csv and three meta files)."""
MAX_UNPACKED = 64 * 1024 * 1024
"""Most bytes a zip's files may declare unpacked, together (an hour at 100 Hz is about 30 MB of CSV)."""
MAX_ZIP_RATIO = 100
"""Largest ratio of unpacked to packed bytes of a zip's file over 1 MB: a CSV of numbers packs 3 to 10
times; a file packed 1000 times over is made to exhaust the reader (a zip bomb)."""

# In flight, on the wire (app.guards.uploads).
MAX_TRANSFERS = 8
"""Uploads in flight at once from all browsers together (each holds at most MAX_BYTES until complete)."""
PER_CLIENT = 1
"""Uploads in flight at once from one browser (its page sends one file at a time)."""
PER_ADDRESS = 1
"""Uploads in flight at once from one address, however many browsers or connections it opens (a script
cannot hold every place of :data:`MAX_TRANSFERS`)."""
IDLE_SECONDS = 30.0
"""A transfer that has sent no part for this long, s, is dropped when another starts (a page sends its
parts back to back: a silent one has stalled, or is holding its place on purpose)."""
MAX_PARTS = 1024
"""Most parts a transfer may declare (a page sends 512 kB parts: 40 for 20 MB)."""
MAX_NAME = 255
"""Longest file name taken, characters."""
STALL_SECONDS = 300.0
"""A transfer unfinished after this long, s, is dropped when another starts (20 MB at 70 kB/s)."""

# While it is parsed (app.uploads.worker).
MEMORY_LIMIT = 1024 * 1024 * 1024
"""Address space a worker may use, bytes (1 GiB)."""
TIME_LIMIT = 30.0
"""Seconds a worker may take to read one file."""
READERS = 2
"""Workers that may read files at once (one per core of a small server)."""
MAX_MESSAGE = 600
"""Longest refusal sent back from a worker, characters (a reader may quote a cell of the file)."""

_COMPONENTS = {"SCALAR": 1, "VEC2": 2, "VEC3": 3, "VEC4": 4, "MAT2": 4, "MAT3": 9, "MAT4": 16}


def _size_text(n_bytes: int) -> str:
    if n_bytes >= 1024 * 1024:
        return say("{size:.1f} MB", size=n_bytes / 1024 / 1024)
    return say("{size:.0f} kB", size=n_bytes / 1024)


def size_refusal(name: str, n_bytes: int) -> str | None:
    """Why a file of ``n_bytes`` is refused (over :data:`MAX_BYTES`, read when called), or None."""
    if n_bytes <= MAX_BYTES:
        return None
    advice = (
        mark("Record a shorter stretch (a toss lasts a second) and upload it again.")
        if PurePath(name).suffix.lower().lstrip(".") in RECORDING_FORMATS
        else mark("Simplify the mesh (fewer triangles) and upload it again.")
    )
    return say(
        "{name} is {size}; the limit is {limit}. {advice}",
        name=name,
        size=_size_text(n_bytes),
        limit=_size_text(MAX_BYTES),
        advice=advice,
    )


def check_size(filename: str, content: bytes) -> None:
    """Refuse (ValueError) a file over :data:`MAX_BYTES`."""
    refusal = size_refusal(PurePath(filename or "upload").name, len(content))
    if refusal is not None:
        raise ValueError(refusal)


def check_upload(filename: str, content: bytes) -> None:
    """The check before a worker parses a file: its size, then what its header declares (ValueError)."""
    check_size(filename, content)
    check_declared_size(filename, content)


def check_declared_size(filename: str, content: bytes) -> None:
    """Refuse a file whose header declares more than the limits; ValueError says what and how much."""
    name = PurePath(filename or "upload").name
    ext = PurePath(name).suffix.lower().lstrip(".")
    if ext == "glb":
        _check_glb(name, content)
    elif ext == "stl":
        _check_stl(name, content)
    elif ext == "ply":
        _check_ply(name, content)
    elif ext == "obj":
        _check_obj(name, content)
    elif ext == "zip":
        _check_zip(name, content)


def _too_many(name: str, what: str, count: int, limit: int) -> ValueError:
    return ValueError(
        say(
            "{name} declares {count:,} {what}; the limit is {limit:,}. Simplify the model and upload it again.",
            name=name,
            count=count,
            what=what,
            limit=limit,
        )
    )


def _check_glb(name: str, content: bytes) -> None:
    # GLB: 12-byte header (magic, version, length), then chunks of (length, type, data); the first is JSON.
    if len(content) < 20 or content[:4] != b"glTF":
        raise ValueError(say("{name} is not a GLB file (it does not start with the glTF header).", name=name))
    (json_length, chunk_type) = struct.unpack_from("<II", content, 12)
    if chunk_type != 0x4E4F534A or json_length > len(content) - 20:
        raise ValueError(say("{name} is a damaged GLB file (its JSON chunk is missing or cut short).", name=name))
    try:
        document = json.loads(content[20 : 20 + json_length])
    except (UnicodeDecodeError, json.JSONDecodeError) as exc:
        raise ValueError(
            say("{name} is a damaged GLB file (its JSON chunk does not parse: {reason}).", name=name, reason=str(exc))
        ) from None
    if not isinstance(document, dict):
        raise ValueError(say("{name} is a damaged GLB file (its JSON chunk is not an object).", name=name))
    required = document.get("extensionsRequired") or []
    if required:
        raise ValueError(
            say(
                "{name} needs the glTF extensions {extensions} (compressed geometry); export it without compression.",
                name=name,
                extensions=", ".join(map(str, required)),
            )
        )
    for key, limit, what in (
        ("nodes", MAX_NODES, mark("nodes")),
        ("meshes", MAX_MESHES, mark("meshes")),
        ("accessors", MAX_ACCESSORS, mark("accessors")),
    ):
        items = document.get(key) or []
        if not isinstance(items, list):
            raise ValueError(say("{name} is a damaged GLB file ({key} is not a list).", name=name, key=key))
        if len(items) > limit:
            raise _too_many(name, what, len(items), limit)
    primitives = sum(len(m.get("primitives") or []) for m in document.get("meshes") or [] if isinstance(m, dict))
    if primitives > MAX_MESHES:
        raise _too_many(name, mark("mesh primitives"), primitives, MAX_MESHES)
    elements = 0
    for accessor in document.get("accessors") or []:
        if not isinstance(accessor, dict):
            raise ValueError(say("{name} is a damaged GLB file (an accessor is not an object).", name=name))
        count = accessor.get("count", 0)
        if not isinstance(count, int) or count < 0:
            raise ValueError(
                say("{name} is a damaged GLB file (an accessor's count is {count}).", name=name, count=repr(count))
            )
        elements += count * _COMPONENTS.get(str(accessor.get("type")), 16)
    # Instancing multiplies the geometry: every node that shows a mesh draws all of it again.
    shown = sum(1 for node in document.get("nodes") or [] if isinstance(node, dict) and "mesh" in node)
    if elements * max(shown, 1) > MAX_ELEMENTS:
        raise ValueError(
            say(
                "{name} holds {elements:,} numbers of geometry shown by {nodes:,} nodes; the limit is {limit:,} in "
                "all. Simplify the model (fewer triangles or instances) and upload it again.",
                name=name,
                elements=elements,
                nodes=max(shown, 1),
                limit=MAX_ELEMENTS,
            )
        )


def _check_stl(name: str, content: bytes) -> None:
    if content[:5].lower() == b"solid" and b"facet" in content[:1024]:
        facets = content.count(b"facet normal")
        if facets > MAX_FACES:
            raise _too_many(name, mark("triangles"), facets, MAX_FACES)
        return
    if len(content) >= 84:
        (count,) = struct.unpack_from("<I", content, 80)
        # A binary STL is exactly 84 + 50 n bytes; a file that is not is no binary STL at all (garbage or
        # a mislabelled text), and the reader says so, in its worker.
        if 84 + 50 * count == len(content) and count > MAX_FACES:
            raise _too_many(name, mark("triangles"), count, MAX_FACES)


_PLY_ELEMENT = re.compile(rb"^element\s+(\w+)\s+(\d+)\s*$", re.MULTILINE)


def _check_ply(name: str, content: bytes) -> None:
    end = content.find(b"end_header")
    header = content[: end if end >= 0 else 4096]
    for element, count_text in _PLY_ELEMENT.findall(header):
        count = int(count_text)
        limit = MAX_FACES if element == b"face" else 3 * MAX_FACES
        if count > limit:
            raise _too_many(name, element.decode("ascii", "replace") + "s", count, limit)


def _check_obj(name: str, content: bytes) -> None:
    faces = content.count(b"\nf ") + int(content.startswith(b"f "))
    vertices = content.count(b"\nv ") + int(content.startswith(b"v "))
    if faces > MAX_FACES:
        raise _too_many(name, mark("faces"), faces, MAX_FACES)
    if vertices > 3 * MAX_FACES:
        raise _too_many(name, mark("vertices"), vertices, 3 * MAX_FACES)


def _too_many_files(name: str, count: int) -> ValueError:
    return ValueError(
        say(
            "{name} holds {count:,} files; a phyphox export holds a handful (at most {most}).",
            name=name,
            count=count,
            most=MAX_ZIP_ENTRIES,
        )
    )


def _check_zip(name: str, content: bytes) -> None:
    # The end record (the last 22 bytes, before a comment of at most 64 kB) says how many files the central
    # directory lists: read before the directory itself, whose parsing costs a little per file.
    end = content.rfind(b"PK\x05\x06", max(0, len(content) - 22 - 65535))
    if end < 0 or end + 22 > len(content):
        raise ValueError(
            say("{name} is not a zip archive (it has no zip directory); upload phyphox's shared .zip.", name=name)
        )
    (entries,) = struct.unpack_from("<H", content, end + 10)
    if entries > MAX_ZIP_ENTRIES:
        raise _too_many_files(name, entries)
    try:
        with zipfile.ZipFile(io.BytesIO(content)) as archive:
            infos = archive.infolist()
    except (zipfile.BadZipFile, OSError, ValueError, NotImplementedError) as exc:
        raise ValueError(say("{name} is a damaged zip archive ({reason}).", name=name, reason=str(exc))) from None
    if len(infos) > MAX_ZIP_ENTRIES:
        raise _too_many_files(name, len(infos))
    unpacked = sum(info.file_size for info in infos)
    if unpacked > MAX_UNPACKED:
        raise ValueError(
            say(
                "{name} unpacks to {size}; the limit is {limit}. Record a shorter stretch and upload it again.",
                name=name,
                size=_size_text(unpacked),
                limit=_size_text(MAX_UNPACKED),
            )
        )
    for info in infos:
        if info.file_size > 1024 * 1024 and info.file_size > MAX_ZIP_RATIO * max(info.compress_size, 1):
            raise ValueError(
                say(
                    "{name} packs {member} {ratio:,.0f} times over (a recording packs at most {most} times): it is "
                    "not a phyphox export.",
                    name=name,
                    member=PurePath(info.filename).name[:80],
                    ratio=info.file_size / max(info.compress_size, 1),
                    most=MAX_ZIP_RATIO,
                )
            )
