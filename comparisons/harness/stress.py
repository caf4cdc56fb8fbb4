"""Stability stress tests: where each engine breaks and whether it says so.

* time step past the usual: free rocking of the Housner block and Newmark's
  pulse at growing dt (for the native core, multiples of its stability limit
  with the check off); each run is "ok", "stopped" (the engine's own
  stability error) or "silently wrong" (finished, but off its analytical
  reference by 10% or more);
* contact stiffness: the native core's free-rocking block for K_n from 1e6
  to 1e11 N/m^2: time step, wall time, errors;
* a resting 8-drum column over a long run: drift in every engine;
* a very large ground motion (El Centro scaled to 10 m/s^2) on the column:
  what every engine does.

All rows go into one table (test, engine, setting, status, message, metric, value, wall time).  The
status of an error measure is "ok", "silently wrong" or "stopped"; a measure that is not an error (the
time step a run chose) carries the run's outcome only ("ok" or "stopped"): it cannot be wrong.  A
stopped run's message is kept whole in ``message``.
"""

import time
import warnings

import numpy as np
import pandas as pd

import adapters
import dem_core
from comparisons.cases import catalogue
from comparisons.harness.engines import NATIVE_INTEGRATORS, is_native
from comparisons.harness.progress import terminal_bar
from dem_core import excitation, scenes, stability
from dem_core.engine.model import compile_model

ENGINES = ("dem", "dem-moreau", "pymunk", "pybullet", "mujoco")
#: engines that take a step in seconds (the explicit native core's steps are multiples of its stability limit)
FIXED_STEP = ENGINES[1:]
WRONG = 0.10  # relative error from which a finished run counts as silently wrong


def _run(engine, scene, motion, duration, **kwargs):
    """(result, status, message, wall time) of one run of ``engine``; a native engine name picks its
    integrator (``NATIVE_INTEGRATORS``), the contact law is the scene's."""
    if is_native(engine):
        engine, kwargs = "dem", {**kwargs, "integrator": NATIVE_INTEGRATORS[engine]}
    start = time.perf_counter()
    try:
        with warnings.catch_warnings():
            warnings.filterwarnings("ignore", message=".*product of their coefficients")
            warnings.filterwarnings("ignore", message="dt = .* times the stability limit")  # the map's purpose
            result = adapters.simulate(scene, motion, duration, engine=engine, **kwargs)
        return result, "ok", "", time.perf_counter() - start
    except dem_core.SimulationUnstable as exc:
        return exc.partial, "stopped", str(exc), time.perf_counter() - start


def time_step_ladder(quick, progress):
    """Free rocking and Newmark's pulse at growing time steps, judged against their analytical references."""
    rows = []
    chosen = [c for c in catalogue.all_cases() if c.name in ("free_rocking", "newmark")]
    for case in terminal_bar(chosen, desc="time-step ladder", progress=progress):
        reference = case.reference()
        metric = case.primary or "max_slip"
        limit = stability.stability_limit(compile_model(case.scene()))
        ladders = {"dem": [(f"{f:g} x limit", f * limit) for f in (1.0, 1.25, 2.0, 3.0)]}
        for engine in FIXED_STEP:
            ladders[engine] = [(f"{dt:g} s", dt) for dt in (2e-3, 5e-3, 1e-2, 2e-2)]
        for engine, ladder in ladders.items():
            for label, dt in ladder:
                extra = ({"enforce_stability_limit": False, "stop_at_overturn": False} if engine == "dem"
                         else {"stop_at_overturn": False} if engine == "dem-moreau" else {})
                result, status, message, wall = _run(engine, case.scene(), case.motion(), case.duration, dt=dt,
                                                     output_dt=case.output_dt, **extra)
                error = case.errors(result, reference)[metric] if status == "ok" else np.nan
                if status == "ok" and not abs(error) < WRONG:
                    status = "silently wrong"
                rows.append({"test": f"{case.name} at growing dt", "engine": engine, "setting": label,
                             "status": status, "message": message, "metric": metric, "value": error,
                             "wall_time_s": wall})
    return rows


def stiffness_sweep(quick, progress):
    rows = []
    stiffnesses = (1e6, 1e8, 1e10, 1e11) if quick else (1e6, 1e7, 1e8, 1e9, 1e10, 1e11)
    case = catalogue.case("free_rocking")
    reference = case.reference()
    for kn in terminal_bar(stiffnesses, desc="contact stiffness", progress=progress):
        scene = catalogue.housner_scene(contact=dem_core.ContactParameters(kn=kn))
        result, status, message, wall = _run("dem", scene, None, case.duration, output_dt=case.output_dt)
        errors = case.errors(result, reference) if status == "ok" else {"peak_decay": np.nan}
        verdict = "silently wrong" if status == "ok" and not abs(errors["peak_decay"]) < WRONG else status
        common = {"test": "free rocking, contact stiffness", "engine": "dem", "setting": f"kn = {kn:.0e}",
                  "message": message, "wall_time_s": wall}
        for metric, value in errors.items():
            rows.append({**common, "status": verdict, "metric": metric, "value": value})
        rows.append({**common, "status": status, "metric": "dt_s", "value": result.dt if result is not None
                     else np.nan})
    return rows


def resting_stack(quick, progress):
    """Drift and change of potential energy (after the first second's settling) of a resting column."""
    rows = []
    duration = 10.0 if quick else 60.0
    column = scenes.column(8)
    weight = np.array([b.mass for b in column.blocks]) * column.gravity
    for engine in terminal_bar(ENGINES, desc="resting stack", progress=progress):
        result, status, message, wall = _run(engine, column, None, duration)
        settled = result.t >= 1.0
        values = {"horizontal_drift_m": np.max(np.abs(result.x - result.x[0])),
                  "potential_energy_change_J": float(np.max(np.abs((result.y[settled] - result.y[settled][0])
                                                                    @ weight)))}
        for metric, value in values.items():
            rows.append({"test": f"8-drum column at rest for {duration:g} s", "engine": engine,
                         "setting": "default dt", "status": status, "message": message, "metric": metric,
                         "value": value, "wall_time_s": wall})
    return rows


def large_motion(quick, progress):
    rows = []
    motion = excitation.record("el_centro_1940", pga=10.0)
    for engine in terminal_bar(ENGINES, desc="very large motion", progress=progress):
        extra = {"stop_at_overturn": False} if engine.startswith("dem") else {}
        result, status, message, wall = _run(engine, scenes.column(8), motion, 8.0 if quick else 20.0, **extra)
        overturn = result.time_of_overturn if result is not None else np.nan
        rows.append({"test": "8-drum column, El Centro at 10 m/s^2", "engine": engine, "setting": "default dt",
                     "status": status, "message": message, "metric": "overturn_time_s", "value": overturn,
                     "wall_time_s": wall})
    return rows


def run_stress(quick: bool = True, progress: bool = True) -> pd.DataFrame:
    rows = []
    for test in (time_step_ladder, stiffness_sweep, resting_stack, large_motion):
        rows += test(quick, progress)
    return pd.DataFrame(rows)
