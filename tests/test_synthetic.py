"""Synthetic motions (dem_core.inputs.synthetic) against the models they come from and the pulse's closed form."""

import math
from pathlib import Path

import numpy as np
import pygmm
import pytest

from dem_core.analyses.spectra import response_spectrum
from dem_core.inputs.excitation import strong_motion
from dem_core.inputs.records import G_STANDARD
from dem_core.inputs.synthetic import (
    DT,
    PULSE_GAMMA,
    PULSE_PHASE,
    Scenario,
    motion_rng,
    near_fault_accelerations,
    pulse_acceleration,
    pulse_period,
    pulse_velocity,
    significant_share,
    stochastic_accelerations,
    stochastic_motion,
    synthetic_suite,
    velocity_pulse,
)

#: s, the periods over which a suite's median spectrum is held to the model's (the issue's 0.1 to 4 s)
PERIODS = np.geomspace(0.1, 4.0, 25)
SUITE_SIZE = 30


@pytest.mark.parametrize("scenario", [Scenario(6.5, 20.0, 400.0, "SS"), Scenario(6.0, 10.0, 760.0, "NS")],
                         ids=lambda s: s.label)
def test_a_suites_median_spectrum_is_within_one_sigma_of_the_models(scenario):
    """The 5%-damped spectra of 30 stochastic motions (Bayless-Abrahamson 2019 Fourier amplitudes, Afshari-Stewart
    2016 durations): their median within the median +- one standard deviation of Boore, Stewart, Seyhan and
    Atkinson (2014) for the scenario, a response-spectrum model fitted to the same NGA-West2 records, at every
    period from 0.1 to 4 s."""
    suite = synthetic_suite(scenario, SUITE_SIZE, seed=1)
    psa = np.array([response_spectrum(motion, PERIODS).psa for motion in suite.values()]) / G_STANDARD
    median = np.exp(np.log(psa).mean(axis=0))
    model = pygmm.BooreStewartSeyhanAtkinson2014(scenario.pygmm())
    log_periods = np.log(model.periods)
    model_median = np.exp(np.interp(np.log(PERIODS), log_periods, np.log(model.spec_accels)))
    sigma = np.interp(np.log(PERIODS), log_periods, model.ln_stds)
    deviation = np.log(median / model_median) / sigma
    assert np.all(np.abs(deviation) <= 1.0), dict(zip(PERIODS.round(2), deviation.round(2)))


def test_a_suites_significant_durations_have_the_models_median():
    """The 5-95% significant durations of 30 motions: their log mean within two standard errors (the suite's own
    log standard deviation over sqrt(30)) of Afshari and Stewart's (2016) median, and their log standard deviation
    at least 0.8 of the model's (each motion draws its duration with the model's; 30 of them estimate a standard
    deviation to about 13%)."""
    scenario = Scenario(6.5, 20.0, 400.0, "SS")
    durations = [np.subtract(*strong_motion(m.horizontal)[::-1]) for m in synthetic_suite(scenario, SUITE_SIZE, 2)
                 .values()]
    model = pygmm.AfshariStewart2016(scenario.pygmm())
    logs = np.log(durations)
    assert abs(logs.mean() - math.log(model.duration["D_5t95"])) <= 2.0 * logs.std(ddof=1) / math.sqrt(SUITE_SIZE)
    assert logs.std(ddof=1) >= 0.8 * float(model.std_err["D_5t95"])


def test_the_envelopes_significant_duration_is_the_share_it_is_stretched_by():
    """Without residuals, a motion's significant duration over its envelope's length is about
    significant_share(): white noise under the envelope holds its energy where the envelope squared does."""
    scenario = Scenario(6.0, 10.0, 760.0, "NS")
    median = float(pygmm.AfshariStewart2016(scenario.pygmm()).duration["D_5t95"])
    found = [np.subtract(*strong_motion(stochastic_motion(scenario, 3, k, variability=False).horizontal)[::-1])
             for k in range(10)]
    assert np.exp(np.mean(np.log(found))) == pytest.approx(median, rel=0.15)
    assert 0.4 < significant_share() < 0.55


def test_a_motion_depends_only_on_its_seed_and_index():
    scenario = Scenario(5.5, 10.0)
    small, large = synthetic_suite(scenario, 2, seed=7), synthetic_suite(scenario, 3, seed=7)
    assert list(small) == list(large)[:2]
    for name in small:
        np.testing.assert_array_equal(small[name].horizontal.samples, large[name].horizontal.samples)
    other = stochastic_motion(scenario, seed=8)
    assert not np.array_equal(other.horizontal.samples, next(iter(small.values())).horizontal.samples)


def test_the_pulse_is_its_closed_form():
    """Mavroeidis-Papageorgiou: the sampled acceleration integrates to the closed-form velocity (to O(dt^2)),
    which peaks at A at t_0 for nu = 0 and is zero at both ends; the acceleration is the velocity's derivative."""
    amplitude, period, gamma = 0.8, 1.5, 2.0
    motion = velocity_pulse(amplitude, period, gamma, 0.0, dt=1e-3)
    t = np.linspace(0.0, gamma * period, 3001)
    exact = pulse_velocity(t, amplitude, period, gamma, 0.0)
    np.testing.assert_allclose(motion.horizontal.velocity(t), exact, atol=1e-5 * amplitude)
    assert pulse_velocity(gamma * period / 2, amplitude, period, gamma) == pytest.approx(amplitude)
    assert pulse_velocity([0.0, gamma * period], amplitude, period, gamma) == pytest.approx([0.0, 0.0], abs=1e-12)
    h = 1e-6
    derivative = (pulse_velocity(t[1:-1] + h, amplitude, period, gamma, 1.0)
                  - pulse_velocity(t[1:-1] - h, amplitude, period, gamma, 1.0)) / (2 * h)
    np.testing.assert_allclose(pulse_acceleration(t[1:-1], amplitude, period, gamma, 1.0), derivative,
                               atol=1e-6 * amplitude / period)


def test_the_pulse_period_follows_its_regression():
    assert pulse_period(6.0) == pytest.approx(10 ** 0.1)
    assert pulse_period(7.0) / pulse_period(6.0) == pytest.approx(10 ** 0.5)


def test_a_near_fault_motion_is_its_stochastic_motion_plus_its_pulse():
    """Drawn from the same stream, a near-fault motion's accelerations are the stochastic motion's plus the
    Mavroeidis-Papageorgiou pulse of the parameters it returns: the median PGV of BSSA14 for the scenario, the
    period of the regression, gamma and nu within the ranges drawn from."""
    scenario = Scenario(6.7, 5.0, 760.0, "SS")
    for index in range(3):
        background = stochastic_accelerations(scenario, motion_rng(4, index))
        near, (amplitude, period, gamma, phase, peak) = near_fault_accelerations(scenario, motion_rng(4, index))
        t = np.arange(len(near)) * DT
        added = np.pad(background, (0, len(near) - len(background)))
        np.testing.assert_allclose(near - added, pulse_acceleration(t, amplitude, period, gamma, phase, peak),
                                   atol=1e-12)
        assert amplitude == pytest.approx(pygmm.BooreStewartSeyhanAtkinson2014(scenario.pygmm()).pgv / 100.0)
        assert period == pulse_period(6.7) and PULSE_GAMMA[0] <= gamma <= PULSE_GAMMA[1]
        assert PULSE_PHASE[0] <= phase <= PULSE_PHASE[1]


def test_the_limits_docs_records_md_states_are_the_codes():
    """docs/records.md quotes the envelope's share of 5-75% in the 5-95% duration, the same share in Afshari and
    Stewart's medians for M6.5 at 20 km, and the highest frequency of Bayless and Abrahamson's standard deviation."""
    text = (Path(__file__).resolve().parents[1] / "docs" / "records.md").read_text()
    envelope = significant_share(0.05, 0.75) / significant_share()
    medians = pygmm.AfshariStewart2016(Scenario(6.5, 20.0, 400.0, "SS").pygmm()).duration
    records_share = float(medians["D_5t75"] / medians["D_5t95"])
    spectrum = pygmm.BaylessAbrahamson2019(Scenario(6.5, 20.0, 400.0, "SS").pygmm())
    highest = spectrum.freqs[np.flatnonzero(np.isfinite(spectrum.ln_std))[-1]]
    assert f"energy in {envelope:.2f} of the 5-95% duration" in text
    assert f"the share is {records_share:.2f} for M6.5 at 20 km" in text
    assert f"no standard deviation above {highest:.1f} Hz" in text


@pytest.mark.parametrize(("arguments", "said"), [
    ((2.0, 10.0), "magnitude must be a number from 3 to 8"),
    ((6.0, -1.0), "distance_km must be a number from 0 to 300"),
    ((6.0, 10.0, 100.0), "vs30 must be a number from 180 to 1500"),
    ((6.0, 10.0, 400.0, "thrust"), "mechanism must be one of SS, NS, RS"),
])
def test_a_scenario_out_of_the_models_range_is_refused_naming_it(arguments, said):
    with pytest.raises(ValueError, match=said):
        Scenario(*arguments)


def test_a_pulse_with_gamma_of_one_or_less_is_refused():
    with pytest.raises(ValueError, match="gamma must be a number above 1"):
        velocity_pulse(0.5, 1.0, gamma=1.0)
    with pytest.raises(ValueError, match="suite needs a whole number of motions"):
        synthetic_suite(Scenario(6.0, 10.0), 0)
