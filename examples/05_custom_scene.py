"""A custom scene in the app: a symmetric body wobbling torque-free, in about forty lines.

A scene composes the shared pieces (app.draw: body mesh, arrows; app.controls: sliders, readouts)
with one physics model. Registering it puts it in the app's scene picker; this script serves it at
http://127.0.0.1:8080 (or --port) for --seconds seconds (0: until Ctrl-C), then prints what it drew.

Run: python examples/05_custom_scene.py [--port 8080] [--seconds 0]
"""

from __future__ import annotations

import argparse
import time
from typing import Any

import numpy as np
import trimesh

from app import controls, draw
from app.scenes import Scene, register
from physics.free_body import FreeBody


@register
class Coin(Scene):
    name = "coin"
    title = "A tossed coin"
    order = 90
    quantities = ("L", "omega")
    caption = "**A tossed coin** wobbles: ω precesses about the fixed L at φ̇ = L/I1."
    camera = ((0.35, -0.35, 0.25), (0.0, 0.0, 0.0))

    def build(self) -> None:
        server, root = self.ctx.server, self.ctx.root
        radius, thickness = 0.0125, 0.002  # m: a 2-euro-sized coin
        self.body = draw.BodyMesh(server, root + "/coin", trimesh.creation.cylinder(radius, thickness))
        self.L_arrow = draw.Arrow(server, root + "/L", "L", scale=2e4, shaft_radius=0.001)
        self.omega_arrow = draw.Arrow(server, root + "/omega", "omega", scale=0.004, shaft_radius=0.001)
        self.moments = np.array([0.25, 0.25, 0.5]) * 0.0075 * radius**2  # kg m² (thin disc, 7.5 g)
        self.model = FreeBody(self.moments)
        self.params = controls.ParameterPanel(
            self.ctx, [controls.SliderSpec("tilt", "tilt of ω from the axis (deg)", 0.0, 60.0, 1.0, 20.0)], self.apply
        )
        self.rate = controls.Readout(self.ctx, "precession φ̇ = L/I1 (rad/s)")
        self.apply(self.params.values)

    def apply(self, values: dict[str, float]) -> None:
        tilt = np.radians(values["tilt"])
        self.omega0 = 30.0 * np.array([np.sin(tilt), 0.0, np.cos(tilt)])  # rad/s, body frame
        self.ctx.restart()

    def compute(self, t: float, dt: float) -> dict[str, Any]:
        omega, R = self.model.motion(self.omega0, [t])
        return {"R": R[0], "omega": R[0] @ omega[0], "L": R[0] @ (self.moments * omega[0])}

    def draw(self, state: dict[str, Any]) -> None:
        self.body.set_pose(state["R"])
        self.L_arrow.set(state["L"])
        self.omega_arrow.set(state["omega"])
        self.rate.set(np.linalg.norm(state["L"]) / self.moments[0])


def main(argv: list[str] | None = None) -> None:
    from app.serving.app import App

    parser = argparse.ArgumentParser(description=__doc__.splitlines()[0])
    parser.add_argument("--port", type=int, default=8080)
    parser.add_argument("--seconds", type=float, default=0.0, help="stop after this long (0: run until Ctrl-C)")
    args = parser.parse_args(argv)

    app = App(host="127.0.0.1", port=args.port, scene="coin")
    print(f"serving the coin on {app.url}", flush=True)
    try:
        start = time.monotonic()
        while args.seconds <= 0 or time.monotonic() - start < args.seconds:
            time.sleep(0.1)
    except KeyboardInterrupt:
        pass
    finally:
        app.stop()
    scene = app.scene
    assert isinstance(scene, Coin)
    print(f"frames drawn: {app.frames}; simulated time {app.time:.3f} s")
    print(f"precession rate shown: {scene.rate.text} rad/s")
    print(f"lecture: L/I1 = {np.linalg.norm(scene.moments * scene.omega0) / scene.moments[0]:.4g} rad/s")


if __name__ == "__main__":
    main()
