"""The logarithmic speed slider: 0.01× to 10× with 1× in the middle, each half logarithmic."""

import math

import numpy as np
import pytest

from app.panel.speed import POSITION_MARKS, POSITION_STEP, SPEED_MAX, SPEED_MIN, position_of, speed_at, speed_label


def test_ends_and_middle():
    assert speed_at(-1.0) == pytest.approx(SPEED_MIN, rel=1e-15) and SPEED_MIN == 0.01
    assert speed_at(0.0) == 1.0
    assert speed_at(1.0) == pytest.approx(SPEED_MAX, rel=1e-15) and SPEED_MAX == 10.0


def test_each_half_is_logarithmic_and_the_whole_is_increasing():
    positions = np.arange(-1.0, 1.0 + POSITION_STEP / 2, POSITION_STEP)
    speeds = np.array([speed_at(p) for p in positions])
    assert np.all(np.diff(speeds) > 0)
    ratios = speeds[1:] / speeds[:-1]
    half = len(positions) // 2
    # Equal steps give equal ratios: 100^0.05 on the slow half, 10^0.05 on the fast half.
    np.testing.assert_allclose(ratios[:half], 100**POSITION_STEP, rtol=1e-12)
    np.testing.assert_allclose(ratios[half:], 10**POSITION_STEP, rtol=1e-12)
    # A lecturer's slow speeds get half the slider, not its first millimetre.
    assert speed_at(-0.5) == pytest.approx(0.1, rel=1e-15)


@pytest.mark.parametrize("speed", [0.01, 0.02, 0.1, 0.5, 1.0, 2.0, 3.7, 10.0])
def test_position_inverts_speed(speed):
    assert speed_at(position_of(speed)) == pytest.approx(speed, rel=1e-14)


def test_out_of_range_is_clamped():
    assert speed_at(-7) == pytest.approx(SPEED_MIN) and speed_at(math.inf) == pytest.approx(SPEED_MAX)
    assert position_of(1e9) == 1.0 and position_of(0.0) == -1.0


def test_marks_sit_at_their_speeds():
    labelled = [mark for mark in POSITION_MARKS if isinstance(mark, tuple)]
    assert [p for p, _ in labelled] == [-1.0, 0.0, 1.0]
    for position, label in labelled:
        assert float(label.rstrip("×")) == pytest.approx(
            speed_at(position), rel=0.02
        )  # labels carry two significant digits


@pytest.mark.parametrize(
    ("speed", "label"), [(1.0, "Speed 1×"), (0.01, "Speed 0.01×"), (10**0.5, "Speed 3.2×"), (0.0316, "Speed 0.032×")]
)
def test_label_has_two_significant_digits(speed, label):
    assert speed_label(speed) == label
