"""Nested damage states fitted together (dem_core/analyses/nested_fragility.py): their curves never cross, the fit
maximises the states' summed likelihood, and the bootstrap by record covers a known fragility where the bootstrap
by run does not; the IDA-style estimate reads each record's first exceedance."""

import math
from pathlib import Path

import numpy as np
import pandas as pd
import pytest

from dem_core.analyses import fragility, nested_fragility

LEVELS = np.linspace(0.5, 10.0, 20)


def _records(capacities: np.ndarray, levels=LEVELS) -> np.ndarray:
    """(R, L, K) outcomes of records whose capacity for state k is ``capacities[r, k]``: a record exceeds a state at
    every level from its capacity up (a record's response grows with its scale, as an IDA curve does)."""
    return (levels[None, :, None] >= capacities[:, None, :]).astype(float)


def _counts_that_cross() -> tuple:
    """Counts of two nested states whose separate fits cross: the milder rises slowly over the whole range, the
    severe one steeply in its middle, below the milder's median."""
    n = np.full(LEVELS.size, 40)
    mild = np.round(n * fragility._probability(LEVELS, 6.0, 1.2)).astype(int)
    severe = np.minimum(np.round(n * fragility._probability(LEVELS, 5.0, 0.15)).astype(int), mild)
    return n, mild, severe


def test_counts_made_to_tempt_them_cross_when_fitted_apart_and_never_together():
    n, mild, severe = _counts_that_cross()
    apart = [fragility.fit_lognormal(LEVELS, n, z)[:2] for z in (mild, severe)]
    x = np.geomspace(0.1, 100.0, 2000)
    p_apart = [fragility._probability(x, m, b) for m, b in apart]
    assert np.any(p_apart[1] > p_apart[0] + 0.05)  # they do cross
    medians, beta, note = nested_fragility.fit_nested(LEVELS, np.stack([n, n], 1), np.stack([mild, severe], 1))
    assert note == "" and medians[0] <= medians[1]
    together = [fragility._probability(x, m, beta) for m in medians]
    assert np.all(together[0] >= together[1])


def test_the_joint_fit_maximises_the_summed_likelihood_and_is_the_single_fit_for_one_state():
    n, mild, severe = _counts_that_cross()
    runs, exceed = np.stack([n, n], 1), np.stack([mild, severe], 1)
    medians, beta, _ = nested_fragility.fit_nested(LEVELS, runs, exceed)

    def log_likelihood(mu, b):
        p = np.clip(fragility._probability(LEVELS[:, None], np.exp(np.asarray(mu))[None, :], b), 1e-300, 1 - 1e-16)
        return float(np.sum(exceed * np.log(p) + (runs - exceed) * np.log1p(-p)))

    best = log_likelihood(np.log(medians), beta)
    rng = np.random.default_rng(1)
    for _ in range(50):
        mu = np.sort(np.log(medians) + rng.normal(0.0, 0.02, 2))
        assert log_likelihood(mu, beta * math.exp(rng.normal(0.0, 0.02))) <= best + 1e-9
    one, one_beta, _ = nested_fragility.fit_nested(LEVELS, n[:, None], mild[:, None])
    alone = fragility.fit_lognormal(LEVELS, n, mild)
    assert one[0] == pytest.approx(alone[0], rel=1e-5) and one_beta == pytest.approx(alone[1], rel=1e-5)


def test_counts_a_step_fits_as_well_as_any_lognormal_get_a_note_saying_beta_is_not_measured():
    """Two records at four levels, as a newcomer's first study: the milder state exceeded by one record at the
    lowest level and by both above it, the severe one by neither at the lowest, one at the next and both above.
    Steps at those stripes give every stripe its observed fraction (1/2, 0 or 1), so the likelihood grows as beta
    shrinks toward them: the stripes do not measure beta, and the fit says so.  Counts that rise over several
    stripes (the crossing counts, above) get no note."""
    levels, runs = np.array([2.5, 4.9, 7.4, 9.8]), np.full((4, 2), 2)
    exceed = np.array([[1, 0], [2, 1], [2, 2], [2, 2]])
    medians, beta, note = nested_fragility.fit_nested(levels, runs, exceed)
    assert note == fragility.UNMEASURED_BETA
    np.testing.assert_allclose(medians, [2.5, 4.9], rtol=0.05)
    assert beta < 0.1
    for state in (0, 1):  # each state fitted on its own says so too
        assert fragility.fit_lognormal(levels, runs[:, state], exceed[:, state])[2] == fragility.UNMEASURED_BETA
    # one run a level, as the intensity measures' fits take them: two runs of the lowest level, one exceeding,
    # are its stripe whichever comes first
    for order in ([0, 1, 2, 3, 4], [1, 0, 2, 3, 4]):
        single = np.array([2.5, 2.5, 4.9, 7.4, 9.8])[order], np.ones(5), np.array([1, 0, 1, 1, 1])[order]
        assert fragility.step_like(np.log(single[0]), *single[1:])
    n, mild, severe = _counts_that_cross()
    _, beta, note = nested_fragility.fit_nested(LEVELS, np.stack([n, n], 1), np.stack([mild, severe], 1))
    assert beta > 0.1 and note == ""


#: seeded suites of 10 records from a known lognormal, and the least of them whose band drawn by record covers its
#: median (docs/method.md quotes both, tests/test_method_figures.py reads them here)
COVERAGE_SUITES, COVERED_AT_LEAST = 100, 80


@pytest.mark.slow
def test_the_bootstrap_by_record_covers_a_known_fragility_and_the_bootstrap_by_run_less_often():
    """10 records whose capacities are drawn from a known lognormal (median 3, beta 0.4), :data:`COVERAGE_SUITES`
    seeded suites: the 90% band of the median drawn by record covers 3 in at least :data:`COVERED_AT_LEAST` suites;
    drawn by run, fewer."""
    median, beta, covered = 3.0, 0.4, {"records": 0, "runs": 0}
    for seed in range(COVERAGE_SUITES):
        rng = np.random.default_rng(seed)
        capacities = median * np.exp(beta * rng.standard_normal((10, 1)))
        outcomes = _records(capacities)
        for resample in covered:
            fit, = nested_fragility.fit_states(LEVELS, outcomes, samples=200, seed=seed, resample=resample)
            low, high = fit.median_band
            covered[resample] += low <= median <= high
    assert covered["records"] >= COVERED_AT_LEAST
    assert covered["runs"] < covered["records"]


def test_states_without_a_median_get_a_note_and_the_others_are_fitted_together():
    capacities = np.column_stack([np.linspace(2.0, 6.0, 8), np.full(8, 50.0)])
    first, never = nested_fragility.fit_states(LEVELS, _records(capacities), samples=50)
    assert math.isfinite(first.median) and first.resampled == "records" and len(first.samples) > 0
    assert math.isnan(never.median) and "no run exceeded" in never.note


def test_outcomes_that_are_not_nested_are_refused():
    outcomes = _records(np.column_stack([np.full(4, 3.0), np.full(4, 2.0)]))  # the severe state first
    with pytest.raises(ValueError, match="nested"):
        nested_fragility.fit_states(LEVELS, outcomes)


def test_the_ida_estimate_is_the_geometric_mean_of_each_records_first_exceedance():
    capacities = np.array([1.2, 2.7, 4.1, 8.0, 20.0])  # the last never exceeds within the levels
    median, beta, reached = nested_fragility.ida_estimate(LEVELS, _records(capacities[:, None])[:, :, 0])
    first = np.array([LEVELS[LEVELS >= c][0] for c in capacities[:4]])
    assert reached == 4
    assert median == pytest.approx(math.exp(np.mean(np.log(first))))
    assert beta == pytest.approx(np.std(np.log(first), ddof=1))


@pytest.mark.parametrize("path", sorted(Path(__file__).resolve().parents[1].glob("reports/studies/*/fragility.csv")),
                         ids=lambda path: path.parent.name)
def test_no_committed_studys_curves_cross(path):
    """Each damage measure's fitted states in a committed study share their dispersion and their medians rise with
    the state, so that their curves P_k(x) = Phi(ln(x / median_k) / beta) cannot cross; bands drawn by record."""
    table = pd.read_csv(path)
    fitted = table[np.isfinite(table["median"])]
    assert len(fitted) >= 2 and (fitted["resampled"] == "records").all()
    for measure, family in fitted.groupby("measure"):
        family = family.sort_values("state")
        assert family["beta"].nunique() == 1 and family["median"].is_monotonic_increasing, measure