"""app.guards.prop_hints: every handle's property hints are viser's own, looked up once per props class."""

from __future__ import annotations

import typing

import numpy as np
import viser
from viser import _assignable_props_api

from app.guards import prop_hints
from app.guards.prop_hints import cache_prop_hints
from tests.harness import free_port


def test_the_hints_are_viser_s_and_a_second_handle_of_a_kind_evaluates_no_annotation(monkeypatch):
    cache_prop_hints()
    cache_prop_hints()  # twice changes nothing
    base = _assignable_props_api.AssignablePropsBase
    assert base.__dict__["_prop_hints"].func is prop_hints._prop_hints
    server = viser.ViserServer(host="127.0.0.1", port=free_port(), verbose=False)
    try:
        first = [
            server.scene.add_line_segments("/a", points=[[[0, 0, 0], [1, 0, 0]]], colors=(1, 2, 3)),
            server.scene.add_icosphere("/b", radius=0.5),
            server.gui.add_slider("s", min=0.0, max=1.0, step=0.1, initial_value=0.5),
            server.gui.add_dropdown("d", options=("x", "y")),
        ]
        for handle in first:
            assert handle._prop_hints == typing.get_type_hints(type(handle._impl.props))
            assert handle._prop_hints  # a handle has properties: an empty table would refuse every write
        evaluated: list[type] = []
        real = typing.get_type_hints
        monkeypatch.setattr(prop_hints, "get_type_hints", lambda cls: evaluated.append(cls) or real(cls))
        second = server.scene.add_line_segments("/c", points=[[[0, 0, 0], [0, 1, 0]]], colors=(4, 5, 6))
        # A write goes through the hints: without them the list would stay on the handle, not cast into props.
        second.points = [[[0, 0, 0], [0, 0, 2]]]
        assert second._impl.props.points.dtype == np.float32 and second._impl.props.points[0, 1, 2] == 2.0
        assert second._prop_hints is first[0]._prop_hints
        assert evaluated == []
        prop_hints._HINTS.clear()  # a kind never seen is looked up, once
        boxes = [server.gui.add_checkbox(f"c{k}", initial_value=True) for k in range(2)]
        assert [box._prop_hints for box in boxes] == [typing.get_type_hints(type(boxes[0]._impl.props))] * 2
        assert evaluated == [type(boxes[0]._impl.props)]
    finally:
        server.stop()
