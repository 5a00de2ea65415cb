"""Rigid Body Lab physics: headless, exact where possible, geometric where not.

Modules (one topic each): :mod:`physics.inertia`, :mod:`physics.rotations`,
:mod:`physics.elliptic`, :mod:`physics.free_body`, :mod:`physics.heavy_top`, :mod:`physics.pendulum`,
:mod:`physics.integrators`; :data:`G` from :mod:`physics.constants`. This package never imports the app or
viser; docs/physics-notes.md describes the methods.
"""

from physics.constants import G

__all__ = ["G"]
