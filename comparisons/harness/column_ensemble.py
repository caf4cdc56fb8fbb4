"""The 8-drum column's ensemble: Moreau-Jean's convergence in its step, and its agreement with the explicit core
and pymunk, on many record runs instead of one.

A column under a record is chaotic: one run (the report's case ``column_record``) may land on either side of a
jump in its response, so a step is judged on an ensemble.  Members: the column of :func:`dem_core.scenes.column`
(8 drums, 1 x 6 m) under each bundled record's strong-motion window
(:func:`comparisons.cases.strong_motion.strong_motion`) at :data:`SCALES` times its rocking threshold
g tan(alpha), for :data:`DURATION` s.  Each member runs in every configuration of :data:`RUNS`.

Per pair of configurations (:data:`PAIRS`), :func:`summarise_pairs` gives the typical member difference of the
top drum's peak rotation: the median of ``|log(peak_a / peak_b)|`` over the members that stand in both and rock in
the second (peak above the ensembles' floor of alpha/30), with a 90% bootstrap interval of that median (the
members resampled: the variability lives in the records and amplitudes), its 90th percentile, and the share of
members on whose overturning the two agree.  :func:`summarise_runs` gives each configuration's median time of a
run.  There is no exact answer for a column: the ensemble shows whether Moreau-Jean's step has converged on what
studies measure (its 1e-3 s against 2.5e-4 s), and how close the integrators and pymunk come to each other.
"""

import warnings

import numpy as np
import pandas as pd

import adapters
from comparisons.cases.strong_motion import strong_motion
from comparisons.harness.ensembles import ROCKING_FLOOR
from comparisons.harness.progress import terminal_bar
from dem_core import records, scenes

DRUMS = 8
#: the column's overall width and height (m): it starts to rock at g width / height
WIDTH, HEIGHT = 1.0, 6.0
#: multiples of the rocking threshold: 13 from 1.2 to 2.4, where the column rocks without certainly overturning;
#: the members are chaotic and their differences heavy-tailed, so many of them narrow the median's interval
SCALES = tuple(np.round(np.arange(1.2, 2.45, 0.1), 2))
QUICK_SCALES = (1.6, 2.2)
#: s of each record's strong motion
DURATION = 20.0
#: (label, engine of adapters.simulate, options)
RUNS = (
    ("dem-moreau 1e-3 s", "dem", {"integrator": "moreau", "dt": 1e-3}),
    ("dem-moreau 5e-4 s", "dem", {"integrator": "moreau", "dt": 5e-4}),
    ("dem-moreau 2.5e-4 s", "dem", {"integrator": "moreau", "dt": 2.5e-4}),
    ("dem automatic step", "dem", {"integrator": "explicit"}),
    ("pymunk 1e-3 s", "pymunk", {"dt": 1e-3}),
)
#: the pairs compared, Moreau-Jean's convergence in its step first
PAIRS = (("dem-moreau 1e-3 s", "dem-moreau 2.5e-4 s"), ("dem-moreau 5e-4 s", "dem-moreau 2.5e-4 s"),
         ("dem-moreau 1e-3 s", "dem automatic step"), ("dem-moreau 2.5e-4 s", "dem automatic step"),
         ("pymunk 1e-3 s", "dem automatic step"))
#: resamples of the bootstrap interval of the typical member difference
BOOTSTRAP_SAMPLES = 2000


def members(scales=SCALES) -> list:
    """``[(record, scale)]``: every bundled record at every scale."""
    return [(name, float(scale)) for name in records.BUNDLED for scale in scales]


def run_column_ensemble(quick: bool = False, progress: bool = True, scales=None,
                        duration: float = DURATION) -> pd.DataFrame:
    """Every member in every configuration: one row per run with ``record, scale, pga (m/s^2), run (label),
    peak (rad, the top drum's peak |theta| up to an overturn), overturned, wall_time_s, steps``.  ``scales``
    (default :data:`SCALES`, or :data:`QUICK_SCALES` where ``quick``)."""
    column = scenes.column(DRUMS, WIDTH, HEIGHT)
    threshold = column.gravity * WIDTH / HEIGHT
    chosen = members((QUICK_SCALES if quick else SCALES) if scales is None else scales)
    rows = []
    for name, scale in terminal_bar(chosen, desc="column ensemble", progress=progress):
        motion = strong_motion(name, scale * threshold)
        for label, engine, options in RUNS:
            with warnings.catch_warnings():
                warnings.simplefilter("ignore")
                result = adapters.simulate(column, motion, duration, engine=engine, output_dt=0.005, **options)
            rows.append({"record": name, "scale": scale, "pga": scale * threshold, "run": label,
                         "peak": float(np.nanmax(np.abs(result.theta[:, -1]))),
                         "overturned": bool(np.isfinite(result.time_of_overturn)),
                         "wall_time_s": float(result.info["run_time_s"]), "steps": int(result.info["steps"])})
    return pd.DataFrame(rows)


def summarise_runs(table: pd.DataFrame) -> pd.DataFrame:
    """Per configuration: ``run, members, overturned, median_wall_time_s, ns_per_block_step, time_vs_pymunk``."""
    pymunk = table[table.run == "pymunk 1e-3 s"].wall_time_s.median()
    out = []
    for label, _, _ in RUNS:
        mine = table[table.run == label]
        if len(mine):
            out.append({"run": label, "members": len(mine), "overturned": int(mine.overturned.sum()),
                        "median_wall_time_s": mine.wall_time_s.median(),
                        "ns_per_block_step": 1e9 * (mine.wall_time_s / mine.steps / DRUMS).median(),
                        "time_vs_pymunk": mine.wall_time_s.median() / pymunk})
    return pd.DataFrame(out)


def summarise_pairs(table: pd.DataFrame) -> pd.DataFrame:
    """Per pair of :data:`PAIRS`: ``run, against, typical_difference`` (median |log peak ratio|),
    ``interval_low, interval_high`` (its 90% bootstrap interval over members), ``p90_difference, compared``
    (members standing in both and rocking in the second), ``overturn_agreement``."""
    floor = ROCKING_FLOOR * np.arctan(WIDTH / HEIGHT)
    wide = table.pivot_table(index=["record", "scale"], columns="run", values=["peak", "overturned"],
                             aggfunc="first")
    out = []
    for a, b in PAIRS:
        if a not in wide["peak"] or b not in wide["peak"]:
            continue
        over_a, over_b = wide["overturned"][a].astype(bool), wide["overturned"][b].astype(bool)
        standing = ~over_a & ~over_b & (wide["peak"][b] >= floor)
        logs = np.abs(np.log(wide["peak"][a][standing] / wide["peak"][b][standing])).to_numpy()
        low = high = median = p90 = np.nan
        if len(logs):
            draws = np.random.default_rng(0).choice(logs, (BOOTSTRAP_SAMPLES, len(logs)))
            low, high = np.percentile(np.median(draws, axis=1), [5.0, 95.0])
            median, p90 = np.median(logs), np.percentile(logs, 90)
        out.append({"run": a, "against": b, "typical_difference": median, "interval_low": low,
                    "interval_high": high, "p90_difference": p90, "compared": len(logs),
                    "overturn_agreement": float(np.mean(over_a == over_b))})
    return pd.DataFrame(out)
