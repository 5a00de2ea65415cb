"""Compile (or load from numba's cache) every kernel once, so that no caller waits for the compiler.

The first call of a kernel in a fresh environment compiles it (a few seconds); later processes load the
machine code from numba's on-disk cache (``cache=True``). :func:`warm` takes one tiny step of each kernel;
the app runs it in a background thread when it starts (``app.server.App``), so a scene's first friction
step or integrator ghost does not freeze a frame.
"""

from __future__ import annotations

import time

import numpy as np

from physics.integrators.classical_rk4 import ClassicalRK4
from physics.integrators.drivers import integrate
from physics.integrators.lie_poisson import LiePoissonStrang
from physics.integrators.lie_rk4 import LieRK4
from physics.integrators.torques import GravityTorque, SpinFriction

__all__ = ["warm"]


def warm() -> float:
    """Compile or load every kernel of :mod:`physics.integrators.kernels`; returns the seconds it took."""
    start = time.perf_counter()
    moments = np.array([1.0, 1.0, 0.5])
    torques = [GravityTorque(1.0, [0.0, 0.0, 0.5]), SpinFriction(0.01, moments)]
    for method in (LiePoissonStrang(moments, torques), LieRK4(moments, torques), ClassicalRK4(moments, torques)):
        integrate(method, np.eye(3), [0.1, 0.0, 5.0], 0.01, 2)
    return time.perf_counter() - start
