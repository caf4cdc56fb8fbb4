"""Run every case in every engine over a ladder of time steps and solver settings: one tidy table.

Each row is one metric of one run: case, engine, step (its label, :func:`comparisons.harness.engines.step_label`),
dt, solver settings, status ("ok", or "stopped" with the engine's message), wall time of the run
(building and compiling apart), steps, the metric, its error and, for the consensus cases, the
measured value, the consensus and its uncertainty (:mod:`comparisons.harness.consensus`).  The native core
runs at its automatic step and fractions of it; the other engines at fixed steps around their usual
1e-3 s, and in the full run at 1e-3 s with more solver iterations too.  Consensus cases run every
engine at its finest and next-finest settings instead (the native core at 10 and 100 times K_n).
"""

import numpy as np
import pandas as pd

from comparisons.cases.case import ENGINES
from comparisons.cases.catalogue import all_cases
from comparisons.harness import consensus, engines
from comparisons.harness.engines import settings_label
from comparisons.harness.progress import terminal_bar

#: steps of each engine: for the native core, divisors of its automatic step; for the others, s.  PyBullet's
#: quick ladder stops at 5e-4 s: its steps cost five times pymunk's (docs/performance.md), and the quick run
#: has to fit in CI's 3 minutes
LADDER = {
    "dem": {"full": (1, 2, 4, 8), "quick": (1, 4)},
    "dem-overlap": {"full": (1, 2, 4, 8), "quick": (1, 4)},
    "dem-moreau": {"full": (1, 2, 4, 10), "quick": (1, 4)},
    "pymunk": {"full": (2e-3, 1e-3, 5e-4, 2.5e-4), "quick": (1e-3, 2.5e-4)},
    "pybullet": {"full": (2e-3, 1e-3, 5e-4, 2.5e-4), "quick": (1e-3, 5e-4)},
    "mujoco": {"full": (2e-3, 1e-3, 5e-4, 2.5e-4), "quick": (1e-3, 2.5e-4)},
}
#: solver settings that trade speed for accuracy, tried at 1e-3 s in the full run
SETTINGS = {
    "pymunk": ({"iterations": 30},),
    "pybullet": ({"iterations": 200},),
    "mujoco": ({"iterations": 200},),
}


def plan(quick: bool, cases=None, engine_names=ENGINES) -> list:
    """The runs as (case, engine, step, settings) tuples."""
    mode = "quick" if quick else "full"
    runs = []
    for case in cases or [c for c in all_cases() if c.quick or not quick]:
        for engine in (e for e in engine_names if e in case.engines):
            mine = [(step, {}) for step in LADDER[engine][mode]]
            if not quick and not case.by_consensus:
                mine += [(1e-3, dict(s)) for s in SETTINGS.get(engine, ())]
            if case.by_consensus:
                mine += [which[engine] for which in (engines.NEXT_FINEST, engines.FINEST)
                         if which[engine] not in mine]
            runs += [(case, engine, step, settings) for step, settings in mine]
    return runs


def run_one(case, engine, step, settings, reference) -> list:
    """Rows for one run (one per metric; a single ``metric = "none"`` row if it stopped)."""
    run = engines.simulate(case.scene(), case.motion(), case.duration, engine, step, settings,
                           output_dt=case.output_dt)
    common = {"case": case.name, "engine": engine, "dt": run.dt, "step": run.label,
              "settings": settings_label(settings), "status": run.status, "message": run.message,
              "wall_time_s": run.wall_time_s, "compile_time_s": run.compile_time_s, "steps": run.steps}
    if run.status != "ok":
        return [{**common, "metric": "none", "value": np.nan, "error": np.nan}]
    if case.by_consensus:
        return [{**common, "metric": m, "value": v, "error": np.nan} for m, v in case.measures(run.result).items()]
    return [{**common, "metric": m, "value": np.nan, "error": e} for m, e in case.errors(run.result, reference).items()]


def run_harness(quick: bool = True, cases=None, engine_names=ENGINES, progress: bool = True) -> pd.DataFrame:
    """Run the plan and return the tidy table (references computed once per case; consensus cases
    judged once all their runs are in).

    progress : a bar of the runs with the case and engine at hand and the time left, shown only
        when stderr is a terminal (not in CI or a log file).
    """
    runs = plan(quick, cases, engine_names)
    references = {}
    rows = []
    bar = terminal_bar(runs, desc="runs", unit="run", progress=progress)
    for case, engine, step, settings in bar:
        bar.set_postfix_str(f"{case.name}, {engine}", refresh=False)
        if case.name not in references:
            references[case.name] = None if case.by_consensus else case.reference()
        rows += run_one(case, engine, step, settings, references[case.name])
    table = pd.DataFrame(rows)
    judged = [consensus.judge(table[table.case == name]) for name in dict.fromkeys(table.case)
              if next(c for c, *_ in runs if c.name == name).by_consensus]
    if judged:
        plain = table[~table.case.isin([j.case.iloc[0] for j in judged if len(j)])]
        table = pd.concat([plain, *judged], ignore_index=True)
    return table
