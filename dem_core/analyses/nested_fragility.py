"""Fragility curves of nested damage states fitted together, with their uncertainty drawn by record.

Damage states are nested when exceeding one implies exceeding every milder one (peak theta/alpha of 0.1, 0.3,
0.5, then overturning).  Their curves must not cross, which separate fits do not ensure.  Here the K states share
one dispersion beta and have ordered medians ``median_1 <= ... <= median_K``,

    P_k(exceed | x) = Phi(ln(x / median_k) / beta),

so that ``P_1(x) >= P_2(x) >= ... >= P_K(x)`` at every x (Porter, Kennedy and Bachman 2007, "Creating fragility
functions for performance-based earthquake engineering", Earthquake Spectra 23(2), discuss the crossing of
sequential damage states' fragility functions; one dispersion is the mend taken here).  The K + 1 parameters
maximise the multiple-stripe binomial likelihood (Baker 2015, eq. 11) summed over the states, with
``mu_k = ln median_k`` written as ``mu_1 + sum_{i <= k} exp(d_i)``, so the order holds by construction.

The uncertainty comes from the suite, not from the runs: a run's outcome is fixed by its record and its level,
so the runs of one record are not independent draws.  The bootstrap draws the suite's records again with
replacement, each drawn record with all its stripes, and refits (:func:`fit_states`, ``resample="records"``).
Drawing each stripe's runs on their own (``resample="runs"``, the bootstrap of :func:`.fragility.fit_fragility`)
treats every run as an independent draw and gives bands too narrow for the variability between records.

An IDA-style estimate is given beside it (Baker 2015, eqs. 2-3): each record's own first intensity of
exceedance, the median as their geometric mean and beta as the standard deviation of their logarithms.
"""

from __future__ import annotations

import math

import numpy as np
from scipy import optimize, special

from .fragility import (BOOTSTRAP_SAMPLES, HALF_LOG_TWO_PI, LARGEST_BETA, SMALLEST_BETA, UNMEASURED_BETA, Fragility,
                        fit_lognormal, step_like)

#: what a bootstrap can draw again: the suite's records (every stripe of a drawn record together), or each
#: stripe's runs on its own
RESAMPLING = ("records", "runs")
#: fewer records than this give a median whose record-to-record uncertainty is wide: with a dispersion of 0.4 the
#: standard error of ln(median) is 0.4 / sqrt(n), 9% at 20 records and 20% at 4 (Baker 2015 used 20 to 40)
ADVISED_RECORDS = 20


def _checked(levels, outcomes) -> tuple[np.ndarray, np.ndarray]:
    levels = np.asarray(levels, float)
    outcomes = np.asarray(outcomes, float)
    if outcomes.ndim != 3 or levels.ndim != 1 or outcomes.shape[1] != len(levels):
        raise ValueError(f"outcomes must be (records, levels, states) with one column per level, got {outcomes.shape}"
                         f" for {levels.shape} levels")
    if not np.all(np.isfinite(levels) & (levels > 0.0)):
        raise ValueError("intensity levels must be finite and positive")
    known = outcomes[np.isfinite(outcomes)]
    if np.any((known != 0.0) & (known != 1.0)):
        raise ValueError("outcomes are 1 (exceeded), 0 (not) or nan (the run did not finish)")
    exceeded = np.nan_to_num(outcomes, nan=0.0)
    if np.any(np.diff(exceeded, axis=2) > 0.0):
        raise ValueError("the states must be nested, mildest first: a run that exceeds a state exceeds every milder "
                         "one")
    return levels, outcomes


def counts(outcomes: np.ndarray) -> tuple[np.ndarray, np.ndarray]:
    """``(runs, exceed)``, each (L, K): per level and state, the runs that finished and those that exceeded."""
    finished = np.isfinite(outcomes)
    return finished.sum(axis=0).astype(np.int64), np.nansum(outcomes, axis=0).astype(np.int64)


def _log_likelihood(params, x, n, z):
    """The negated log-likelihood of the stripes' counts ``n``, ``z`` (L, K) at log levels ``x`` (L,), and its
    gradient, for ``params`` = (mu_1, d_2 .. d_K, ln beta)."""
    k = n.shape[1]
    lowest = math.log(SMALLEST_BETA)
    log_beta = params[-1]
    beta = math.exp(max(log_beta, lowest))
    steps = np.exp(params[1:k])
    mu = params[0] + np.concatenate(([0.0], np.cumsum(steps)))
    s = (x[:, None] - mu[None, :]) / beta
    log_p = special.log_ndtr(s)
    log_q = special.log_ndtr(-s)
    value = -np.sum(z * log_p + (n - z) * log_q)
    log_phi = -0.5 * s * s - HALF_LOG_TWO_PI
    d_s = z * np.exp(log_phi - log_p) - (n - z) * np.exp(log_phi - log_q)
    d_mu = -np.sum(d_s, axis=0) / beta  # d(log-likelihood)/d(mu_k)
    gradient = np.empty_like(params)
    gradient[0] = np.sum(d_mu)
    tail = np.cumsum(d_mu[::-1])[::-1]  # sum over the states at and above each one
    gradient[1:k] = tail[1:] * steps
    gradient[-1] = -np.sum(d_s * s) if log_beta > lowest else 0.0
    return value, -gradient


def fit_nested(levels, runs, exceed, start: tuple | None = None) -> tuple[np.ndarray, float, str]:
    """Maximum-likelihood ordered medians and common dispersion of nested states from their counts.

    levels : (L,) intensities; runs, exceed : (L, K) per level and state (mildest state first), each state placing
    a median (some run exceeds it, some does not).  start : ``(medians, beta)`` to start the search from (default:
    each state's own fit, :func:`~.fragility.fit_lognormal`).  Returns ``(medians (K,), beta, note)``; nan medians
    and the reason where the counts place none; UNMEASURED_BETA where they do not measure the dispersion
    (:func:`~.fragility.step_like`)."""
    levels = np.asarray(levels, float)
    n = np.asarray(runs, float)
    z = np.asarray(exceed, float)
    used = np.flatnonzero(n[:, 0] > 0)
    x, n, z = np.log(levels[used]), n[used], z[used]
    k = n.shape[1]
    if start is None:
        separate = [fit_lognormal(levels[used], n[:, s], z[:, s]) for s in range(k)]
        if any(math.isnan(m) for m, _, _ in separate):
            return np.full(k, np.nan), math.nan, next(note for m, _, note in separate if math.isnan(m))
        start = ([m for m, _, _ in separate], float(np.median([b for _, b, _ in separate])))
    start_mu = np.maximum.accumulate(np.log(start[0]))
    initial = np.concatenate(([start_mu[0]], np.log(np.maximum(np.diff(start_mu), 1e-3)), [math.log(start[1])]))
    best = optimize.minimize(_log_likelihood, initial, args=(x, n, z), jac=True, method="BFGS",
                             options={"gtol": 1e-9, "maxiter": 1000})
    params = best.x
    beta = math.exp(max(params[-1], math.log(SMALLEST_BETA)))
    if beta > LARGEST_BETA:
        return np.full(k, np.nan), math.nan, (f"the counts barely rise with the intensity: the best common "
                                              f"dispersion is above {LARGEST_BETA:g} and places no median")
    mu = params[0] + np.concatenate(([0.0], np.cumsum(np.exp(params[1:k]))))
    return np.exp(mu), beta, UNMEASURED_BETA if step_like(x, n, z) else ""


def fit_states(levels, outcomes, samples: int = BOOTSTRAP_SAMPLES, seed: int = 0,
               resample: str = "records") -> list[Fragility]:
    """The nested states' fragilities fitted together (:func:`fit_nested`), with bootstrap bands.

    levels : (L,) intensities.  outcomes : (R, L, K) per record, level and state (mildest first): 1 exceeded, 0 not,
    nan where the run did not finish.  States that no run exceeds, or that every run exceeds, place no median:
    they get no curve and a note, and the others are fitted together.  ``resample`` : "records" (default) or
    "runs" (module docstring); ``samples`` refits, ``seed`` for the draws.  Returns one
    :class:`~.fragility.Fragility` per state, its ``samples`` (median, beta) from the bootstrap."""
    if resample not in RESAMPLING:
        raise ValueError(f"resample must be one of {RESAMPLING}, got {resample!r}")
    levels, outcomes = _checked(levels, outcomes)
    n, z = counts(outcomes)
    placed = [s for s in range(n.shape[1]) if 0 < z[:, s].sum() < n[:, s].sum()]
    medians, beta, note = fit_nested(levels, n[:, placed], z[:, placed]) if placed else (np.array([]), math.nan, "")
    drawn = np.full((samples, len(placed) + 1), np.nan)
    if placed and not math.isnan(beta):
        rng = np.random.default_rng(seed)
        records, stripes = outcomes.shape[:2]
        for i in range(samples):
            if resample == "records":
                again = outcomes[rng.integers(0, records, records)][:, :, placed]
            else:
                again = outcomes[rng.integers(0, records, (records, stripes)), np.arange(stripes)][:, :, placed]
            n_again, z_again = counts(again)
            if np.all((z_again.sum(axis=0) > 0) & (z_again.sum(axis=0) < n_again.sum(axis=0))):
                m, b, _ = fit_nested(levels, n_again, z_again, start=(medians, beta))
                drawn[i, :-1], drawn[i, -1] = m, b
    drawn = drawn[np.all(np.isfinite(drawn), axis=1)]
    fits = []
    for s in range(n.shape[1]):
        if s in placed:
            j = placed.index(s)
            fits.append(Fragility(float(medians[j]), beta, levels, n[:, s], z[:, s], drawn[:, [j, -1]], note,
                                  resampled=resample))
        else:
            missing = ("no run exceeded: the median is above the highest level" if z[:, s].sum() == 0 else
                       "every run exceeded: the median is below the lowest level")
            fits.append(Fragility(math.nan, math.nan, levels, n[:, s], z[:, s], np.empty((0, 2)), missing,
                                  resampled=resample))
    return fits


def ida_estimate(levels, outcomes) -> tuple[float, float, int]:
    """IDA-style median and dispersion of one state from each record's first level of exceedance (Baker 2015,
    eqs. 2-3): ``(median, beta, records that reached it)``.  outcomes : (R, L) 1, 0 or nan per record and level;
    a record that never exceeds is left out (so with such records the median is biased low); nan where fewer than
    two records reached the state."""
    levels = np.asarray(levels, float)
    order = np.argsort(levels)
    hit = np.asarray(outcomes, float)[:, order] == 1.0
    reached = hit.any(axis=1)
    first = np.log(levels[order][np.argmax(hit[reached], axis=1)])
    if len(first) < 2:
        return math.nan, math.nan, int(len(first))
    return float(np.exp(first.mean())), float(first.std(ddof=1)), int(len(first))
