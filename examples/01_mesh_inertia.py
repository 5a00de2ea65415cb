"""Inertia of a mesh: mass properties of the tennis-racket asset, its principal moments and axes.

The tensor comes from the mesh's exact volume integrals (uniform density, the catalogue mass); the
principal moments are printed in the lecture's order I1 ≥ I2 ≥ I3 with right-handed axes, then the
tensor is moved to the handle's end with the parallel-axis theorem.

Run: python examples/01_mesh_inertia.py [--asset NAME]
"""

from __future__ import annotations

import argparse

import numpy as np

from assets import ASSETS, load_mesh, mass_properties


def main(argv: list[str] | None = None) -> None:
    parser = argparse.ArgumentParser(description=__doc__.splitlines()[0])
    parser.add_argument("--asset", default="tennis_racket", choices=sorted(ASSETS))
    args = parser.parse_args(argv)

    mesh = load_mesh(args.asset)
    body = mass_properties(args.asset)
    moments, axes = body.principal()
    print(f"asset: {ASSETS[args.asset].label} ({len(mesh.faces)} triangles, watertight={mesh.is_watertight})")
    print(f"mass: {body.mass:.4f} kg")
    print(f"centre of mass: {np.array2string(body.center_of_mass, precision=5)} m")
    print("moments I1 >= I2 >= I3: " + "  ".join(f"{m:.9e}" for m in moments) + " kg m^2")
    for i in range(3):
        print(f"axis {i + 1}: {np.array2string(axes[:, i], precision=5, suppress_small=True)}")
    print(f"det(axes) = {np.linalg.det(axes):+.15f}")
    end = mesh.vertices[np.argmin(mesh.vertices @ axes[:, 2])]  # the point farthest along -axis 3
    about_end = body.tensor_about(end)
    print(f"tensor about {np.array2string(end, precision=4)} m (parallel-axis theorem):")
    print(np.array2string(about_end, precision=6, suppress_small=True))


if __name__ == "__main__":
    main()
