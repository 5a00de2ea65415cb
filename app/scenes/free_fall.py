"""A body in free fall: the same torque-free wobble while the centre of mass follows a parabola.

More in docs/app-notes.md (``app.scenes.free_fall``).
"""

from __future__ import annotations

from typing import Any

import numpy as np

from app import draw
from app.language.words import keep, mark, say
from app.scenes.base import register
from app.scenes.wobble import Wobble
from app.scenes.wording import amount
from physics import G

START = np.array([-0.9, 0.0, 0.3])  # launch point of the centre of mass (m)
VELOCITY = np.array([1.6, 0.0, 5.0])  # launch velocity (m/s): flight time 2 v_z / g ≈ 1.02 s
FLIGHT_TIME = 2.0 * float(VELOCITY[2]) / G  # s
RISE = float(VELOCITY[2]) ** 2 / (2.0 * G)  # m, launch point to the top of the parabola
LABEL_GAP = 0.05  # m between the body's widest reach from its path and the path's label


@register
class FreeFall(Wobble):
    name = "free_fall"
    title = mark("Body in free fall")
    order = 30
    quantities = ("L", "omega", "body_cone", "space_cone", "trace", "axes", "path", "ghost")
    caption = keep(  # made once: it must not be forgotten among the frames' readouts
        say(
            "**Body in free fall.** Gravity acts at the centre of mass: no torque about it, so L about the "
            "centre of mass stays fixed and the body wobbles exactly as in the torque-free scene while the "
            "centre of mass follows the parabola r = r₀ + v₀ τ − ½ g τ² ẑ. At 1× it runs in real time: each throw "
            "rises {rise:.3g} m and lasts its flight time 2 v₀z/g = {flight:.3g} s, then starts again.",
            rise=RISE,
            flight=FLIGHT_TIME,
        )
    )
    camera = ((0.4, -3.3, 1.7), (0.0, 0.0, 1.05))
    view = (2.3, 2.4)  # the whole flight, and the arrows at its top
    size = 0.8
    reach = 0.75  # L and ω leave the body and, at the flight's top, stay in the view

    def build(self) -> None:
        self.flight_time = FLIGHT_TIME
        tau = np.linspace(0.0, self.flight_time, 80)
        path = START + VELOCITY * tau[:, None] - 0.5 * G * tau[:, None] ** 2 * np.array([0.0, 0.0, 1.0])
        self.ctx.server.scene.add_line_segments(
            self.ctx.root + "/path",
            points=np.stack([path[:-1], path[1:]], axis=1),
            colors=draw.colour("path", self.ctx.dark),
            thickness=2.5,
            thickness_units="screen",
        )
        # Two parabolas: the centre of mass's (grey, fixed) and the axis tip's trace (the trace's colour);
        # the fixed one is named right of its launch point, under its rising leg: L and ω (L along +z, ω
        # within its cone about L) carry their labels above the body, and the body passes there only at launch.
        self.path_label = draw.add_label(
            self.ctx.server,
            self.ctx.root + "/path_label",
            mark("centre of mass"),
            position=path[0] + [LABEL_GAP + self.size / 2, 0.0, 0.0],
            anchor="center-left",
        )
        super().build()

    def centre_at(self, t: float) -> np.ndarray:
        tau = t % self.flight_time
        return START + VELOCITY * tau - 0.5 * G * tau * tau * np.array([0.0, 0.0, 1.0])

    def describe(self, state: dict[str, Any]) -> str:
        flight = say(
            "its centre of mass rises {rise} and lands after {flight}, again and again",
            rise=amount(RISE, "m"),
            flight=amount(self.flight_time, "s"),
        )
        return say("{title}: {flight}; {wobble}.", title=self.title, flight=flight, wobble=self.wobble_words())

    def draw(self, state: dict[str, Any]) -> None:
        # A new throw starts a new trace (the axis tip trace would otherwise jump across the scene).
        tau = state["t"] % self.flight_time
        if getattr(self, "_last_tau", 0.0) > tau:
            self.trace.clear()
        self._last_tau = tau
        super().draw(state)
