"""The check every frame's state passes before it is drawn: no NaN, no inf."""

from __future__ import annotations

import math
from typing import Any

import numpy as np

__all__ = ["NumericalFailure", "check_finite"]


class NumericalFailure(ValueError):
    """A scene produced NaN or inf."""


def check_finite(state: dict[str, Any], where: str = "") -> None:
    """Raise :class:`NumericalFailure` naming the first non-finite number in a state dict (recursing
    into nested dicts, lists and tuples of numbers/arrays; other values are ignored)."""
    for key, value in state.items():
        name = f"{where}{key}"
        if isinstance(value, dict):
            check_finite(value, name + ".")
        elif isinstance(value, (float, int, np.floating, np.integer)) and not isinstance(value, bool):
            if not math.isfinite(float(value)):
                raise NumericalFailure(f"{name} = {value} is not a finite number")
        elif isinstance(value, np.ndarray) and value.dtype.kind in "fc":
            if not np.all(np.isfinite(value)):
                raise NumericalFailure(f"{name} contains NaN or inf")
        elif isinstance(value, (list, tuple)) and value and all(isinstance(v, (float, int, np.ndarray)) for v in value):
            check_finite({str(i): v for i, v in enumerate(value)}, name + "[")
