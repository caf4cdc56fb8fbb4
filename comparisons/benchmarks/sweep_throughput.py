"""Sweep throughput on this machine: runs per minute of a 100-run frequency x PGA grid of the 8-drum column.

The grid: 10 frequencies (0.5 to 5 Hz) x 10 PGAs (1 to 5.5 m/s^2) of harmonic motion, 10 s each, the
6 m x 1 m column of 8 drums, measures only (no time histories).  The same sweep runs on 1 worker
process, on as many as the machine has cores, and (``--dask``) on a local Dask cluster of that many
worker processes, each time from an empty output folder; the ratios are measured in the same run.

    python -m comparisons sweep-throughput [--runs 100] [--dask]
"""

import argparse
import os
import tempfile
import time

import numpy as np

from dem_core import excitation, scenes
from dem_core.analyses.cluster import local_cluster
from dem_core.analyses.sweep import RunSpec, Sweep, run_sweep

DURATION = 10.0  # s simulated per run


def column_under_harmonic(params):
    return RunSpec(scenes.column(8), excitation.harmonic(pga=params["pga"], frequency=params["frequency"]),
                   {"duration": DURATION, "output_dt": 0.01})


def grid(runs: int) -> Sweep:
    side = round(np.sqrt(runs))
    return Sweep(column_under_harmonic, {"frequency": list(np.round(np.linspace(0.5, 5.0, side), 3)),
                                         "pga": list(np.round(np.linspace(1.0, 5.5, side), 3))})


def timed(sweep, **where):
    with tempfile.TemporaryDirectory() as out:
        start = time.perf_counter()
        table = run_sweep(sweep, out, progress=False, **where)
        wall = time.perf_counter() - start
    assert (table.status == "ok").all(), table.status.value_counts()
    return wall, table


def arguments(parser: argparse.ArgumentParser) -> None:
    """The options of its subcommand of ``python -m comparisons``."""
    parser.add_argument("--runs", type=int, default=100, help="grid size (a square: 100 = 10 x 10)")
    parser.add_argument("--dask", action="store_true", help="also on a local Dask cluster")


def run(args: argparse.Namespace) -> None:
    """Run with the options of :func:`arguments` and print the results."""
    sweep = grid(args.runs)
    n = len(sweep.points())
    cores = os.cpu_count()
    print(f"{n} runs of the 8-drum column, {DURATION:g} s of harmonic motion each, {cores} cores")
    timed(grid(4), workers=1)  # compile cache warm, imports loaded
    rows = []
    one, table = timed(sweep, workers=1)
    rows.append(("1 worker", one))
    all_cores, _ = timed(sweep, workers=cores)
    rows.append((f"{cores} workers", all_cores))
    if args.dask:
        with local_cluster(cores) as cluster:
            timed(grid(4), scheduler=cluster.scheduler_address)  # workers import and load the kernel
            dask_wall, _ = timed(sweep, scheduler=cluster.scheduler_address)
        rows.append((f"Dask, {cores} local workers", dask_wall))
    simulated = table.wall_time_s.sum()
    print(f"time inside the runs (1 worker): {simulated:.1f} s, {simulated / n * 1e3:.0f} ms per run; "
          f"{int(table.overturned.sum())} of {n} runs overturned (they stop early)")
    print(f"{'where':28s} {'wall (s)':>9s} {'runs/min':>9s} {'speed-up':>9s}")
    for label, wall in rows:
        print(f"{label:28s} {wall:9.1f} {n / wall * 60:9.0f} {one / wall:9.2f}")

