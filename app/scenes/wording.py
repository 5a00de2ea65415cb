"""The motion in words: the shared wording of every scene's :meth:`app.scenes.base.Scene.describe`.

A screen reader announces the description (an ``aria-live`` region of the panel, :mod:`app.panel.look`),
so each number is said with its unit and three significant digits, the precision the readouts show
rounded for the ear.
"""

from __future__ import annotations

import math

from app.language.words import mark, say

__all__ = ["amount", "angle", "listing", "threshold_words", "tip_path"]

DIGITS = 3
"""Significant digits of every number in a description."""


def amount(value: float, unit: str) -> str:
    """``value`` with its unit, e.g. ``amount(0.5037, "rad/s") == "0.504 rad/s"``; ∞ says "never"."""
    if not math.isfinite(value):
        return mark("never") if value > 0 else mark("minus infinity")
    return say("{value:.3g} {unit}", value=value, unit=unit)  # DIGITS significant digits


def angle(radians: float) -> str:
    """An angle in degrees, e.g. ``angle(math.pi / 4) == "45°"``."""
    return say("{degrees:.3g}°", degrees=math.degrees(radians))  # DIGITS significant digits


def listing(values: list[float] | tuple[float, ...], unit: str) -> str:
    """Several numbers of one unit: ``listing([1, 2, 3], "kg m²") == "1, 2 and 3 kg m²"``."""
    # One template per count (DIGITS significant digits), so a language may order and join them its own way.
    numbers = [float(v) for v in values]
    if len(numbers) == 1:
        return say("{value:.3g} {unit}", value=numbers[0], unit=unit)
    if len(numbers) == 2:
        return say("{a:.3g} and {b:.3g} {unit}", a=numbers[0], b=numbers[1], unit=unit)
    if len(numbers) == 3:
        return say("{a:.3g}, {b:.3g} and {c:.3g} {unit}", a=numbers[0], b=numbers[1], c=numbers[2], unit=unit)
    words = [f"{v:.{DIGITS}g}" for v in numbers]  # never asked for by a scene: English
    return ", ".join(words[:-1]) + " and " + words[-1] + f" {unit}"


def threshold_words(L3: float, threshold: float) -> str:
    """Where the spin's L₃ (kg m²/s) is against the sleeping threshold 2√(M g ℓ I₁) (kg m²/s)."""
    return mark("above the sleeping threshold") if abs(L3) > threshold else mark("below the sleeping threshold")


def tip_path(Lz: float, L3: float, theta_min: float, theta_max: float) -> str:
    """The shape the top's axis tip draws between its turning angles θ_min, θ_max (rad).

    φ̇ = (L_z − L₃ cos θ)/(I₁ sin²θ) (lecture): where it has one sign at both turning angles the tip draws
    waves; where it changes sign, loops; where it vanishes at a turning angle (a top released at rest in
    θ), cusps. Zero is judged against the size of the terms, 1e-9 |L₃|, the round-off of L_z.
    """
    tiny = 1e-9 * max(abs(L3), abs(Lz), 1e-300)
    low, high = Lz - L3 * math.cos(theta_min), Lz - L3 * math.cos(theta_max)
    if abs(low) <= tiny or abs(high) <= tiny:
        return mark("cusps")
    return mark("waves") if (low > 0) == (high > 0) else mark("loops")
