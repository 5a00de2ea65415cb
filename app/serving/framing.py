"""Frame a scene's camera clear of the control panel, for the browser's own viewport.

More in docs/app-notes.md (``app.serving.framing``).
"""

from __future__ import annotations

import math
import time
import weakref
from dataclasses import dataclass, replace
from typing import Any

import numpy as np
import viser
from numpy.typing import ArrayLike, NDArray

from app.guards.responses import user_agent
from app.panel.projector import projector_region

__all__ = [
    "FOV",
    "FRAMING_GRACE",
    "PANEL_PX",
    "PHONE_PX",
    "SHEET_FRACTION",
    "first_view",
    "free_region",
    "is_mobile",
    "phone_layout",
    "framed",
    "label_room",
    "Framing",
    "framing_of",
    "rescaled",
    "show_scene_to",
]

FOV = math.radians(50.0)
"""Vertical field of view (viser's default 75° makes the scene look far away)."""
FRAMING_GRACE = 10.0
"""Seconds after a camera is framed for a page during which a new page size always re-frames it: the page
reports its settled size as it loads, possibly before it has eased to the framed camera."""

PANEL_PX = 400.0
"""Width the floating panel takes at the right, its margins included (viser's "large" control width)."""

PHONE_PX = 576.0
"""viser's phone layout below this width (Mantine's ``xs`` breakpoint, 36 em)."""

SHEET_FRACTION = 0.6
"""Largest share of a phone's height the panel's bottom sheet covers (viser's ``maxHeight: 60%``)."""

SHEET_MARGIN_PX = 12.0
"""Space kept free above a phone's bottom sheet, px."""

LABEL_ROOM_PX = 22.0
"""Room kept at the top of the free region for a label's line, CSS px (viser's label text, measured on
screenshots): the scene is framed below it, so an arrow reaching the top keeps its label on the screen."""

PHONE_CSS_PX = 400.0
"""About a phone's width in CSS px upright (375 to 430): what a phone's view size in device pixels is divided
by to estimate its pixel ratio."""


def label_room(width: float, height: float, mobile: bool = False) -> float:
    """:data:`LABEL_ROOM_PX` in the pixels a browser reports its view in: a phone reports device pixels
    (:func:`phone_layout`), about its width over :data:`PHONE_CSS_PX` to a CSS pixel."""
    ratio = max(1.0, width / PHONE_CSS_PX) if phone_layout(width, height, mobile) else 1.0
    return LABEL_ROOM_PX * ratio


FILL = 0.75
"""Share of the scene's own view that must stay visible in the free region (its views have margins)."""

REFERENCE_ASPECT = 1.6
"""The aspect ratio (width / height) a scene's camera was chosen for: a 1280×800 view, no panel."""

FIRST_VIEW_PX = (1280.0, 800.0)
"""The view a browser's first camera is framed for, before the page reports its own size."""


def phone_layout(width: float, height: float, mobile: bool = False) -> bool:
    """Whether viser lays its panel out as a phone's bottom sheet for a ``width`` × ``height`` view.

    viser reports its canvas in device pixels (CSS pixels × a pixel ratio it lowers when frames are slow), so
    a phone's 390 CSS px arrive as 780 or more: a browser that says it is a phone (``mobile``, from its user
    agent) held upright is laid out as one whatever its pixel count.
    """
    return width <= PHONE_PX or (mobile and height > width)


def is_mobile(agent: str) -> bool:
    """A user agent of a phone's browser (Safari on iPhone, Chrome on Android: both say "Mobile")."""
    return "Mobile" in agent or "Android" in agent


def free_region(
    width: float, height: float, mobile: bool = False, *, projector: bool = False, plot: bool = False
) -> tuple[float, float, float, float]:
    """The part of a ``width`` × ``height`` px view the panel leaves free: (left, top, right, bottom), px
    (``mobile``: see :func:`phone_layout`). In projector mode (``projector``) the panel is a slim bar and the
    whole width is free but for the caption above and the key plot at the right (``plot``: the scene has
    one; :func:`app.panel.projector.projector_region`); a phone keeps its bottom sheet."""
    if phone_layout(width, height, mobile):
        # A few pixels above the sheet's edge: a swinging body framed to the edge itself can reach under it.
        return (0.0, 0.0, width, (1.0 - SHEET_FRACTION) * height - SHEET_MARGIN_PX)
    if projector:
        return projector_region(width, height, plot)
    return (0.0, 0.0, max(width - PANEL_PX, 0.5 * width), height)


def framed(
    position: ArrayLike,
    look_at: ArrayLike,
    width: float,
    height: float,
    fov: float,
    view: tuple[float, float] | None = None,
    mobile: bool = False,
    *,
    projector: bool = False,
    plot: bool = False,
) -> tuple[NDArray[np.float64], NDArray[np.float64]]:
    """A scene's camera moved so that what it frames is seen clear of the panel.

    Parameters
    ----------
    position, look_at : array_like, shape (3,)
        The scene's camera (m), chosen for the whole view; +z is up.
    width, height : float
        The browser's view, px (viser's ``client.camera.image_width`` / ``image_height``).
    fov : float
        Vertical field of view, rad.
    view : (float, float), optional
        The width and height (m), across the look-at point, of what the scene must show
        (:attr:`app.scenes.base.Scene.view`): the camera comes as close as lets that fill the free region
        (its body then as large as it can be). Default: the camera's own distance, backed off to fit.
    mobile : bool
        The browser is a phone's (:func:`phone_layout`).
    projector, plot : bool
        Projector mode, and whether the scene's key plot is shown in it (:func:`free_region`).

    Returns
    -------
    (position, look_at) : ndarrays, shape (3,)
        Unchanged for an unknown view size (0 px), otherwise moved along the line of sight and
        panned so the look-at point is at the centre of :func:`free_region`.
    """
    eye, target = np.asarray(position, dtype=float), np.asarray(look_at, dtype=float)
    if not (width > 0 and height > 0 and math.isfinite(width) and math.isfinite(height)):
        return eye, target
    offset = eye - target
    distance = float(np.linalg.norm(offset))
    forward = -offset / distance
    right = np.cross(forward, (0.0, 0.0, 1.0))
    if np.linalg.norm(right) < 1e-9:  # looking straight down or up: any horizontal "right" will do
        right = np.array([1.0, 0.0, 0.0])
    right /= np.linalg.norm(right)
    up = np.cross(right, forward)
    left, top, right_px, bottom = free_region(width, height, mobile, projector=projector, plot=plot)
    if not projector or phone_layout(width, height, mobile):  # (projector mode frames below its caption's band)
        top += label_room(width, height, mobile)  # a label hung above the view's highest tip stays on the screen
    free_w, free_h = right_px - left, bottom - top
    if view is not None:
        # The distance at which the free region just holds view[0] × view[1] metres at the look-at point.
        per_px = max(view[0] / free_w, view[1] / free_h)  # m per px
        distance = per_px * height / (2.0 * math.tan(0.5 * fov))
    else:
        # Back off until FILL of the scene's own view (REFERENCE_ASPECT wide, the same height) fits.
        distance *= max(1.0, FILL * REFERENCE_ASPECT * height / free_w, FILL * height / free_h)
    metres_per_px = 2.0 * distance * math.tan(0.5 * fov) / height
    dx = 0.5 * (left + right_px) - 0.5 * width  # where the free centre is, from the view's centre, px
    dy = 0.5 * (top + bottom) - 0.5 * height  # (down is positive)
    shift = metres_per_px * (-dx * right + dy * up)
    return target + shift - distance * forward, target + shift


def first_view(
    position: ArrayLike, look_at: ArrayLike, view: tuple[float, float] | None = None
) -> tuple[NDArray[np.float64], NDArray[np.float64]]:
    """The camera (position, look_at), m, each shape (3,), a new browser starts from (viser's initial
    camera): the scene's camera framed for :data:`FIRST_VIEW_PX`."""
    return framed(position, look_at, *FIRST_VIEW_PX, FOV, view)


def show_scene_to(
    client: viser.ClientHandle,
    position: Any,
    look_at: Any,
    view: tuple[float, float] | None = None,
    *,
    projector: bool = False,
    plot: bool = False,
) -> None:
    """Point a browser's camera at a scene (its camera ``position``, ``look_at``), framed clear of the panel
    (in projector mode, ``projector``, clear of the caption and of the key plot if shown, ``plot``).

    A page reports its real size only after its layout settles (and again when the window or a phone's
    orientation changes, or a loaded page lowers its pixel ratio): until the viewer moves the camera, a new
    size re-frames it. A camera away from the framed eye is the viewer's once the page has echoed that eye
    (it has arrived), or :data:`FRAMING_GRACE` after the framing; before either, the page may report its
    settled size while still easing to the camera it was sent, which would look like a viewer's move. A page that puts its camera back on
    the first view is framed again for its size: viser's client resets to its initial camera when the
    scene's root arrives, which on a loaded machine can come after the framing (and "Reset View" does it too).
    """
    size = (client.camera.image_width, client.camera.image_height)
    before = _FRAMINGS.get(client)
    mobile = before.mobile if before is not None else is_mobile(user_agent(client))
    eye, target = framed(position, look_at, size[0], size[1], FOV, view, mobile, projector=projector, plot=plot)
    start = first_view(position, look_at, view)[0]  # where viser's client resets to: kept, echoes compare to it
    _FRAMINGS[client] = Framing(size, eye, position, look_at, time.monotonic(), start, view, projector, plot, mobile)
    with client.atomic():
        client.camera.fov = FOV
        client.camera.position = eye
        client.camera.look_at = target
    if before is None:
        client.camera.on_update(_reframe)


@dataclass(frozen=True)
class Framing:
    """How a browser's camera was last framed (:func:`show_scene_to`).

    Attributes
    ----------
    size : (int, int)
        The page's view in pixels it was framed for (a change of its pixel ratio alone updates it and keeps
        the framing: the layout in CSS px is the same).
    eye : array (3,)
        The camera position sent, in m.
    position, look_at : array-like (3,)
        The scene's camera and target it was framed from, in m.
    when : float
        ``time.monotonic()`` when it was sent.
    start : array (3,)
        Where viser's client resets its camera to (the scene's first view).
    view : (float, float) or None
        The scene's extent the framing keeps in view.
    projector, plot : bool
        Projector mode, and its key plot shown.
    mobile : bool
        The browser said it is a phone or a tablet.
    arrived : bool
        The page has echoed ``eye`` at ``size``: a camera away from it since is the viewer's.
    """

    size: tuple[int, int]
    eye: Any
    position: Any
    look_at: Any
    when: float
    start: Any
    view: tuple[float, float] | None
    projector: bool
    plot: bool
    mobile: bool
    arrived: bool = False


_FRAMINGS: weakref.WeakKeyDictionary[Any, Framing] = weakref.WeakKeyDictionary()
"""Each browser's last framing, forgotten with its client handle (nothing of ours is stored on viser's)."""


def framing_of(client: viser.ClientHandle) -> Framing | None:
    """How this browser's camera was last framed, or None before the first framing."""
    return _FRAMINGS.get(client)


def _reframe(camera: Any) -> None:
    client = camera.client
    last = _FRAMINGS.get(client)
    if last is None:
        return
    size = (camera.image_width, camera.image_height)
    if _near(camera.position, last.start) and not _near(last.eye, last.start):
        # Reset to the first view (the scene's root arrived, or "Reset View"): framed for this page again.
        show_scene_to(client, last.position, last.look_at, last.view, projector=last.projector, plot=last.plot)
        return
    at_eye = _near(camera.position, last.eye)
    if size != last.size and rescaled(last.size, size):
        # Only the page's pixel ratio changed (viser lowers it when frames are slow, often mid-drag): the
        # layout in CSS px, and so the framing, is the same; re-framing would yank the viewer's camera back.
        _FRAMINGS[client] = last = replace(last, size=size)
    if size == last.size:
        if at_eye and not last.arrived:
            _FRAMINGS[client] = replace(last, arrived=True)
        return
    # A new shape while the camera is away from the framed eye (a phone turned after an orbit): the viewer's
    # camera once the page had arrived at the eye, else only after the grace.
    if not at_eye and (last.arrived or time.monotonic() - last.when > FRAMING_GRACE):
        return
    show_scene_to(client, last.position, last.look_at, last.view, projector=last.projector, plot=last.plot)


def rescaled(before: tuple[int, int], after: tuple[int, int]) -> bool:
    """Whether a page's view of ``after`` pixels (width, height) is its view of ``before`` at another pixel ratio:
    the same shape, to the pixel each side loses to rounding down (a canvas is its CSS size × ratio, floored).

    viser reports its canvas in device pixels and scales its pixel ratio between 0.75 and 1 of the screen's
    as the frame rate falls and recovers; a window resized to exactly its old shape is read as a rescale too.
    """
    (w0, h0), (w1, h1) = before, after
    if min(w0, h0, w1, h1) <= 0:
        return False
    return abs(w0 * h1 - w1 * h0) <= w0 + h0 + w1 + h1


def _near(echo: Any, eye: Any) -> bool:
    """A camera position the page echoed is ``eye``: to 1e-3 of the distance, as the page echoes in float32
    and after its own easing (an orbit by a person moves it by far more)."""
    eye = np.asarray(eye, dtype=float)
    return bool(np.linalg.norm(np.asarray(echo, dtype=float) - eye) <= 1e-3 * max(1.0, float(np.linalg.norm(eye))))
