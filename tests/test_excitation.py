"""Ground motion: exact integrals, scaling, baseline correction, horizontal and vertical together."""

import dataclasses
import math

import numpy as np
import pytest

from dem_core import excitation


def _derivative(f, t, h=1e-6):
    return (f(t + h) - f(t - h)) / (2 * h)


MOTIONS = [
    excitation.harmonic(0.05, 1.5),
    excitation.rectangular_pulse(2.0, 0.4),
    excitation.sine_pulse(3.0, 0.5),
    excitation.cosine_pulse(3.0, 0.5),
    excitation.ramp(0.5),
    excitation.ramp(2.0, peak=3.0),
    excitation.record(np.sin(np.linspace(0, 20, 501)) * 2.0, dt=0.01, baseline=False),
]


@pytest.mark.parametrize("motion", MOTIONS, ids=lambda m: m.name)
def test_velocity_and_displacement_are_the_integrals_of_acceleration(motion):
    c = motion.horizontal
    t = np.linspace(0.013, 4.9, 97)
    t = t[np.all(np.abs(t[:, None] - np.array([0.4, 0.5, 1.5, 5.0])[None, :]) > 1e-3, axis=1)]  # skip pulse edges
    np.testing.assert_allclose(_derivative(c.displacement, t), c.velocity(t), rtol=1e-6, atol=1e-8)
    np.testing.assert_allclose(_derivative(c.velocity, t), c.acceleration(t), rtol=1e-5, atol=1e-6)


def test_pulses_start_and_end_where_they_should():
    p = excitation.sine_pulse(3.0, 0.5).horizontal
    assert p.acceleration(np.array([-0.1, 0.6]))[0] == 0.0
    assert p.acceleration(0.125) == pytest.approx(3.0)
    assert p.velocity(0.7) == pytest.approx(0.0, abs=1e-12)  # one full sine: the ground is back at rest
    assert p.displacement(0.7) == pytest.approx(3.0 * 0.5**2 / (2 * np.pi), rel=1e-12)
    r = excitation.rectangular_pulse(2.0, 0.4).horizontal
    assert r.velocity(1.0) == pytest.approx(0.8)
    assert r.displacement(1.0) == pytest.approx(2.0 * 0.16 / 2 + 0.8 * 0.6)


def test_harmonic_from_peak_acceleration():
    m = excitation.harmonic(pga=3.0, frequency=2.0)
    t = np.linspace(0, 1, 2001)
    assert np.max(np.abs(m.horizontal.acceleration(t))) == pytest.approx(3.0, rel=1e-5)
    with pytest.raises(ValueError, match="exactly one"):
        excitation.harmonic(0.1, 1.0, pga=2.0)


@pytest.mark.parametrize("baseline", [False, True])
def test_record_scaled_to_a_target_pga(baseline):
    """The peak asked for is the peak of the samples the run takes, after the baseline correction."""
    m = excitation.record("el_centro_1940", pga=4.0, baseline=baseline)
    assert m.horizontal.peak_acceleration == pytest.approx(4.0, rel=1e-15)
    doubled = excitation.record("el_centro_1940", scale=2.0, baseline=False)
    base = excitation.record("el_centro_1940", baseline=False)
    np.testing.assert_allclose(doubled.horizontal.samples, 2.0 * base.horizontal.samples)


@pytest.mark.parametrize("name", ["el_centro_1940", "northridge_1994", "kalamata_1986", "mexico_city_1985"])
def test_baseline_correction_brings_the_ground_back_to_rest(name):
    raw = excitation.record(name, baseline=False).horizontal
    corrected = excitation.record(name).horizontal
    end = raw.end_time
    peak_v = np.max(np.abs(corrected.velocity(np.linspace(0, end, 2001))))
    assert abs(corrected.velocity(end)) < 1e-9 * max(peak_v, 1.0)
    assert abs(corrected.displacement(end)) < 1e-9
    # the correction is a small change of the accelerations
    assert np.max(np.abs(corrected.samples - raw.samples)) < 0.02 * raw.peak_acceleration


def test_horizontal_and_vertical_components_together():
    m = excitation.record("mexico_city_1985", vertical=True, baseline=False)
    # SOURCES.md: EW 0.1712 g, vertical 0.0373 g
    assert m.horizontal.peak_acceleration == pytest.approx(0.1712 * 9.80665, rel=2e-3)
    assert m.vertical.peak_acceleration == pytest.approx(0.0373 * 9.80665, rel=3e-3)
    ax, ay = m.acceleration(np.array([10.0, 20.0]))
    assert ax.shape == ay.shape == (2,)
    scaled = excitation.record("mexico_city_1985", vertical=True, pga=1.0, baseline=False)
    ratio = scaled.vertical.peak_acceleration / scaled.horizontal.peak_acceleration
    assert ratio == pytest.approx(0.0373 / 0.1712, rel=5e-3)


@pytest.mark.parametrize("motion", [
    excitation.scaled(excitation.record("mexico_city_1985", vertical=True), 1.7),
    excitation.scaled(excitation.extended(excitation.record("kalamata_1986"), 4.0), 0.3),
    excitation.harmonic(0.05, 1.5),
    excitation.sequence([excitation.record("kalamata_1986"), excitation.sine_pulse(3.0, 0.5)], rest=1.0),
], ids=lambda m: m.name)
@pytest.mark.parametrize("duration", [0.0005, 0.7, 12.0, 60.0])
def test_the_velocity_range_is_the_sampled_velocitys_max_less_min(motion, duration):
    """velocity_range, which takes a record's range once for all the factors that scale it, is the sum over the
    components of max - min of the velocity sampled every VELOCITY_SAMPLING s (2 samples at the least), to
    rounding: past a record's end too, and across a sequence's events."""
    t = np.linspace(0.0, duration, math.ceil(max(duration / excitation.VELOCITY_SAMPLING, 2)) + 1)
    vx, vy = motion.velocity(t)
    for _ in range(2):
        assert excitation.velocity_range(motion, duration) == pytest.approx(np.ptp(vx) + np.ptp(vy), rel=1e-14)


def test_only_a_records_velocity_range_is_kept_and_any_component_is_taken():
    """A motion of the user's own that cannot be hashed (a plain dataclass) has its range computed, and neither it
    nor a harmonic or a sequence, whose members each build their own components, holds a place in the records'
    cache."""
    @dataclasses.dataclass
    class Steady(excitation.Component):
        speed: float

        def velocity(self, t):
            return self.speed * np.minimum(np.asarray(t, dtype=float), 1.0)

    kept = excitation._record_measure.cache_info().currsize
    motions = [excitation.GroundMotion(Steady(0.3)), excitation.harmonic(0.05, 1.5),
               excitation.sequence([excitation.sine_pulse(3.0, 0.5)] * 2, rest=1.0)]
    assert excitation.velocity_range(motions[0], 2.0) == pytest.approx(0.3, rel=1e-15)
    for motion in motions[1:]:
        excitation.velocity_range(excitation.scaled(motion, 1.5), 2.0)
    assert excitation._record_measure.cache_info().currsize == kept


def test_a_records_velocity_range_is_found_once_for_all_its_factors():
    record = excitation.record("kalamata_1986")
    first = excitation.velocity_range(excitation.scaled(record, 0.5), 10.0)
    found = excitation._record_measure.cache_info()
    assert excitation.velocity_range(excitation.scaled(record, 2.0), 10.0) == pytest.approx(4.0 * first, rel=1e-15)
    after = excitation._record_measure.cache_info()
    assert (after.hits, after.misses) == (found.hits + 1, found.misses)


def test_array_record_needs_dt():
    with pytest.raises(ValueError, match="dt"):
        excitation.record(np.zeros(10))


def test_harmonic_with_both_amplitude_and_pga_names_both_as_given():
    """Both amplitude and pga: the error names both keys with their values, and carries them (``keys``) so that
    a caller that set one of them (``threshold --parameter pga``) can say so."""
    both = (r"harmonic: give exactly one of amplitude \(m\) and pga \(m/s\^2\), got both: "
            r"amplitude = 0\.1 and pga = 2\.0")
    with pytest.raises(excitation.ExcitationError, match=both) as info:
        excitation.harmonic(0.1, 1.0, pga=2.0)
    assert info.value.keys == ("amplitude", "pga")
    with pytest.raises(excitation.ExcitationError, match="got neither"):
        excitation.harmonic(frequency=1.0)


@pytest.mark.parametrize("make, message", [
    (lambda: excitation.ramp(0.0), r"ramp rate must not be zero, got 0 m/s\^2 per s"),
    (lambda: excitation.ramp(float("nan")), r"ramp rate \(m/s\^2 per s\) must be a finite number, got nan"),
    (lambda: excitation.ramp(1.0, peak=-2.0), r"ramp peak must be positive, got -2\.0 m/s\^2"),
    (lambda: excitation.rectangular_pulse(2.0, 0.0), r"rectangular pulse duration must be positive, got 0\.0 s"),
    (lambda: excitation.sine_pulse(float("inf"), 0.5), r"sine pulse amplitude \(m/s\^2\) must be a finite number"),
    (lambda: excitation.cosine_pulse(1.0, -0.5), r"cosine pulse duration must be positive, got -0\.5 s"),
    (lambda: excitation.harmonic(0.1, 0.0), r"harmonic frequency must be positive, got 0\.0 Hz"),
    (lambda: excitation.harmonic(pga=-1.0, frequency=1.0), r"harmonic pga must not be negative, got -1\.0 m/s\^2"),
    (lambda: excitation.harmonic(0.1, 1.0, vertical_amplitude=float("nan")),
     r"harmonic vertical_amplitude \(m\) must be a finite number, got nan"),
])
def test_numbers_are_checked_for_finiteness_and_sign_naming_the_input_and_its_unit(make, message):
    with pytest.raises(ValueError, match=message):
        make()


def test_a_scaled_motion_is_the_motion_times_the_factor():
    base = excitation.record("kalamata_1986")
    times = np.linspace(-1.0, base.end_time + 2.0, 777)
    louder = excitation.scaled(base, 1.7)
    for what in ("acceleration", "velocity", "displacement"):
        np.testing.assert_allclose(getattr(louder, what)(times), 1.7 * np.array(getattr(base, what)(times)),
                                   rtol=1e-15, atol=0.0)
    assert louder.end_time == base.end_time and louder.horizontal.peak_acceleration == pytest.approx(
        1.7 * base.horizontal.peak_acceleration)
    with pytest.raises(ValueError, match="factor must be a finite positive number"):
        excitation.scaled(base, 0.0)


def test_a_reversed_record_has_the_peak_ground_velocity_of_its_record():
    """PGV is a peak |velocity|: a record turned the other way (a negative factor) has its record's, times the
    factor's size, taken from the record's once found."""
    record = excitation.record("kalamata_1986")
    reversed_twice = excitation.GroundMotion(excitation.Scaled(record.horizontal, -2.0), name="reversed")
    own = excitation.peak_velocity(record)
    found = excitation._record_measure.cache_info()
    assert excitation.peak_velocity(reversed_twice) == 2.0 * own > 0.0
    after = excitation._record_measure.cache_info()
    assert (after.hits, after.misses) == (found.hits + 1, found.misses)
