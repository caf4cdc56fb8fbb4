"""Fragility curves by multiple-stripe analysis: a lognormal fitted by maximum likelihood to counts of exceedance.

At each intensity level ``x_j`` (a stripe) ``n_j`` runs, one per record, of which ``z_j`` exceed a damage state.
The fragility is the lognormal distribution function

    P(exceed | x) = Phi(ln(x / median) / beta),

and its median and dispersion ``beta`` maximise the binomial likelihood of the counts,

    sum_j  z_j ln P(x_j) + (n_j - z_j) ln(1 - P(x_j))

(Baker 2015, "Efficient analytical fragility function fitting using dynamic structural analysis", Earthquake
Spectra 31(1), eq. 11).  Its uncertainty comes from a bootstrap over the runs: each stripe's runs drawn again with
replacement (``z_j* ~ Binomial(n_j, z_j / n_j)``) and the fit repeated.
"""

from __future__ import annotations

import math
from dataclasses import dataclass

import numpy as np
from scipy import optimize, special

#: the bootstrap's central interval
BAND_LEVEL = 0.9
BOOTSTRAP_SAMPLES = 1000
#: smallest dispersion fitted: counts that jump from none to all between two stripes are fitted by this step
SMALLEST_BETA = 1e-3
#: largest dispersion fitted: counts that barely rise with the intensity drive the likelihood's maximum to an
#: ever wider lognormal whose median runs off to infinity; such counts place no median
LARGEST_BETA = 10.0
#: largest |ln median| fitted: beyond it the median overflows a float, a fit that never settled
LARGEST_LOG_MEDIAN = 700.0
HALF_LOG_TWO_PI = 0.5 * math.log(2.0 * math.pi)


@dataclass(frozen=True)
class Fragility:
    """One damage state's fitted fragility and what it was fitted to.

    median : intensity at 50% probability of exceedance (the levels' unit); nan if the counts cannot place it
    (no run or every run exceeds); beta : lognormal dispersion; levels, runs, exceed : (L,) the stripes'
    intensities, runs and exceedances; samples : (S, 2) the bootstrap's fits (median, beta), whose BAND_LEVEL
    central intervals are ``median_band`` and ``beta_band``; note : why a fit is missing or degenerate, else
    empty; resampled : what the bootstrap drew again, each stripe's ``"runs"`` or the suite's ``"records"``
    (:mod:`.nested_fragility`)."""

    median: float
    beta: float
    levels: np.ndarray
    runs: np.ndarray
    exceed: np.ndarray
    samples: np.ndarray
    note: str = ""
    resampled: str = "runs"

    @property
    def median_band(self) -> tuple[float, float]:
        low, high = _central(self.samples[:, 0])
        return float(low), float(high)

    @property
    def beta_band(self) -> tuple[float, float]:
        low, high = _central(self.samples[:, 1])
        return float(low), float(high)

    def probability(self, x) -> np.ndarray:
        """P(exceed | x) of the fit at intensities ``x`` (any shape)."""
        return _probability(np.asarray(x, float), self.median, self.beta)

    def probability_band(self, x) -> tuple[np.ndarray, np.ndarray]:
        """The bootstrap's BAND_LEVEL pointwise interval of P(exceed | x): ``(low, high)``, each shaped as ``x``."""
        x = np.asarray(x, float)
        return _central(_probability(x[..., None], self.samples[:, 0], self.samples[:, 1]))


def _central(values):
    """The BAND_LEVEL central interval of ``values`` along their last axis: ``(low, high)``; nan where there are
    none."""
    if values.shape[-1] == 0:
        nan = np.full(values.shape[:-1], np.nan)
        return nan, nan
    tail = 50.0 * (1.0 - BAND_LEVEL)
    return np.percentile(values, tail, axis=-1), np.percentile(values, 100.0 - tail, axis=-1)


def _probability(x, median, beta):
    with np.errstate(divide="ignore", invalid="ignore"):
        return special.ndtr(np.log(x / median) / beta)


def _counts(levels, runs, exceed) -> tuple[np.ndarray, np.ndarray, np.ndarray]:
    levels = np.asarray(levels, float)
    runs = np.asarray(runs, np.int64)
    exceed = np.asarray(exceed, np.int64)
    if not (levels.ndim == runs.ndim == exceed.ndim == 1 and len(levels) == len(runs) == len(exceed)):
        raise ValueError(f"levels, runs and exceed must be three 1-D arrays of one length, got shapes "
                         f"{levels.shape}, {runs.shape}, {exceed.shape}")
    if not np.all(np.isfinite(levels) & (levels > 0.0)):
        raise ValueError(f"intensity levels must be finite and positive, got {levels[~(levels > 0.0)][:3]}")
    if np.any(runs < 0) or np.any(exceed < 0) or np.any(exceed > runs):
        raise ValueError("each stripe needs 0 <= exceed <= runs")
    return levels, runs, exceed


#: the note of a fit whose counts do not measure its dispersion (:func:`step_like`)
UNMEASURED_BETA = ("no state has two stripes between none and all: a step fits the counts at least as well as any "
                   "lognormal, and beta is not measured (finer stripes or more records measure it)")


def _stripes(x, n, z) -> tuple[np.ndarray, np.ndarray, np.ndarray]:
    """``(x, n, z)``: the counts ``n``, ``z`` ((L,) or (L, K) states) at log levels ``x`` (L,) with the stripes
    whose log levels are equal rounded to 9 decimals taken together, in rising order of level (S stripes).  Runs at
    one level are one binomial draw, so the likelihood is the same; a test of the counts' shape (none, then all) is
    then the same whatever order tied stripes came in."""
    x = np.asarray(x, float)
    _, first, inverse = np.unique(np.round(x, 9), return_index=True, return_inverse=True)
    stripes = (len(first),) + np.shape(n)[1:]
    runs, exceeded = np.zeros(stripes), np.zeros(stripes)
    np.add.at(runs, inverse, n)
    np.add.at(exceeded, inverse, z)
    return x[first], runs, exceeded


def step_like(x, n, z) -> bool:
    """Whether the counts ``n``, ``z`` ((L,) or (L, K) states) at log levels ``x`` (L,) rise in every state from
    none to all with at most one stripe between (:func:`_stripes`: tied levels taken together): each state's
    median can then sit where that stripe's fraction puts it for any beta, and the likelihood's supremum is
    approached as beta -> 0."""
    x, runs, exceeded = _stripes(x, n, z)
    runs, exceeded = runs.reshape(len(x), -1), exceeded.reshape(len(x), -1)
    for n_s, z_s in zip(runs.T, exceeded.T):
        placed = n_s > 0
        fraction = z_s[placed] / n_s[placed]
        if np.sum((fraction > 0) & (fraction < 1)) > 1 or np.any(np.diff(fraction) < 0):
            return False
    return True


def fit_lognormal(levels, runs, exceed) -> tuple[float, float, str]:
    """Maximum-likelihood median and dispersion of a lognormal fragility to the stripes' counts.

    levels, runs, exceed : (L,) intensity (> 0), runs and exceedances per stripe.  Returns ``(median, beta,
    note)``: nan, nan and the reason where the counts place no median (no exceedance at all, exceedance in
    every run, or counts so flat that the likelihood grows as beta passes LARGEST_BETA); where the counts jump
    from none to all between two stripes (the likelihood grows as beta -> 0), SMALLEST_BETA and the median midway
    between them in log intensity, with the note saying so; UNMEASURED_BETA where one stripe lies between
    (:func:`step_like`)."""
    levels, runs, exceed = _counts(levels, runs, exceed)
    x, n, z = _stripes(np.log(levels), runs, exceed)
    x, n, z = x[n > 0], n[n > 0], z[n > 0]
    if z.sum() == 0:
        return math.nan, math.nan, "no run exceeded: the median is above the highest level"
    if z.sum() == n.sum():
        return math.nan, math.nan, "every run exceeded: the median is below the lowest level"
    below = z == 0
    above = z == n
    if np.all(below | above) and not np.any(above[:-1] & below[1:]):  # none, then all: beta -> 0
        last_none = np.flatnonzero(below)[-1] if below.any() else None
        first_all = np.flatnonzero(above)[0]
        mu = x[first_all] if last_none is None else 0.5 * (x[last_none] + x[first_all])
        return math.exp(mu), SMALLEST_BETA, "the counts jump from none to all between two stripes"
    lowest = math.log(SMALLEST_BETA)

    def loss(params):
        mu, log_beta = params
        beta = math.exp(max(log_beta, lowest))
        s = (x - mu) / beta
        log_p = special.log_ndtr(s)
        log_q = special.log_ndtr(-s)
        value = -np.sum(z * log_p + (n - z) * log_q)
        # d/ds of the log-likelihood per stripe: z phi/Phi - (n - z) phi/(1 - Phi)
        log_phi = -0.5 * s * s - HALF_LOG_TWO_PI
        ratio_p = np.exp(log_phi - log_p)
        ratio_q = np.exp(log_phi - log_q)
        d_s = z * ratio_p - (n - z) * ratio_q
        grad_mu = np.sum(d_s) / beta
        grad_log_beta = np.sum(d_s * s) if log_beta > lowest else 0.0
        return value, np.array([grad_mu, grad_log_beta])

    fraction = z / n
    middle = float(np.interp(0.5, np.maximum.accumulate(fraction) + 1e-9 * np.arange(len(fraction)), x))
    spread = max(float(np.std(x)), 0.1)
    best = optimize.minimize(loss, np.array([middle, math.log(0.5 * spread + 0.1)]), jac=True, method="BFGS",
                             options={"gtol": 1e-9, "maxiter": 500})
    mu, log_beta = best.x
    if not (log_beta <= math.log(LARGEST_BETA) and abs(mu) < LARGEST_LOG_MEDIAN):
        return math.nan, math.nan, (f"the counts barely rise with the intensity: the best lognormal is wider than "
                                    f"beta = {LARGEST_BETA:g} and places no median")
    return math.exp(mu), math.exp(max(log_beta, lowest)), UNMEASURED_BETA if step_like(x, n, z) else ""


def fit_fragility(levels, runs, exceed, samples: int = BOOTSTRAP_SAMPLES, seed: int = 0) -> Fragility:
    """:func:`fit_lognormal` with the bootstrap's BAND_LEVEL intervals of the median and dispersion, from
    ``samples`` refits to each stripe's runs drawn again with replacement (``seed`` for the draws).  Resamples
    whose counts place no median are left out of the intervals."""
    levels, runs, exceed = _counts(levels, runs, exceed)
    median, beta, note = fit_lognormal(levels, runs, exceed)
    if math.isnan(median):
        return Fragility(median, beta, levels, runs, exceed, np.empty((0, 2)), note)
    rng = np.random.default_rng(seed)
    fraction = np.divide(exceed, runs, out=np.zeros(len(runs)), where=runs > 0)
    found = []
    for _ in range(samples):
        drawn = rng.binomial(runs, fraction)
        m, b, _ = fit_lognormal(levels, runs, drawn)
        if not math.isnan(m):
            found.append((m, b))
    return Fragility(median, beta, levels, runs, exceed, np.array(found).reshape(-1, 2), note)


#: what the bootstrap drew again, in a figure's words
RESAMPLED_WORDS = {"runs": "each stripe's runs drawn again", "records": "the suite's records drawn again"}


def fragility_figure(fits: dict, intensity: str = "PGA (m/s$^2$)", title: str = "Fragility",
                     median_text=lambda median: f"{median:.3g}", ax=None):
    """Figure of the probability of exceedance against the intensity measure: per damage state (``fits``:
    {label: :class:`Fragility`}) the fitted lognormal as a line, its bootstrap band shaded, and the stripes'
    observed fractions as points; a state without a fit shows its points and its note in the legend, and the
    legend says what the bands and the points are.  median_text : a median in words (its units).  ax : the
    axes to draw in (default: a new figure's)."""
    import matplotlib

    matplotlib.use("Agg")
    import matplotlib.pyplot as plt
    from matplotlib.patches import Patch

    fig, ax = plt.subplots(figsize=(7.5, 4.8)) if ax is None else (ax.figure, ax)
    colours = plt.get_cmap("viridis")(np.linspace(0.0, 0.85, max(len(fits), 1)))
    resampled = {fit.resampled for fit in fits.values() if fit.samples.size}
    for colour, (label, fit) in zip(colours, fits.items()):
        used = fit.runs > 0
        ax.plot(fit.levels[used], fit.exceed[used] / fit.runs[used], "o", color=colour, markersize=3.5, alpha=0.7)
        if math.isnan(fit.median):
            ax.plot([], [], "o", color=colour, label=f"{label}: {fit.note}")
            continue
        x = np.geomspace(fit.levels[used].min(), fit.levels[used].max(), 200)
        if fit.samples.size:
            low, high = fit.probability_band(x)
            ax.fill_between(x, low, high, color=colour, alpha=0.2, linewidth=0)
        ax.plot(x, fit.probability(x), color=colour,
                label=f"{label}: median {median_text(fit.median)}, beta {fit.beta:.2f}")
    ax.plot([], [], "o", color="grey", markersize=3.5, label="points: the fraction of a stripe's runs exceeding")
    handles, _ = ax.get_legend_handles_labels()
    handles += [Patch(color="grey", alpha=0.2,
                      label=f"shaded: {BAND_LEVEL:.0%} bootstrap band, {RESAMPLED_WORDS[kind]}")
                for kind in sorted(resampled)]
    ax.set(xlabel=intensity, ylabel="probability of exceedance", ylim=(-0.02, 1.02))
    ax.set_title(title, fontsize=9)
    ax.grid(True, alpha=0.3)
    ax.legend(handles=handles, fontsize=7, loc="lower right")
    fig.tight_layout()
    return fig
