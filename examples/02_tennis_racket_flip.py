"""The tennis-racket (intermediate-axis) flip: the lecture's growth rate against the exact motion.

A body spun about its intermediate axis with a small push about another axis: the push grows like
exp(σ t) with the lecture's σ = Ω sqrt((I1 − I2)(I2 − I3)/(I1 I3)) until the body flips over; the exact
solution (Jacobi elliptic functions) gives the flip's period. The spins about the largest and smallest
axes are stable and wobble at the lecture's frequency.

Run: python examples/02_tennis_racket_flip.py [--push 1e-3]
"""

from __future__ import annotations

import argparse

import numpy as np

from physics.free_body import FreeBody


def main(argv: list[str] | None = None) -> None:
    parser = argparse.ArgumentParser(description=__doc__.splitlines()[0])
    parser.add_argument("--push", type=float, default=1e-3, help="initial ω about axis 3 relative to the spin")
    args = parser.parse_args(argv)

    moments = np.array([2.0, 1.5, 1.0])  # kg m², I1 > I2 > I3
    spin = 3.0  # rad/s about axis 2, the intermediate one
    body = FreeBody(moments)
    for axis in range(3):
        s = body.stability(axis, spin)
        print(f"spin about axis {axis + 1} (I = {moments[axis]}): {s.kind}, rate {s.rate:.6f}")

    omega0 = np.array([0.0, spin, args.push * spin])
    sigma = body.stability(1, spin).rate
    # Linearised (lecture): η3'' = σ² η3, and a push about axis 3 alone has η3'(0) = 0, so
    # ω3(t) = ω3(0) cosh(σ t) until the push is no longer small.
    t = np.array([1.0, 2.0, 3.0]) / sigma
    growth = body.omega(omega0, t)[:, 2] / omega0[2]
    print(f"lecture growth rate sigma = {sigma:.6f} 1/s")
    for ti, g in zip(t, growth):
        print(f"  t = {ti:.4f} s: omega_3(t)/omega_3(0) = {g:.6f}, cosh(sigma t) = {np.cosh(sigma * ti):.6f}")
    period = body.period(omega0)
    t_flip = np.linspace(0.0, period, 2001)
    w2 = body.omega(omega0, t_flip)[:, 1]
    print(
        f"flip period {period:.6f} s; omega_2 goes from {w2[0]:+.4f} to {w2.min():+.4f} and back to {w2[-1]:+.4f} rad/s"
    )
    print(f"angular momentum is fixed in space: |L| = {np.linalg.norm(body.angular_momentum(omega0)):.12f} kg m^2/s")


if __name__ == "__main__":
    main()
