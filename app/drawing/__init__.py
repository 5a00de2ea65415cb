"""Drawing: what a scene shows in 3D.

The palette and legend, the light, meshes, kept-handle pieces (arrows, traces, cones), the integrator's ghost.
"""
