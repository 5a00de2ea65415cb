"""Geometric integrators for a rigid body about a fixed point (or its centre of mass) under a torque.

State: the attitude ``R`` (body to space, ``x_space = R @ x_body``, ``Ṙ = R hat(ω)``) and the body-frame
angular momentum ``L_body = I ω`` (principal axes, so ``I`` is the diagonal ``moments``). The equations are
Euler's equations with a torque (lecture, "Euler's equations")

    dL_body/dt = L_body × ω + τ_body(R, L_body),    Ṙ = R hat(ω),    ω = L_body / I.

Methods (each declares ``name``, ``order``, ``symplectic`` and ``conserves``):

* :class:`LiePoissonStrang` — the free rotation ``H = Σ L_i²/(2 I_i)`` is split into the three exactly
  solvable flows of ``L_i²/(2 I_i)``, each a rotation about the principal axis ``e_i`` by the angle
  ``h L_i / I_i`` (of ``R`` forwards, of ``L_body`` backwards) (McLachlan 1993; Touma & Wisdom 1994;
  Dullweber, Leimkuhler & McLachlan 1997, "NO_SQUISH"); a torque enters as a kick with ``R`` frozen.
  Symmetric (Strang) composition ``K(h/2) X(h/2) Y(h/2) Z(h) Y(h/2) X(h/2) K(h/2)``: order 2.
* :class:`Yoshida4`, :class:`Yoshida6`, :class:`Yoshida8` — symmetric compositions of that Strang step
  (Yoshida 1990: triple jump, "solution A", "solution D"), orders 4, 6 and 8; :class:`Suzuki4` — Suzuki's five-stage fourth-order
  composition (smaller error constant than the triple jump).
* :class:`BlanesMoan6`, :class:`KahanLi8`, :class:`SofroniouSpaletta10` — the optimised ones (issue 25):
  Blanes & Moan's S6 (2002; ten stages, as a composition of the Lie–Trotter step and its adjoint), Kahan &
  Li's s17odr8a (1997) and Sofroniou & Spaletta's s35odr10 (2005) compositions of the Strang step, orders 6,
  8, 10, with error constants one to four orders of magnitude below Yoshida's; the cheapest of the project's
  methods at errors of 1e-7 and below on the bodies without a closed form (benchmarks/results/work_precision.md).
* :class:`ExactFreeSplitting` — the free rotation is taken whole from its exact flow
  (:meth:`physics.free_body.FreeBody.flow`; for a body with two equal moments the lecture's closed form
  ``R ← R exp(h hat(L_body)/I⊥) exp(h Ω_s hat(e_s))`` is evaluated inline, which is the same formula and
  much cheaper per step), plus torque kicks; order 2 (``composition="yoshida4"``, ``"yoshida6"``,
  ``"yoshida8"`` give 4, 6, 8).
  Without torque it is exact for any step.
* :class:`ClassicalRK4` — classical RK4 on the components of ``(R, L_body)``: order 4, conserves nothing,
  ``R`` leaves SO(3) (stepped by :func:`advance`); the careless baseline the app shows beside the exact motion.
* :class:`LieRK4` — Runge–Kutta–Munthe-Kaas of order 4 with the classical RK4 tableau (the attitude is
  advanced by the exponential map, so it stays on SO(3)); the non-symplectic baseline.

Torques. A torque is a callable ``torque(R (n,3,3), L_body (n,3)) -> τ_body (n,3)`` (N m) with an attribute
``conservative`` (True when it depends on the attitude only, i.e. comes from a potential ``V(R)``: its
sub-flow is the symplectic kick ``L ← L + h τ(R)``). A non-conservative torque (friction) is advanced with
``R`` frozen by its exact flow when it provides one (:class:`SpinFriction` does: the flow is linear in
``L``), else by one classical RK4 step (which keeps the Strang and fourth-order compositions at their
order; :class:`Yoshida6` then drops to order 4).

A zero principal moment (a rod, lecture: "a rod has one moment 0") is allowed: the rod cannot carry
angular momentum about its own axis, so ``L_body`` along that axis is held at 0 (any torque component
along it is dropped), its angular velocity component is taken as 0, and its axis rotation sub-flow is
the identity. Nothing is divided by the zero moment.

Layout (one method per module, in the manner of diffrax's ``_solver/``): :mod:`.lie_poisson`,
:mod:`.yoshida4`, :mod:`.suzuki4`, :mod:`.yoshida6`, :mod:`.yoshida8`, :mod:`.exact_free`, :mod:`.lie_rk4`,
:mod:`.classical_rk4`; torques in :mod:`.torques`; ``integrate`` and ``advance`` in :mod:`.drivers`; the
component state and its exact sub-flows in ``_state``; :data:`REGISTRY` lists every method by name.

Speed. The splittings and Lie RK4 with the project's torques (gravity, spin friction, the air drag of
:mod:`physics.heavy_body`) run compiled (numba, ``cache=True``; :mod:`.kernels`, :mod:`.compiled`): a
splitting is a *program* of sub-flows that one loop runs over a batch of bodies, rows of twelve components
``(R row-major, L_body)``, so ``integrate`` takes ``(n, 3, 3)``, ``(n, 3)`` in one call. Measured
(``python -m benchmarks.compile_time``, benchmarks/results/compile_time.md): 0.34 µs of CPU per Yoshida 4
step of the friction top; the first call in a fresh environment compiles every kernel in about 6 s, a later
process loads them from numba's cache in about 0.5 s (:func:`physics.integrators.warm.warm`, which the app
runs in the background at start); :class:`ClassicalRK4` has its own kernel (the app's ghost at its finest
step). A torque the kernels do not know (any other callable) and a triaxial exact
free flow run interpreted on the same component state (Python floats with
:mod:`math`, or numpy arrays of shape ``(n,)`` for a batch): 221 µs per step with the friction top's torques
as Python callables, about 650 times slower.
"""

from __future__ import annotations

from physics.integrators._base import _Method
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
from physics.integrators.torques import GravityTorque, SpinFriction
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
    "advance",
    "Trajectory",
    "integrate",
    "kinetic_energy",
]

REGISTRY: dict[str, type[_Method]] = {
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
