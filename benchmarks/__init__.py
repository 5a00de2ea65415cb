"""Benchmarks of speed against error: ``python -m benchmarks.work_precision`` (see its docstring)."""
