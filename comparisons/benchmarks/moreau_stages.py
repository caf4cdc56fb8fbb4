"""Where Moreau-Jean's step spends its time: the driver built again with one stage done twice, or the position
correction left out, each timed on the same run against the driver as built.

A stage that can run twice without changing the run (the ground's input, the world geometry, the joints' offsets,
the checks, the contact manifolds) costs what running it twice adds.  The direct solve done twice starts the second
time from its own answer, whose statuses hold at once: what it adds is a solve of the step's points (its matrix,
one pass), about what the solve costs.  The position correction, which cannot run twice, is left out instead (the
run then drifts, not enough to change its work over the run).  The rest (the index set's rows, the smooth impulse,
the warm start, the positions' update, the impulses kept, the broad phase, the outputs) is what the stages
measured leave.  Each variant compiles once (about 30 s each, in a cache of its own); times are the best of
``--repeats`` runs.

    python -m comparisons moreau-stages [--duration 30] [--repeats 4]
"""

import argparse
import inspect
import time

import numba as nb

from dem_core import excitation, scenes
from dem_core.engine import _active_set, _checks, _driver, _ground, _interfaces, _manifold, _moreau, _world
from dem_core.simulation import Simulation


def _wrapped(body: str, function):
    """An inlined function of ``function``'s parameters whose body is ``body`` (``{names}``: the parameters)."""
    names = ", ".join(inspect.signature(function.py_func).parameters)
    scope = {"f": function}
    exec(f"def wrapped({names}):\n" + body.format(names=names), scope)  # noqa: S102 (a fixed signature to inline)
    return nb.njit(inline="always")(scope["wrapped"])


def _twice(function):
    return _wrapped("    f({names})\n    return f({names})\n", function)


def _moreau_part(name: str, **replaced):
    return nb.njit(_nrt=False)(_driver.variant(_moreau.moreau_part, name, **replaced))


def variants() -> dict:
    """{label: the driver's globals replaced (None: the driver as built)}."""
    checks = nb.njit(inline="always")(_driver.variant(_checks.end_step, "end_step_checked_twice",
                                                      check_bodies=_twice(_checks.check_bodies),
                                                      mark_overturns=_twice(_checks.mark_overturns)))
    manifolds = nb.njit(inline="always")(_driver.variant(_moreau.collect_points, "collect_points_manifolds_twice",
                                                         corner_manifold=_twice(_manifold.corner_manifold)))
    return {
        "as built": None,
        "ground's input twice": {"ground_at": _twice(_ground.ground_at)},
        "world geometry and boxes twice": {"world_geometry": _twice(_world.world_geometry),
                                           "bounding_boxes": _twice(_world.bounding_boxes)},
        "joints' offsets twice": {"follow_interfaces": _twice(_interfaces.follow_interfaces)},
        "checks twice": {"end_step": checks},
        "contact manifolds twice": {"moreau_part": _moreau_part("moreau_part_manifolds_twice",
                                                                collect_points=manifolds)},
        "direct solve twice": {"moreau_part": _moreau_part("moreau_part_solve_twice",
                                                           solve_statuses=_twice(_active_set.solve_statuses))},
        "no position correction": {"moreau_part": _moreau_part(
            "moreau_part_uncorrected", project_positions=_wrapped("    return False\n", _moreau.project_positions))},
    }


def arguments(parser: argparse.ArgumentParser) -> None:
    """The options of its subcommand of ``python -m comparisons``."""
    parser.add_argument("--duration", type=float, default=30.0, help="s of El Centro as recorded")
    parser.add_argument("--repeats", type=int, default=4, help="runs of each variant; the best is kept")


def run(args: argparse.Namespace) -> None:
    """Run with the options of :func:`arguments` and print each variant's time and its change."""
    motion = excitation.record("el_centro_1940")
    base = None
    print(f"8-drum column under {args.duration:g} s of El Centro, Moreau-Jean at 1e-3 s; best of {args.repeats}")
    for label, replaced in variants().items():
        driver = _driver.drive_serial if replaced is None else nb.njit(nogil=True, _nrt=False)(
            _driver.variant(_driver.drive, "drive_" + "".join(c if c.isalnum() else "_" for c in label), **replaced))
        best = float("inf")
        for _ in range(args.repeats + 1):  # the first compiles
            run_ = Simulation(scenes.column(8), motion, args.duration, integrator="moreau")
            kept, _driver.drive_serial = _driver.drive_serial, driver
            try:
                start = time.perf_counter()
                run_.advance()
                best = min(best, time.perf_counter() - start)
            finally:
                _driver.drive_serial = kept
        base = best if base is None else base
        change = "" if replaced is None else f"  {best - base:+.4f} s ({(best - base) / base:+.0%})"
        print(f"  {label:32s} {best:.4f} s{change}", flush=True)
