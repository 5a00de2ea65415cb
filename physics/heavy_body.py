"""A heavy body on a fixed pivot stepped with friction: the names of :mod:`physics.heavy_top.stepped`."""

from __future__ import annotations

from physics.heavy_top.stepped import FrictionRun, SteppedRun, simulate_heavy_body
from physics.integrators.torques import TransverseAirDrag

__all__ = ["FrictionRun", "SteppedRun", "TransverseAirDrag", "simulate_heavy_body"]
