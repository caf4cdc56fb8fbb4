"""Whether a block that passes its critical angle comes back: the rocking reference counting the overturn at alpha
(the project's rule, docs/method.md section 3) and at pi/2 (the block lands on its side), and the native core run
on to the end with either integrator.

Members: the report's rocking ensemble (:func:`comparisons.harness.ensembles.ensemble` ``"rocking_records"``) and
a wider one, five blocks from 0.25 x 1 m to 1.5 x 6 m under the four bundled records at ``--scales`` amplitudes
from 1.2 to ``--highest`` g tan(alpha).  For each it prints the members, how many pass alpha and how many of those
come back (the reference at pi/2 does not overturn; a native run ends upright).

    python -m comparisons overturn-rule [--scales 25] [--highest 6] [--no-native]
"""

import argparse
import warnings

import numpy as np

import dem_core
from comparisons.cases.strong_motion import strong_motion
from comparisons.harness.ensembles import Ensemble, ensemble
from comparisons.references import analytical
from comparisons.references.rocking_equation import rocking_response

#: the wider ensemble's blocks (width, height), m
WIDE_BLOCKS = ((1.0, 6.0), (1.5, 6.0), (0.6, 3.0), (1.0, 3.0), (0.25, 1.0))


def arguments(parser: argparse.ArgumentParser) -> None:
    """The options of its subcommand of ``python -m comparisons``."""
    parser.add_argument("--scales", type=int, default=25, help="amplitudes per record in the wider ensemble")
    parser.add_argument("--highest", type=float, default=6.0, help="its largest multiple of g tan(alpha)")
    parser.add_argument("--no-native", action="store_true", help="the reference alone")


def reference_counts(ens: Ensemble) -> tuple[int, int, int]:
    """(members, members whose reference passes alpha, of those the ones that do not fall to pi/2)."""
    passed = came_back = 0
    members = ens.members()
    for m in members:
        motion, block = strong_motion(m.record, m.pga), analytical.RockingBlock.from_size(*m.block)
        at_alpha = rocking_response(block, motion, m.duration).overturned
        falls = rocking_response(block, motion, m.duration, overturn_angle=0.5 * np.pi).overturned
        passed += at_alpha
        came_back += at_alpha and not falls
    return len(members), passed, came_back


def native_counts(ens: Ensemble, integrator: str) -> tuple[int, int, int]:
    """(members, native runs that pass alpha, of those the ones upright at the end), each run to its end."""
    passed = came_back = 0
    members = ens.members()
    for m in members:
        result = dem_core.simulate(ens.scene(m.block), strong_motion(m.record, m.pga), duration=m.duration,
                                   stop_at_overturn=False, integrator=integrator)
        passed += result.overturned
        came_back += result.overturned and abs(result.theta[-1, 0]) < result.critical_angle[0]
    return len(members), passed, came_back


def run(args: argparse.Namespace) -> None:
    """Run with the options of :func:`arguments` and print the counts."""
    warnings.simplefilter("ignore")
    report = ensemble("rocking_records")
    wide = Ensemble(name="overturn_rule_wide", title="", kind="rocking", blocks=WIDE_BLOCKS,
                    scales=tuple(np.round(np.linspace(1.2, args.highest, args.scales), 3)))
    print(f"{'':66s} {'members':>10s} {'pass alpha':>10s} {'come back':>10s}")
    wide_label = f"{len(WIDE_BLOCKS)} blocks x 4 records x {args.scales} amplitudes to {args.highest:g} g tan(alpha)"
    for label, ens in ((report.name, report), (wide_label, wide)):
        _row(f"{label}, reference", reference_counts(ens))
    if not args.no_native:
        for integrator in dem_core.simulation.INTEGRATORS:
            _row(f"{report.name}, dem {integrator} to the end", native_counts(report, integrator))


def _row(label: str, counts: tuple) -> None:
    print(f"{label:66s} " + " ".join(f"{n:>10d}" for n in counts), flush=True)
