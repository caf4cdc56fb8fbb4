"""What the report concludes: per case, the engines that are right and the fastest of them; per
ensemble and spectrum, the same on their statistics.

An engine is right on a case when one of its runs comes within the case's verdict level on the
primary measure (:meth:`comparisons.cases.case.Case.verdict_level`: the case's accuracy, or the
reference's uncertainty where that is larger) and agrees on every mismatch measure.  Errors below
the exact floor (:func:`comparisons.cases.case.exact_floor`) are reported as exact and never ranked
against each other.
"""

import numpy as np
import pandas as pd

from comparisons.cases.case import exact_floor, metric_kind
from comparisons.harness.engines import USUAL_STEP, step_label
from comparisons.report.glossary import METRICS

ACCURACY_LEVELS = (0.10, 0.03, 0.01)


def describe(error: float, metric: str) -> str:
    """An error as the page prints it: ``1.2%``, ``2.4e-04 m``, ``exact (below 1e-06)``, ``yes``/``no``."""
    if not np.isfinite(error):
        return "no result"
    kind = metric_kind(metric)
    if kind == "mismatch":
        return "disagrees" if error else "agrees"
    floor = exact_floor(metric)
    if abs(error) < floor:
        return f"exact (below {floor:g})"
    if kind == "absolute":
        unit = metric.rsplit("_", 1)[-1]
        return f"{abs(error):.2g} {unit}"
    return f"{100 * abs(error):.2g}%"


def describe_band(band: float, metric: str) -> str:
    """A band as the page prints it: ``1.5%``, ``0.001 m``, ``must agree``."""
    kind = metric_kind(metric)
    if kind == "mismatch":
        return "must agree"
    if kind == "absolute":
        return f"{band:.2g} {metric.rsplit('_', 1)[-1]}"
    return f"{100 * band:.2g}%"


def primary_metric(case, table) -> str:
    if case.primary:
        return case.primary
    if case.by_consensus:
        return "peak_rotation"
    metrics = table.loc[(table.case == case.name) & (table.metric != "none"), "metric"].unique()
    return metrics[0] if len(metrics) else "none"


def observed_order(dts, errors) -> float:
    """Slope of log|error| against log dt (NaN with fewer than two errors above the exact floor)."""
    dts, errors = np.asarray(dts, float), np.abs(np.asarray(errors, float))
    keep = np.isfinite(errors) & (errors > 0)
    if keep.sum() < 2 or np.ptp(np.log(dts[keep])) == 0:
        return float("nan")
    return float(np.polyfit(np.log(dts[keep]), np.log(errors[keep]), 1)[0])


def _runs(table, case):
    """One row per ok run of the case: its primary error, whether it is right, and its wall time."""
    metric = primary_metric(case, table)
    rows = table[(table.case == case.name) & (table.status == "ok")]
    primary = rows[rows.metric == metric].copy()
    mismatch = rows[rows.metric.map(metric_kind) == "mismatch"]
    bad = mismatch[mismatch.error != 0].groupby(["engine", "step", "settings"]).size()
    keys = list(zip(primary.engine, primary.step, primary.settings, strict=True))
    agrees = np.array([key not in bad.index for key in keys], dtype=bool)
    level = case.verdict_level(metric)
    if case.by_consensus:  # no consensus (NaN uncertainty): no level, so never right
        level = np.maximum(level, primary.reference_uncertainty.to_numpy(dtype=float))
    primary["right"] = (primary.error.abs() <= np.maximum(level, exact_floor(metric))) & agrees
    primary["level"] = level
    return metric, primary


def case_summary(table, case) -> pd.DataFrame:
    """Per engine, on the primary measure: smallest error (step, run time), the fastest run within each
    accuracy level, the observed order in dt, the error at the usual step against its band."""
    metric, runs = _runs(table, case)
    out = []
    for engine, mine in runs.groupby("engine", sort=False):
        plain = mine[mine.settings == "{}"]
        finite = mine[np.isfinite(mine.error)]
        entry = {"engine": engine, "metric": metric}
        if len(finite):
            best = finite.loc[finite.error.abs().idxmin()]
            entry.update(best_error=describe(best.error, metric), best_step=best.step, best_wall_s=best.wall_time_s)
        relative = metric_kind(metric) == "relative"
        for level in ACCURACY_LEVELS:
            within = mine[mine.error.abs() <= level] if relative else mine.iloc[0:0]
            entry[f"fastest_within_{level * 100:.0f}pct"] = within.wall_time_s.min() if len(within) else np.nan
        floor = exact_floor(metric)
        entry["order"] = observed_order(plain["dt"], np.where(plain.error.abs() < floor, np.nan, plain.error))
        usual = mine[(mine.step == step_label(engine, USUAL_STEP[engine])) & (mine.settings == "{}")]
        entry["usual_error"] = describe(usual.error.iloc[0], metric) if len(usual) else "not run"
        band = case.bands.get(metric, {}).get(engine)
        entry["band"] = "none declared" if band is None else describe_band(band, metric)
        if band is not None and len(usual):
            entry["within_band"] = "yes" if abs(usual.error.iloc[0]) <= band else "NO"
        out.append(entry)
    return pd.DataFrame(out)


def _fastest_right(runs):
    right = runs[runs.right]
    return right.loc[right.wall_time_s.idxmin()] if len(right) else None


def missing_consensus(table, case, metric) -> dict:
    """``{engine: why}`` for each engine of a consensus case that no consensus judges on ``metric`` (empty
    for a case with a closed-form reference, or where every engine that ran has a consensus)."""
    if not case.by_consensus:
        return {}
    rows = table[(table.case == case.name) & (table.metric == metric)]
    missing = {}
    for engine, mine in rows.groupby("engine", sort=False):
        reasons = {r for r in mine.get("no_reference", pd.Series(dtype=object)).dropna() if r}
        uncertain = mine.reference_uncertainty.to_numpy(dtype=float) if "reference_uncertainty" in mine else []
        if reasons or not np.isfinite(uncertain).any():
            missing[engine] = "; ".join(sorted(reasons)) or "no consensus"
    return missing


def case_verdict(table, case) -> dict:
    """``{"reference", "short_reference", "has_reference", "right", "fastest", "text"}``: the reference (in
    full and in a few words), whether one exists, the engines that are right, the fastest right run, and the
    whole verdict as a sentence.

    A consensus case has a reference only where every engine that ran is judged by one: where the consensus
    cannot be formed for some engine (too few other engines converged, they disagree about overturning or
    spread too far), the case has no reference, and no engine is called right or fastest on it."""
    metric, runs = _runs(table, case)
    level = case.verdict_level(metric)
    if case.by_consensus:
        missing = missing_consensus(table, case, metric)
        finite = runs[np.isfinite(runs.error)]
        if missing or not len(finite):
            why = "; ".join(f"{e}: {r}" for e, r in missing.items()) or "no engine converged"
            text = f"No reference: the consensus cannot be formed ({why}). No engine is ranked."
            if len(finite):
                text += (" The errors shown below are against the consensus of the engines that converged, where "
                         "one formed, for information only.")
            return {"reference": "none", "short_reference": "no reference", "has_reference": False, "right": [],
                    "fastest": None, "text": text}
        some = finite.iloc[0]
        reference = (f"consensus of the converged engines, {some.reference:.3g} rad +-{some.reference_uncertainty:.0%} "
                     f"when judging {some.engine} (from {some.reference_members})")
        spread = finite.drop_duplicates("engine").reference_uncertainty
        low, high = spread.min(), spread.max()
        short = (f"consensus, +-{high:.0%}" if f"{low:.0%}" == f"{high:.0%}"
                 else f"consensus, +-{low:.0%} to {high:.0%}")
    else:
        reference = f"{case.reference_kind} (uncertainty {case.reference_uncertainty:g})"
        short = case.reference_kind
    if runs.empty:
        return {"reference": reference, "short_reference": short, "has_reference": True, "right": [],
                "fastest": None, "text": "No engine completed this case."}
    right = [e for e, mine in runs.groupby("engine", sort=False) if mine.right.any()]
    from_step = {e: mine[mine.right].sort_values("wall_time_s").step.iloc[0]
                 for e, mine in runs.groupby("engine", sort=False) if mine.right.any()}
    kind = metric_kind(metric)
    name = METRICS.get(metric, metric).split(" (1 where")[0].removeprefix("the ")
    within = describe_band(level, metric)
    if case.by_consensus and np.isfinite(runs.level).any():
        within += f" or the consensus's uncertainty (up to {describe_band(np.nanmax(runs.level), metric)})"
    what = f"agreeing with the reference on {name}" if kind == "mismatch" else (
        f"within {within} on the {name}, agreeing on every yes-or-no measure")
    if right:
        fastest = _fastest_right(runs)
        slower = runs[runs.right & (runs.engine != fastest.engine)].groupby("engine").wall_time_s.min()
        listed = ", ".join(f"{e} (fastest right at {from_step[e]})" for e in right)
        text = (f"Right ({what}): {listed}. Fastest of them: "
                f"{fastest.engine} at {fastest.step} ({fastest.wall_time_s:.3g} s, |error| "
                f"{describe(fastest.error, metric)})")
        if len(slower):
            text += f"; next {slower.idxmin()} ({slower.min():.3g} s)"
        text += "."
    else:
        fastest = None
        finite = runs[np.isfinite(runs.error)]
        closest = finite.loc[finite.error.abs().idxmin()] if len(finite) else None
        text = f"No engine is right ({what})."
        if closest is not None:
            text += f" Closest: {closest.engine} at {closest.step}, |error| {describe(closest.error, metric)}."
    exact = sorted(runs[runs.error.abs() < exact_floor(metric)].engine.unique()) if kind != "mismatch" else []
    if exact:
        text += f" Exact (error below {exact_floor(metric):g}, not ranked): {', '.join(exact)}."
    return {"reference": reference, "short_reference": short, "has_reference": True, "right": right,
            "fastest": fastest, "text": text}


def _leaders(summary, column, largest=True) -> str:
    """Every engine and step tied for the best ``column``."""
    best = summary[column].max() if largest else summary[column].min()
    tied = summary[np.isclose(summary[column], best)]
    return ", ".join(f"{r.engine} at {r.step}" for r in tied.itertuples())


def ensemble_verdict(summary: pd.DataFrame, overturning: bool = True, median_level: float = 0.03,
                     agreement_level: float = 0.95) -> dict:
    """The engines whose median |peak error| is within ``median_level`` (and, with ``overturning``, who agree
    on overturning in at least ``agreement_level`` of the runs) at some step, and the fastest of them."""
    if summary.empty:
        return {"right": [], "fastest": None, "has_reference": True, "text": "No engine completed this ensemble."}
    ok = summary[summary.median_error <= median_level]
    best = summary.loc[summary.median_error.idxmin()]
    text = f"Lowest median |peak error|: {best.engine} at {best.step} ({100 * best.median_error:.2g}% of the peak, "
    text += f"90th percentile {100 * best.p90_error:.2g}%). "
    condition = f"median within {median_level:.0%}"
    if overturning:
        ok = ok[ok.overturn_agreement >= agreement_level]
        text += (f"Agreeing on overturning most often ({summary.overturn_agreement.max():.0%} of the runs): "
                 f"{_leaders(summary, 'overturn_agreement')}. ")
        condition += f", agreeing on overturning in {agreement_level:.0%} of the runs or more"
    right, fastest = _right_and_fastest(ok)
    text += (f"Right ({condition}): {', '.join(right)}; fastest of them: {fastest.engine} at {fastest.step} "
             f"({fastest.median_wall_time_s:.3g} s a run)." if right else f"No engine is right ({condition}).")
    return {"right": right, "fastest": fastest, "has_reference": True, "text": text}


def spectrum_verdict(summary: pd.DataFrame, agreement_level: float = 0.95) -> dict:
    """The engines agreeing with the reference on at least ``agreement_level`` of the points, the fastest."""
    if summary.empty:
        return {"right": [], "fastest": None, "has_reference": True, "text": "No engine completed this spectrum."}
    ok = summary[summary.agreement >= agreement_level]
    best = summary.agreement.max()
    text = (f"Best agreement ({best:.0%} of {summary.points.iloc[0]} points): "
            f"{_leaders(summary, 'agreement')}. ")
    right, fastest = _right_and_fastest(ok)
    text += (f"Right (agreeing on {agreement_level:.0%} of the points or more): {', '.join(right)}; fastest of "
             f"them: {fastest.engine} ({fastest.median_wall_time_s:.3g} s a run)." if right
             else f"No engine agrees on {agreement_level:.0%} of the points.")
    return {"right": right, "fastest": fastest, "has_reference": True, "text": text}


def _right_and_fastest(ok: pd.DataFrame) -> tuple[list, pd.Series | None]:
    """The engines of the rows judged right, in order, and the row of the fastest of them (None if none)."""
    right = list(dict.fromkeys(ok.engine))
    return right, (ok.loc[ok.median_wall_time_s.idxmin()] if right else None)
