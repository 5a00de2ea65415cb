"""The free-fall scene headless: the centre of mass on its parabola, the spin as in the wobble."""

from __future__ import annotations

import numpy as np
import pytest

from physics import G
from physics.free_body import FreeBody
from tests.harness import FRAME, matrix, open_scene

SCENES = ["heavy_top", "wobble", "free_fall"]


# --------------------------------------------------------------------------------------------------
# Shared pieces
# --------------------------------------------------------------------------------------------------


def test_free_fall_centre_follows_the_parabola_and_spins_like_the_wobble(app):
    from app.scenes.free_fall import START, VELOCITY

    scene = open_scene(app, "free_fall")
    for _ in range(20):
        app.frame(FRAME)
    tau = app.time % scene.flight_time
    expected = START + VELOCITY * tau - 0.5 * G * tau**2 * np.array([0, 0, 1.0])
    np.testing.assert_allclose(scene.body.handle.position, expected, atol=1e-6)
    # The arrows start at the centre of mass.
    np.testing.assert_allclose(scene.L_arrow.handle.position, expected, atol=1e-6)
    np.testing.assert_allclose(scene.L_arrow.handle.points[0, 0], 0.0)
    R_expected = FreeBody(scene.moments).attitude(scene.omega0, [app.time], scene.attitude0)[0]
    np.testing.assert_allclose(matrix(scene.body.handle), R_expected, atol=2e-6)


class _FakeClock:
    """The loop's clock and its pauses, faked: ``wait(t)`` advances the clock by ``t`` plus an oversleep (the
    OS wakes a thread late), and the loop stops after ``until`` seconds."""

    def __init__(self, until: float, oversleep: list[float]) -> None:
        self.now, self.until, self.oversleep, self.waits = 1000.0, until, oversleep, 0

    def perf_counter(self) -> float:
        return self.now

    def wait(self, timeout: float) -> bool:
        self.now += timeout + self.oversleep[self.waits % len(self.oversleep)]
        self.waits += 1
        return self.is_set()

    def is_set(self) -> bool:
        return self.now >= 1000.0 + self.until

    def clear(self) -> None:
        pass


def test_free_fall_runs_in_real_time_through_the_loop(app, monkeypatch):
    """The real-time loop (App.run) on a fake clock whose pauses overrun by 0 to 12 ms: after 10 s of wall
    time the free fall's simulated time is 10 s (to within the last frame) and the body is where the
    parabola puts it then; a throw lasts its flight time, 1.02 s ("a second too fast")."""
    import app.serving.app as server
    from app.scenes.free_fall import FLIGHT_TIME, START, VELOCITY

    scene = open_scene(app, "free_fall")
    app.restart()
    clock = _FakeClock(10.0, [0.0, 0.004, 0.012, 0.001])
    monkeypatch.setattr(server.time, "perf_counter", clock.perf_counter)
    monkeypatch.setattr(app, "_stop", clock)
    times = []
    frame = app.shared.frame

    def recording(dt):
        drawn = frame(dt)
        times.append((clock.now, app.time))
        return drawn

    monkeypatch.setattr(app.shared, "frame", recording)
    app.run()
    wall = np.array([w for w, _ in times]) - 1000.0
    simulated = np.array([t for _, t in times])
    assert len(times) > 400  # about 48 frames a second: 16.7 ms a frame, and the pauses overrun
    # Each frame advances the simulation by the wall time since the last: sim = wall, to round-off.
    np.testing.assert_allclose(simulated, wall - wall[0] + simulated[0], rtol=0, atol=1e-9)
    assert simulated[-1] == pytest.approx(10.0, abs=0.03)
    tau = app.time % FLIGHT_TIME
    expected = START + VELOCITY * tau - 0.5 * G * tau**2 * np.array([0, 0, 1.0])
    np.testing.assert_allclose(scene.body.handle.position, expected, atol=1e-9)
    assert FLIGHT_TIME == pytest.approx(1.0194, abs=1e-4)  # 2 v_z/g: a real throw 1.27 m high takes this long
