"""A heavy top released with spin only: the cusps of its axis trace and the effective potential U(θ).

The exact solution (elliptic functions) gives θ(t), φ(t); the axis tip traces cusps where φ̇ = 0
(docs/conventions.md, erratum 5: θ moves between the release angle θ0 and a lower turning point
θ1 > θ0). The plot shows the trace seen from above and U(θ) with the energy line.

Run: python examples/03_heavy_top_trace.py [--out heavy_top_trace.png]
"""

from __future__ import annotations

import argparse
import math
import os
import tempfile

import matplotlib

matplotlib.use("Agg")  # no screen needed
import matplotlib.pyplot as plt
import numpy as np

from physics.heavy_top import HeavyTop


def main(argv: list[str] | None = None) -> None:
    parser = argparse.ArgumentParser(description=__doc__.splitlines()[0])
    parser.add_argument("--out", default=os.path.join(tempfile.gettempdir(), "heavy_top_trace.png"))
    args = parser.parse_args(argv)

    top = HeavyTop(I1=1.0, I3=0.5, mgl=2.0)  # kg m², kg m², J
    theta0, spin = 0.5, 20.0  # rad, rad/s: released at rest apart from the spin
    period = top.nutation_period(theta0, 0.0, 0.0, spin)
    t = np.linspace(0.0, 4 * period, 4001)
    sol = top.solve(theta0, 0.0, 0.0, spin, t)
    print(f"sleeping threshold L3 = 2 sqrt(M g l I1) = {top.sleeping_threshold():.4f} kg m^2/s; L3 = {sol.L3:.4f}")
    print(f"theta between {math.degrees(sol.theta_min):.4f} and {math.degrees(sol.theta_max):.4f} deg")
    print(f"nutation period {sol.nutation_period:.6f} s; mean precession rate {sol.precession_rate:.6f} rad/s")
    print(f"min phi-dot {sol.phidot.min():+.2e} rad/s (0 at the cusps, never negative)")
    drift = np.max(np.abs(sol.energy_along(top) - sol.energy)) / abs(sol.energy)
    print(f"energy drift along the exact solution: {drift:.1e} (relative)")

    theta = np.linspace(0.05, 2.5, 500)
    U = top.effective_potential(theta, sol.Lz, sol.L3)
    fig, (ax1, ax2) = plt.subplots(1, 2, figsize=(9, 4))
    ax1.plot(sol.axis[:, 0], sol.axis[:, 1], color="#009E73")
    ax1.set_aspect("equal")
    ax1.set_title("axis tip from above (cusps)")
    ax2.plot(np.degrees(theta), U, color="#0072B2", label="U(θ)")
    ax2.axhline(U[np.argmin(np.abs(theta - theta0))], color="#D55E00", ls="--", label="energy ℰ")
    ax2.set_ylim(U.min() - 1, U.min() + 20)
    ax2.set_xlabel("θ (deg)")
    ax2.legend()
    fig.tight_layout()
    fig.savefig(args.out, dpi=80)
    print(f"plot written to {args.out}")


if __name__ == "__main__":
    main()
