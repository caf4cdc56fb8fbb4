"""The scoreboard at the top of the report: one row per engine, computed from the tables the report already has.

* **right**: the verdict rows (cases, ensembles, spectra) on which the engine is right, out of **judged**: the
  rows that have a reference and on which the engine ran (a case without a reference counts in neither);
* **fastest**: the verdict rows on which it is the fastest of the right engines;
* **rocking_median**, **sliding_median**: the median |peak error| of the rocking and of the sliding ensembles
  at the engine's usual step, over the members whose reference does not overturn (as in the ensemble tables);
* **overturn_agreement**: the share of the overturning spectra's points, at the engine's usual step, where the
  engine overturns exactly when the rocking equation does (out of **overturn_points**);
* **median_wall_time_s**: the median wall time of its case runs at its usual step and default settings.
"""

from collections.abc import Mapping

import numpy as np
import pandas as pd

from comparisons.cases.case import ENGINES
from comparisons.harness.engines import USUAL_STEP, step_label

COLUMNS = ("engine", "right", "judged", "fastest", "rocking_median", "sliding_median", "overturn_agreement",
           "overturn_points", "median_wall_time_s", "case_runs")


def usual_steps(engines=ENGINES) -> dict:
    """``{engine: label of its usual step}`` (``auto/1``, ``0.001``)."""
    return {e: step_label(e, USUAL_STEP[e]) for e in engines}


def _at_usual(table: pd.DataFrame, usual: Mapping) -> pd.DataFrame:
    """The rows of ``table`` at each engine's usual step and (where the table has settings) default settings."""
    if table is None or table.empty:
        return pd.DataFrame(columns=[] if table is None else table.columns)
    keep = np.array([usual.get(e) == s for e, s in zip(table.engine, table.step, strict=True)], dtype=bool)
    if "settings" in table:
        keep &= (table.settings == "{}").to_numpy()
    return table[keep]


def _ensemble_median(rows: pd.DataFrame) -> float:
    """Median |peak error| over the members whose reference does not overturn (NaN if a judged run stopped)."""
    judged = rows[~rows.reference_overturned.astype(bool)]
    errors = np.abs(judged.error.to_numpy(dtype=float))
    return float(np.median(errors)) if len(errors) else np.nan


def scoreboard(verdicts: pd.DataFrame, ensembles: pd.DataFrame | None, spectra: pd.DataFrame | None,
               results: pd.DataFrame, *, ensemble_kinds: Mapping, engines=None,
               usual: Mapping | None = None) -> pd.DataFrame:
    """One row per engine with the columns of :data:`COLUMNS` (shares as fractions, times in s).

    verdicts : one row per case, ensemble and spectrum: ``has_reference`` (bool), ``engines`` (those that ran
        it), ``right`` (the engines that are right) and ``fastest`` (the fastest right engine, or None).
    ensembles, spectra, results : the report's tidy tables (``ensembles.csv``, ``spectra.csv``, ``results.csv``).
    ensemble_kinds : ``{ensemble name: "rocking" or "sliding"}``.
    engines : the rows, in order (default: every engine in ``results``, in :data:`ENGINES` order first).
    usual : ``{engine: usual step label}`` (default :func:`usual_steps`).
    """
    if engines is None:
        seen = set(results.engine)
        engines = [e for e in ENGINES if e in seen] + sorted(seen - set(ENGINES))
    usual = usual_steps([e for e in engines if e in USUAL_STEP]) if usual is None else usual
    referenced = verdicts[verdicts.has_reference.astype(bool)]
    ens = _at_usual(ensembles, usual)
    spec = _at_usual(spectra, usual)
    runs = _at_usual(results, usual)
    if "status" in runs:
        runs = runs[runs.status == "ok"]
    runs = runs.drop_duplicates([c for c in ("case", "engine", "step", "settings") if c in runs])
    out = []
    for engine in engines:
        row = {"engine": engine,
               "right": int(sum(engine in r for r in referenced.right)),
               "judged": int(sum(engine in e for e in referenced.engines)),
               "fastest": int(sum(f == engine for f in referenced.fastest))}
        for kind in ("rocking", "sliding"):
            if len(ens):
                mine = ens[(ens.engine == engine) & ens.ensemble.map(lambda n, k=kind: ensemble_kinds.get(n) == k)]
            else:
                mine = ens
            row[f"{kind}_median"] = _ensemble_median(mine) if len(mine) else np.nan
        points = spec[spec.engine == engine] if len(spec) else spec
        row["overturn_points"] = len(points)
        row["overturn_agreement"] = (float(np.mean(points.overturned.astype(bool)
                                                   == points.reference_overturned.astype(bool)))
                                     if len(points) else np.nan)
        mine = runs[runs.engine == engine] if len(runs) else runs
        row["case_runs"] = len(mine)
        row["median_wall_time_s"] = float(mine.wall_time_s.median()) if len(mine) else np.nan
        out.append(row)
    return pd.DataFrame(out, columns=list(COLUMNS))
