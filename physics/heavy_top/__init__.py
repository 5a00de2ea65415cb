"""The heavy symmetric (Lagrange) top on its tip, and any heavy body on a pivot stepped with friction.

:class:`HeavyTop` is the model (:mod:`.model`); one exact motion is a :class:`HeavyTopTrajectory`
(:mod:`.trajectory`) built from its constants (:mod:`.motion`, the roots in :mod:`.nutation_cubic`, the
pole terms in :mod:`.pole_terms`); the stepped runs with spin friction and air drag are in :mod:`.stepped`,
the table a top on its tip lies on in :mod:`.table`.
"""

from __future__ import annotations

from physics.constants import G
from physics.euler_angles import euler_attitude, omega_body_from_euler, symmetry_axis
from physics.heavy_top.model import HeavyTop
from physics.heavy_top.motion import ScaledTop, motion_constants
from physics.heavy_top.nutation_cubic import NutationCubic
from physics.heavy_top.stepped import (
    FrictionRun,
    SteppedRun,
    friction_stepper,
    run_stepper,
    simulate_heavy_body,
)
from physics.heavy_top.table import on_the_table, touch_angle
from physics.heavy_top.trajectory import HeavyTopSolution, HeavyTopTrajectory
from physics.integrators.torques import TransverseAirDrag
from physics.validation import MAX_RATE, MAX_STEPS

__all__ = [
    "G",
    "MAX_RATE",
    "MAX_STEPS",
    "FrictionRun",
    "HeavyTop",
    "HeavyTopSolution",
    "HeavyTopTrajectory",
    "NutationCubic",
    "ScaledTop",
    "SteppedRun",
    "TransverseAirDrag",
    "euler_attitude",
    "friction_stepper",
    "motion_constants",
    "omega_body_from_euler",
    "on_the_table",
    "run_stepper",
    "simulate_heavy_body",
    "symmetry_axis",
    "touch_angle",
]
