"""A phone's gyroscope recording of a toss, read, cut into free flights and fitted with the free body.

:func:`read_gyroscope` (:mod:`.reading`) reads phyphox's exports into a :class:`Recording`
(:mod:`.recording`); :func:`free_flights` (:mod:`.flights`) finds the tosses; :func:`fit_free_body`
(:mod:`.fit`) fits the moments' ratios, the axes, the drag and each toss's initial ω with the model of
:mod:`.model` (the closed form, and :mod:`.kernel`'s compiled steps with drag); :func:`synthetic_recording`
(:mod:`.synthetic`) makes a recording from the model itself, for tests and demonstrations.
"""

from physics.gyro.fit import FreeBodyFit, HalfTurns, fit_free_body
from physics.gyro.flights import free_flights
from physics.gyro.reading import read_gyroscope
from physics.gyro.recording import CLIP_RATE, Recording, Segment
from physics.gyro.synthetic import Toss, synthetic_recording

__all__ = [
    "CLIP_RATE",
    "FreeBodyFit",
    "HalfTurns",
    "Recording",
    "Segment",
    "Toss",
    "fit_free_body",
    "free_flights",
    "read_gyroscope",
    "synthetic_recording",
]
