"""A trace: the bounded path of a point, drawn in chunks of line segments so that a frame sends one chunk,
fading with age, and moved back with the timeline (each point keeps its time)."""

from __future__ import annotations

import numpy as np
import viser
from numpy.typing import ArrayLike, NDArray

from app.drawing.palette import colour
from app.guards.wire import send_points

__all__ = ["TRACE_CHUNK", "TRACE_FADE", "VIEW_BACKGROUND", "Trace"]

TRACE_CHUNK = 32
"""Segments per line-segments node of a :class:`Trace`: a frame rewrites one such node, not the trace."""

TRACE_FADE = (0.0, 0.25, 0.45, 0.62)
"""How far a trace's chunks are blended toward the background, newest quarter first to oldest quarter: old
loops recede behind new ones instead of tangling with them (recoloured only when a chunk changes quarter)."""

VIEW_BACKGROUND = {False: (255, 255, 255), True: (20, 20, 20)}
"""The 3D view's background in the light and dark looks (viser's client: white, or Mantine's dark[9])."""


class Trace:
    """A bounded trace of a point, drawn as line segments in chunks so that a frame sends one chunk.

    Resending a whole trace every frame would send 1,500 segments (36 kB a frame, 2 MB/s a browser), so
    the segments live in chunks of :data:`TRACE_CHUNK`, each its own viser node; a new point adds
    one segment to the newest chunk and only that chunk is sent (768 bytes). When it is full, the oldest
    chunk is emptied and becomes the newest, so the oldest segments drop out a chunk at a time.

    Parameters
    ----------
    capacity : int
        Number of points kept (the oldest drop out); :meth:`resize` changes it. The drawing shows at
        least the last ``capacity`` points and fewer than 2 × :data:`TRACE_CHUNK` more (the chunks are whole:
        the oldest holds up to a chunk's worth the capacity does not need, the newest fills before it goes).
    min_step : float
        A new point closer than this (m) to the last one replaces nothing and is skipped, so a paused or
        slow motion does not fill the buffer with duplicates.
    dark : bool
        Drawn in the dark look's colour (:func:`app.drawing.palette.colour`).
    """

    def __init__(
        self,
        server: viser.ViserServer,
        name: str,
        *,
        quantity: str = "trace",
        capacity: int = 1500,
        thickness: float = 2.5,
        min_step: float = 1e-4,
        dark: bool = False,
    ) -> None:
        self._server = server
        self._colour = colour(quantity, dark)  # the dark look's where the light look's would vanish
        self._background = VIEW_BACKGROUND[dark]
        self._name = name
        self.quantity = quantity
        self._thickness = thickness
        self.min_step = min_step
        self._chunks: list[viser.LineSegmentsHandle] = []
        self.resize(capacity)

    def resize(self, capacity: int) -> None:
        """Change the number of points kept (re-creates the chunks; the trace restarts)."""
        if capacity < 2:
            raise ValueError(f"a trace needs at least 2 points, got {capacity}")
        self.capacity = int(capacity)
        self._buf = np.zeros((self.capacity, 3))
        self._times = np.full(self.capacity, np.nan)  # each point's time (s); NaN: appended without one
        self._count = 0
        self._head = 0  # index of the next write
        self.remove()
        length = min(TRACE_CHUNK, self.capacity - 1)
        # One chunk more than the capacity needs: the newest may be nearly empty while the oldest is full.
        n_chunks = -(-(self.capacity - 1) // length) + 1
        self._segments = np.zeros((n_chunks, length, 2, 3), dtype=np.float32)
        self._fill = np.zeros(n_chunks, dtype=int)
        self._newest = 0
        self._fade = [0] * n_chunks  # each chunk's quarter of TRACE_FADE, as last sent
        self._chunks = [
            self._server.scene.add_line_segments(
                f"{self._name}/{k}",
                points=self._segments[k],
                colors=self._colour,
                thickness=self._thickness,
                thickness_units="screen",
                visible=False,
            )
            for k in range(n_chunks)
        ]

    def remove(self) -> None:
        """Remove the trace's nodes from the scene."""
        for chunk in self._chunks:
            chunk.remove()
        self._chunks = []

    def clear(self) -> None:
        self._count = 0
        self._head = 0
        self._fill[:] = 0
        for chunk in self._chunks:
            if chunk.visible:
                chunk.visible = False

    def points(self) -> NDArray[np.float64]:
        """The kept points, oldest first, shape (k, 3)."""
        if self._count < self.capacity:
            return self._buf[: self._count].copy()
        return np.roll(self._buf, -self._head, axis=0)

    def drawn_segments(self) -> NDArray[np.float32]:
        """The segments on screen, oldest first, shape (k, 2, 3) (what the browsers were sent)."""
        n = len(self._chunks)
        order = [(self._newest + 1 + i) % n for i in range(n)]
        return np.concatenate([self._segments[k, : self._fill[k]] for k in order])

    def append(self, point: ArrayLike, t: float | None = None) -> None:
        """Add a point (m), drawn at time ``t`` (s; what :meth:`rewind` goes back by): one segment from the
        previous point, sent with its chunk only."""
        p = np.asarray(point, dtype=float)
        previous = self._buf[(self._head - 1) % self.capacity]
        if self._count and np.linalg.norm(p - previous) < self.min_step:
            return
        self._buf[self._head] = p
        self._times[self._head] = np.nan if t is None else float(t)
        self._head = (self._head + 1) % self.capacity
        self._count = min(self._count + 1, self.capacity)
        if self._count < 2:
            return
        k = self._newest
        if self._fill[k] == self._segments.shape[1]:
            k = self._newest = (k + 1) % len(self._chunks)  # the oldest chunk becomes the newest
            self._fill[k] = 0
            self._recolour()
        f = self._fill[k]
        self._segments[k, f, 0] = previous
        self._segments[k, f, 1] = p
        self._segments[k, f + 1 :] = p  # unused segments collapse onto the newest point (invisible)
        self._fill[k] = f + 1
        chunk = self._chunks[k]
        send_points(chunk, self._segments[k])
        if not chunk.visible:
            chunk.visible = True

    def rewind(self, t: float) -> None:
        """The clock went back (or on) to ``t`` (s, the timeline): the points drawn after ``t`` go, newest
        first, so the trace shows the path up to that instant (one chunk or two sent, not the whole trace);
        a trace with a point of no time starts again."""
        times = self._times[(self._head - 1 - np.arange(self._count)) % self.capacity]  # newest first
        if np.isnan(times).any():
            self.clear()
            return
        kept = times <= t
        drop = int(np.argmax(kept)) if kept.any() else self._count
        if drop == 0:
            return
        if self._count - drop < 2:
            self.clear()
            return
        self._head = (self._head - drop) % self.capacity
        self._count -= drop
        n = len(self._chunks)
        touched = set()
        while drop > 0:  # a point dropped is the segment that ended at it
            k = self._newest
            taken = min(drop, int(self._fill[k]))
            self._fill[k] -= taken
            drop -= taken
            touched.add(k)
            if self._fill[k] == 0 and drop > 0:
                self._newest = (k - 1) % n
        for k in touched:
            f = int(self._fill[k])
            if f:
                self._segments[k, f:] = self._segments[k, f - 1, 1]  # unused segments collapse (invisible)
                send_points(self._chunks[k], self._segments[k])
            elif self._chunks[k].visible:
                self._chunks[k].visible = False
        if self._fill[self._newest] == 0:  # emptied to a chunk boundary: the one before is the newest
            self._newest = (self._newest - 1) % n
        self._recolour()

    def _recolour(self) -> None:
        """Give each chunk the colour of its age's quarter (:data:`TRACE_FADE`): sent only where it changed."""
        n = len(self._chunks)
        for age in range(n):  # 0: the newest chunk
            k = (self._newest - age) % n
            level = min(len(TRACE_FADE) - 1, age * len(TRACE_FADE) // n)
            if level != self._fade[k]:
                self._fade[k] = level
                self._chunks[k].colors = np.broadcast_to(
                    np.asarray(self.faded(level), dtype=np.uint8), self._segments.shape[1:]
                ).copy()

    def faded(self, level: int) -> tuple[int, int, int]:
        """The trace's colour at fade ``level`` (an index of :data:`TRACE_FADE`), RGB 0-255."""
        f = TRACE_FADE[level]
        (r, g, b), (br, bg, bb) = self._colour, self._background
        return (round((1 - f) * r + f * br), round((1 - f) * g + f * bg), round((1 - f) * b + f * bb))

    def chunk_colours(self) -> list[tuple[int, int, int]]:
        """Each chunk's colour as sent, newest first."""
        n = len(self._chunks)
        return [self.faded(self._fade[(self._newest - age) % n]) for age in range(n)]
