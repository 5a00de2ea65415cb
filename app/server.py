"""``from app.server import App``: the App (:mod:`app.serving.app`), for scripts written against this path."""

from __future__ import annotations

from app.serving.app import App
from app.serving.simulation import Simulation

__all__ = ["App", "Simulation"]
