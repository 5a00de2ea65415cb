"""The heavy top near its separatrix (issue 15, item 3): starts within 1e-6 rad of the vertical with the
spin just below, at and above the sleeping threshold L3 = 2 sqrt(M g ℓ I1), against a 60-digit reference.

At the threshold the coefficient 4a − β² of the nutation cubic, (4 M g ℓ I1 − L3²)/I1², is the tiny
difference of the data's two large products; formed in double-double (physics.top_motion._threshold_gap)
it keeps the roots near u = 1 those of the floats given. Before, θ was off by 4e-12 rad at exactly the
threshold with θ0 = 1e-8 (and φ by 7e-9 relative); now θ is within 5e-15 rad, φ and ψ within 5e-16.
"""

from __future__ import annotations

import numpy as np
import pytest

from tests.physics.test_heavy_top import TOP, mp_reference


@pytest.mark.parametrize("theta0", [1e-6, 1e-8])
@pytest.mark.parametrize("fraction", [0.9, 1.0, 1.001])
def test_starts_near_the_vertical_around_the_sleeping_threshold(fraction, theta0):
    ic = (theta0, 0.0, 0.0, fraction * TOP.sleeping_threshold() / TOP.I3)
    T = TOP.nutation_period(*ic)
    times = np.linspace(0.0, 2.0 * T, 5)
    reference, *_ = mp_reference(TOP, ic, times, dps=60)
    s = TOP.solve(*ic, times)
    assert np.max(np.abs(s.theta - reference[:, 0])) <= 1e-12
    for computed, exact in ((s.phi, reference[:, 1]), (s.psi, reference[:, 2])):
        assert np.max(np.abs(computed - exact)) <= 1e-12 * np.max(np.abs(exact))
