"""A bounded trace of a point (:class:`Trace`), drawn in few nodes and sent a small chunk a frame.

Created once (in a scene's ``build``) and updated in place through its kept viser handles, like
:mod:`app.drawing.pieces`.
"""

from __future__ import annotations

from typing import Any

import numpy as np
import viser
from numpy.typing import ArrayLike, NDArray

from app.drawing.palette import colour
from app.guards.wire import send_points

__all__ = ["TRACE_BLOCK", "TRACE_CHUNK", "TRACE_FADE", "VIEW_BACKGROUND", "Trace"]


TRACE_CHUNK = 32
"""Segments a frame rewrites in a :class:`Trace`: its newest chunk of this many, one small node of its own."""

TRACE_BLOCK = 8
"""Chunks of a :class:`Trace` drawn by one line-segments node once they are full: every node costs a software-
rendering browser (a phone, a test's Chromium) a draw call each frame, and 48 of them made the heavy top's page
draw at half the frame rate of the same page without its trace."""

TRACE_FADE = (0.0, 0.25, 0.45, 0.62)
"""How far a trace's chunks are blended toward the background, newest quarter first to oldest quarter: old
loops recede behind new ones instead of tangling with them (recoloured only when a chunk changes quarter)."""

VIEW_BACKGROUND = {False: (255, 255, 255), True: (20, 20, 20)}
"""The 3D view's background in the light and dark looks (viser's client: white, or Mantine's dark[9])."""


class Trace:
    """A bounded trace of a point, drawn as line segments in chunks so that a frame sends one chunk.

    Resending a whole trace every frame would send 1,500 segments (36 kB a frame, 2 MB/s a browser), so
    the segments live in a ring of chunks of :data:`TRACE_CHUNK`; a new point adds one segment to the newest
    chunk, which has a node of its own (the *live* node), and only that node is sent (768 bytes). When the
    chunk is full, the oldest chunk is emptied and becomes the newest, so the oldest segments drop out a chunk
    at a time. The chunks before the newest are drawn :data:`TRACE_BLOCK` to a node (the *blocks*): a block
    is resent when a chunk in it fills or empties, once every :data:`TRACE_CHUNK` points (6 kB), so a page
    draws a 1,500-point trace in 7 nodes, not 48.

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
        self._live: viser.LineSegmentsHandle | None = None
        self._blocks: list[viser.LineSegmentsHandle] = []
        self.resize(capacity)

    def _add(self, name: str, segments: NDArray[np.float32], colours: Any) -> viser.LineSegmentsHandle:
        return self._server.scene.add_line_segments(
            name,
            points=segments,
            colors=colours,
            thickness=self._thickness,
            thickness_units="screen",
            visible=False,
        )

    def resize(self, capacity: int) -> None:
        """Change the number of points kept (re-creates the nodes; the trace restarts)."""
        if capacity < 2:
            raise ValueError(f"a trace needs at least 2 points, got {capacity}")
        self.capacity = int(capacity)
        self._buf = np.zeros((self.capacity, 3))
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
        self._live = self._add(f"{self._name}/live", self._segments[0], self._colour)
        self._blocks = [
            self._add(f"{self._name}/{b}", self._block_segments(b), self._colour)
            for b in range(-(-n_chunks // TRACE_BLOCK))
        ]

    def remove(self) -> None:
        """Remove the trace's nodes from the scene."""
        for node in [*self._blocks, *([self._live] if self._live is not None else [])]:
            node.remove()
        self._blocks = []
        self._live = None

    def clear(self) -> None:
        self._count = 0
        self._head = 0
        self._fill[:] = 0
        for node in self._nodes():
            if node.visible:
                node.visible = False

    def _nodes(self) -> list[viser.LineSegmentsHandle]:
        return [*self._blocks, *([self._live] if self._live is not None else [])]

    def points(self) -> NDArray[np.float64]:
        """The kept points, oldest first, shape (k, 3)."""
        if self._count < self.capacity:
            return self._buf[: self._count].copy()
        return np.roll(self._buf, -self._head, axis=0)

    def _block_segments(self, b: int) -> NDArray[np.float32]:
        """What block ``b`` draws, shape (chunks × TRACE_CHUNK, 2, 3): its chunks, the newest (the live node's)
        and the empty ones collapsed to nothing (zero-length segments, not drawn)."""
        chunks = self._segments[b * TRACE_BLOCK : (b + 1) * TRACE_BLOCK].copy()
        for i in range(len(chunks)):
            k = b * TRACE_BLOCK + i
            if k == self._newest or self._fill[k] == 0:
                chunks[i] = chunks[i, :1, 0]  # every segment a point: nothing drawn
            else:
                chunks[i, self._fill[k] :] = chunks[i, self._fill[k] - 1, 1]
        return chunks.reshape(-1, 2, 3)

    def drawn_segments(self) -> NDArray[np.float32]:
        """The segments on screen, oldest first, shape (k, 2, 3), read from what the nodes were sent."""
        n, length = self._segments.shape[:2]
        order = [(self._newest + 1 + i) % n for i in range(n)]
        out = []
        for k in order:
            if k == self._newest:
                assert self._live is not None
                sent = np.asarray(self._live.points)
            else:
                block = np.asarray(self._blocks[k // TRACE_BLOCK].points)
                sent = block[(k % TRACE_BLOCK) * length : (k % TRACE_BLOCK + 1) * length]
            out.append(sent[: self._fill[k]])
        return np.concatenate(out).astype(np.float32)

    def append(self, point: ArrayLike) -> None:
        """Add a point (m): one segment from the previous point, sent with the live chunk only."""
        p = np.asarray(point, dtype=float)
        previous = self._buf[(self._head - 1) % self.capacity]
        if self._count and np.linalg.norm(p - previous) < self.min_step:
            return
        self._buf[self._head] = p
        self._head = (self._head + 1) % self.capacity
        self._count = min(self._count + 1, self.capacity)
        if self._count < 2:
            return
        k = self._newest
        if self._fill[k] == self._segments.shape[1]:
            k = self._newest = (k + 1) % len(self._segments)  # the oldest chunk becomes the newest
            self._fill[k] = 0
            # The full chunk joins its block and the emptied one leaves its own (one message if the same).
            for b in {(k - 1) % len(self._segments) // TRACE_BLOCK, k // TRACE_BLOCK}:
                block = self._blocks[b]
                send_points(block, self._block_segments(b))
                if not block.visible:
                    block.visible = True
            self._recolour()
        f = self._fill[k]
        self._segments[k, f, 0] = previous
        self._segments[k, f, 1] = p
        self._segments[k, f + 1 :] = p  # unused segments collapse onto the newest point (invisible)
        self._fill[k] = f + 1
        assert self._live is not None
        send_points(self._live, self._segments[k])
        if not self._live.visible:
            self._live.visible = True

    def _recolour(self) -> None:
        """Give each chunk the colour of its age's quarter (:data:`TRACE_FADE`): a block's colours are sent
        only when one of its chunks changed quarter."""
        n = len(self._segments)
        changed = set()
        for age in range(n):  # 0: the newest chunk
            k = (self._newest - age) % n
            level = min(len(TRACE_FADE) - 1, age * len(TRACE_FADE) // n)
            if level != self._fade[k]:
                self._fade[k] = level
                changed.add(k // TRACE_BLOCK)
        length = self._segments.shape[1]
        for b in sorted(changed):
            levels = self._fade[b * TRACE_BLOCK : (b + 1) * TRACE_BLOCK]
            colours = np.repeat(np.asarray([self.faded(level) for level in levels], dtype=np.uint8), length, axis=0)
            self._blocks[b].colors = np.repeat(colours[:, None, :], 2, axis=1)

    def chunk_colour(self, k: int) -> tuple[int, int, int]:
        """The colour chunk ``k`` (an index of the ring) is drawn in, as its node holds it, RGB 0-255."""
        if k == self._newest:
            return self._colour  # the live node: always the newest quarter
        colours = np.asarray(self._blocks[k // TRACE_BLOCK].colors)
        if colours.shape == (3,):  # one colour for the whole block, as created
            return (int(colours[0]), int(colours[1]), int(colours[2]))
        length = self._segments.shape[1]
        chunk = colours[(k % TRACE_BLOCK) * length : (k % TRACE_BLOCK + 1) * length].reshape(-1, 3)
        if not np.all(chunk == chunk[0]):
            raise ValueError(f"chunk {k} is drawn in more than one colour")
        return (int(chunk[0, 0]), int(chunk[0, 1]), int(chunk[0, 2]))

    def faded(self, level: int) -> tuple[int, int, int]:
        """The trace's colour at fade ``level`` (an index of :data:`TRACE_FADE`), RGB 0-255."""
        f = TRACE_FADE[level]
        (r, g, b), (br, bg, bb) = self._colour, self._background
        return (round((1 - f) * r + f * br), round((1 - f) * g + f * bg), round((1 - f) * b + f * bb))

    def chunk_colours(self) -> list[tuple[int, int, int]]:
        """Each chunk's colour as computed, newest first."""
        n = len(self._segments)
        return [self.faded(self._fade[(self._newest - age) % n]) for age in range(n)]
