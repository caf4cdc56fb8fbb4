"""Parametric sweeps: one scene and excitation, parameters varied over lists, run in parallel.

A :class:`Sweep` is a ``build(params) -> RunSpec`` function and the values of
each parameter; its points are their grid (every combination) or their zip.
:func:`run_sweep` builds every point in this process and names each run by a
digest of everything it runs (:mod:`dem_core.analyses.run_identity`: scene,
ground motion, simulation settings, contact parameters, dem_core version), then
runs the points on this machine's cores (:mod:`dem_core.analyses.worker_pool`:
a worker that dies fails only its own run, which is tried once more; killing the
sweep ends its workers) or on a Dask distributed cluster
(``scheduler="tcp://host:8786"``).  Each finished run is written at once to
``OUT/runs/<run_id>.parquet`` (one row: parameters, status, measures), so a
sweep that is killed and started again skips what is done and loses nothing;
a failing point, first or last, is recorded with its error and the sweep goes
on.  Every file is written under a temporary name and renamed when complete
(:mod:`dem_core.output_files`); a saved run that cannot be read (a file left
empty or damaged by something else) is run again, with a warning saying so.
At the end the rows of this sweep's points are gathered into
``OUT/results.parquet``.

``OUT/sweep.json`` holds the sweep's spec (its parameters, its runs and, for a
sweep file, the file's tables).  A folder holding another sweep's results is
refused, so that results of two sweeps are never mixed nor stale: give a new
folder, or ``overwrite=True`` (``--overwrite``) to delete them first.

Sweep files are scene files (:mod:`dem_core.inputs.scene_file`) with a ``[sweep]``
table whose sub-tables name the table and key to vary::

    [scene]
    builder = "column"
    n_drums = 8
    [excitation]
    kind = "harmonic"
    frequency = 1.0
    pga = 1.0
    [simulation]
    duration = 10.0

    [sweep]
    mode = "grid"                 # grid (every combination) | zip (lists side by side)
    time_histories = false        # also write OUT/histories/<run_id>.parquet
    [sweep.excitation]
    frequency = {start = 0.5, stop = 5.0, num = 10}   # evenly spaced, ends included
    pga = [1.0, 2.0, 3.0]
    [sweep.scene]
    friction = {values = [0.4, 0.7]}

Parameter names in the results are ``table.key`` (``excitation.frequency``).
"""

import copy
import dataclasses
import itertools
import json
import math
import os
import sys
import time
import traceback
import warnings
from collections.abc import Callable
from dataclasses import dataclass, field
from pathlib import Path

import numpy as np
import pandas as pd
from tqdm import tqdm

from ..batch import block_columns
from ..simulation import SimulationUnstable, simulate
from ..inputs import scene_file
from ..inputs.text_files import did_you_mean
from ..inputs.excitation import GroundMotion, strong_motion_cuts
from ..inputs.number_types import is_integer, is_real
from ..inputs.scene import Scene
from ..output_files import PARTIAL, OutputPathError, output_folder, replacing
from . import run_identity
from .cluster import ClusterError, completed, dask_client
from .worker_pool import TaskFailed, WorkerDied, run_tasks

RESULTS = "results.parquet"
SPEC = "sweep.json"
MODES = ("grid", "zip")
SECTIONS = ("scene", "contact", "excitation", "simulation")
#: times a run is started again on a fresh worker after its worker process died
WORKER_RETRIES = 1


class SweepError(ValueError):
    """A sweep that cannot be set up; the message names the file and the culprit."""


@dataclass(frozen=True)
class RunSpec:
    """What one point of a sweep runs: ``simulate(scene, excitation, **simulation)``."""

    scene: Scene
    excitation: GroundMotion
    simulation: dict = field(default_factory=dict)


@dataclass(frozen=True)
class Sweep:
    """A parametric study.

    build : ``params -> RunSpec``; called in this process for every point (the runs go to workers).
    parameters : {name: sequence of values}.
    mode : "grid" (every combination, the first parameter varying slowest) or "zip".
    time_histories : also write each run's time history (Result.to_frame()).
    """

    build: Callable
    parameters: dict
    mode: str = "grid"
    time_histories: bool = False

    def __post_init__(self):
        if self.mode not in MODES:
            raise SweepError(f"sweep mode must be one of {MODES}, got {self.mode!r}")
        if not self.parameters:
            raise SweepError("a sweep needs at least one parameter to vary")
        for name, values in self.parameters.items():
            if len(values) == 0:
                raise SweepError(f"sweep parameter {name!r} has no values")
        if self.mode == "zip" and len({len(v) for v in self.parameters.values()}) > 1:
            lengths = {k: len(v) for k, v in self.parameters.items()}
            raise SweepError(f"zip sweep: every parameter needs as many values; got {lengths}")

    def points(self) -> list:
        """The parameter sets, as dicts, in order."""
        names = list(self.parameters)
        values = [list(v) for v in self.parameters.values()]
        combos = itertools.product(*values) if self.mode == "grid" else zip(*values)
        return [dict(zip(names, (_plain(x) for x in combo))) for combo in combos]


def _plain(value):
    """numpy scalars as Python ones, so parameters hash and serialise the same way."""
    return value.item() if isinstance(value, np.generic) else value


def run_id(spec: RunSpec) -> str:
    """The identifier of a run: a digest of everything it runs (see :mod:`dem_core.analyses.run_identity`)."""
    return run_identity.run_digest(spec.scene, spec.excitation, spec.simulation)


# --- sweep files ---------------------------------------------------------------------------------

@dataclass(frozen=True)
class SceneFileBuild:
    """``build`` for sweep files: the scene file's tables with the point's values put in."""

    data: dict
    path: str

    def tables(self, params: dict) -> dict:
        """The scene file's tables with the point's values put in (``[sweep]`` left out)."""
        data = copy.deepcopy(self.data)
        data.pop("sweep", None)
        for name, value in params.items():
            table, key = name.split(".", 1)
            if isinstance(data.setdefault(table, {}), dict):  # a value where a table belongs: check() says so
                data[table][key] = value
        return data

    def __call__(self, params: dict) -> RunSpec:
        loaded = scene_file.from_dict(self.tables(params), self.path)
        return RunSpec(loaded.scene, loaded.excitation, loaded.simulation)


def _values(spec, where):
    if isinstance(spec, list) and spec:
        return spec
    if isinstance(spec, dict) and set(spec) == {"values"} and isinstance(spec["values"], list) and spec["values"]:
        return list(spec["values"])
    if isinstance(spec, dict) and set(spec) in ({"start", "stop", "num"}, {"start", "stop", "step"}):
        start, stop = (_sweep_number(spec[k], f"{where} {k}") for k in ("start", "stop"))
        if "num" in spec:
            num = spec["num"]
            if not is_integer(num) or num < 1:
                raise SweepError(f"{where}: num must be a positive integer, got {num!r}")
            return [float(v) for v in np.linspace(start, stop, num)]
        step = _sweep_number(spec["step"], f"{where} step")
        if step == 0 or (stop - start) / step < 0:
            raise SweepError(f"{where}: step {step:g} does not lead from {start:g} to {stop:g}")
        n = int(np.floor((stop - start) / step + 1e-9)) + 1
        return [float(start + k * step) for k in range(n)]
    raise SweepError(f"{where}: give a non-empty list, {{values = [...]}}, {{start, stop, num}} or "
                     f"{{start, stop, step}}; got {spec!r}")


def _sweep_number(value, where) -> float:
    if not is_real(value) or not math.isfinite(value):
        raise SweepError(f"{where}: expected a finite number, got {value!r}")
    return float(value)


def load_sweep(path) -> Sweep:
    """Read a sweep file (a scene file with a ``[sweep]`` table).

    Every point's tables are checked for names and types here (a misspelt key or a value of the
    wrong type refuses the sweep, naming the file and the key); values a builder refuses (a negative
    friction) are failed runs, recorded when the sweep runs.
    """
    path = Path(path)
    data = scene_file.read_toml(path, SweepError, "sweep file")
    table = data.get("sweep", {})
    if not isinstance(table, dict) or not table:
        raise SweepError(f"{path}: no [sweep] table: nothing to vary"
                         f"{did_you_mean(set(data) - set(scene_file.TOP_LEVEL), ['sweep'])}")
    table = dict(table)
    mode = table.pop("mode", "grid")
    histories = table.pop("time_histories", False)
    if not isinstance(histories, bool):
        raise SweepError(f"{path}: [sweep] time_histories: expected true or false, got {histories!r}")
    if mode not in MODES:
        raise SweepError(f"{path}: [sweep] mode must be one of {', '.join(MODES)}, got {mode!r}"
                         f"{did_you_mean(mode, MODES) if isinstance(mode, str) else ''}")
    parameters = {}
    for section, entries in table.items():
        if not isinstance(entries, dict) and section in SECTIONS:
            raise SweepError(f"{path}: [sweep] {section} must be a table, [sweep.{section}], of the keys to vary; "
                             f"got {entries!r}")
        if not isinstance(entries, dict):
            tables = ", ".join(f"[sweep.{name}]" for name in SECTIONS)
            raise SweepError(f"{path}: [sweep] has no key {section!r}"
                             f"{did_you_mean(section, ['mode', 'time_histories', *SECTIONS])}; it takes mode, "
                             f"time_histories and the tables {tables} of the keys to vary")
        if section not in SECTIONS:
            raise SweepError(f"{path}: [sweep.{section}] is not a table of {', '.join(SECTIONS)} keys"
                             f"{did_you_mean(section, SECTIONS)}")
        for key, spec in entries.items():
            parameters[f"{section}.{key}"] = _values(spec, f"{path}: [sweep.{section}] {key}")
    build = SceneFileBuild(data, str(path))
    sweep = Sweep(build, parameters, mode, histories)
    for point in sweep.points():
        try:
            scene_file.check(build.tables(point), path)
        except scene_file.SceneFileError as exc:
            raise SweepError(f"{exc} (at the point {point} of [sweep])") from None
    return sweep


def with_simulation(sweep: Sweep, **settings) -> Sweep:
    """``sweep`` with ``settings`` (keyword arguments of ``simulate``, e.g. ``duration``) replacing its
    ``[simulation]`` values at every point: written into a sweep file's tables (so that ``OUT/sweep.json``
    records them, and a folder of runs made with other values is refused naming the key), and part of each
    run's id like any setting.  A parameter the sweep varies cannot be replaced: :class:`SweepError`."""
    varied = [f"simulation.{key}" for key in settings if f"simulation.{key}" in sweep.parameters]
    if varied:
        raise SweepError(f"the sweep varies {', '.join(varied)} ([sweep.simulation]): it cannot also be set for "
                         f"every point")
    if isinstance(sweep.build, SceneFileBuild):
        data = copy.deepcopy(sweep.build.data)
        table = data.get("simulation", {})
        data["simulation"] = {**(table if isinstance(table, dict) else {}), **settings}
        build = SceneFileBuild(data, sweep.build.path)
    else:
        build = _WithSimulation(sweep.build, dict(settings))
    return dataclasses.replace(sweep, build=build)


@dataclass(frozen=True)
class _WithSimulation:
    """``build`` whose runs have ``settings`` replacing their simulation settings (:func:`with_simulation`)."""

    build: Callable
    settings: dict

    def __call__(self, params: dict) -> RunSpec:
        spec = self.build(params)
        return dataclasses.replace(spec, simulation={**spec.simulation, **self.settings})


# --- points and their runs -------------------------------------------------------------------------

@dataclass(frozen=True)
class _Point:
    """A point of a sweep as built here: its run, or why it could not be built."""

    params: dict
    run_id: str
    spec: RunSpec | None
    error: str = ""


def _plan(sweep: Sweep) -> list:
    """Every point built here, in order: its run and run id, or why it cannot be built (its id then
    digests the build and the point's values)."""
    points = []
    for params in sweep.points():
        try:
            spec = sweep.build(params)
            points.append(_Point(params, run_id(spec), spec))
        except Exception as exc:  # noqa: BLE001 - a point that cannot be built is a failed run
            unbuilt = {"build": run_identity.describe(sweep.build), "params": run_identity.describe(params),
                       "dem_core": run_identity.package_version(), "code": run_identity.code_digest()}
            points.append(_Point(params, run_identity.digest(unbuilt), None,
                                 f"{type(exc).__name__}: {exc}\n{traceback.format_exc(limit=3)}"))
    seen = {}
    for point in points:
        if point.run_id in seen:
            raise SweepError(f"the points {seen[point.run_id]} and {point.params} run the same thing: the values "
                             f"varied between them make no difference to the run")
        seen[point.run_id] = point.params
    return points


def measures(result) -> dict:
    """The scene-level measures of a run (those of ``Result.summary`` that are numbers), the largest peak
    displacement of any block (m), its end time (s), and each block's measures as a batch's rows have them
    (:func:`~dem_core.batch.block_columns`: ``<measure>[<block>]``)."""
    row = {k: v for k, v in result.summary().items() if isinstance(v, (bool, int, float, np.number))}
    row.update(max_peak_displacement_m=float(np.max(result.peak_displacement)), end_time_s=float(result.t[-1]))
    return {**row, **block_columns(result)}


def run_point(spec: RunSpec, params: dict, run: str, history_dir: str | None = None) -> dict:
    """Run one point and return its row; any error becomes the row's ``status``, never an exception."""
    row = {"run_id": run, **params}
    start = time.perf_counter()
    try:
        result = simulate(spec.scene, spec.excitation, **spec.simulation)
        row.update(status="ok", error="", **measures(result))
    except SimulationUnstable as exc:
        row.update(status="unstable", error=str(exc))
        if exc.partial is not None:
            row.update(measures(exc.partial))
        result = None
    except Exception as exc:  # noqa: BLE001 - a failing point is recorded and the sweep goes on
        row.update(status="failed", error=f"{type(exc).__name__}: {exc}\n{traceback.format_exc(limit=3)}")
        result = None
    row["wall_time_s"] = time.perf_counter() - start
    row["worker"] = f"{os.uname().nodename}:{os.getpid()}"
    if history_dir is not None and result is not None:
        _write_atomic(result.to_frame(), Path(history_dir) / f"{run}.parquet")
    return row


def _failed_row(point: _Point, error: str) -> dict:
    """The row of a point that could not be built: no run was attempted (``attempts`` 0)."""
    return {"run_id": point.run_id, **point.params, "status": "failed", "error": error, "wall_time_s": 0.0,
            "worker": "", "attempts": 0}


def _write_atomic(frame: pd.DataFrame, path: Path) -> None:
    """Write ``frame`` to ``path`` whole or not at all (:func:`dem_core.output_files.replacing`)."""
    with replacing(path) as tmp:
        frame.to_parquet(tmp, index=False)


def _read_run(path: Path):
    """The one-row table of a saved run, or why it cannot be read (a string): empty, damaged, not one row of
    that run."""
    try:
        row = pd.read_parquet(path)
    except Exception as exc:  # noqa: BLE001 - pyarrow raises ArrowInvalid, OSError and others for a bad file
        return str(exc).splitlines()[0] if str(exc) else type(exc).__name__
    if len(row) != 1 or "status" not in row or "run_id" not in row or row.run_id.iloc[0] != path.stem:
        return f"not the one row of run {path.stem}"
    return row


def _warn_unreadable(unreadable: list, what: str) -> None:
    """One warning for the saved runs that cannot be read: ``[(path, why), ...]``."""
    if not unreadable:
        return
    shown = "; ".join(f"{path.name}: {why}" for path, why in unreadable[:3])
    more = f"; and {len(unreadable) - 3} more" if len(unreadable) > 3 else ""
    folder = unreadable[0][0].parent
    count = "a saved run" if len(unreadable) == 1 else f"{len(unreadable)} saved runs"
    warnings.warn(f"{count} in {folder} cannot be read ({shown}{more}): {what}", RuntimeWarning, stacklevel=3)


def _finished(runs_dir: Path, ids, retry_failed: bool) -> set:
    """The runs of ``ids`` saved in ``runs_dir`` (with ``retry_failed``, those that went well); a saved file that
    cannot be read is deleted, with a warning, and its run done again."""
    done, unreadable = set(), []
    for run in ids:
        part = runs_dir / f"{run}.parquet"
        if not part.is_file():
            continue
        row = _read_run(part)
        if isinstance(row, str):
            unreadable.append((part, row))
            part.unlink(missing_ok=True)
            continue
        if retry_failed and row.status.iloc[0] != "ok":
            continue
        done.add(run)
    _warn_unreadable(unreadable, "run again")
    return done


def saved_runs(out) -> tuple:
    """``(saved, total)``: the runs of the sweep in ``out`` (its sweep.json) saved so far in ``out/runs``, and
    all its runs; ``(0, 0)`` when ``out`` holds no readable sweep.json."""
    out = Path(out)
    try:
        runs = json.loads((out / SPEC).read_text())["runs"]
        ids = [run["run_id"] for run in runs]
    except (OSError, ValueError, KeyError, TypeError):
        return 0, 0
    return sum((out / "runs" / f"{run}.parquet").is_file() for run in ids), len(ids)


# --- the output folder -----------------------------------------------------------------------------

def _spec(sweep: Sweep, points: list) -> dict:
    """What ``OUT/sweep.json`` holds; ``"sweep"`` is the digest that tells sweeps apart."""
    runs = [{"run_id": p.run_id, "parameters": p.params} for p in points]
    spec = {"sweep": run_identity.digest({"runs": runs, "time_histories": sweep.time_histories}),
            "dem_core": run_identity.package_version(), "code": run_identity.code_digest(), "mode": sweep.mode,
            "time_histories": sweep.time_histories,
            "parameters": {k: [_plain(v) for v in values] for k, values in sweep.parameters.items()}, "runs": runs}
    if isinstance(sweep.build, SceneFileBuild):
        spec.update(file=sweep.build.path, tables=sweep.build.data)
    else:
        spec.update(build=run_identity.describe(sweep.build))
    return spec


def _claim(out: Path, spec: dict, overwrite: bool) -> None:
    """Make ``out`` this sweep's folder and write its spec: with ``overwrite`` delete whatever results
    it holds; otherwise resume the same sweep, and refuse another sweep's results."""
    try:
        output_folder(out, "sweep folder")
    except OutputPathError as exc:
        raise SweepError(str(exc)) from None
    spec_path = out / SPEC
    results = [*(out / "runs").glob("*.parquet"), *(out / "histories").glob("*.parquet"), out / RESULTS]
    if overwrite:
        partial = [path for folder in (out / "runs", out / "histories") for pattern in ("*.tmp", f"*{PARTIAL}")
                   for path in folder.glob(pattern)]
        for path in [*results, *partial, spec_path]:
            path.unlink(missing_ok=True)
    elif spec_path.is_file():
        try:
            previous = json.loads(spec_path.read_text())
        except (OSError, ValueError):
            previous = {}
        if previous.get("sweep") == spec["sweep"]:
            return
        raise SweepError(_refusal(out, _difference(previous, spec)))
    elif any(p.is_file() for p in results):
        raise SweepError(_refusal(out, _difference(None, spec)))
    _write_spec(spec_path, spec)


def _refusal(out: Path, difference: str) -> str:
    return (f"{out} holds the results of another sweep ({difference}); the results of two sweeps are not mixed. "
            f"Give a new output folder, or --overwrite (overwrite=True) to delete them and run this sweep")


def _write_spec(path: Path, spec: dict) -> None:
    with replacing(path) as tmp:
        tmp.write_text(json.dumps(spec, indent=1, default=str))


def _difference(previous: dict | None, spec: dict) -> str:
    """How the sweep whose spec is ``previous`` differs from this one, in words."""
    if not previous:
        return f"written without a readable {SPEC}: by an older dem_core, or by hand"
    if previous.get("parameters") != json.loads(json.dumps(spec["parameters"], default=str)):
        def listed(s):
            return "; ".join(f"{k} = {v}" for k, v in s.get("parameters", {}).items())
        return (f"{len(previous.get('runs', []))} runs over {listed(previous)}, where this sweep has "
                f"{len(spec['runs'])} over {listed(spec)}")
    changed = _changed_keys(previous.get("tables"), json.loads(json.dumps(spec.get("tables"), default=str)))
    if changed:
        return f"the same parameter values, but {', '.join(changed[:5])} changed since"
    if previous.get("dem_core") != spec["dem_core"]:
        return f"the same parameter values, run by dem_core {previous.get('dem_core')} (this is {spec['dem_core']})"
    if previous.get("code") != spec["code"]:
        return "the same parameter values, run by other dem_core code (its source files changed since)"
    return "the same parameter values, but the runs differ: the scene, ground motion or settings they build changed"


def _changed_keys(old, new) -> list:
    """``[table] key: old -> new`` for the keys of two scene files' tables that differ."""
    if not isinstance(old, dict) or not isinstance(new, dict):
        return []
    changed = []
    for table in sorted(set(old) | set(new)):
        a, b = old.get(table, {}), new.get(table, {})
        if not isinstance(a, dict) or not isinstance(b, dict):
            if a != b:
                changed.append(f"[{table}]")
            continue
        changed += [f"[{table}] {key}: {a.get(key, '(none)')!r} -> {b.get(key, '(none)')!r}"
                    for key in sorted(set(a) | set(b)) if a.get(key) != b.get(key)]
    return changed


# --- running ---------------------------------------------------------------------------------------

def run_sweep(sweep: Sweep, out, *, workers: int | None = None, scheduler=None, progress: bool | None = None,
              progress_bar: Callable | None = None, retry_failed: bool = False, overwrite: bool = False,
              on_start: Callable[[int, int], None] | None = None) -> pd.DataFrame:
    """Run every point of ``sweep`` not already finished in ``out`` and return the sweep's rows.

    workers : processes on this machine, at least 1 (default: one per core); ignored with a scheduler.
    scheduler : address of a running Dask scheduler, or a ``distributed.Client``.
    progress : a progress bar on stderr; None: only when stderr is a terminal (quiet in logs and CI).
    progress_bar : what makes the bar, called with tqdm's keywords (``total``, ``initial``, ``unit``, ``desc``) and
        used as a context with ``update()``; default tqdm (the command line's writes lines in a log).
    retry_failed : run again the points recorded as failed or unstable.
    overwrite : delete whatever results ``out`` holds and run every point; without it, the results
        of another sweep in ``out`` raise :class:`SweepError` and those of this sweep are resumed.
    on_start : called as ``on_start(done, total)`` once the folder is claimed, before any run: ``done`` of the
        sweep's ``total`` runs are already saved in ``out`` and will not run again (a resumed sweep).
    Returns the table also written to ``out/results.parquet``: one row per point with its
    parameters, ``status`` ("ok", "unstable", "failed"), ``error`` and the measures of
    :func:`measures`, ``wall_time_s``, and (local runs) ``attempts``: 2 when the first worker died,
    0 for a point that could not be built.
    """
    out = Path(out)
    if workers is not None and (not is_integer(workers) or workers < 1):
        raise SweepError(f"workers must be a whole number of at least 1, got {workers!r}")
    points = _plan(sweep)
    for said in strong_motion_cuts((p.spec.excitation, p.spec.simulation.get("duration")) for p in points
                                   if p.spec is not None):
        warnings.warn(f"the strong motion is cut: {said}", RuntimeWarning, stacklevel=2)
    _claim(out, _spec(sweep, points), overwrite)
    runs_dir = out / "runs"
    runs_dir.mkdir(exist_ok=True)
    history_dir = out / "histories" if sweep.time_histories else None
    if history_dir is not None:
        history_dir.mkdir(exist_ok=True)
    done = _finished(runs_dir, [p.run_id for p in points], retry_failed)
    todo = [p for p in points if p.run_id not in done]
    if on_start is not None:
        on_start(len(points) - len(todo), len(points))
    for point in [p for p in todo if p.spec is None]:
        _write_atomic(pd.DataFrame([_failed_row(point, point.error)]), runs_dir / f"{point.run_id}.parquet")
    todo = [p for p in todo if p.spec is not None]
    show = sys.stderr.isatty() if progress is None else progress
    bar = (progress_bar or tqdm)(total=len(points), initial=len(points) - len(todo), unit="run", desc="sweep",
                                 disable=not show)
    with bar:
        for row in _run(todo, None if history_dir is None else str(history_dir), workers, scheduler):
            _write_atomic(pd.DataFrame([row]), runs_dir / f"{row['run_id']}.parquet")
            bar.update()
    return collect(out, order=[p.run_id for p in points])


def _run(points: list, history_dir, workers, scheduler):
    """The rows of ``points`` as their runs finish, on local worker processes or a Dask cluster."""
    if not points:
        return
    by_id = {p.run_id: p for p in points}
    if scheduler is None:
        tasks = [(p.run_id, run_point, (p.spec, p.params, p.run_id, history_dir)) for p in points]
        for run, outcome, attempts in run_tasks(tasks, workers or os.cpu_count() or 1, retries=WORKER_RETRIES):
            if isinstance(outcome, (WorkerDied, TaskFailed)):
                outcome = _failed_row(by_id[run], f"{type(outcome).__name__}: {outcome}")
            yield {**outcome, "attempts": attempts}
        return
    try:
        with dask_client(scheduler) as client:
            yield from _on_cluster(client, points, history_dir)
    except ClusterError as exc:
        raise SweepError(str(exc)) from None


def _on_cluster(client, points: list, history_dir):
    """The rows of ``points`` as their runs finish on the Dask cluster of ``client``."""
    executor = client.get_executor()
    try:
        futures = {executor.submit(run_point, p.spec, p.params, p.run_id, history_dir): p for p in points}
        for point, row in completed(futures):
            yield _failed_row(point, f"{type(row).__name__}: {row}") if isinstance(row, Exception) else row
    finally:
        executor.shutdown(wait=False)  # on an interruption, do not wait for the cluster


def collect(out, order=None) -> pd.DataFrame:
    """Gather the rows of ``out/runs/`` into one table and write ``out/results.parquet``: the runs of
    ``order`` (run ids), in that order, or every run found (a file that cannot be read is left out, with a
    warning)."""
    out = Path(out)
    if order is None:
        paths = sorted((out / "runs").glob("*.parquet"))
    else:
        paths = [p for p in (out / "runs" / f"{run}.parquet" for run in order) if p.is_file()]
    parts, unreadable = [], []
    for path in paths:
        row = _read_run(path)
        if isinstance(row, str):
            unreadable.append((path, row))
        else:
            parts.append(row)
    _warn_unreadable(unreadable, f"left out of {RESULTS}; run the sweep again to redo them")
    if not parts:
        return pd.DataFrame()
    table = pd.concat(parts, ignore_index=True)
    _write_atomic(table, out / RESULTS)
    return table
