"""The panel: the part every scene shares (picker, clock, state, Export), and the pieces a scene's own is built of.

Sliders refused or accepted together, their rollback, readouts, presets, the drift plot, the speed scale, the look.
"""
