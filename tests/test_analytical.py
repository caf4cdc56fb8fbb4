"""The references themselves: consistent with each other and with their closed forms."""

import numpy as np
import pytest

from comparisons.cases.measures import peaks_between_crossings
from comparisons.references import analytical


@pytest.mark.slow
def test_rocking_equation_reproduces_housner_peaks(housner_block):
    """Housner's peak formula counts energy with the small-angle potential, 1 - (1 - theta/alpha)^2, so the
    exact rocking equation agrees with it to the size of that approximation (0.12% here)."""
    theta0 = 0.05236
    ode = analytical.rocking_response(housner_block, lambda t: 0.0, 3.0, theta0=theta0, max_step=1e-4)
    peaks = peaks_between_crossings(ode.theta, 6)
    np.testing.assert_allclose(peaks, analytical.housner_peaks(housner_block, theta0, 5), rtol=2e-3)


@pytest.mark.slow
def test_housner_period_is_the_small_angle_limit_of_the_rocking_equation():
    block = analytical.RockingBlock.from_size(0.2, 2.0)
    for ratio, band in ((0.05, 2e-3), (0.2, 1e-2)):
        theta0 = ratio * block.alpha
        ode = analytical.rocking_response(block, lambda t: 0.0, 3.0, theta0=theta0, max_step=1e-4)
        assert ode.impacts[0] == pytest.approx(analytical.housner_period(block, theta0) / 4, rel=band)


def test_rigid_plastic_integration_matches_newmark():
    mu, t_p, dt = 0.25, 0.4, 1e-4
    for ratio in (1.5, 3.0):
        a_p = ratio * mu * analytical.G
        n = round(t_p / dt)
        pulse = np.concatenate([np.full(n, a_p), [a_p], np.zeros(4 * n)])  # the step lands on a sample
        pulse[n] = 0.0
        slip = analytical.rigid_plastic_sliding(pulse, dt, mu)
        # the record is linear between samples, so the pulse end is a one-sample ramp: O(dt / T_p)
        assert slip.max_slip == pytest.approx(analytical.newmark_max_slip(a_p, t_p, mu), rel=2 * dt / t_p)


def test_rigid_plastic_block_sticks_below_the_friction_limit():
    a = 0.9 * 0.3 * analytical.G * np.sin(np.linspace(0, 20, 2001))
    assert analytical.rigid_plastic_sliding(a, 0.01, 0.3).total_slip == 0.0


def test_block_at_rest_lifts_off_exactly_at_g_tan_alpha():
    block = analytical.RockingBlock.from_size(1.0, 6.0)
    ode = analytical.rocking_response(block, lambda t: 0.5 * t, 4.0)
    assert 0.5 * ode.uplift_time == pytest.approx(9.81 / 6.0, rel=1e-9)


def test_slide_rock_threshold_meets_the_rocking_threshold_at_mu_tan_alpha():
    block = analytical.RockingBlock.from_size(0.25, 1.0)
    assert analytical.slide_rock_acceleration(block, 0.25) == pytest.approx(analytical.G * 0.25, rel=1e-12)
    assert analytical.slide_rock_acceleration(block, 0.3) > analytical.G * 0.25
    assert analytical.slide_rock_acceleration(block, 10.0) == float("inf")


def test_initial_mode_under_a_pulse_follows_the_four_regions():
    block = analytical.RockingBlock.from_size(0.25, 1.0)
    threshold = analytical.slide_rock_acceleration(block, 0.3)
    assert analytical.initial_mode_under_pulse(block, 0.3, 2.0) == "rest"
    assert analytical.initial_mode_under_pulse(block, 0.3, 0.9 * threshold) == "rocking"
    assert analytical.initial_mode_under_pulse(block, 0.3, 1.1 * threshold) == "slide-rock"
    assert analytical.initial_mode_under_pulse(block, 0.2, 2.0) == "sliding"
    assert analytical.initial_mode_under_pulse(block, 0.2, 1.9) == "rest"


def test_rocking_from_theta_zero_takes_the_corner_its_speed_points_to(housner_block):
    """Started at exactly theta = 0, the block rocks on the corner its angular velocity turns it onto;
    the two directions are mirror images to round-off (the corner is the segment's, not sign(theta)'s)."""
    omega0 = 0.5 * housner_block.p * housner_block.alpha
    left = analytical.rocking_response(housner_block, lambda t: 0.0, 1.5, theta0=0.0, omega0=omega0, max_step=1e-3)
    right = analytical.rocking_response(housner_block, lambda t: 0.0, 1.5, theta0=0.0, omega0=-omega0,
                                        max_step=1e-3)
    assert left.theta[1] > 0 > right.theta[1]
    np.testing.assert_allclose(right.theta, -left.theta, atol=1e-12 * housner_block.alpha)
    np.testing.assert_allclose(right.impacts, left.impacts, rtol=1e-9)


def test_sliding_reference_is_odd_in_the_ground_motion():
    """Leaving rest exactly where |a| reaches mu g, the block slides the way the ground drags it."""
    t = np.arange(0.0, 2.0, 0.01)
    a = 4.0 * np.sin(2.0 * np.pi * t)
    forward = analytical.rigid_plastic_sliding(a, 0.01, 0.2)
    backward = analytical.rigid_plastic_sliding(-a, 0.01, 0.2)
    assert forward.max_slip > 0.01
    np.testing.assert_allclose(backward.u, -forward.u, atol=1e-15)
    assert backward.total_slip == pytest.approx(forward.total_slip, rel=1e-12)
