"""Statics and invariants: a resting stack stays put, energy does not grow (docs/method.md 4.8)."""

import numpy as np
import pytest

import dem_core
from dem_core import scenes


@pytest.fixture(scope="module")
def resting_column():
    return dem_core.simulate(scenes.column(8), duration=10.0, output_dt=0.01, integrator="explicit")


def test_eight_drum_column_at_rest_does_not_drift(resting_column):
    r = resting_column
    settled = r.t >= 1.0  # the drums sink into equilibrium (tens of micrometres) in the first moments
    drift_x = np.max(np.abs(r.x - r.x[0]))
    drift_y = np.max(np.abs(r.y[settled] - r.y[settled][0]))
    assert drift_x < 1e-6
    assert drift_y < 1e-6
    assert np.max(np.abs(r.theta)) < 1e-6
    assert r.total_sliding < 1e-6
    assert not r.overturned


def test_resting_column_sinks_by_its_static_penetration(resting_column):
    """Every interface carries the weight above it: penetration = weight / (K_n d L)."""
    r = resting_column
    scene = scenes.column(8)
    kn = scene.contact.kn
    weights = np.array([b.mass for b in scene.blocks]) * scene.gravity
    load_below = np.cumsum(weights[::-1])[::-1]  # force on the interface under each drum
    expected_sink = np.cumsum(load_below / (kn * 1.0 * 1.0))
    sink = np.array([b.centroid[1] for b in scene.blocks]) - r.y[-1]
    np.testing.assert_allclose(sink, expected_sink, rtol=1e-3)


def test_mirror_symmetric_motion_gives_mirror_symmetric_response():
    """A column under a ground motion and under its mirror image rotates by equal and opposite angles."""
    scene = scenes.column(4)
    motion = dem_core.excitation.sine_pulse(3.0, 0.4)
    mirrored = dem_core.excitation.sine_pulse(-3.0, 0.4)
    a = dem_core.simulate(scene, motion, duration=1.5, output_dt=1e-3, integrator="explicit")
    b = dem_core.simulate(scene, mirrored, duration=1.5, output_dt=1e-3, integrator="explicit")
    assert np.max(np.abs(a.theta)) > 1e-3
    np.testing.assert_allclose(a.theta, -b.theta, atol=1e-6 * np.max(np.abs(a.theta)) + 1e-12)
