"""A record's strong motion (the 5-95% of its Arias intensity, dem_core.inputs.excitation.strong_motion) and the
warning of a batch whose duration cuts it."""

import numpy as np
import pytest

from dem_core import scenes, simulate_batch
from dem_core.inputs.excitation import (GroundMotion, Sampled, cuts_strong_motion, record, record_name, scaled,
                                        strong_motion)


def _shaking(start: float, end: float, length: float = 10.0, dt: float = 0.01) -> GroundMotion:
    """A record of steady amplitude between ``start`` and ``end`` s and still outside: its Arias intensity grows
    evenly over the shaking, so its 5% and 95% times are a twentieth of the shaking from either end."""
    t = np.arange(0.0, length + dt / 2, dt)
    a = np.where((t >= start) & (t <= end), np.where(np.arange(t.size) % 2 == 0, 1.0, -1.0), 0.0)
    return GroundMotion(Sampled(a, dt), name="steady x1")


def test_steady_shaking_has_its_strong_motion_within_a_twentieth_of_either_end():
    start, end = strong_motion(_shaking(2.0, 6.0).horizontal)
    assert start == pytest.approx(2.0 + 0.05 * 4.0, abs=0.011) and end == pytest.approx(2.0 + 0.95 * 4.0, abs=0.011)


def test_the_strong_motion_does_not_depend_on_the_scale_and_names_the_record():
    el_centro = record("el_centro_1940")
    assert strong_motion(scaled(el_centro, 3.7).horizontal) == strong_motion(el_centro.horizontal)
    assert record_name(scaled(el_centro, 3.7)) == "el_centro_1940"
    assert cuts_strong_motion(scaled(el_centro, 3.7), None) == ""
    assert cuts_strong_motion(scaled(el_centro, 3.7), 27.0) == ""
    assert cuts_strong_motion(scaled(el_centro, 3.7), 20.0).startswith("20 s of el_centro_1940 stop before")


def test_a_batch_that_cuts_a_records_strong_motion_says_so_once_naming_it():
    shaking = _shaking(1.0, 3.0, length=4.0)
    motions = [scaled(shaking, factor) for factor in (2.0, 3.0)]
    with pytest.warns(RuntimeWarning, match=r"the strong motion is cut: 2 s of steady stop before") as said:
        simulate_batch(scenes.block(1.0, 6.0), motions, 2.0, threads=1)
    assert sum("strong motion" in str(w.message) for w in said) == 1
