"""The hard cases of the work-precision benchmark, each with its reference solution.

A case is a rigid body about a fixed point (free body: its centre of mass) with an initial attitude
``R0`` (body to space), body angular momentum ``L0``, a final time ``t_end``, its torques (gravity, spin
friction, transverse air drag) and a reference final state: the closed forms
(:class:`physics.free_body.FreeBody`, :class:`physics.heavy_top.HeavyTop`) where they exist, else a Taylor
series in extended precision (:mod:`benchmarks.taylor`), cross-checked and stated with the case.
"""

from __future__ import annotations

import warnings
from collections.abc import Callable
from dataclasses import dataclass, field

import numpy as np
from numpy.typing import NDArray

from physics import G
from physics.free_body import FreeBody
from physics.heavy_top import HeavyTop


@dataclass
class Case:
    """One benchmark problem.

    Attributes
    ----------
    name, description : str
    moments : ndarray (3,)
        Principal moments about the fixed point, kg m².
    mass, com : float, ndarray (3,)
        Mass (kg) and centre of mass in body axes (m) for gravity; ``mass = 0`` means no gravity.
    friction, friction_axis : float, ndarray (3,)
        Spin friction ``τ = −c (ω · a) a`` (c in N m s) about the unit body axis ``a`` (default z).
    drag : float
        Transverse air drag ``τ_body = −c_air (ω1, ω2, 0)``, N m s.
    R0 : ndarray (3, 3); L0 : ndarray (3,)
    t_end : float
        Final time, s.
    exact : callable () -> (R (3,3), omega (3,))
        The closed-form final state (timed as "our exact solution"), or for a case without one
        (``closed_form = False``) the numerical reference.
    """

    name: str
    description: str
    moments: NDArray[np.float64]
    R0: NDArray[np.float64]
    L0: NDArray[np.float64]
    t_end: float
    exact: Callable
    mass: float = 0.0
    com: NDArray[np.float64] = field(default_factory=lambda: np.zeros(3))
    time_scale: float = 1.0  # a typical period, s (to choose the coarsest step)
    budget_scale: float = 1.0  # the long run gets a larger per-run CPU budget
    R_ref: NDArray[np.float64] | None = None
    omega_ref: NDArray[np.float64] | None = None
    closed_form: bool = True  # False: ``exact`` is a numerical reference, not one of our solutions
    reference_note: str = ""  # how that reference was made and checked
    reference_gaps: dict[str, float] = field(default_factory=dict)  # its distance to each cross-check
    friction: float = 0.0
    friction_axis: NDArray[np.float64] = field(default_factory=lambda: np.array([0.0, 0.0, 1.0]))
    drag: float = 0.0

    def reference(self):
        if self.R_ref is None:
            self.R_ref, self.omega_ref = self.exact()
        return self.R_ref, self.omega_ref

    @property
    def dissipative(self) -> bool:
        """Friction or drag: the energy falls, so a run's energy is compared with the reference's final one."""
        return bool(self.friction or self.drag)

    def torques(self) -> list:
        """The project's torque objects of this case (for :mod:`physics.integrators`)."""
        from physics.integrators import GravityTorque, SpinFriction, TransverseAirDrag

        out: list = []
        if self.mass:
            out.append(GravityTorque(self.mass, self.com))
        if self.friction:
            out.append(SpinFriction(self.friction, self.moments, self.friction_axis))
        if self.drag:
            out.append(TransverseAirDrag(self.drag, self.moments))
        return out

    def body(self):
        """The constants of the equations for :mod:`benchmarks.taylor`."""
        from benchmarks.taylor import Body

        axis = np.asarray(self.friction_axis, dtype=float)
        return Body(
            self.moments, self.mass * G * np.asarray(self.com), self.friction, axis / np.linalg.norm(axis), self.drag
        )

    def energy(self, R, L):
        """Kinetic + potential energy, J, for (k,3,3),(k,3) or single states."""
        inv = np.where(self.moments > 0, 1.0 / np.where(self.moments > 0, self.moments, 1.0), 0.0)
        e = 0.5 * np.sum(np.asarray(L) ** 2 * inv, axis=-1)
        if self.mass:
            e = e + self.mass * G * (np.asarray(R)[..., 2, :] @ self.com)
        return e

    def energy_reference(self) -> float:
        """The energy a run should end with: the initial one, or the reference's final one when dissipative."""
        if not self.dissipative:
            return float(self.energy(self.R0, self.L0))
        R_ref, w_ref = self.reference()
        return float(self.energy(R_ref, self.moments * w_ref))


def _free(name, description, moments, omega0, t_end, periods_hint=None) -> Case:
    moments = np.asarray(moments, dtype=float)
    omega0 = np.asarray(omega0, dtype=float)
    body = FreeBody(moments)

    def exact():
        w, R = body.motion(omega0, t_end)
        return R[0], w[0]

    period = body.period(omega0)
    scale = period if np.isfinite(period) else 2 * np.pi / np.linalg.norm(omega0)
    scale = min(scale, 2 * np.pi / np.linalg.norm(omega0))
    return Case(name, description, moments, np.eye(3), moments * omega0, float(t_end), exact, time_scale=scale)


def _top(name, description, theta0, thetadot0, phidot0, psidot0, t_end, I1=1.0, I3=0.5, mass=1.0, ell=0.3) -> Case:
    top = HeavyTop(I1, I3, mass * G * ell)
    sol0 = top.solve(theta0, thetadot0, phidot0, psidot0, [0.0])
    moments = np.array([I1, I1, I3])

    def exact():
        s = top.solve(theta0, thetadot0, phidot0, psidot0, [t_end])
        return s.attitude[0], s.omega_body[0]

    w = sol0.omega_body[0]
    scale = 2 * np.pi / max(np.linalg.norm(w), np.sqrt(mass * G * ell / I1))
    return Case(
        name,
        description,
        moments,
        sol0.attitude[0],
        moments * w,
        float(t_end),
        exact,
        mass=mass,
        com=np.array([0.0, 0.0, ell]),
        time_scale=scale,
    )


def _gap(R_a, w_a, R_b, w_b) -> float:
    """max(chordal attitude angle, relative ω error) between two final states, in their own precision."""
    d = np.asarray(R_a) - np.asarray(R_b)
    angle = 2.0 * np.arcsin(min(1.0, float(np.sqrt(np.sum(d * d)) / np.sqrt(8.0))))
    return max(angle, float(np.max(np.abs(np.asarray(w_a) - w_b)) / np.max(np.abs(w_b))))


_REFERENCES: dict[tuple, tuple] = {}
"""Numerical references made in this process, by :func:`_reference_key`: (R, ω, gaps, note). A case is
built afresh by each :func:`all_cases`; its reference (0.3 to 1 s of CPU) depends only on these data."""


def _reference_key(case: Case) -> tuple:
    """Everything a numerical reference depends on: the body, its torques, the start and the span."""
    arrays = (case.moments, case.R0, case.L0, case.com, case.friction_axis)
    return (case.name, case.t_end, case.mass, case.friction, case.drag) + tuple(a.tobytes() for a in arrays)


def _numerical_reference(case: Case) -> Case:
    """Give a case without a closed form its reference (made on first use): the Taylor series of
    :mod:`benchmarks.taylor` (order 30, long double), checked against the same series at order 24 and a
    smaller tolerance, and against scipy's DOP853 at its rtol floor (float64). The gaps go to
    ``case.reference_gaps`` and ``case.reference_note``; :func:`check_with_mpmath` adds mpmath's Taylor."""
    case.closed_form = False
    case.exact = lambda: (np.eye(3), np.zeros(3))  # not a solution of ours: nothing to time

    def reference():
        key = _reference_key(case)
        if key not in _REFERENCES:
            _REFERENCES[key] = compute()
        R, w, gaps, case.reference_note = _REFERENCES[key]
        case.reference_gaps = dict(gaps)  # check_with_mpmath adds to this case's
        return R.copy(), w.copy()

    def compute():
        from benchmarks.peers import scipy_run
        from benchmarks.taylor import taylor_flow

        body = case.body()
        R, L, steps = taylor_flow(body, case.R0, case.L0, case.t_end)
        R2, L2, steps2 = taylor_flow(body, case.R0, case.L0, case.t_end, order=24, tol=1e-23)
        w, w2 = L / case.moments, L2 / case.moments
        with warnings.catch_warnings():  # scipy raises rtol 1e-14 to its floor 2.2e-14, and says so
            warnings.simplefilter("ignore", UserWarning)
            R_dop, w_dop, _ = scipy_run(case, "DOP853", 1e-14)
        gaps = {"taylor": _gap(R, w, R2, w2), "DOP853": _gap(R_dop, w_dop, R, w)}
        digits = np.finfo(np.longdouble).precision
        note = (
            f"reference: Taylor series of order 30 in long double ({digits} digits), {steps} steps "
            f"(benchmarks/taylor.py); the series of order 24 at a 100x smaller tolerance ({steps2} steps) agrees "
            f"to {gaps['taylor']:.1e}; scipy's DOP853 at rtol 2.2e-14 (its floor, float64) is "
            f"{gaps['DOP853']:.1e} away (its own error"
            + (", above the 1e-13 asked of a reference" if gaps["DOP853"] > 1e-13 else "")
            + ")"
        )
        return np.asarray(R, dtype=float), np.asarray(w, dtype=float), gaps, note

    case.exact = reference
    return case


def check_with_mpmath(case: Case, dps: int = 20) -> float:
    """Cross-check a case's numerical reference with mpmath's Taylor integrator (``mpmath.odefun`` at ``dps``
    digits; 10 to 20 s of CPU per case): returns the gap and adds it to the case's note."""
    from benchmarks.taylor import mpmath_flow

    R_ref, w_ref = case.reference()
    R, L = mpmath_flow(case.body(), case.R0, case.L0, case.t_end, dps)
    gap = _gap(R, L / case.moments, R_ref, w_ref)
    case.reference_gaps["mpmath"] = gap
    case.reference_note += f"; mpmath.odefun (Taylor, {dps} digits) agrees to {gap:.1e}"
    return gap


def _asymmetric_top(name, description, moments, tilt, omega0, t_end, mass=1.0, ell=0.3, drag=0.0) -> Case:
    """A heavy top with three different moments (no closed form), tilted by ``tilt`` about x."""
    moments = np.asarray(moments, dtype=float)
    omega0 = np.asarray(omega0, dtype=float)
    R0 = np.array([[1.0, 0.0, 0.0], [0.0, np.cos(tilt), -np.sin(tilt)], [0.0, np.sin(tilt), np.cos(tilt)]])
    scale = 2 * np.pi / max(np.linalg.norm(omega0), np.sqrt(mass * G * ell / moments[0]))
    case = Case(
        name,
        description,
        moments,
        R0,
        moments * omega0,
        float(t_end),
        lambda: (np.eye(3), np.zeros(3)),
        mass=mass,
        com=np.array([0.0, 0.0, ell]),
        time_scale=scale,
        drag=drag,
    )
    return _numerical_reference(case)


def all_cases(quick: bool = False) -> list[Case]:
    """The benchmark's cases; ``quick`` shortens the long run (100 instead of 10^4 periods)."""
    generic_w = np.array([1.0, 0.3, 2.0])
    gen_period = FreeBody([2.0, 1.5, 1.0]).period(generic_w)
    long_periods = 100 if quick else 10_000
    # Sleeping top: threshold L3 = 2 sqrt(M g l I1) (lecture); spin ω3 = L3 / I3.
    I1, I3, mgl = 1.0, 0.5, 1.0 * G * 0.3
    w_crit = 2.0 * np.sqrt(mgl * I1) / I3
    # Axis passing near the vertical: Lz = L3 (1 - 1e-6) (Lz = L3 exactly passes through the pole).
    th0, w3 = 0.3, 10.0
    phidot_pole = I3 * w3 * (1.0 - np.cos(th0)) * (1.0 - 1e-6) / (I1 * np.sin(th0) ** 2)
    cases = [
        _free(
            "free_generic",
            "free body, I = (2, 1.5, 1), ω0 = (1, 0.3, 2), 10 periods",
            [2.0, 1.5, 1.0],
            generic_w,
            10 * gen_period,
        ),
        _free(
            "free_separatrix",
            "free body, spin 2 rad/s about the intermediate axis perturbed by 1e-6, t = 40 s",
            [2.0, 1.5, 1.0],
            [1e-6, 2.0, 1e-6],
            40.0,
        ),
        _free(
            "free_near_symmetric",
            "free body, I = (1, 1 − 1e-9, 0.5), ω0 = (1, 0.5, 3), t = 20 s",
            [1.0, 1.0 - 1e-9, 0.5],
            [1.0, 0.5, 3.0],
            20.0,
        ),
        _free(
            "free_flat_lamina",
            "flat lamina I = (3, 2, 1) (I1 = I2 + I3), ω0 = (0.5, 1, 1.5), t = 20 s",
            [3.0, 2.0, 1.0],
            [0.5, 1.0, 1.5],
            20.0,
        ),
        _free(
            "free_fast_spin",
            "fast spin ω0 = (0.5, 0.3, 100) rad/s, I = (2, 1.5, 1), t = 2 s",
            [2.0, 1.5, 1.0],
            [0.5, 0.3, 100.0],
            2.0,
        ),
        _free(
            "free_long_run",
            f"free generic body over {long_periods} periods ({long_periods * gen_period:.0f} s)",
            [2.0, 1.5, 1.0],
            generic_w,
            long_periods * gen_period,
        ),
        _top(
            "top_big_nutation",
            "heavy top I1 = 1, I3 = 0.5, Mgl = 2.94 J; θ0 = 0.8, φ̇0 = −2 (loops), ψ̇0 = 15, t = 10 s",
            0.8,
            0.0,
            -2.0,
            15.0,
            10.0,
        ),
        _top(
            "top_cusps",
            "heavy top released from rest in θ, φ (cusps): θ0 = 0.8, ψ̇0 = 15, t = 10 s",
            0.8,
            0.0,
            0.0,
            15.0,
            10.0,
        ),
        _top("top_fast", "fast top ω3 = 500 rad/s, θ0 = 0.5, t = 2 s", 0.5, 0.0, 0.0, 500.0, 2.0),
        _top(
            "top_sleeping_above",
            "sleeping top, ω3 = 1.05 × threshold, θ0 = 1e-3, t = 10 s",
            1e-3,
            0.0,
            0.0,
            1.05 * w_crit,
            10.0,
        ),
        _top(
            "top_sleeping_below",
            "sleeping top, ω3 = 0.95 × threshold, θ0 = 1e-3 (falls), t = 10 s",
            1e-3,
            0.0,
            0.0,
            0.95 * w_crit,
            10.0,
        ),
        _top(
            "top_near_vertical",
            "axis passing 1e-6 (in Lz/L3) from the vertical: θ0 = 0.3, ω3 = 10, t = 10 s",
            th0,
            0.0,
            phidot_pole,
            w3 - phidot_pole * np.cos(th0),
            10.0,
        ),
    ]
    cases[5].budget_scale = 8.0  # 10^4 periods: a run that reaches 1e-4 needs ~10^6 steps
    # No closed form: an asymmetric heavy top, slow and fast.
    cases += [
        _asymmetric_top(
            "asym_top_slow",
            "asymmetric heavy top I = (1, 0.8, 0.5), M g ℓ = 2.94 J, tilt 0.8, ω0 = (0, 0, 15), t = 10 s",
            [1.0, 0.8, 0.5],
            0.8,
            [0.0, 0.0, 15.0],
            10.0,
        ),
        _asymmetric_top(
            "asym_top_fast",
            "asymmetric heavy top I = (1, 0.8, 0.5), tilt 0.5, ω0 = (0.3, 0, 200), t = 2 s",
            [1.0, 0.8, 0.5],
            0.5,
            [0.3, 0.0, 200.0],
            2.0,
        ),
    ]
    # No closed form: dissipation. The symmetric top with spin friction (the app's preset c = 0.02 N m s,
    # app/scenes/heavy_top.py) and the asymmetric slow top with transverse air drag.
    friction_top = _top(
        "top_spin_friction",
        "heavy top I1 = 1, I3 = 0.5, Mgl = 2.94 J with spin friction c = 0.02 N m s: θ0 = 0.8, ψ̇0 = 15, t = 10 s",
        0.8,
        0.0,
        0.0,
        15.0,
        10.0,
    )
    friction_top.friction = 0.02
    cases += [
        _numerical_reference(friction_top),
        _asymmetric_top(
            "body_air_drag",
            "asymmetric heavy top I = (1, 0.8, 0.5), tilt 0.8, ω0 = (0, 0, 15), transverse air drag "
            "c_air = 0.05 N m s, t = 10 s",
            [1.0, 0.8, 0.5],
            0.8,
            [0.0, 0.0, 15.0],
            10.0,
            drag=0.05,
        ),
    ]
    return cases
