"""What connectors cost a run: the 8-drum column (the bundled default scene) under the whole of El Centro 1940 at
``--pga``, as built and with each preset at every joint, by each integrator at its automatic step: wall time of the
run (compiled beforehand), the ratio to the bare column's by the same integrator, the peak |theta|/alpha and how
many connectors yielded and ruptured.

    python -m comparisons connector-cost [--pga 3.0] [--repeats 3]
"""

import argparse

from dem_core import excitation, scenes, simulate
from dem_core.analyses.run_identity import machine
from dem_core.inputs.connectors import OAK_POLOS, Placement, titanium_bar

VARIANTS = {"as built": [], "oak poles at every joint": [Placement(OAK_POLOS, "all")],
            "titanium bars at every joint": [Placement(titanium_bar(), "all")]}


def arguments(parser: argparse.ArgumentParser) -> None:
    """The options of its subcommand of ``python -m comparisons``."""
    parser.add_argument("--pga", type=float, default=3.0, help="El Centro's PGA, m/s^2")
    parser.add_argument("--repeats", type=int, default=3, help="runs of each; the fastest is kept")


def run(args: argparse.Namespace) -> None:
    """Run with the options of :func:`arguments` and print the results."""
    motion = excitation.record("el_centro_1940", pga=args.pga)
    print(f"8-drum column, El Centro 1940 whole at {args.pga:g} m/s^2; {machine()}")
    print(f"{'integrator':10s} {'variant':30s} {'wall (s)':>9s} {'x bare':>7s} {'peak/alpha':>10s} {'yielded':>8s} "
          f"{'ruptured':>9s}")
    for integrator in ("moreau", "explicit"):
        bare = None
        for variant, placements in VARIANTS.items():
            scene = scenes.column(connectors=placements)
            simulate(scene, motion, duration=0.01, integrator=integrator)  # compiled, or loaded from the cache
            results = [simulate(scene, motion, integrator=integrator) for _ in range(args.repeats)]
            wall = min(r.info["run_time_s"] for r in results)
            bare = wall if bare is None else bare
            table = results[0].connectors
            yielded = "" if table is None else str(int(table.yielded.sum()))
            ruptured = "" if table is None else str(int(table.ruptured.sum()))
            print(f"{integrator:10s} {variant:30s} {wall:9.3f} {wall / bare:7.2f} {results[0].damage_ratio:10.3f} "
                  f"{yielded:>8s} {ruptured:>9s}")
