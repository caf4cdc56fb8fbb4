"""The Kalamata record at its settled sampling interval (0.01 s) looks like the 1986 mainshock the thesis used."""

import numpy as np
import pytest

from dem_core import excitation, records

THESIS_PREDOMINANT_HZ = (2.9, 3.5)  # the thesis' Kalamata record: predominant frequencies
#: Afshari and Stewart (2016) D5-95 median range for the scenario (Mw 5.9, 3-6 km, Vs30 300-450 m/s), widened
#: by one log standard deviation (0.43) each way
D5_95_BAND_S = (6.02 * np.exp(-0.43), 7.52 * np.exp(0.43))


def test_kalamata_is_read_at_0_01_s():
    assert records.BUNDLED["kalamata_1986"].dt == 0.01
    motion = excitation.record("kalamata_1986")
    assert motion.horizontal.dt == 0.01
    assert motion.end_time == pytest.approx(25.9, abs=0.011)


def test_kalamata_spectrum_peak_and_duration_match_the_earthquake(load_study):
    study = load_study("kalamata_sampling")
    samples = np.loadtxt(records.bundled_path("kalamata_1986"))
    found = study.measure(samples, records.BUNDLED["kalamata_1986"].dt)
    assert THESIS_PREDOMINANT_HZ[0] <= found["psa_peak_hz"] <= THESIS_PREDOMINANT_HZ[1]  # measured 3.24 Hz
    assert D5_95_BAND_S[0] <= found["d5_95_s"] <= D5_95_BAND_S[1]  # measured 7.08 s
    at_source_dt = study.measure(samples, 0.02)
    assert not D5_95_BAND_S[0] <= at_source_dt["d5_95_s"] <= D5_95_BAND_S[1]  # measured 14.2 s
    assert not THESIS_PREDOMINANT_HZ[0] <= at_source_dt["psa_peak_hz"] <= THESIS_PREDOMINANT_HZ[1]  # 1.69 Hz


def test_significant_duration_of_a_constant_signal_is_its_share_of_the_length(load_study):
    study = load_study("kalamata_sampling")
    assert study.significant_duration(np.ones(1001), 0.01, 0.05, 0.95) == pytest.approx(9.0, rel=1e-9)
