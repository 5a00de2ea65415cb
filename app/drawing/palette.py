"""The palette: one colour per physical quantity in every scene (Okabe–Ito), the legend, the light.

Each quantity has one colour everywhere (:data:`COLOURS`) and a legend text (:data:`LABELS`);
:func:`legend_html` draws the legend for the quantities a scene shows.
"""

from __future__ import annotations

import math

import numpy as np
import viser
from numpy.typing import ArrayLike

from app.language.words import joined, keep, mark, say

__all__ = [
    "OKABE_ITO",
    "COLOURS",
    "LABELS",
    "GHOST_OPACITY",
    "SWATCH_OPACITY",
    "DARK_COLOURS",
    "colour",
    "hex_colour",
    "instance_colour",
    "shown_colour",
    "legend_html",
    "light",
]

OKABE_ITO: dict[str, tuple[int, int, int]] = {
    "orange": (230, 159, 0),
    "sky_blue": (86, 180, 233),
    "bluish_green": (0, 158, 115),
    "yellow": (240, 228, 66),
    "blue": (0, 114, 178),
    "vermillion": (213, 94, 0),
    "reddish_purple": (204, 121, 167),
    "black": (0, 0, 0),
}
"""Okabe & Ito (2008), *Color Universal Design*: eight colours that stay distinct under every common
colour-vision deficiency. Every quantity below takes one of them; the body and the guides are greys."""

# One colour per quantity, the same in every scene (RGB 0-255); the legend shows exactly these, and
# tests/app/drawing/test_palette.py checks that every node a scene sends is drawn in one of them.
COLOURS: dict[str, tuple[int, int, int]] = {
    "L": OKABE_ITO["orange"],  # angular momentum
    "omega": OKABE_ITO["blue"],  # angular velocity
    "torque": OKABE_ITO["reddish_purple"],  # torque
    "trace": OKABE_ITO["vermillion"],  # trace of the symmetry-axis tip
    "polhode": OKABE_ITO["bluish_green"],  # the polhode: the path L draws in the body (no body cone there)
    "body_cone": OKABE_ITO["bluish_green"],  # body cone
    "space_cone": OKABE_ITO["sky_blue"],  # space cone
    "path": (96, 96, 96),  # path of the centre of mass: dark grey
    "axes": OKABE_ITO["black"],  # principal axes e1, e2, e3 (not RGB: the quantities have those colours)
    "body": (92, 105, 126),  # the body: slate, opaque, 3.7-7.8:1 light and 3.2-5.0:1 dark (docs/look.md)
    "impulse": OKABE_ITO["vermillion"],  # an impulse (strike); the pendulum shows no trace
    "reaction": OKABE_ITO["reddish_purple"],  # a constraint's reaction; the pendulum shows no torque
    "ghost": OKABE_ITO["black"],  # the body moved by an integrator: translucent (GHOST_OPACITY), a grey shadow
    # A fixed point or axle (the pendulum's), the explorer's point the tensor is about and its axes: not the
    # principal axes' black (the explorer draws both); the colour of the pivot's reaction, its push.
    "pivot": OKABE_ITO["reddish_purple"],
    "ellipsoid": OKABE_ITO["yellow"],  # the inertia ellipsoid, translucent
    "guide": (150, 150, 150),  # construction lines: spheres, equators, the separatrix
}


DARK_COLOURS: dict[str, tuple[int, int, int]] = {
    "axes": (225, 225, 225),  # black lines vanish on the dark look's near-black: light grey, 12:1 on it
    "path": (170, 170, 170),  # the light look's dark grey is 2.6:1 on near-black; this grey is 7:1
}
"""The dark look's colours where the light look's would vanish against its background (:func:`colour`)."""


def colour(quantity: str, dark: bool = False) -> tuple[int, int, int]:
    """A quantity's RGB colour (0-255) in the light look or, with ``dark``, the dark look."""
    return DARK_COLOURS.get(quantity, COLOURS[quantity]) if dark else COLOURS[quantity]


GHOST_OPACITY = 0.35
"""Opacity of the integrator's ghost body (app.drawing.ghost), and of its swatch in the legend."""

SWATCH_OPACITY: dict[str, float] = {"ghost": GHOST_OPACITY}
"""Quantities drawn translucent whose legend swatch is shown as they look (the cones and the ellipsoid have
rims or are large enough to read at full colour)."""


def hex_colour(name: str) -> str:
    """``#rrggbb`` of a quantity's colour (a key of :data:`COLOURS`) or of an :data:`OKABE_ITO` name, for
    plots and HTML."""
    return _rgb_hex(COLOURS[name] if name in COLOURS else OKABE_ITO[name])


# Legend text per quantity (Unicode: viser's markdown has no LaTeX).
LABELS: dict[str, str] = {
    "L": mark("L — angular momentum (fixed in space without torque)"),
    "omega": mark("ω — angular velocity"),
    "torque": mark("τ — torque"),
    "trace": mark("trace of the axis tip (a top's symmetry axis, the racket's spin axis; ω's tip in a body view)"),
    "polhode": mark("polhode: the path of L seen from the body, on the L-sphere"),
    "body_cone": mark("body cone (turns with the body)"),
    "space_cone": mark("space cone (fixed about L)"),
    "path": mark("path of the centre of mass"),
    "axes": mark("principal axes e₁, e₂, e₃ (e₃ longest)"),
    "body": mark("the body"),
    "impulse": mark("J — impulse"),
    "reaction": mark("pivot reaction"),
    "ghost": mark("ghost (translucent) — the body moved by the integrator of “Compare with integrator”"),
    "pivot": mark("pivot — the fixed axle, or the point the tensor is taken about (and its lever to the CM)"),
    "ellipsoid": mark("inertia ellipsoid (long where the moment is small)"),
    "guide": mark("guides (the sphere the axis tip moves on, the L-sphere, equators, the separatrix)"),
}


def _rgb_hex(rgb: tuple[int, int, int]) -> str:
    return "#{:02x}{:02x}{:02x}".format(*rgb)


def instance_colour(quantity: str) -> tuple[int, int, int]:
    """What to send as an arrow's colour so that the page shows ``COLOURS[quantity]``.

    viser's client reads the per-instance colours of batched meshes (arrows; ``new THREE.Color(r, g, b)``
    in its ``BatchedMeshBase.tsx``) as *linear* RGB, but a mesh's or a line's colour as sRGB. Sent as it
    is, an arrow's colour comes out washed out (dark blue shows as sky blue, red as pink); so it goes
    out converted to linear light (IEC 61966-2-1's sRGB transfer function), and the page converts it
    back to within one level in 255.
    """
    c = np.asarray(COLOURS[quantity], dtype=float) / 255.0
    linear = np.where(c <= 0.04045, c / 12.92, ((c + 0.055) / 1.055) ** 2.4)
    r, g, b = (int(v) for v in np.rint(255.0 * linear))
    return (r, g, b)


def shown_colour(sent: ArrayLike) -> tuple[int, int, int]:
    """The sRGB colour a page shows for an arrow colour ``sent`` (the inverse of :func:`instance_colour`)."""
    c = np.asarray(sent, dtype=float) / 255.0
    srgb = np.where(c <= 0.0031308, 12.92 * c, 1.055 * c ** (1 / 2.4) - 0.055)
    r, g, b = (int(v) for v in np.rint(255.0 * srgb))
    return (r, g, b)


def legend_html(quantities: tuple[str, ...] | list[str], dark: bool = False) -> str:
    """HTML legend: a coloured swatch (as the look draws it, :func:`colour`) and a name for each quantity key
    of :data:`COLOURS`."""
    rows = []
    for key in quantities:
        swatch = _rgb_hex(colour(key, dark))
        # A translucent quantity: its colour at its opacity inside an outline of the full colour (the ghost's
        # swatch would otherwise be the guides' grey).
        opacity = (
            f";background:rgba({','.join(str(c) for c in COLOURS[key])},{SWATCH_OPACITY[key]})"
            f";box-shadow:inset 0 0 0 1px {swatch}"
            if key in SWATCH_OPACITY
            else ""
        )
        rows.append(say(_ROW, style=swatch + opacity, label=LABELS[key]))
    # One text made of said parts, so that each name is translated on the wire; kept: a legend lives as long
    # as its scene, and there are few of them.
    return keep(say(_LEGEND, rows=joined(rows)))


# Markup alone (not for the translators): the names inside are the values, each translated.
_ROW = (
    '<div style="display:flex;align-items:center;gap:6px;margin:1px 0">'
    '<span style="display:inline-block;width:22px;height:6px;border-radius:3px;background:{style}">'
    "</span>{label}</div>"
)
_LEGEND = '<div class="rbl-legend">{rows}</div>'


def light(scene: viser.SceneApi, dark: bool = False) -> None:
    """Light a scene so that a surface facing the viewer shows its colour as the legend does.

    viser's defaults (a warehouse environment map plus a directional light of intensity 3) wash the
    colours out: amber turns pale yellow, red turns pink. three.js's physically based lights give a
    Lambertian surface its own colour under an ambient intensity of π, so the scene gets 0.6 π of ambient
    light and 0.55 π from a light above and in front (faces towards it a little brighter than the legend,
    faces away at 0.6 of it, in linear light): solid bodies keep their shading, colours keep their hue.
    Against the dark look's near-black background the faces away from the light need more: 1.15 π of
    ambient and 0.4 π of key light keep the slate body above 3:1: measured 3.2 to 5.0:1 in the dark look and
    3.7 to 8.0:1 in the light one, every scene (docs/look.md, written by docs/look.py, checked by
    tests/browser/test_look.py).
    """
    ambient, key = (1.15, 0.4) if dark else (0.6, 0.55)
    scene.configure_environment_map(hdri=None)
    scene.configure_default_lights(enabled=False)
    scene.add_light_ambient("/lights/ambient", intensity=ambient * math.pi)
    scene.add_light_directional("/lights/key", intensity=key * math.pi, position=(2.0, -3.0, 5.0))
