"""The integrators never return NaN or inf silently: a step beyond a method's stability
is refused up front, an angular momentum whose rate L × ω leaves the float range too, and a state that
stops being finite on the way is reported after the chunk it happened in, naming the step."""

from __future__ import annotations

import re

import numpy as np
import pytest

from physics.integrators import ClassicalRK4, LiePoissonStrang, LieRK4, advance, integrate


def _state(L):
    return np.concatenate([np.eye(3).ravel(), np.asarray(L, dtype=float)])


def _run(cls, moments, L, dt, n):
    """Through integrate for LieRK4 (its compiled kernel), through advance for ClassicalRK4 (interpreted)."""
    method = cls(moments)
    if cls is ClassicalRK4:
        return advance(method, _state(L), dt, n)
    tr = integrate(method, np.eye(3), L, dt, n, save_every=max(n // 4, 1))
    return np.concatenate([tr.attitude[-1].ravel(), tr.L_body[-1]])


@pytest.mark.parametrize("cls", [LieRK4, ClassicalRK4])
@pytest.mark.parametrize(
    "moments, L, dt, n",
    [
        ([2.0, 1.5, 1.0], [50.0, 100.0, 150.0], 0.1, 5000),  # ordinary input; reached NaN
        ([2.0, 1.5, 1.0], [1e200, 0.1, 0.2], 0.01, 100),
        ([1e-300, 1.0, 1.0], [1.0, 1.0, 1.0], 0.01, 100),
        ([2e-300, 1.5e-300, 1e-300], [1.0, 2.0, 3.0], 0.01, 100),
    ],
)
def test_a_step_beyond_the_stability_limit_is_refused_up_front(cls, moments, L, dt, n):
    """The audit's repros, all NaN before. |ω| = sqrt(2E/I_min), the fastest rate of the free motion."""
    with pytest.raises(ValueError, match=r"(dt = .* too large .*|too large for these moments)") as info:
        _run(cls, moments, L, dt, n)
    assert "L0_body" in str(info.value) or "state[9:]" in str(info.value)


@pytest.mark.parametrize("cls", [LieRK4, ClassicalRK4])
def test_just_inside_the_limit_the_same_motion_stays_finite(cls):
    """L = (50, 100, 150) with the step the refusal suggests: 5,000 steps, finite, |L| kept to the method's
    accuracy (RK4 at |ω| dt = 2.8 is dissipative, not explosive)."""
    moments, L = np.array([2.0, 1.5, 1.0]), np.array([50.0, 100.0, 150.0])
    rate = np.sqrt(np.sum(L**2 / moments) / moments.min())
    out = _run(cls, moments, L, 2.8 / rate, 5000)
    assert np.all(np.isfinite(out))
    assert np.linalg.norm(out[9:]) <= np.linalg.norm(L) * (1 + 1e-12)


@pytest.mark.parametrize("cls", [LieRK4, ClassicalRK4])
def test_an_angular_momentum_whose_rate_overflows_is_refused_by_name(cls):
    """L = 1e200 with dt small enough to be stable: L × ω ≈ 1e400 is beyond the float range."""
    with pytest.raises(ValueError, match=r"too large for these moments.*scaled down together"):
        _run(cls, [2.0, 1.5, 1.0], [1e200, 1e200, 0.2], 1e-205, 10)


@pytest.mark.parametrize("cls", [LieRK4, ClassicalRK4, LiePoissonStrang])
def test_the_moments_scale_is_free(cls):
    """Moments (and L) of 1e-300 or 1e300 scale: the same motion as at scale 1 (ω is scale-free), finite."""
    moments, L = np.array([2.0, 1.5, 1.0]), np.array([0.3, -1.0, 0.5])
    ref = _run(cls, moments, L, 0.01, 200)
    for c in (2.0**-1000, 2.0**1000):
        out = _run(cls, c * moments, c * L, 0.01, 200)
        assert np.all(np.isfinite(out))
        assert np.max(np.abs(out[:9] - ref[:9])) < 1e-14
        assert np.max(np.abs(out[9:] / c - ref[9:])) < 1e-14


@pytest.mark.parametrize("cls", [LieRK4, ClassicalRK4, LiePoissonStrang])
def test_moments_without_a_finite_inverse_are_refused(cls):
    with pytest.raises(ValueError, match="moments .* at least"):
        cls([2e-310, 1.5e-310, 1e-310])


class _Pump:
    """A torque that feeds the body (τ = 500 L): |L| grows like e^{500 t} until it overflows."""

    conservative = False

    def __call__(self, R, L):
        return 500.0 * np.asarray(L)


@pytest.mark.parametrize("cls", [LieRK4, ClassicalRK4, LiePoissonStrang])
@pytest.mark.parametrize("batched", [False, True])
def test_a_state_that_stops_being_finite_is_reported_with_its_step(cls, batched):
    """The torque speeds the body up past any step's stability: the refusal names the chunk where the
    state stopped being finite, and it was finite at the step it says."""
    method = cls([2.0, 1.5, 1.0], torque=_Pump())
    R0 = np.stack([np.eye(3)] * 2) if batched else np.eye(3)
    L0 = np.array([[0.3, -1.0, 0.5]] * 2) if batched else np.array([0.3, -1.0, 0.5])
    with pytest.raises(ValueError, match=r"diverged: .* between step (\d+) and step (\d+) .*smaller dt") as info:
        integrate(method, R0, L0, 0.001, 3000, save_every=5)
    first, last = (int(x) for x in re.search(r"between step (\d+) and step (\d+)", str(info.value)).groups())
    assert last == first + 5 and first > 0
    tr = integrate(method, R0, L0, 0.001, first, save_every=5)
    assert np.all(np.isfinite(tr.L_body)) and np.all(np.isfinite(tr.attitude))
    if not batched:
        with pytest.raises(ValueError, match=r"diverged: .* between step 0 and step 3000"):
            advance(method, _state(L0), 0.001, 3000)


def test_one_step_is_checked_too():
    method = LieRK4([2.0, 1.5, 1.0])
    with pytest.raises(ValueError, match="dt = 0.1 s is too large"):
        method.step(np.eye(3), [50.0, 100.0, 150.0], 0.1)
    R, L = method.step(np.eye(3), [50.0, 100.0, 150.0], 0.01)
    assert np.all(np.isfinite(R)) and np.all(np.isfinite(L))
