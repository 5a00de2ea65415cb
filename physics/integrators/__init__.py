"""Geometric integrators for a rigid body about a fixed point (or its centre of mass) under a torque.

State: the attitude ``R`` (body to space) and the body-frame angular momentum ``L_body`` (principal axes).
One method per module (:mod:`.lie_poisson`, :mod:`.yoshida4`, :mod:`.suzuki4`, :mod:`.yoshida6`,
:mod:`.yoshida8`, the optimised :mod:`.blanes_moan6`, :mod:`.kahan_li8` and :mod:`.sofroniou_spaletta10`,
:mod:`.exact_free`, :mod:`.lie_rk4`, :mod:`.classical_rk4`), each declaring ``name``,
``order``, ``symplectic`` and ``conserves``; torques in :mod:`.torques`; ``integrate`` and ``advance`` in
:mod:`.drivers`; the compiled steps in :mod:`.kernels` and :mod:`.compiled`. :data:`REGISTRY` lists every
method by name. The methods, the torques and the measured speed are described in docs/physics-notes.md.
"""

from __future__ import annotations

from physics.integrators._base import Method
from physics.integrators._state import kinetic_energy
from physics.integrators.blanes_moan6 import BlanesMoan6
from physics.integrators.classical_rk4 import ClassicalRK4
from physics.integrators.drivers import Trajectory, advance, integrate
from physics.integrators.exact_free import ExactFreeSplitting
from physics.integrators.kahan_li8 import KahanLi8
from physics.integrators.lie_poisson import LiePoissonStrang
from physics.integrators.lie_rk4 import LieRK4
from physics.integrators.sofroniou_spaletta10 import SofroniouSpaletta10
from physics.integrators.suzuki4 import Suzuki4
from physics.integrators.torques import GravityTorque, SpinFriction, TransverseAirDrag
from physics.integrators.yoshida4 import Yoshida4
from physics.integrators.yoshida6 import Yoshida6
from physics.integrators.yoshida8 import Yoshida8

__all__ = [
    "GravityTorque",
    "SpinFriction",
    "LiePoissonStrang",
    "Yoshida4",
    "Suzuki4",
    "Yoshida6",
    "Yoshida8",
    "BlanesMoan6",
    "KahanLi8",
    "SofroniouSpaletta10",
    "ExactFreeSplitting",
    "LieRK4",
    "ClassicalRK4",
    "REGISTRY",
    "Method",
    "TransverseAirDrag",
    "advance",
    "Trajectory",
    "integrate",
    "kinetic_energy",
]

REGISTRY: dict[str, type[Method]] = {
    cls.name: cls
    for cls in (
        LiePoissonStrang,
        Yoshida4,
        Suzuki4,
        Yoshida6,
        Yoshida8,
        BlanesMoan6,
        KahanLi8,
        SofroniouSpaletta10,
        ExactFreeSplitting,
        LieRK4,
        ClassicalRK4,
    )
}
"""Every method by its ``name``; each class declares ``name``, ``order``, ``symplectic`` and ``conserves``."""
