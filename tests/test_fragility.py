"""Lognormal fragility fits to counts of exceedance (multiple-stripe analysis, Baker 2015) on synthetic counts
drawn from a known lognormal."""

import math

import numpy as np
import pytest

from dem_core.analyses import fragility

LEVELS = np.linspace(0.5, 8.0, 12)
TRUE_MEDIAN, TRUE_BETA = 3.0, 0.4


def drawn(runs, seed):
    """Exceedance counts at LEVELS of ``runs`` runs a stripe from the true lognormal."""
    rng = np.random.default_rng(seed)
    return rng.binomial(runs, fragility._probability(LEVELS, TRUE_MEDIAN, TRUE_BETA))


def log_likelihood(median, beta, runs, exceed):
    p = fragility._probability(LEVELS, median, beta)
    return float(np.sum(exceed * np.log(p) + (runs - exceed) * np.log1p(-p)))


def test_the_fit_converges_to_the_true_lognormal_as_the_runs_grow():
    """With 10^5 runs a stripe the sampling error of the median is about 0.1%, of beta 0.2%: within 1%."""
    runs = np.full(LEVELS.size, 100_000)
    median, beta, note = fragility.fit_lognormal(LEVELS, runs, drawn(runs, 5))
    assert median == pytest.approx(TRUE_MEDIAN, rel=0.01) and beta == pytest.approx(TRUE_BETA, rel=0.01)
    assert note == ""


def test_the_fit_maximises_the_likelihood():
    runs = np.full(LEVELS.size, 40)
    exceed = drawn(runs, 7)
    median, beta, _ = fragility.fit_lognormal(LEVELS, runs, exceed)
    best = log_likelihood(median, beta, runs, exceed)
    for dm, db in ((1.01, 1.0), (0.99, 1.0), (1.0, 1.02), (1.0, 0.98)):
        assert log_likelihood(median * dm, beta * db, runs, exceed) < best


def test_the_bootstrap_band_covers_the_true_lognormal_about_as_often_as_its_level():
    """Twenty synthetic suites of 40 runs a stripe: the 90% bands hold the true median and beta in 18 of 20 on
    average; fewer than 15 has a probability of about 1% (binomial, 20 trials at 0.9)."""
    runs = np.full(LEVELS.size, 40)
    covered = np.zeros(2, int)
    for seed in range(20):
        fit = fragility.fit_fragility(LEVELS, runs, drawn(runs, 100 + seed), samples=200, seed=seed)
        covered += [fit.median_band[0] <= TRUE_MEDIAN <= fit.median_band[1],
                    fit.beta_band[0] <= TRUE_BETA <= fit.beta_band[1]]
    assert np.all(covered >= 15), covered


def test_the_probability_band_holds_the_fitted_curve():
    runs = np.full(LEVELS.size, 40)
    fit = fragility.fit_fragility(LEVELS, runs, drawn(runs, 11), samples=200)
    x = np.linspace(0.5, 8.0, 50)
    low, high = fit.probability_band(x)
    curve = fit.probability(x)
    assert np.all(low <= curve + 1e-12) and np.all(curve <= high + 1e-12)
    assert np.all(np.diff(curve) > 0.0) and curve[0] < 0.05 and curve[-1] > 0.95


def test_counts_that_jump_from_none_to_all_are_fitted_by_a_step_between_the_two_stripes():
    runs = np.full(LEVELS.size, 4)
    exceed = np.where(LEVELS > 4.0, 4, 0)
    median, beta, note = fragility.fit_lognormal(LEVELS, runs, exceed)
    below, above = LEVELS[LEVELS <= 4.0][-1], LEVELS[LEVELS > 4.0][0]
    assert median == pytest.approx(math.sqrt(below * above)) and beta == fragility.SMALLEST_BETA
    assert "none to all" in note


def test_runs_of_one_level_are_one_stripe_whatever_order_they_come_in():
    """One run a level, as the intensity measures' fits take them: of two runs at 4.9, one exceeded.  That level is
    a stripe of 1 in 2, between none (2.5) and all (7.4): a lognormal with a fitted median near 4.9 and no measured
    beta, the fit of the same counts given as one stripe, whichever of the two runs comes first (taken apart in
    the order none, all, they would read as a jump from none to all between two stripes)."""
    merged = fragility.fit_lognormal([2.5, 4.9, 7.4], [1, 2, 1], [0, 1, 1])
    assert merged[2] == fragility.UNMEASURED_BETA and merged[0] == pytest.approx(4.9, rel=0.05)
    for exceeded in ([0, 1, 0, 1], [0, 0, 1, 1]):
        assert fragility.fit_lognormal([2.5, 4.9, 4.9, 7.4], [1, 1, 1, 1], exceeded) == merged


@pytest.mark.parametrize("exceed, words", [(0, "no run exceeded"), (4, "every run exceeded")])
def test_counts_that_place_no_median_give_none_and_say_why(exceed, words):
    runs = np.full(LEVELS.size, 4)
    fit = fragility.fit_fragility(LEVELS, runs, np.full(LEVELS.size, exceed))
    assert math.isnan(fit.median) and math.isnan(fit.beta) and words in fit.note


def test_counts_that_do_not_rise_with_the_intensity_place_no_median():
    """One run in four exceeds at every stripe: the likelihood grows without bound as the lognormal widens and its
    median runs off, so no median is fitted."""
    runs = np.full(LEVELS.size, 4)
    median, beta, note = fragility.fit_lognormal(LEVELS, runs, np.ones(LEVELS.size, int))
    assert math.isnan(median) and math.isnan(beta) and "barely rise" in note


@pytest.mark.parametrize("levels, runs, exceed, words", [
    ([1.0, -2.0], [4, 4], [0, 1], "positive"),
    ([1.0, 2.0], [4, 4], [0, 5], "exceed <= runs"),
    ([1.0, 2.0], [4, 4, 4], [0, 1, 2], "one length"),
])
def test_bad_counts_are_refused_naming_the_fault(levels, runs, exceed, words):
    with pytest.raises(ValueError, match=words):
        fragility.fit_lognormal(levels, runs, exceed)


def test_the_figure_draws_each_fit_and_the_observed_fractions():
    """One fitted curve per state over the stripes' range, its points the observed fractions; a state with no
    fit draws its points and says why in the legend."""
    import matplotlib.pyplot as plt

    runs = np.full(LEVELS.size, 40)
    fit = fragility.fit_fragility(LEVELS, runs, drawn(runs, 13), samples=50)
    none = fragility.fit_fragility(LEVELS, runs, np.zeros(LEVELS.size, int), samples=50)
    fig = fragility.fragility_figure({"0.5": fit, "1.0": none})
    ax = fig.axes[0]
    curves = [line for line in ax.lines if line.get_linestyle() == "-"]
    points = [line for line in ax.lines if line.get_marker() == "o" and len(line.get_xdata())]
    assert len(curves) == 1
    np.testing.assert_allclose(curves[0].get_ydata(), fit.probability(curves[0].get_xdata()))
    x = curves[0].get_xdata()
    assert x[0] == pytest.approx(LEVELS[0]) and x[-1] == pytest.approx(LEVELS[-1])
    np.testing.assert_allclose(points[0].get_ydata(), fit.exceed / runs)
    np.testing.assert_allclose(points[1].get_ydata(), 0.0)
    assert any("no run exceeded" in text.get_text() for text in ax.get_legend().get_texts())
    plt.close(fig)
