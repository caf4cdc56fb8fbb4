"""The joints' slip of the bundled default (the 8-drum column under El Centro) per restitution and integrator.

Moreau-Jean imposes Newton's coefficient ``e`` at the points; the explicit core gives it by the points' dashpots
(:mod:`dem_core.engine.contact`), at least ``EXPLICIT_LEAST_RESTITUTION`` where ``e = 0`` is asked, at ``K_n``,
ten and a hundred times it.  Each row is one run of ``--duration`` s: its wall time and the slip of each joint,
base first (mm of kinematic travel, docs/method.md section 3).  The explicit core's rows below its least
restitution show where its slips go as its dashpots grow (damping ratios past 5, shorter steps).

    python -m comparisons restitution [--duration 20] [--restitutions 0 0.1 0.2] [--below 0.005]
"""

import argparse
import time

import dem_core
from dem_core import excitation, scenes
from dem_core.engine.contact import EXPLICIT_LEAST_RESTITUTION, ContactParameters, damping_ratio_for_restitution

#: the explicit core's stiffness factors
KN_FACTORS = (1.0, 10.0, 100.0)


def arguments(parser: argparse.ArgumentParser) -> None:
    """The options of its subcommand of ``python -m comparisons``."""
    parser.add_argument("--duration", type=float, default=20.0, help="seconds of El Centro")
    parser.add_argument("--restitutions", type=float, nargs="+", default=[0.0, 0.1, 0.2],
                        help="the restitutions asked of both integrators")
    parser.add_argument("--below", type=float, nargs="*", default=[0.005],
                        help="restitutions under the explicit core's least, given by its damping ratio")


def joint_slips(contact: ContactParameters, integrator: str, duration: float) -> tuple[float, list]:
    """(wall time s, [slip of each joint, m, base first]) of one run of the 8-drum column under El Centro."""
    scene = scenes.column(8, contact=contact)
    began = time.perf_counter()
    result = dem_core.simulate(scene, excitation.record("el_centro_1940"), duration, integrator=integrator)
    wall = time.perf_counter() - began
    return wall, [result.interface_slip.get(tuple(pair), 0.0) for pair in result.interfaces]


def _row(label: str, wall: float, slips: list) -> None:
    print(f"  {label:44s} {wall:6.1f} s  " + " ".join(f"{1e3 * s:6.3f}" for s in slips)
          + f"   max {1e3 * max(slips):.3f} mm", flush=True)


def run(args: argparse.Namespace) -> None:
    print(f"8-drum column, El Centro, {args.duration:g} s: joint slips in mm, base first "
          f"(the explicit core's least restitution: {EXPLICIT_LEAST_RESTITUTION:g})")
    for e in args.restitutions:
        contact = ContactParameters(restitution=e)
        _row(f"moreau   e = {e:g}", *joint_slips(contact, "moreau", args.duration))
        for factor in KN_FACTORS:
            stiff = dem_core.contact.stiffer(contact, factor)
            given = stiff.explicit_restitution
            _row(f"explicit e = {given:g}, K_n x{factor:g}", *joint_slips(stiff, "explicit", args.duration))
    for e in args.below:
        zeta = damping_ratio_for_restitution(e)
        for factor in KN_FACTORS:
            contact = dem_core.contact.stiffer(ContactParameters(damping_ratio=zeta), factor)
            _row(f"explicit e = {e:g} (zeta {zeta:.3g}), K_n x{factor:g}",
                 *joint_slips(contact, "explicit", args.duration))
