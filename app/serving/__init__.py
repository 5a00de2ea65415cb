"""Serving: the App (a viser server, its simulations, the real-time loop) and one Simulation's parts.

The clock, the frame, the scene's lifecycle, notifications, snapshots, camera framing, addresses.
"""
