"""The check every frame's state passes before it is drawn: no NaN, no inf."""

from __future__ import annotations

import cmath
import math
from typing import Any

import numpy as np

from app.language.words import say

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
                raise NumericalFailure(say("{name!s} = {value} is not a finite number", name=name, value=value))
        elif isinstance(value, np.ndarray) and value.dtype.kind in "fc":
            if not _all_finite(value):
                raise NumericalFailure(say("{name!s} contains NaN or inf", name=name))
        elif isinstance(value, (list, tuple)) and value and all(isinstance(v, (float, int, np.ndarray)) for v in value):
            check_finite({str(i): v for i, v in enumerate(value)}, name + "[")


SMALL = 64
"""Arrays up to this size are checked number by number in Python: a frame's vectors and matrices, where
numpy's per-call overhead is most of the cost (every session checks its state every frame)."""


_EXACT_IN_PYTHON = frozenset(np.dtype(t) for t in (np.float16, np.float32, np.float64, np.complex64, np.complex128))
"""Dtypes whose elements become Python floats or complexes exactly (a long double might not)."""


def _all_finite(value: np.ndarray) -> bool:
    """Whether every element of a float or complex array is finite."""
    if value.size > SMALL or value.dtype not in _EXACT_IN_PYTHON:
        return bool(np.isfinite(value).all())
    isfinite = math.isfinite if value.dtype.kind == "f" else cmath.isfinite
    return all(map(isfinite, value.ravel().tolist()))
