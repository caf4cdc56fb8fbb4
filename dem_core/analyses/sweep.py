"""Parametric sweeps: one scene and excitation, parameters varied over lists, run in parallel.

A :class:`Sweep` is a ``build(params) -> RunSpec`` function and the values of
each parameter; its points are their grid (every combination) or their zip.
:func:`run_sweep` runs the points on this machine's cores
(``concurrent.futures.ProcessPoolExecutor``) or on a Dask distributed cluster
(``scheduler="tcp://host:8786"``, through the cluster's own ``concurrent.futures``
executor: the same code path).  Each finished run is written at once to
``OUT/runs/<run_id>.parquet`` (one row: parameters, status, measures), so a
sweep that is killed and started again skips what is done and loses nothing;
a failing run is recorded with its error and the sweep goes on.  At the end the
rows are gathered into ``OUT/results.parquet``.

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
import hashlib
import itertools
import json
import os
import time
import traceback
from collections.abc import Callable
from concurrent.futures import ProcessPoolExecutor, as_completed
from dataclasses import dataclass, field
from pathlib import Path

import numpy as np
import pandas as pd
from tqdm import tqdm

from ..inputs import scene_file
from ..inputs.excitation import GroundMotion
from ..inputs.scene import Scene
from ..engine.simulation import SimulationUnstable, simulate

RESULTS = "results.parquet"
MODES = ("grid", "zip")


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

    build : ``params -> RunSpec``; must be picklable (a module-level function or object)
        to run in worker processes.
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


def run_id(params: dict) -> str:
    """A stable identifier of a parameter set (12 hex digits)."""
    text = json.dumps(params, sort_keys=True, default=str)
    return hashlib.sha1(text.encode()).hexdigest()[:12]


# --- sweep files ---------------------------------------------------------------------------------

@dataclass(frozen=True)
class SceneFileBuild:
    """``build`` for sweep files: the scene file's tables with the point's values put in."""

    data: dict
    path: str

    def __call__(self, params: dict) -> RunSpec:
        data = copy.deepcopy(self.data)
        data.pop("sweep", None)
        for name, value in params.items():
            table, key = name.split(".", 1)
            data.setdefault(table, {})[key] = value
        loaded = scene_file.from_dict(data, self.path)
        return RunSpec(loaded.scene, loaded.excitation, loaded.simulation)


def _values(spec, where):
    if isinstance(spec, list):
        return spec
    if isinstance(spec, dict) and "values" in spec and len(spec) == 1:
        return list(spec["values"])
    if isinstance(spec, dict) and {"start", "stop", "num"} == set(spec):
        return [float(v) for v in np.linspace(spec["start"], spec["stop"], int(spec["num"]))]
    if isinstance(spec, dict) and {"start", "stop", "step"} == set(spec):
        n = int(np.floor((spec["stop"] - spec["start"]) / spec["step"] + 1e-9)) + 1
        return [float(spec["start"] + k * spec["step"]) for k in range(n)]
    raise SweepError(f"{where}: give a list, {{values = [...]}}, {{start, stop, num}} or {{start, stop, step}}; "
                     f"got {spec!r}")


def load_sweep(path) -> Sweep:
    """Read a sweep file (a scene file with a ``[sweep]`` table); errors name the file and key."""
    path = Path(path)
    data = scene_file.read_toml(path, SweepError, "sweep file")
    table = dict(data.get("sweep", {}))
    if not table:
        raise SweepError(f"{path}: no [sweep] table: nothing to vary")
    mode = table.pop("mode", "grid")
    histories = bool(table.pop("time_histories", False))
    parameters = {}
    for section, entries in table.items():
        if section not in ("scene", "contact", "excitation", "simulation") or not isinstance(entries, dict):
            raise SweepError(f"{path}: [sweep.{section}] is not a table of scene, contact, excitation or simulation "
                             f"keys")
        for key, spec in entries.items():
            parameters[f"{section}.{key}"] = _values(spec, f"{path}: [sweep.{section}] {key}")
    build = SceneFileBuild(data, str(path))
    sweep = Sweep(build, parameters, mode, histories)
    try:  # build the first point now: a misspelt key fails here, not in every worker
        build(sweep.points()[0])
    except scene_file.SceneFileError as exc:
        raise SweepError(f"{exc} (with the first point of [sweep])") from None
    return sweep


# --- running ---------------------------------------------------------------------------------------

def measures(result) -> dict:
    """The scene-level measures of a run (those of ``Result.summary`` that are numbers), its end time,
    and peak rotation / displacement of each block."""
    rel = result.relative_x - result.relative_x[0]
    row = {k: v for k, v in result.summary().items() if isinstance(v, (bool, int, float, np.number))}
    row.update(max_peak_displacement_m=float(np.max(np.abs(rel))), end_time_s=float(result.t[-1]))
    for k, name in enumerate(result.names):
        row[f"peak_theta:{name}"] = float(result.peak_theta[k])
        row[f"peak_displacement:{name}"] = float(np.max(np.abs(rel[:, k])))
    return row


def run_point(build, params: dict, history_dir: str | None = None) -> dict:
    """Run one point and return its row; any error becomes the row's ``status``, never an exception."""
    row = {"run_id": run_id(params), **params}
    start = time.perf_counter()
    try:
        spec = build(params)
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
        _write_atomic(result.to_frame(), Path(history_dir) / f"{row['run_id']}.parquet")
    return row


def _write_atomic(frame: pd.DataFrame, path: Path) -> None:
    tmp = path.with_name(path.name + ".tmp")
    frame.to_parquet(tmp, index=False)
    os.replace(tmp, path)


def _finished(runs_dir: Path, retry_failed: bool) -> set:
    done = set()
    for part in runs_dir.glob("*.parquet"):
        if retry_failed:
            status = pd.read_parquet(part, columns=["status"]).status.iloc[0]
            if status != "ok":
                continue
        done.add(part.stem)
    return done


def _executor(workers, scheduler):
    if scheduler is not None:
        try:
            from distributed import Client
        except ImportError:
            raise SweepError("running on a Dask cluster needs dask.distributed: pip install 'dask[distributed]'") from None
        client = scheduler if isinstance(scheduler, Client) else Client(scheduler)
        return client.get_executor(), (None if client is scheduler else client)
    return ProcessPoolExecutor(max_workers=workers or os.cpu_count()), None


def run_sweep(sweep: Sweep, out, *, workers: int | None = None, scheduler=None, progress: bool = True,
              retry_failed: bool = False) -> pd.DataFrame:
    """Run every point not already in ``out`` and return all rows (finished before or now).

    workers : processes on this machine (default: one per core); ignored with a scheduler.
    scheduler : address of a running Dask scheduler, or a ``distributed.Client``.
    retry_failed : run again the points recorded as failed or unstable.
    Returns the table also written to ``out/results.parquet``: one row per point with its
    parameters, ``status`` ("ok", "unstable", "failed"), ``error`` and the measures of
    :func:`measures`, ``wall_time_s``.
    """
    out = Path(out)
    runs_dir = out / "runs"
    runs_dir.mkdir(parents=True, exist_ok=True)
    history_dir = out / "histories" if sweep.time_histories else None
    if history_dir is not None:
        history_dir.mkdir(exist_ok=True)
    points = sweep.points()
    ids = [run_id(p) for p in points]
    if len(set(ids)) != len(ids):
        raise SweepError("the sweep has repeated points; give each parameter distinct values")
    done = _finished(runs_dir, retry_failed)
    todo = [p for p, i in zip(points, ids) if i not in done]
    if todo:
        executor, own_client = _executor(workers, scheduler)
        try:
            futures = [executor.submit(run_point, sweep.build, p, None if history_dir is None else str(history_dir))
                       for p in todo]
            with tqdm(total=len(points), initial=len(points) - len(todo), unit="run", desc="sweep",
                      disable=not progress, smoothing=0.1) as bar:
                for future in as_completed(futures):
                    row = future.result()
                    _write_atomic(pd.DataFrame([row]), runs_dir / f"{row['run_id']}.parquet")
                    bar.update()
        finally:
            if isinstance(executor, ProcessPoolExecutor):
                executor.shutdown(wait=True, cancel_futures=True)
            else:  # Dask's executor: on an interruption, do not wait for the cluster
                executor.shutdown(wait=False)
            if own_client is not None:
                own_client.close()
    return collect(out, order=ids)


def collect(out, order=None) -> pd.DataFrame:
    """Gather ``out/runs/*.parquet`` into one table (in ``order`` of run ids if given) and write
    ``out/results.parquet``."""
    out = Path(out)
    parts = [pd.read_parquet(p) for p in sorted((out / "runs").glob("*.parquet"))]
    if not parts:
        return pd.DataFrame()
    table = pd.concat(parts, ignore_index=True)
    if order is not None:
        rank = {i: k for k, i in enumerate(order)}
        table = table.assign(_rank=table.run_id.map(rank)).sort_values("_rank").drop(columns="_rank")
        table = table.reset_index(drop=True)
    _write_atomic(table, out / RESULTS)
    return table
