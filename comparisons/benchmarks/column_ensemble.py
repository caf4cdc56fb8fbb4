"""The 8-drum column under the bundled records: Moreau-Jean's convergence in dt, its agreement with the explicit
core and pymunk, and the time of each, measured in the same run (:mod:`comparisons.harness.column_ensemble`, which
the report also runs).

Printed: per configuration, the median time of a run, its cost per block-step and its time against pymunk's; per
pair of configurations, the typical member difference of the top drum's peak rotation with its 90% bootstrap
interval over members, its 90th percentile, and the share of members on whose overturning the two agree.

    python -m comparisons column-ensemble [--scales 1.2,1.3,...,2.4] [--duration 20]
"""

import argparse
import time

import dem_core
from comparisons.harness import column_ensemble
from dem_core import records, scenes


def arguments(parser: argparse.ArgumentParser) -> None:
    """The options of its subcommand of ``python -m comparisons``."""
    parser.add_argument("--scales", default=",".join(f"{s:g}" for s in column_ensemble.SCALES),
                        help="multiples of the column's rocking threshold g tan(alpha) (comma-separated)")
    parser.add_argument("--duration", type=float, default=column_ensemble.DURATION,
                        help="s of each record's strong motion")


def run(args: argparse.Namespace) -> None:
    """Run with the options of :func:`arguments` and print the results."""
    scales = [float(s) for s in args.scales.split(",")]
    dem_core.simulate(scenes.column(2), duration=0.01, integrator="moreau")  # compile before timing
    dem_core.simulate(scenes.column(2), duration=0.01, integrator="explicit")
    start = time.perf_counter()
    table = column_ensemble.run_column_ensemble(scales=scales, duration=args.duration)
    members = len(table.drop_duplicates(["record", "scale"]))
    print(f"8-drum column, {members} members ({', '.join(records.BUNDLED)} at {args.scales} x g tan(alpha)), "
          f"{args.duration:g} s each; {time.perf_counter() - start:.0f} s in all\n")
    for r in column_ensemble.summarise_runs(table).itertuples():
        print(f"  {r.run:22s} median {r.median_wall_time_s:7.3f} s a run ({r.ns_per_block_step:6.0f} ns per "
              f"block-step), time / pymunk {r.time_vs_pymunk:5.2f}, overturned in {r.overturned} of {r.members}")
    print()
    for r in column_ensemble.summarise_pairs(table).itertuples():
        print(f"  {r.run:22s} against {r.against:22s}: typical member difference {r.typical_difference:.2%} "
              f"(bootstrap 90% {r.interval_low:.2%} to {r.interval_high:.2%}; 90th percentile "
              f"{r.p90_difference:.1%}; {r.compared} standing and rocking), agree on overturning "
              f"{r.overturn_agreement:.0%}")
