"""Wall time and error of the native core against pymunk, measured in the same run.

For every single-block case of :mod:`comparisons.cases.catalogue` and for the 8-drum column under 20 s of the
1940 El Centro record: the native core at its automatic step (both contact laws, and Moreau-Jean) and pymunk
at 1e-3 s,
interleaved so that all see the same machine, each timing the best of ``--repeats`` runs of the
engine's own stepping (compile or build time apart).  Printed per case: the time step, the wall time,
the case's primary error, and the ratio of the native core's time to pymunk's (below 1: faster).
The column has no closed form: its error is against the native core at an eighth of its step.

    python -m comparisons against-pymunk [--repeats 5] [--cases free_rocking,newmark]
"""

import argparse
import os
import subprocess
import sys
import tempfile

import numpy as np

import dem_core
from adapters import pymunk_adapter
from comparisons.cases.catalogue import all_cases
from comparisons.harness.engines import NATIVE_INTEGRATORS, NATIVE_LAWS, native_scene
from dem_core import excitation, scenes

PYMUNK_DT = 1e-3
COLUMN_DURATION = 20.0  # s of El Centro


def cold_compile_time() -> float:
    """Compile time of the stepping kernel in a new process with an empty numba cache (s)."""
    probe = ("import dem_core; r = dem_core.simulate(dem_core.scenes.column(2), duration=0.01, "
             "integrator='explicit'); "
             "print(r.info['compile_time_s'])")
    with tempfile.TemporaryDirectory() as cache:
        env = {**os.environ, "NUMBA_CACHE_DIR": cache}
        done = subprocess.run([sys.executable, "-c", probe], env=env, capture_output=True, text=True, check=True)
    return float(done.stdout.split()[-1])


def _runners(scene, motion, duration, output_dt):
    runs = {engine: (lambda engine=engine: dem_core.simulate(native_scene(scene, engine), motion, duration=duration,
                                                              output_dt=output_dt,
                                                              integrator=NATIVE_INTEGRATORS[engine]))
            for engine in NATIVE_LAWS}
    runs["pymunk"] = lambda: pymunk_adapter.simulate(scene, motion, duration=duration, dt=PYMUNK_DT,
                                                     output_dt=output_dt)
    return runs


def _best_of(runs, repeats):
    """{engine: fastest result} with the engines interleaved ``repeats`` times."""
    best = {}
    for _ in range(repeats):
        for engine, make in runs.items():
            result = make()
            if engine not in best or result.info["run_time_s"] < best[engine].info["run_time_s"]:
                best[engine] = result
    return best


def single_block_cases(names=None):
    return [c for c in all_cases() if len(c.scene().blocks) == 1 and (names is None or c.name in names)]


def arguments(parser: argparse.ArgumentParser) -> None:
    """The options of its subcommand of ``python -m comparisons``."""
    parser.add_argument("--repeats", type=int, default=5)
    parser.add_argument("--cases", help="comma-separated case names (default: every single-block case)")


def run(args: argparse.Namespace) -> None:
    """Run with the options of :func:`arguments` and print the results."""
    names = args.cases.split(",") if args.cases else None

    first = dem_core.simulate(scenes.block(1.0, 2.0), duration=0.01)
    print(f"native kernel: loaded from numba's cache in {first.info['compile_time_s']:.3f} s; compiled from "
          f"scratch in {cold_compile_time():.1f} s (a fresh process with an empty cache)\n")
    header = f"{'case':28s} {'engine':12s} {'dt (s)':>9s} {'wall (s)':>9s} {'error':>10s} {'time / pymunk':>14s}"
    print(header)
    worst = {engine: 0.0 for engine in NATIVE_LAWS}
    for case in single_block_cases(names):
        reference = case.reference()
        best = _best_of(_runners(case.scene(), case.motion(), case.duration, case.output_dt), args.repeats)
        pymunk_time = best["pymunk"].info["run_time_s"]
        for engine, result in best.items():
            errors = case.errors(result, reference)
            metric = case.primary or next(iter(errors))
            ratio = result.info["run_time_s"] / pymunk_time
            if engine in worst:
                worst[engine] = max(worst[engine], ratio)
            print(f"{case.name:28s} {engine:12s} {result.dt:9.2e} {result.info['run_time_s']:9.4f} "
                  f"{errors[metric]:+10.2e} {ratio:14.2f}")
    print("largest time / pymunk over the single-block cases: "
          + ", ".join(f"{engine} {ratio:.2f}" for engine, ratio in worst.items()))

    print(f"\n8-drum column, {COLUMN_DURATION:g} s of El Centro 1940 (outputs every 5 ms)")
    column, motion = scenes.column(8), excitation.record("el_centro_1940")
    reference = dem_core.simulate(column, motion, duration=COLUMN_DURATION, output_dt=0.005, step_fraction=1 / 8,
                                  integrator="explicit")
    best = _best_of(_runners(column, motion, COLUMN_DURATION, 0.005), args.repeats)
    peak = np.max(np.abs(reference.theta[:, -1]))
    for engine, result in best.items():
        ratio = result.info["run_time_s"] / best["pymunk"].info["run_time_s"]
        error = np.max(np.abs(result.theta[:, -1])) / peak - 1.0
        steps = result.info["steps"]
        print(f"  {engine:12s} dt {result.dt:.2e} s, {steps} steps, {result.info['run_time_s']:.3f} s "
              f"({1e9 * result.info['run_time_s'] / steps / len(column.blocks):.0f} ns per block-step), top-drum "
              f"peak {error:+.2%} against the corner law at dt/8, time / pymunk {ratio:.2f}")

