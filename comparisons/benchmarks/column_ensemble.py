"""The 8-drum column under the bundled records: Moreau-Jean's convergence in dt, its agreement with the explicit
core and pymunk, and the time of each, measured in the same run.

Members: the column of :func:`dem_core.scenes.column` (8 drums) under each bundled record's strong-motion window
(:func:`comparisons.cases.strong_motion.strong_motion`) at ``--scales`` times the column's rocking threshold
g tan(alpha), for ``--duration`` s.  Each member runs in

* ``dem-moreau`` at 1e-3, 5e-4 and 2.5e-4 s (its automatic step and two halvings);
* ``dem`` (the explicit core, corner law) at its automatic step;
* ``pymunk`` at 1e-3 s.

Printed: per engine and step, the median time of a run and its cost per block-step; per pair of runs, the typical
member difference of the top drum's peak rotation (median of |log(peak_a / peak_b)| over members that stand in
both and rock in the second, its peak above the ensembles' floor of alpha/30) with a bootstrap interval of that
median, and the share of members on whose overturning the two agree.  The members are chaotic and the
differences heavy-tailed: the default 13 scales (52 members) narrow the median's interval, which on 3 scales
spans a factor of about 20.

    python -m comparisons column-ensemble [--scales 1.2,1.3,...,2.4] [--duration 20]
"""

import argparse
import time
import warnings

import numpy as np

import adapters
import dem_core
from comparisons.cases.strong_motion import strong_motion
from comparisons.harness.ensembles import ROCKING_FLOOR
from dem_core import records, scenes

DRUMS = 8
#: the column's overall width and height (m): it starts to rock at g width / height
WIDTH, HEIGHT = 1.0, 6.0
#: (label, engine of adapters.simulate, options)
RUNS = (
    ("dem-moreau 1e-3 s", "dem", {"integrator": "moreau", "dt": 1e-3}),
    ("dem-moreau 5e-4 s", "dem", {"integrator": "moreau", "dt": 5e-4}),
    ("dem-moreau 2.5e-4 s", "dem", {"integrator": "moreau", "dt": 2.5e-4}),
    ("dem auto", "dem", {}),
    ("pymunk 1e-3 s", "pymunk", {"dt": 1e-3}),
)
#: resamples of the bootstrap interval of the typical member difference
BOOTSTRAP_SAMPLES = 2000
#: the pairs whose member differences are printed
PAIRS = (("dem-moreau 1e-3 s", "dem-moreau 2.5e-4 s"), ("dem-moreau 5e-4 s", "dem-moreau 2.5e-4 s"),
         ("dem-moreau 1e-3 s", "dem auto"), ("dem-moreau 2.5e-4 s", "dem auto"), ("pymunk 1e-3 s", "dem auto"))


def arguments(parser: argparse.ArgumentParser) -> None:
    """The options of its subcommand of ``python -m comparisons``."""
    parser.add_argument("--scales", default=",".join(f"{s:.1f}" for s in np.arange(1.2, 2.45, 0.1)),
                        help="multiples of the column's rocking threshold g tan(alpha) (comma-separated)")
    parser.add_argument("--duration", type=float, default=20.0, help="s of each record's strong motion")


def _member_runs(column, motion, duration):
    """{label: (peak |theta| of the top drum up to an overturn (rad), overturned, wall time (s), steps)}."""
    out = {}
    for label, engine, options in RUNS:
        with warnings.catch_warnings():
            warnings.simplefilter("ignore")
            result = adapters.simulate(column, motion, duration, engine=engine, output_dt=0.005, **options)
        overturned = bool(np.isfinite(result.time_of_overturn))
        theta = result.theta[:, -1]
        out[label] = (float(np.nanmax(np.abs(theta))), overturned, float(result.info["run_time_s"]),
                      float(result.info["steps"]))
    return out


def run(args: argparse.Namespace) -> None:
    """Run with the options of :func:`arguments` and print the results."""
    column = scenes.column(DRUMS, WIDTH, HEIGHT)
    threshold = column.gravity * WIDTH / HEIGHT
    scales = [float(s) for s in args.scales.split(",")]
    members = [(name, scale) for name in records.BUNDLED for scale in scales]
    dem_core.simulate(scenes.column(2), duration=0.01, integrator="moreau")  # compile before timing
    table = {}
    start = time.perf_counter()
    for name, scale in members:
        table[(name, scale)] = _member_runs(column, strong_motion(name, scale * threshold), args.duration)
    print(f"8-drum column, {len(members)} members ({', '.join(records.BUNDLED)} at {args.scales} x g tan(alpha) = "
          f"{threshold:.3g} m/s^2), {args.duration:g} s each; {time.perf_counter() - start:.0f} s in all\n")
    pymunk_time = np.median([table[m]["pymunk 1e-3 s"][2] for m in members])
    for label, _, _ in RUNS:
        times = [table[m][label][2] for m in members]
        cost = np.median([table[m][label][2] / table[m][label][3] / DRUMS for m in members])
        print(f"  {label:22s} median {np.median(times):7.3f} s a run ({1e9 * cost:6.0f} ns per block-step), "
              f"time / pymunk {np.median(times) / pymunk_time:5.2f}, overturned in "
              f"{sum(table[m][label][1] for m in members)} of {len(members)}")
    print()
    floor = ROCKING_FLOOR * np.arctan(WIDTH / HEIGHT)
    for a, b in PAIRS:
        standing = [m for m in members if not table[m][a][1] and not table[m][b][1] and table[m][b][0] >= floor]
        logs = np.array([abs(np.log(table[m][a][0] / table[m][b][0])) for m in standing])
        agree = np.mean([table[m][a][1] == table[m][b][1] for m in members])
        draws = np.random.default_rng(0).choice(logs, (BOOTSTRAP_SAMPLES, len(logs)))
        low, high = np.percentile(np.median(draws, axis=1), [5.0, 95.0])
        print(f"  {a:22s} against {b:22s}: typical member difference {np.median(logs):.2%} "
              f"(bootstrap 90% {low:.2%} to {high:.2%}; 90th percentile {np.percentile(logs, 90):.1%}; "
              f"{len(standing)} standing and rocking), agree on overturning {agree:.0%}")
