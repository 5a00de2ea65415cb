"""Scenes: one module per section of the lecture (``app/scenes/<name>.py``), each a :class:`Scene` subclass.

The base class and the registry live in :mod:`app.scenes.base`; :func:`load_all` imports every scene module.
"""

from __future__ import annotations

import importlib
import pkgutil

from app.scenes.base import REGISTRY, Scene, SceneContext, register

__all__ = ["Scene", "SceneContext", "register", "REGISTRY", "load_all", "scene_names"]


def load_all() -> dict[str, type[Scene]]:
    """Import every module of this package (each registers its scenes) and return the registry."""
    for info in pkgutil.iter_modules(__path__):
        if not info.name.startswith("_") and info.name != "base":
            importlib.import_module(f"{__name__}.{info.name}")
    return REGISTRY


def scene_names() -> list[str]:
    """Registered scene names in picker order."""
    load_all()
    return [c.name for c in sorted(REGISTRY.values(), key=lambda c: (c.order, c.title))]
