"""A trace on the timeline (:meth:`app.drawing.trace.Trace.rewind`): moved back to ``t``, it draws the path up
to ``t`` (the segments the points after it ended go, newest first), sends only the chunks that changed, and
goes on from there joined; a trace holding a point of no time, or none at or before ``t``, starts again."""

from __future__ import annotations

import numpy as np
import pytest

from app import draw


def _point(i: int) -> list[float]:
    return [0.01 * i, 0.001 * i * i, 0.0]


def _timed(app, name: str, capacity: int, times) -> draw.Trace:
    """A trace of ``capacity`` points holding point ``i`` drawn at time ``t`` for each ``(i, t)``."""
    trace = draw.Trace(app.server, name, capacity=capacity)
    for i, t in times:
        trace.append(_point(i), t=t)
    return trace


def _joined_up_to(trace, last: int) -> None:
    """The drawn segments end at point ``last`` and each starts where the one before ended."""
    segs = trace.drawn_segments()
    np.testing.assert_allclose(segs[-1, 1], _point(last), atol=1e-5)
    np.testing.assert_allclose(segs[1:, 0], segs[:-1, 1])


@pytest.mark.parametrize("back_to", [3.5, draw.TRACE_CHUNK + 0.5, 2 * draw.TRACE_CHUNK - 0.5, 4 * draw.TRACE_CHUNK])
def test_moved_back_the_trace_draws_the_path_up_to_that_instant_and_goes_on_joined(app, back_to: float) -> None:
    trace = draw.Trace(app.server, "/test_trace_rewind", capacity=1500)
    n = 5 * draw.TRACE_CHUNK + 7
    for i in range(n):
        trace.append(_point(i), t=float(i))
    trace.rewind(back_to)
    last = int(back_to)
    np.testing.assert_allclose(trace.points(), [_point(i) for i in range(last + 1)])
    assert len(trace.drawn_segments()) == last
    _joined_up_to(trace, last)
    for i in range(last + 1, last + 3 * draw.TRACE_CHUNK):  # on again: the trace grows from there, joined
        trace.append(_point(i), t=float(i))
    _joined_up_to(trace, last + 3 * draw.TRACE_CHUNK - 1)
    assert len(trace.drawn_segments()) == last + 3 * draw.TRACE_CHUNK - 1
    trace.remove()


def test_a_step_back_sends_the_newest_chunk_only(app) -> None:
    trace = _timed(app, "/test_trace_rewind_cost", 1500, ((i, float(i)) for i in range(200)))
    sent = []
    for chunk in trace._chunks:
        chunk_points = chunk.points
        sent.append(chunk_points)
    trace.rewind(197.5)
    changed = [k for k, c in enumerate(trace._chunks) if c.points is not sent[k]]
    assert len(changed) == 1  # one chunk resent, not the trace
    trace.remove()


def test_a_full_ring_moved_back_keeps_the_points_it_still_holds(app) -> None:
    trace = _timed(app, "/test_trace_rewind_ring", 50, ((i, float(i)) for i in range(400)))
    trace.rewind(379.0)
    np.testing.assert_allclose(trace.points(), [_point(i) for i in range(350, 380)])
    _joined_up_to(trace, 379)
    trace.remove()


def test_a_trace_starts_again_without_times_or_before_its_first_point(app) -> None:
    trace = _timed(app, "/test_trace_rewind_clear", 100, ((i, 10.0 + i) for i in range(20)))
    trace.rewind(5.0)  # before its first point
    assert len(trace.points()) == 0 and len(trace.drawn_segments()) == 0
    for i in range(20):
        trace.append(_point(i))  # no times
    trace.rewind(5.0)
    assert len(trace.points()) == 0
    trace.remove()


def test_moved_on_past_its_newest_point_the_trace_keeps_everything(app) -> None:
    trace = _timed(app, "/test_trace_rewind_on", 100, ((i, float(i)) for i in range(30)))
    trace.rewind(100.0)
    assert len(trace.points()) == 30
    _joined_up_to(trace, 29)
    trace.remove()
