"""One palette: every node a scene sends is drawn in a colour of ``app.draw.COLOURS``, every
arrow, trace and cone in exactly its legend's colour (as the page will show it), and the legend shows
the colours of the quantities the scene draws. The palette is Okabe & Ito's."""

from __future__ import annotations

import numpy as np
import pytest

from app import draw
from app.scenes import scene_names
from tests.harness import FRAME, open_scene


def _parts(scene, kinds) -> list:
    """The scene's drawing pieces of the given kinds, in its attributes and their lists and dicts."""
    found = []
    for value in vars(scene).values():
        items = value.values() if isinstance(value, dict) else value if isinstance(value, (list, tuple)) else [value]
        found.extend(item for item in items if isinstance(item, kinds))
    return found


def _colours_of(handle) -> list[tuple[int, int, int]]:
    """The colours a node handle sends: a mesh's single colour, or the rows of a line's or arrow's."""
    if hasattr(handle, "colors"):
        rows = np.asarray(handle.colors).reshape(-1, 3)
        return [tuple(int(v) for v in row) for row in np.unique(rows, axis=0)]
    if hasattr(handle, "color"):
        return [tuple(int(v) for v in handle.color)]
    return []


def test_the_palette_is_okabe_ito_and_each_quantity_has_one_colour():
    assert draw.OKABE_ITO["vermillion"] == (213, 94, 0) and draw.OKABE_ITO["blue"] == (0, 114, 178)
    for quantity in ("L", "omega", "torque", "trace", "body_cone", "space_cone", "ellipsoid"):
        assert draw.COLOURS[quantity] in draw.OKABE_ITO.values(), quantity
    assert set(draw.COLOURS) == set(draw.LABELS)


@pytest.mark.parametrize("name", scene_names())
def test_every_node_is_drawn_in_the_legend_colours(app, name):
    scene = open_scene(app, name)
    for _ in range(3):
        app.frame(FRAME)
    legend = app.simulation.legend.content
    for quantity in scene.quantities:
        assert draw.hex_colour(quantity) in legend, quantity
    arrows = _parts(scene, draw.Arrow)
    for arrow in arrows:
        (sent,) = _colours_of(arrow.handle)
        shown = draw.shown_colour(sent)  # what the page shows: the legend's colour, to one level in 255
        assert np.max(np.abs(np.subtract(shown, draw.COLOURS[arrow.quantity]))) <= 1, arrow.quantity
        assert arrow.quantity in scene.quantities, f"{arrow.quantity} is drawn but not in the legend"
    for piece in _parts(scene, (draw.Trace, draw.Cone)):
        assert piece.quantity in scene.quantities, f"{piece.quantity} is drawn but not in the legend"
    # Every piece drawn has its legend entry: the principal axes, the integrator's ghost, and any node in a
    # colour that only some quantities have (black: the axes, the ghost or a pivot; grey: guides or a path).
    if _parts(scene, draw.PrincipalFrame) or hasattr(scene, "frame"):
        assert "axes" in scene.quantities, "principal axes drawn but not in the legend"
    if hasattr(scene, "ghost"):
        assert "ghost" in scene.quantities, "the integrator's ghost is not in the legend"
    holders: dict[tuple[int, int, int], set[str]] = {}
    for quantity, colour in draw.COLOURS.items():
        holders.setdefault(colour, set()).add(quantity)
    allowed = set(draw.COLOURS.values()) | {draw.instance_colour(q) for q in draw.COLOURS}
    for node, handle in app.server.scene._handle_from_node_name.items():
        if not node.startswith(app.simulation.root):
            continue
        for colour in _colours_of(handle):
            assert colour in allowed, f"{node} is drawn in {colour}, not in the palette"
            if colour in holders and colour != draw.COLOURS["body"]:
                assert holders[colour] & set(scene.quantities), f"{node}: {sorted(holders[colour])} not in the legend"


@pytest.mark.parametrize("quantity", sorted(draw.COLOURS))
def test_an_arrow_colour_goes_out_in_linear_light_and_comes_back(quantity):
    shown = draw.shown_colour(draw.instance_colour(quantity))
    assert np.max(np.abs(np.subtract(shown, draw.COLOURS[quantity]))) <= 1  # one level in 255


@pytest.mark.parametrize("name", scene_names())
def test_every_label_in_the_scene_is_drawn_at_the_projector_size(app, name):
    """Arrow tips, markers (centre of percussion, strike point, CM), axis numbers and guides alike."""
    import viser

    open_scene(app, name)
    app.frame(FRAME)
    labels = {
        node: handle
        for node, handle in app.server.scene._handle_from_node_name.items()
        if node.startswith(app.simulation.root) and isinstance(handle, viser.LabelHandle)
    }
    assert labels, f"{name} draws no label"
    for node, handle in labels.items():
        assert handle.font_screen_scale == draw.LABEL_SCALE, node
