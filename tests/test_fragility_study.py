"""The fragility study's pieces: intensity measures, the damage ratio against the governing critical angle, the
exceedance rule, the stripes, and the study's counts against its own runs."""

import dataclasses
import math

import numpy as np
import pytest

from dem_core import excitation, scenes, simulate
from dem_core.analyses.fragility_study import exceeds, fragility_study, intensity, stripes


def test_pgv_of_a_sine_pulse_is_its_closed_form():
    """a sin(2 pi t / T) for 0 <= t < T: the ground velocity peaks at T/2 at a T / pi."""
    a, period = 3.0, 0.7
    assert intensity(excitation.sine_pulse(a, period), "pgv") == pytest.approx(a * period / math.pi, rel=1e-5)
    assert intensity(excitation.sine_pulse(a, period), "pga") == pytest.approx(a)


def test_scaling_a_record_scales_its_intensities():
    record = excitation.record("kalamata_1986")
    for im in ("pga", "pgv"):
        assert intensity(excitation.scaled(record, 2.5), im) == pytest.approx(2.5 * intensity(record, im), rel=1e-12)


def test_a_record_scaled_to_a_spectral_acceleration_has_it_and_unusable_periods_are_refused():
    """Sa(T) scales with the record (a linear oscillator), so the factor level / Sa(T) gives the level; a period
    under four of El Centro's 0.01 s samples or beyond its 53.7 s is refused, naming the record."""
    el_centro = excitation.record("el_centro_1940")
    sa = intensity(el_centro, "sa", 1.0)
    assert intensity(excitation.scaled(el_centro, 4.0 / sa), "sa", 1.0) == pytest.approx(4.0, rel=1e-9)
    for period, said in ((0.03, "under 4 of its 0.01 s samples"), (60.0, "longer than the record"),
                         (None, "needs a period")):
        with pytest.raises(ValueError, match=said):
            intensity(el_centro, "sa", period)


def test_a_drums_damage_is_measured_against_its_columns_critical_angle():
    column = scenes.column(n_drums=3, width=1.0, height=4.0)
    result = simulate(column, excitation.sine_pulse(3.0, 0.6), 1.5, integrator="moreau")
    (only,) = result.columns
    assert only.critical_angle < result.critical_angle.min(), "the column tips before any drum alone would"
    assert result.damage_ratio == pytest.approx(result.peak_theta.max() / only.critical_angle, rel=1e-12)
    block = simulate(scenes.block(0.6, 3.0), excitation.sine_pulse(3.0, 0.6), 1.5, integrator="moreau")
    assert block.damage_ratio == pytest.approx(block.peak_theta[0] / math.atan(0.6 / 3.0), rel=1e-12)


def test_states_from_one_up_are_overturning_and_an_overturn_exceeds_every_state():
    ratio, overturned = np.array([0.05, 0.4, 1.2, 0.3]), np.array([False, False, False, True])
    assert exceeds(ratio, overturned, 0.3).tolist() == [False, True, True, True]
    assert exceeds(ratio, overturned, 1.0).tolist() == [False, False, False, True]


def test_stripes_are_evenly_spaced_up_to_the_top_and_bad_ones_refused():
    np.testing.assert_allclose(stripes(4, 8.0), [2.0, 4.0, 6.0, 8.0])
    with pytest.raises(ValueError, match="at least 2"):
        stripes(1, 8.0)
    with pytest.raises(ValueError, match="positive and finite"):
        stripes(4, -1.0)


def test_the_study_counts_each_stripes_runs_as_the_runs_themselves_say():
    """Two sine pulses on the 0.6 x 3 m block at five stripes: the counts written out run by run (the block
    overturns from the third stripe under the longer pulse, from the fourth under the shorter), checked against
    the study's, and a mix of exceeding and standing runs in the stripes between."""
    records = {"pulse": excitation.sine_pulse(1.0, 0.5), "long pulse": excitation.sine_pulse(1.0, 0.9)}
    study = fragility_study(scenes.block(0.6, 3.0), records, stripes(5, 10.0), (0.5, 1.0), duration=2.0,
                            integrator="moreau", samples=50)
    assert len(study.runs) == 10 and (study.runs["status"] == "ok").all()
    assert study.described() == "2 records (pulse, long pulse) x 5 stripes; 2 s of each record; moreau, dt 0.001 s"
    measures = study.intensity_measures().set_index("measure")
    assert list(measures.index) == ["PGA (m/s^2)", "PGV (m/s)", "PGA/(g tan alpha)", "PGV/(p R)",
                                    "Sa(0.5 s) (m/s^2)", "Sa(1 s) (m/s^2)", "Sa(2 s) (m/s^2)"]
    # the dimensionless measures of the 0.6 x 3 m block (b/h = 0.2, R = sqrt(0.3^2 + 1.5^2) m): the same fits,
    # their medians divided by g tan(alpha) and p R = sqrt(3 g R / 4)
    radius = math.hypot(0.3, 1.5)
    for measure, named, scale in (("PGA (m/s^2)", "PGA/(g tan alpha)", 9.81 * 0.2),
                                  ("PGV (m/s)", "PGV/(p R)", math.sqrt(3.0 * 9.81 * radius / 4.0))):
        assert measures.loc[named, "beta"] == pytest.approx(measures.loc[measure, "beta"], rel=1e-4)
        assert measures.loc[named, "median_1"] == pytest.approx(measures.loc[measure, "median_1"] / scale, rel=1e-4)
    # every run's PGA is its stripe's level: the fit to the runs is the fit to the stripes
    assert measures.loc["PGA (m/s^2)", "beta"] == pytest.approx(study.fits[1.0].beta, rel=1e-5)
    assert measures.loc["PGA (m/s^2)", "median_1"] == pytest.approx(study.fits[1.0].median, rel=1e-5)
    overturned = {(row.record, row.level): bool(row.overturned) for row in study.runs.itertuples()}
    expected = [sum(overturned[(name, level)] for name in records) for level in (2.0, 4.0, 6.0, 8.0, 10.0)]
    assert study.fits[1.0].exceed.tolist() == expected and study.fits[1.0].runs.tolist() == [2] * 5
    assert 0 in expected and 2 in expected, "the stripes run from none to all overturned"
    half = [sum(overturned[(name, level)] or study.runs.loc[(study.runs.record == name) &
                                                            (study.runs.level == level), "damage_ratio"].item() >= 0.5
                for name in records) for level in (2.0, 4.0, 6.0, 8.0, 10.0)]
    assert study.fits[0.5].exceed.tolist() == half
    np.testing.assert_allclose(study.runs.loc[study.runs.level == 10.0, "scale"], 10.0)
    assert (study.counts()["unfinished"] == 0).all()
    lost = study.runs.assign(status=np.where(study.runs.index == 3, "unstable", study.runs["status"]))
    counts = dataclasses.replace(study, runs=lost).counts()
    assert counts.groupby("level")["unfinished"].first().to_dict() == {
        level: int(level == study.runs["level"][3]) for level in (2.0, 4.0, 6.0, 8.0, 10.0)}


def test_a_colonnades_drums_answer_to_their_columns_and_its_epistyle_to_itself():
    colonnade = scenes.colonnade(n_columns=2, n_drums=2)
    result = simulate(colonnade, excitation.sine_pulse(2.5, 0.6), 1.0, integrator="moreau")
    governing = result.critical_angle.copy()
    for column in result.columns:
        for name in column.blocks:
            governing[result.index(name)] = column.critical_angle
    assert len(result.columns) == 2 and np.any(governing != result.critical_angle)
    assert np.any(governing == result.critical_angle), "the epistyle is on no column: its own angle governs"
    assert result.damage_ratio == pytest.approx(np.max(result.peak_theta / governing), rel=1e-12)


def test_bad_studies_are_refused_naming_the_fault():
    block, records = scenes.block(0.6, 3.0), {"pulse": excitation.sine_pulse(1.0, 0.5)}
    with pytest.raises(ValueError, match="intensity measure"):
        fragility_study(block, records, [1.0, 2.0], im="sd")
    with pytest.raises(ValueError, match="records is empty"):
        fragility_study(block, {}, [1.0, 2.0])
    for states in ((0.5, -1.0), (0.5, 1.5)):
        with pytest.raises(ValueError, match="damage states"):
            fragility_study(block, records, [1.0, 2.0], states=states)
