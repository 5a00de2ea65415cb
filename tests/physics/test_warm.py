"""The kernels are warmed once (physics.integrators.warm): afterwards every kernel has its machine code."""

from __future__ import annotations

from physics.integrators import kernels
from physics.integrators.warm import warm


def test_warm_compiles_every_kernel():
    seconds = warm()
    assert seconds >= 0.0
    for kernel in (kernels.run_splitting, kernels.run_lie_rk4):
        assert kernel.signatures, kernel  # compiled (or loaded from the cache) for the arrays the drivers pass
