"""The small public helpers refuse bad input by name too: NaN, inf, a wrong
shape, a zero axis or a result beyond the float range is a ValueError naming the argument, never a
NaN, an inf, or numpy's IndexError/TypeError/broadcast message. And ``mgl = 0`` reduces to the free
symmetric body in ``HeavyTop.simulate`` as it does in ``solve``."""

from __future__ import annotations

import math

import numpy as np
import pytest

from physics import rotations
from physics.free_body import FreeBody
from physics.heavy_top import HeavyTop
from physics.inertia import parallel_axis, solid_sphere
from physics.integrators import kinetic_energy
from physics.pendulum import PhysicalPendulum

NAN = float("nan")
TOP = HeavyTop(1.0, 0.5, 2.0)


@pytest.mark.parametrize(
    ("call", "named"),
    [
        (lambda: TOP.energy_of(NAN, 0, 0, 0), "theta"),
        (lambda: TOP.energy_of(0.3, 1e200, 0, 0), "rates"),
        (lambda: TOP.energy_of([0.1, 0.2], [1, 2, 3], 0, 0), "broadcast"),
        (lambda: TOP.energy_of("x", 0, 0, 0), "theta"),
        (lambda: TOP.angular_momenta(0.3, math.inf, 0), "phidot"),
        (lambda: TOP.angular_momenta(0.3, 1.7e308, 1.7e308), "rates"),
        (lambda: TOP.angular_momenta([0, 1], [1, 2, 3], 0), "broadcast"),
        (lambda: TOP.vertical_curvature(NAN), "L3"),
        (lambda: TOP.vertical_curvature("x"), "L3"),
        (lambda: TOP.vertical_curvature(1e200), "L3"),
        (lambda: FreeBody([2.0, 1.5, 1.0]).energy([1e200, 1.0, 1.0]), "energy"),
        (lambda: PhysicalPendulum(solid_sphere(1.0, 0.1), (0, 0, 0.5), (1, 0, 0)).energy(0.0, 1e200), "theta_dot"),
        (
            lambda: PhysicalPendulum(solid_sphere(1.0, 0.1), (0, 0, 0.5), (1, 0, 0)).energy([0, 1], [1, 2, 3]),
            "broadcast",
        ),
        (lambda: rotations.hat([1.0, 2.0]), "v"),
        (lambda: rotations.hat([NAN, 0.0, 0.0]), "v"),
        (lambda: rotations.expm_so3([1.0, 2.0]), "v"),
        (lambda: rotations.expm_so3([math.inf, 0.0, 0.0]), "v"),
        (lambda: rotations.rotation_about([0.0, 0.0, 0.0], 1.0), "axis"),
        (lambda: rotations.rotation_about([0.0, 0.0, 1.0], NAN), "angle"),
        (lambda: rotations.rotation_angle(np.eye(3), np.full((3, 3), NAN)), "r_b"),
        (lambda: rotations.rotation_angle(np.eye(3), np.eye(2)), "r_b"),
        (lambda: rotations.rotation_angle(np.stack([np.eye(3)] * 2), np.stack([np.eye(3)] * 3)), "broadcast"),
        (lambda: rotations.frame_from_axis([0.0, 0.0, 0.0]), "axis"),
        (lambda: parallel_axis(NAN, [0.0, 0.0, 1.0]), "mass"),
        (lambda: parallel_axis(1.0, [0.0, 1.0]), "offset"),
        (lambda: parallel_axis(1e300, [0.0, 1e200, 0.0]), "overflows"),
        (lambda: kinetic_energy([1.0, 2.0, 3.0], [NAN, 0.0, 0.0]), "L_body"),
        (lambda: kinetic_energy([1.0, 2.0, 3.0], [1e200, 0.0, 0.0]), "overflows"),
        (lambda: kinetic_energy([1.0, 2.0], [1.0, 0.0, 0.0]), "moments"),
    ],
)
def test_bad_input_or_an_overflowing_result_is_a_value_error_that_names_it(call, named):
    with pytest.raises(ValueError, match=named):
        call()


def test_the_helpers_still_give_the_textbook_values():
    # U''(0) = L3²/(4 I1²) − Mgl/I1 and the sleeping threshold 2 sqrt(Mgl I1) (lecture), exactly.
    assert TOP.vertical_curvature(3.0) == 9.0 / 4.0 - 2.0
    assert TOP.vertical_curvature(TOP.sleeping_threshold()) == pytest.approx(0.0, abs=1e-15)
    assert TOP.sleeping_threshold() == 2.0 * math.sqrt(2.0)
    # Moments near the float range's top: the threshold is 2e300, not inf (mgl I1 alone overflows).
    assert HeavyTop(1e300, 1e300, 1e300).sleeping_threshold() == pytest.approx(2e300, rel=1e-15)
    L3, Lz = TOP.angular_momenta(0.0, 1.0, 2.0)  # upright: Lz = L3 = I3 (ψ̇ + φ̇)
    assert L3 == 1.5 and Lz == 1.5
    assert TOP.energy_of(0.0, 0.0, 0.0, 0.0) == 2.0  # at rest upright: Mgl cos 0
    assert rotations.frame_from_axis([1e-300, 0.0, 1e-300])[:, 2] == pytest.approx([2**-0.5, 0.0, 2**-0.5])
    np.testing.assert_allclose(parallel_axis(2.0, [0.0, 0.0, 3.0]), np.diag([18.0, 18.0, 0.0]))


def test_simulate_without_gravity_is_the_free_symmetric_top():
    """mgl = 0: the simulated axis follows the exact free precession at Lie RK4's fourth order."""
    top = HeavyTop(1.0, 0.5, 0.0)
    start = (0.5, 0.1, 0.3, 5.0)
    errors = []
    for dt in (1e-2, 5e-3):
        run = top.simulate(*start, 2.0, dt)
        exact = top.solve(*start, run.t)
        errors.append(float(np.max(np.abs(run.axis - exact.axis))))
        # No gravity: the energy is the kinetic energy, conserved to the method's accuracy.
        assert np.max(np.abs(run.energy / run.energy[0] - 1.0)) < 1e-11
    assert errors[1] < 1e-9  # measured 2.1e-10
    assert math.log2(errors[0] / errors[1]) == pytest.approx(4.0, abs=0.3)  # measured 4.00
