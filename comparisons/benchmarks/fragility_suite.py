"""A fragility study's time on this machine and on a local Dask cluster: the 8-drum column (the bundled default
scene) under the bundled demonstration suite, each motion scaled to evenly spaced PGA stripes up to 1 g, by the
default integrator at its automatic step; the same study on this machine's cores and on a local Dask cluster of
``--workers`` worker processes, with whether the two give the same table.

    python -m comparisons fragility-suite [--records 40] [--stripes 20] [--workers 2]
"""

import argparse
import tempfile
import time
import warnings

import pandas as pd

from dem_core.analyses.cluster import local_cluster
from dem_core.analyses.fragility_study import DEFAULT_STATES, fragility_study, stripes
from dem_core.analyses.run_identity import machine
from dem_core.cli import default_scene_path
from dem_core.inputs.records import G_STANDARD
from dem_core.inputs.scene_file import load
from dem_core.inputs.suites import DEFAULT_SUITE, load_suite

#: what the two studies must share, run by run (not how long each took)
OUTCOME = ["record", "level", "status", "overturned", "damage_ratio"]


def arguments(parser: argparse.ArgumentParser) -> None:
    """The options of its subcommand of ``python -m comparisons``."""
    parser.add_argument("--records", type=int, default=40, help="the suite's first RECORDS motions")
    parser.add_argument("--stripes", type=int, default=20, help="PGA stripes, evenly spaced up to 1 g")
    parser.add_argument("--workers", type=int, default=2, help="worker processes of the local Dask cluster, each "
                        "with one thread (0: no cluster)")


def run(args: argparse.Namespace) -> None:
    """Run with the options of :func:`arguments` and print the results."""
    scene = load(default_scene_path()).scene
    suite = dict(list(load_suite(DEFAULT_SUITE).motions().items())[:args.records])
    levels = stripes(args.stripes, G_STANDARD)
    runs = len(suite) * len(levels)
    print(f"{len(suite)} motions of the {DEFAULT_SUITE} suite x {len(levels)} PGA stripes up to 1 g = {runs} runs of "
          f"the 8-drum column; {machine()}")
    warnings.simplefilter("ignore", RuntimeWarning)  # a short suite: fewer records than advised, said once here
    fragility_study(scene, dict(list(suite.items())[:1]), levels[:2], DEFAULT_STATES)  # the kernel compiled
    started = time.perf_counter()
    here = fragility_study(scene, suite, levels, DEFAULT_STATES)
    rows = [(f"this machine ({here.device})", time.perf_counter() - started)]
    if args.workers:
        with local_cluster(args.workers) as cluster, \
                tempfile.TemporaryDirectory() as folder:
            started = time.perf_counter()
            there = fragility_study(scene, suite, levels, DEFAULT_STATES, scheduler=cluster.scheduler_address,
                                    log=f"{folder}/members.jsonl")
            rows.append((f"local Dask cluster ({there.device})", time.perf_counter() - started))
        same = here.runs[OUTCOME].equals(there.runs[OUTCOME]) and here.table().equals(there.table())
    print(f"{'where':72s} {'wall (s)':>9s} {'runs/min':>9s}")
    for label, wall in rows:
        print(f"{label:72s} {wall:9.1f} {runs / wall * 60:9.0f}")
    print(here.table()[["state", "median", "median_low", "median_high", "beta", "exceeded"]].to_string(index=False))
    if args.workers:
        print(f"the Dask cluster's runs and table are {'the same' if same else 'NOT the same'} as this machine's")
        if not same:
            print(pd.concat([here.table(), there.table()]).to_string())
