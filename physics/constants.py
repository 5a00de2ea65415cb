"""Physical constants shared by the models."""

from __future__ import annotations

G = 9.81
"""Standard gravitational acceleration used by default, m/s² (docs/conventions.md)."""
