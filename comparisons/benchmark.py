"""Wall time and error of the native core against pymunk, measured in the same run.

Cases (issue 2):
* the Housner block (0.25 x 1.0 m from 0.05236 rad), free rocking: wall time
  per simulated second, error of the peaks after impacts 1-5 against
  Housner's decay and of the first impact time against his quarter period;
* an 8-drum column (6 x 1 m) under 20 s of the 1940 El Centro record: wall
  time, and the error of the top drum's rotation against the native core at
  an eighth of its automatic step (how far a quarter of the step is from
  that reference is printed too: the convergence of the reference).

Each timing is the best of ``--repeats`` runs, the engines interleaved, so
that both see the same machine, recording every 10 ms (pymunk reads its
state from Python, so finer outputs would time the reading); the block's
errors come from a run with the same step recording every millisecond.  The
kernel's compile (or cache load) time is printed apart.

    python -m comparisons.benchmark [--repeats 5]
"""

import argparse
import os
import subprocess
import sys
import tempfile

import numpy as np

import dem_core
from adapters import pymunk_adapter
from comparisons import analytical, cases
from comparisons.measures import first_zero_crossing, peaks_between_crossings
from dem_core import excitation, scenes

BLOCK_DURATION = 10.0  # s of free rocking
COLUMN_DURATION = 20.0  # s of El Centro
PYMUNK_DT = 1e-3
BLOCK_OUTPUT_DT = 1e-3  # both engines record the block every millisecond (the peaks are flat: enough)


def housner_errors(result):
    """(worst relative peak error over impacts 1-5, relative error of the first impact time)."""
    block = analytical.RockingBlock.from_size(cases.HOUSNER_WIDTH, cases.HOUSNER_HEIGHT)
    reference = analytical.housner_peaks(block, cases.HOUSNER_THETA0, 5)
    peaks = peaks_between_crossings(result.theta[:, 0], 6)
    if len(peaks) < 6:
        return np.inf, np.inf
    quarter = analytical.housner_period(block, cases.HOUSNER_THETA0) / 4.0
    return (float(np.max(np.abs(peaks[1:] / reference[1:] - 1.0))),
            first_zero_crossing(result.t, result.theta[:, 0]) / quarter - 1.0)


def column_error(result, reference):
    """(relative error of the top drum's peak |theta|, RMS of its theta error over the peak)."""
    top = np.interp(reference.t, result.t, result.theta[:, -1])
    ref = reference.theta[:, -1]
    peak = np.max(np.abs(ref))
    return float(np.max(np.abs(top)) / peak - 1.0), float(np.sqrt(np.mean((top - ref) ** 2)) / peak)


def cold_compile_time() -> float:
    """Compile time of the time-stepping kernel in a new process with an empty numba cache (s)."""
    probe = ("import dem_core; r = dem_core.simulate(dem_core.scenes.column(2), duration=0.01); "
             "print(r.info['compile_time_s'])")
    with tempfile.TemporaryDirectory() as cache:
        env = {**os.environ, "NUMBA_CACHE_DIR": cache}
        done = subprocess.run([sys.executable, "-c", probe], env=env, capture_output=True, text=True, check=True)
    return float(done.stdout.split()[-1])


def main(argv=None):
    parser = argparse.ArgumentParser(description=__doc__.splitlines()[0])
    parser.add_argument("--repeats", type=int, default=5)
    args = parser.parse_args(argv)

    block = cases.housner_scene()
    first = dem_core.simulate(block, duration=0.01)
    print(f"native time-stepping kernel: loaded from numba's cache in {first.info['compile_time_s']:.3f} s; "
          f"compiled from scratch in {cold_compile_time():.2f} s (in a fresh process with an empty cache)")

    print(f"\nHousner block, {BLOCK_DURATION:g} s of free rocking (timed with outputs every 10 ms; "
          f"errors from a run with the same step recorded every {BLOCK_OUTPUT_DT * 1e3:g} ms)")
    runs = {
        "dem": lambda output_dt: dem_core.simulate(block, duration=BLOCK_DURATION, output_dt=output_dt),
        "pymunk": lambda output_dt: pymunk_adapter.simulate(block, duration=BLOCK_DURATION, dt=PYMUNK_DT,
                                                            output_dt=output_dt),
    }
    walls = {engine: [] for engine in runs}
    for _ in range(args.repeats):  # interleave the engines
        for engine, make in runs.items():
            walls[engine].append(make(0.01).info["run_time_s"])
    timings = {}
    for engine, make in runs.items():
        result = make(BLOCK_OUTPUT_DT)
        decay, quarter = housner_errors(result)
        timings[engine] = min(walls[engine])
        print(f"  {engine:7s} dt {result.dt:.3e} s  {1e3 * timings[engine] / BLOCK_DURATION:7.3f} ms per simulated s  "
              f"decay error {decay:6.2%}  quarter-period error {quarter:+6.2%}")
    print(f"  speed ratio pymunk / dem: {timings['pymunk'] / timings['dem']:.2f} (above 1: the native core is faster)")

    print(f"\n8-drum column, {COLUMN_DURATION:g} s of El Centro 1940")
    column = scenes.column(8)
    motion = excitation.record("el_centro_1940")
    auto_dt = dem_core.automatic_time_step(column)
    reference = dem_core.simulate(column, motion, duration=COLUMN_DURATION, output_dt=0.005, dt=auto_dt / 8)
    check = dem_core.simulate(column, motion, duration=COLUMN_DURATION, output_dt=0.005, dt=auto_dt / 4)
    peak_err, rms_err = column_error(check, reference)
    print(f"  reference: native core at dt/8 = {reference.dt:.2e} s; at dt/4 it differs by "
          f"{peak_err:+.2%} in peak, {rms_err:.2%} RMS (the phase of a long rocking response is sensitive)")
    runs = {
        "dem": lambda: dem_core.simulate(column, motion, duration=COLUMN_DURATION, output_dt=0.005),
        "pymunk": lambda: pymunk_adapter.simulate(column, motion, duration=COLUMN_DURATION, dt=PYMUNK_DT,
                                                  output_dt=0.005),
    }
    results = {engine: [] for engine in runs}
    for _ in range(args.repeats):
        for engine, make in runs.items():
            results[engine].append(make())
    for engine in runs:
        result = min(results[engine], key=lambda r: r.info["run_time_s"])
        peak_err, rms_err = column_error(result, reference)
        timings[engine] = result.info["run_time_s"]
        wall = timings[engine]
        print(f"  {engine:7s} dt {result.dt:.3e} s  {wall:6.3f} s for {COLUMN_DURATION:g} s  "
              f"top-drum peak error {peak_err:+7.2%}  RMS error {rms_err:6.2%}")
    print(f"  speed ratio pymunk / dem: {timings['pymunk'] / timings['dem']:.2f} (above 1: the native core is faster)")


if __name__ == "__main__":
    main()
