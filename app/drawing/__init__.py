"""Drawing: what a scene shows in 3D and how the panel looks.

The palette and legend, meshes, kept-handle pieces (arrows, traces, cones), the integrator's ghost, the look.
"""
