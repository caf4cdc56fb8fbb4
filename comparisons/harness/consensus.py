"""A reference for scenes without a closed form: the converged consensus of the engines.

For a multi-block scene (a column of drums, a colonnade) no analytical answer exists, and judging the
engines against one of them measures agreement with that engine, not accuracy.  Each engine instead
runs the scene at its finest settings and at the settings next to them
(:data:`comparisons.harness.engines.FINEST`, :data:`~comparisons.harness.engines.NEXT_FINEST`: the native core at 100
and 10 times its K_n, the others at 2.5e-4 s and 5e-4 s).  An engine whose two answers differ by less
than :data:`CONVERGED` has converged, and its finest answer joins the consensus.  Measured per metric:

* a value (a peak rotation): the consensus is the median of the converged engines' finest answers; its
  uncertainty is half the range of all their answers, finest and next-finest (relative to the
  consensus), so that it covers both the spread between engines and each engine's own sensitivity to
  its settings, which a response with impacts keeps at a few per cent;
* overturning: the consensus is the answer all converged engines give.

An engine is judged against the consensus of the others (leave-one-out): its own answers never vote,
and the native core's two contact laws, which share the integrator, the geometry and the overturning
test, leave out both.  No reference exists where fewer than two other engines converged, where they
disagree about overturning, or where their half range exceeds :data:`NO_REFERENCE_SPREAD` of their
median; the report says so instead of ranking.
"""

from dataclasses import dataclass

import numpy as np
import pandas as pd

from comparisons.harness.engines import FINEST, NATIVE_LAWS, NEXT_FINEST, settings_label, step_label

#: relative change between an engine's finest and next-finest answer below which it has converged (the
#: 8-drum column's peak moves by up to 9% between steps of 5e-4 and 2.5e-4 s in the engines that are
#: not biased, by 27% in the overlap-area law between 10 and 100 x K_n, which is)
CONVERGED = 0.10
#: half range of the converged answers, relative to their median, above which no reference exists
NO_REFERENCE_SPREAD = 0.20
#: metric name of overturning, and the measure it is judged by
OVERTURN = "overturn_mismatch"
OVERTURNED = "overturned"


@dataclass(frozen=True)
class Consensus:
    """The reference of one metric for one judged engine.

    value : the consensus (NaN where none exists); uncertainty : relative half range (0 for overturning).
    members : the engines whose finest answers voted.  exists : whether a reference exists.
    reason : why none exists ("" when it does).
    """

    value: float
    uncertainty: float
    members: tuple
    exists: bool
    reason: str


def _label(engine, which):
    step, settings = which[engine]
    return step_label(engine, step, settings), settings_label(settings)


def finest_answers(rows: pd.DataFrame, measure: str) -> pd.DataFrame:
    """Per engine: its finest and next-finest answer of ``measure`` and whether it has converged.

    rows : the harness rows of one case (columns engine, step, settings, metric, value, status).
    """
    out = []
    for engine in dict.fromkeys(rows.engine):
        answers = {}
        for name, which in (("finest", FINEST), ("next", NEXT_FINEST)):
            label, settings = _label(engine, which)
            pick = rows[(rows.engine == engine) & (rows.step == label) & (rows.settings == settings)
                        & (rows.metric == measure) & (rows.status == "ok")]
            answers[name] = float(pick.value.iloc[0]) if len(pick) else np.nan
        finest, following = answers["finest"], answers["next"]
        if measure == OVERTURNED:
            converged = np.isfinite(finest) and finest == following
        else:
            converged = bool(np.isfinite(finest) and np.isfinite(following)
                             and abs(finest - following) <= CONVERGED * abs(finest))
        out.append({"engine": engine, "finest": finest, "next": following, "converged": converged})
    return pd.DataFrame(out)


def voters(engine: str, engines) -> list:
    """The engines whose answers judge ``engine``: all others, and for a native engine none of the native core's."""
    family = set(NATIVE_LAWS) if engine in NATIVE_LAWS else {engine}
    return [e for e in engines if e not in family]


def consensus(answers: pd.DataFrame, measure: str, judged: str) -> Consensus:
    """The consensus of the converged engines other than ``judged`` (and its family) on ``measure``."""
    pool = answers[answers.engine.isin(voters(judged, answers.engine)) & answers.converged]
    members = tuple(pool.engine)
    if len(pool) < 2:
        return Consensus(np.nan, np.nan, members, False, f"{len(pool)} other engine(s) converged")
    values = pool.finest.to_numpy(dtype=float)
    if measure == OVERTURNED:
        if np.ptp(values) > 0:
            return Consensus(np.nan, np.nan, members, False, "the converged engines disagree about overturning")
        return Consensus(float(values[0]), 0.0, members, True, "")
    median = float(np.median(values))
    every = np.concatenate([values, pool["next"].to_numpy(dtype=float)])
    spread = float(np.ptp(every) / 2.0 / abs(median)) if median else np.inf
    if spread > NO_REFERENCE_SPREAD:
        return Consensus(median, spread, members, False,
                         f"the converged engines spread by +-{spread:.0%}, more than {NO_REFERENCE_SPREAD:.0%}")
    return Consensus(median, spread, members, True, "")


def judge(rows: pd.DataFrame) -> pd.DataFrame:
    """The rows of one consensus case with their errors: each measure becomes an error against the
    consensus of the other engines (``peak_rotation`` relative; ``overturned`` becomes
    ``overturn_mismatch``), with the consensus, its uncertainty and its members beside it."""
    out = []
    for measure in dict.fromkeys(rows.metric[rows.metric != "none"]):
        answers = finest_answers(rows, measure)
        for engine in dict.fromkeys(rows.engine):
            ref = consensus(answers, measure, engine)
            mine = rows[(rows.engine == engine) & (rows.metric == measure)].copy()
            if measure == OVERTURNED:
                mine["metric"] = OVERTURN
                mine["error"] = (mine.value != ref.value).astype(float) if ref.exists else np.nan
            else:
                mine["error"] = mine.value / ref.value - 1.0 if ref.exists else np.nan
            mine["reference"] = ref.value
            mine["reference_uncertainty"] = ref.uncertainty
            mine["reference_members"] = ", ".join(ref.members)
            mine["no_reference"] = ref.reason
            out.append(mine)
    stopped = rows[rows.metric == "none"]
    return pd.concat(out + [stopped], ignore_index=True) if out else rows
