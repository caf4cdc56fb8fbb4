"""The Python API's arguments checked at the door: a wrong kind of scene, motion or number is named with the
argument it was given as, before anything is compiled; a motion beyond what a stone block can meet is named."""

import warnings

import pytest

import dem_core
from dem_core import excitation, scenes


@pytest.fixture(scope="module")
def two_drums():
    return scenes.column(2)


@pytest.mark.parametrize("scene, words", [
    ("column.toml", r"scene must be a dem_core.Scene, got the path 'column.toml': read a scene file"),
    ({"builder": "column"}, r"scene must be a dem_core.Scene, got a dict"),
    (3, r"scene must be a dem_core.Scene, got int 3"),
])
def test_a_scene_of_the_wrong_kind_is_named(scene, words):
    with pytest.raises(TypeError, match=words):
        dem_core.simulate(scene, excitation.still(), duration=0.1)


def test_a_number_given_as_the_motion_is_named(two_drums):
    with pytest.raises(TypeError, match=r"excitation must be a ground motion .* got float 3.0"):
        dem_core.simulate(two_drums, 3.0, duration=0.1)


@pytest.mark.parametrize("name, value, error, words", [
    ("duration", "1.0", TypeError, r"duration must be a number of seconds, got str '1.0'"),
    ("duration", float("inf"), ValueError, r"duration must be positive and finite, got inf"),
    ("duration", float("nan"), ValueError, r"duration must be positive and finite, got nan"),
    ("duration", -2.0, ValueError, r"duration must be positive and finite, got -2.0"),
    ("output_dt", -0.5, ValueError, r"output_dt must be positive and finite, got -0.5"),
    ("output_dt", 0.0, ValueError, r"output_dt must be positive and finite, got 0.0"),
    ("dt", float("inf"), ValueError, r"dt must be positive and finite, got inf"),
    ("dt", True, TypeError, r"dt must be a number of seconds, got bool True"),
])
def test_times_that_are_not_positive_finite_seconds_are_named(two_drums, name, value, error, words):
    arguments = {"duration": 0.1, name: value}
    with pytest.raises(error, match=words):
        dem_core.simulate(two_drums, excitation.still(), **arguments)


def test_a_motion_beyond_fifty_g_is_refused_naming_it_and_its_peak(two_drums):
    """A harmonic of 1e4 m/s^2 (about 1000 g) is a mistake of units or scale, not an earthquake: the run is refused
    with the motion's name and peak, the policy a scene file follows; a ramp is judged by its value at the run's
    end."""
    words = r"ground motion 'harmonic.*' would peak at 1e\+04 m/s\^2 \(1.02e\+03 g\), beyond the 50 g"
    with pytest.raises(ValueError, match=words):
        dem_core.Simulation(two_drums, excitation.harmonic(pga=1e4, frequency=5.0), duration=0.05)
    ramp = excitation.ramp(rate=100.0)
    dem_core.simulate(two_drums, ramp, duration=0.05)  # 5 m/s^2 at its end
    with pytest.raises(ValueError, match=r"would peak at 600 m/s\^2"):
        dem_core.Simulation(two_drums, ramp, duration=6.0)


def test_an_ordinary_record_is_not_announced(two_drums):
    with warnings.catch_warnings():
        warnings.simplefilter("error")
        dem_core.simulate(two_drums, excitation.record("el_centro_1940"), duration=0.05)
