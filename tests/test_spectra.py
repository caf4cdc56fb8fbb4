"""Elastic response spectra: the exact piecewise-linear recurrence against scipy and the limits of the spectrum."""

import numpy as np
import pytest
from scipy import signal

from dem_core import excitation, spectra


@pytest.fixture(scope="module")
def el_centro():
    return excitation.record("el_centro_1940")


@pytest.mark.parametrize("period, damping", [(0.1, 0.05), (0.5, 0.02), (2.0, 0.1)])
def test_oscillator_matches_scipy_lsim(el_centro, period, damping):
    dt = el_centro.horizontal.dt
    t = np.arange(0.0, el_centro.end_time, dt)
    acc = el_centro.horizontal.acceleration(t)
    omega = 2 * np.pi / period
    _, reference, _ = signal.lsim(signal.lti([-1.0], [1.0, 2 * damping * omega, omega ** 2]), acc, t)
    ours = spectra.oscillator_response(acc, dt, [period], damping)[:, 0]
    assert np.max(np.abs(ours - reference)) < 1e-9 * np.max(np.abs(reference))


def test_spectrum_limits(el_centro):
    s = spectra.response_spectrum(el_centro, periods=[0.005, 1.0, 30.0])
    assert s.psa[0] == pytest.approx(s.pga, rel=0.002)  # a rigid oscillator follows the ground: measured -0.02%
    peak_ground_displacement = np.max(np.abs(el_centro.displacement(np.arange(0, el_centro.end_time, 0.01))[0]))
    # a very soft one stays put: measured -5.2% at T = 30 s (the oscillator still moves a little)
    assert s.sd[2] == pytest.approx(peak_ground_displacement, rel=0.07)
    np.testing.assert_allclose(s.psa, (2 * np.pi / s.periods) ** 2 * s.sd)


def test_spectrum_scales_linearly_with_the_record():
    a = spectra.response_spectrum(excitation.record("kalamata_1986"))
    b = spectra.response_spectrum(excitation.record("kalamata_1986", scale=2.0))
    np.testing.assert_allclose(b.psa, 2.0 * a.psa, rtol=1e-10)
