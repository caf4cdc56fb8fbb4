"""Run every case in every engine over a ladder of time steps and solver settings: one tidy table.

Each row is one error metric of one run: case, engine, time step, settings,
metric, error, wall time of the run (compile or build time apart), steps,
and the run's status ("ok", or the engine's stability error).  The native
core runs at its automatic step and at fractions of it; the other engines at
fixed steps around their usual 1e-3 s.
"""

import json
import sys
import time
import warnings

import numpy as np
import pandas as pd
from tqdm import tqdm

import adapters
import dem_core
from comparisons.cases import all_cases

#: time steps of each engine: for the native core, divisors of its automatic step
LADDER = {
    "dem": {"full": (1, 2, 4, 8), "quick": (1, 4)},
    "pymunk": {"full": (2e-3, 1e-3, 5e-4, 2.5e-4), "quick": (1e-3, 2.5e-4)},
    "pybullet": {"full": (2e-3, 1e-3, 5e-4, 2.5e-4), "quick": (1e-3, 2.5e-4)},
    "mujoco": {"full": (2e-3, 1e-3, 5e-4, 2.5e-4), "quick": (1e-3, 2.5e-4)},
}
#: solver settings that trade speed for accuracy, tried at 1e-3 s in the full run
SETTINGS = {
    "pymunk": ({"iterations": 30},),
    "pybullet": ({"iterations": 200},),
    "mujoco": ({"iterations": 200},),
}
ENGINES = tuple(LADDER)


def plan(quick: bool, cases=None, engines=ENGINES) -> list:
    """The runs as (case, engine, dt or divisor, settings) tuples."""
    mode = "quick" if quick else "full"
    runs = []
    for case in cases or [c for c in all_cases() if c.quick or not quick]:
        for engine in engines:
            runs += [(case, engine, step, {}) for step in LADDER[engine][mode]]
            if not quick:
                runs += [(case, engine, 1e-3, dict(s)) for s in SETTINGS.get(engine, ())]
    return runs


def run_one(case, engine, step, settings, reference) -> list:
    """Rows for one run (one per metric)."""
    scene, motion = case.scene(), case.motion()
    if engine == "dem":
        # the user's default step, kept below the limit of toppled blocks (these runs go on through a collapse)
        auto = dem_core.automatic_time_step(scene, toppled=True)
        dt, label = auto / step, f"auto/{step}"
        options = {"stop_at_overturn": False, **settings}
    else:
        dt, label, options = step, f"{step:g}", settings
    base = {"case": case.name, "engine": engine, "dt": dt, "step": label, "settings": json.dumps(settings)}
    start = time.perf_counter()
    try:
        with warnings.catch_warnings():
            warnings.filterwarnings("ignore", message=".*product of their coefficients")
            result = adapters.simulate(scene, motion, case.duration, engine=engine, dt=dt, output_dt=case.output_dt,
                                       **options)
        errors = case.errors(result, reference)
        status = "ok"
    except (dem_core.SimulationUnstable, adapters.EngineUnstable) as exc:
        result, errors, status = exc.partial, {}, f"unstable: {exc}"
    wall = time.perf_counter() - start
    info = result.info if result is not None else {}
    common = {**base, "status": status, "wall_time_s": info.get("run_time_s", wall),
              "compile_time_s": info.get("compile_time_s", np.nan), "steps": info.get("steps", np.nan)}
    if not errors:
        return [{**common, "metric": "none", "error": np.nan}]
    return [{**common, "metric": metric, "error": value} for metric, value in errors.items()]


def run_harness(quick: bool = True, cases=None, engines=ENGINES, progress: bool = True) -> pd.DataFrame:
    """Run the plan and return the tidy table (references computed once per case).

    progress : a bar of the runs with the case and engine at hand and the time left, shown only
        when stderr is a terminal (not in CI or a log file).
    """
    runs = plan(quick, cases, engines)
    references = {}
    rows = []
    bar = tqdm(runs, desc="runs", unit="run", disable=not (progress and sys.stderr.isatty()))
    for case, engine, step, settings in bar:
        bar.set_postfix_str(f"{case.name}, {engine}", refresh=False)
        if case.name not in references:
            references[case.name] = case.reference()
        rows += run_one(case, engine, step, settings, references[case.name])
    return pd.DataFrame(rows)
