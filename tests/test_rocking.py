"""Rocking of rigid blocks against Housner's solution and the rocking equation (FORMULATION 4.1-4.3, 4.6)."""

import numpy as np
import pytest

import dem_core
from comparisons import analytical, cases
from comparisons.cases import HOUSNER_HEIGHT, HOUSNER_THETA0, HOUSNER_WIDTH
from comparisons.measures import first_exceedance, first_zero_crossing, peaks_between_crossings
from dem_core import excitation, scenes

# Bands (relative errors) from the issue; the comments give what the default contact gives today.
# Housner's period formula linearises sin(alpha - theta); the exact solution of his equation of motion
# reaches theta = 0 0.34% later for this release.  The soft contact adds its own delay: the pivot sits
# inside the corner, at the centroid of the triangular overlap.
QUARTER_PERIOD_BAND = 0.01  # measured +0.91% against the formula, +0.56% against the exact equation
PEAK_DECAY_BAND = 0.03  # measured +0.7%, +1.3%, +1.5%, +1.8%, +2.0% after impacts 1 to 5
PULSE_PEAK_BAND = 0.05  # measured +1.3% (6 m/s^2, 0.25 s) and +1.6% (10 m/s^2, 0.15 s)


@pytest.fixture(scope="module")
def free_rocking(housner_scene):
    return dem_core.simulate(housner_scene, duration=3.0, output_dt=1e-9)  # every step


def test_free_rocking_quarter_period_matches_housner(free_rocking, housner_block):
    housner = analytical.housner_period(housner_block, HOUSNER_THETA0) / 4.0
    exact = analytical.rocking_response(housner_block, lambda t: 0.0, 0.5, theta0=HOUSNER_THETA0, max_step=1e-4)
    quarter = first_zero_crossing(free_rocking.t, free_rocking.theta[:, 0])
    assert quarter == pytest.approx(housner, rel=QUARTER_PERIOD_BAND)
    assert quarter == pytest.approx(exact.impacts[0], rel=QUARTER_PERIOD_BAND)


def test_free_rocking_peaks_decay_as_housner_predicts(free_rocking, housner_block):
    n = 5
    reference = analytical.housner_peaks(housner_block, HOUSNER_THETA0, n)
    peaks = peaks_between_crossings(free_rocking.theta[:, 0], n + 1)
    assert len(peaks) == n + 1
    np.testing.assert_allclose(peaks[1:], reference[1:], rtol=PEAK_DECAY_BAND)


def test_default_rocking_damping_follows_the_calibrated_slenderness_law(housner_scene):
    alpha = np.arctan2(HOUSNER_WIDTH, HOUSNER_HEIGHT)
    assert housner_scene.rocking_slenderness == pytest.approx(alpha)
    zeta_r = dem_core.contact.rocking_damping_ratio(housner_scene)
    assert zeta_r == pytest.approx(dem_core.contact.housner_damping_ratio(alpha))


@pytest.mark.parametrize("amplitude, duration", [(6.0, 0.25), (10.0, 0.15)])
def test_one_sine_pulse_peak_matches_the_rocking_equation(housner_block, amplitude, duration):
    motion = excitation.sine_pulse(amplitude, duration)
    scene = scenes.block(HOUSNER_WIDTH, HOUSNER_HEIGHT, friction=0.7)
    result = dem_core.simulate(scene, motion, duration=2.5, output_dt=1e-3)
    ode = analytical.rocking_response(housner_block, lambda t: float(motion.horizontal.acceleration(t)), 2.5,
                                      max_step=1e-3)
    assert not ode.overturned and not result.overturned
    assert result.peak_theta[0] == pytest.approx(ode.peak, rel=PULSE_PEAK_BAND)


RAMP_RATE = cases.ONSET_RAMP_RATE


def _ramp_onset(kn=None):
    """Ground acceleration at which the 1 x 6 m block's rotation passes theta_cr / 30 under the ramp."""
    contact = None if kn is None else dem_core.ContactParameters(kn=kn)
    scene = scenes.block(cases.ONSET_WIDTH, cases.ONSET_HEIGHT, contact=contact)
    result = dem_core.simulate(scene, excitation.ramp(RAMP_RATE), duration=4.5, output_dt=1e-3)
    return RAMP_RATE * first_exceedance(result.t, result.theta[:, 0], scene.blocks[0].critical_angle / 30.0)


@pytest.fixture(scope="module")
def rigid_ramp_onset():
    block = analytical.RockingBlock.from_size(cases.ONSET_WIDTH, cases.ONSET_HEIGHT)
    ode = analytical.rocking_response(block, lambda t: RAMP_RATE * t, 6.0, max_step=1e-3)
    assert RAMP_RATE * ode.uplift_time == pytest.approx(analytical.rocking_onset_acceleration(block), rel=1e-9)
    assert analytical.rocking_onset_acceleration(block) == pytest.approx(1.635, abs=5e-4)
    return RAMP_RATE * first_exceedance(ode.t, ode.theta, block.alpha / 30.0)


def test_rocking_onset_under_a_ramp_converges_to_the_rigid_value(rigid_ramp_onset):
    """A soft contact lifts a corner before a rigid one does: the overturning moment it can resist
    is cut by the triangular overlap (its centroid sits l/3 inside the corner), a bias that shrinks
    like K_n^(-1/3).  Stiff contacts must reach the rigid answer; each 8-fold stiffening halves the bias."""
    stiff = _ramp_onset(kn=1e12)
    assert stiff == pytest.approx(rigid_ramp_onset, rel=0.03)  # measured -2.3%
    bias = [_ramp_onset(kn) / rigid_ramp_onset - 1.0 for kn in (2e10, 1.6e11)]
    assert bias[0] < bias[1] < 0.0
    assert bias[0] / bias[1] == pytest.approx(2.0, rel=0.2)  # measured 2.03


def test_rocking_onset_at_default_stiffness_is_below_the_rigid_threshold_by_the_soft_contact_bias(rigid_ramp_onset):
    # measured -8.9% against the rigid equation under the same criterion (1.78 against 1.95 m/s^2)
    onset = _ramp_onset()
    assert 0.85 * rigid_ramp_onset < onset < rigid_ramp_onset


def test_onset_mode_follows_friction_against_slenderness():
    """FORMULATION 4.6: rocking first when mu > tan(alpha), sliding first when mu < tan(alpha)."""
    block = analytical.RockingBlock.from_size(1.0, 2.0)  # tan(alpha) = 0.5
    g = block.g
    assert analytical.initial_mode(block, mu=0.7) == "rocking"
    assert analytical.initial_mode(block, mu=0.3) == "sliding"
    # the ramp stops between the two thresholds: only the first mode can start
    for mu, peak, mode in ((0.3, 0.4 * g, "sliding"), (0.7, 0.6 * g, "rocking")):
        scene = scenes.block(1.0, 2.0, friction=mu, base_width=20.0)
        result = dem_core.simulate(scene, excitation.ramp(2.0, peak=peak), duration=4.0, output_dt=1e-3)
        rocked = result.peak_theta[0] > block.alpha / 30.0
        slid = result.total_sliding > 0.05  # a rocking block slips a millimetre or so at its pivot
        assert (rocked, slid) == ((mode == "rocking"), (mode == "sliding")), (mu, result.peak_theta, result.total_sliding)


# Under a record the soft contact's own rocking mode (about 15 Hz for the 1 x 6 m monolith at the default
# K_n, inside a record's band) amplifies the motion: the peak under Northridge at 4 m/s^2 is +110% at
# K_n = 2e10, +29% at 2e11 and -1.8% at 2e12 against the rocking equation.
RECORD_STIFF_CONTACT_BAND = 0.05  # at K_n = 2e12


def test_record_rocking_converges_to_the_rocking_equation_as_the_contact_stiffens():
    block = analytical.RockingBlock.from_size(1.0, 6.0)
    motion = excitation.record("northridge_1994", pga=4.0)
    reference = analytical.rocking_response(block, lambda t: float(motion.horizontal.acceleration(t)), 15.0,
                                            max_step=motion.horizontal.dt)
    assert not reference.overturned
    errors = []
    for kn in (2e10, 2e11, 2e12):
        result = dem_core.simulate(scenes.block(1.0, 6.0, contact=dem_core.ContactParameters(kn=kn)), motion,
                                   duration=15.0)
        errors.append(abs(result.peak_theta[0] / reference.peak - 1.0))
    assert errors[0] > errors[1] > errors[2]
    assert errors[2] < RECORD_STIFF_CONTACT_BAND
