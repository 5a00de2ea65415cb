"""The panel: sliders refused or accepted together, their rollback, readouts, presets, the drift plot.

Also the clock's speed scale and the Export folder (which is handed the export to run).
"""
