"""The drawing kit a scene is built from (``from app import controls, draw``): palette, meshes, pieces.

Re-exported from :mod:`app.drawing` for scenes, in app/ and outside it (examples/05_custom_scene.py).
"""

from __future__ import annotations

from app.drawing.meshes import (
    cylinder_mesh,
    rotation_z_to,
    top_mesh,
    wxyz,
)
from app.drawing.palette import (
    COLOURS,
    DARK_COLOURS,
    GHOST_OPACITY,
    LABELS,
    OKABE_ITO,
    SWATCH_OPACITY,
    colour,
    hex_colour,
    instance_colour,
    legend_html,
    light,
    shown_colour,
)
from app.drawing.pieces import (
    LABEL_SCALE,
    Arrow,
    BodyMesh,
    Cone,
    InertiaEllipsoid,
    PrincipalFrame,
    add_label,
    faint_sphere,
    move,
    screen_axes,
)
from app.drawing.trace import TRACE_CHUNK, TRACE_FADE, VIEW_BACKGROUND, Trace

__all__ = [
    "OKABE_ITO",
    "COLOURS",
    "LABELS",
    "GHOST_OPACITY",
    "SWATCH_OPACITY",
    "hex_colour",
    "instance_colour",
    "shown_colour",
    "legend_html",
    "colour",
    "DARK_COLOURS",
    "light",
    "wxyz",
    "rotation_z_to",
    "top_mesh",
    "cylinder_mesh",
    "LABEL_SCALE",
    "TRACE_CHUNK",
    "TRACE_FADE",
    "VIEW_BACKGROUND",
    "move",
    "add_label",
    "BodyMesh",
    "Arrow",
    "screen_axes",
    "PrincipalFrame",
    "Trace",
    "Cone",
    "faint_sphere",
    "InertiaEllipsoid",
]
