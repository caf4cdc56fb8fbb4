"""Do multi-block scenes' answers depend on the contact stiffness?  An ensemble at several K_n.

The 8-drum column and a three-column colonnade (three drums each, a single epistyle of 8000 kg/m^3)
under each bundled record's strong motion (:mod:`comparisons.strong_motion`) at five amplitudes from
1.2 to 3 times the scene's uplift acceleration ``g tan(alpha)``, with the native core's default contact
law at multiples of its default stiffness.  Printed per stiffness: how many members overturn, the
median peak rotation (largest |theta| of any block) over the members that stand at every stiffness,
and, against the stiffest, the median ratio of those peaks and the agreement on overturning.  A member
near a jump of the response can change by a factor under any change; the ensemble median is the measure.

    python -m comparisons.stiffness_ensembles [--scene column|colonnade] [--factors 1 10 100]
"""

import argparse
import time

import numpy as np

import dem_core
from comparisons.strong_motion import strong_motion
from dem_core import records, scenes

SCALES = (1.2, 1.65, 2.1, 2.55, 3.0)
SCENES = {
    "column": lambda: scenes.column(8),
    "colonnade": lambda: scenes.colonnade(3, 3, spacing=2.5, epistyle="a", epistyle_density=8000.0),
}


def peaks(scene, factor: float) -> tuple:
    """(peak |theta| (members,) rad, overturned (members,) bool) of the ensemble at ``factor`` x K_n."""
    contact = dem_core.ContactParameters(kn=factor * dem_core.ContactParameters().kn)
    scene = scene.replace(contact=contact)
    uplift = scene.gravity * np.tan(scene.rocking_slenderness)
    out, over = [], []
    for name in records.BUNDLED:
        for scale in SCALES:
            motion = strong_motion(name, scale * uplift)
            try:
                result = dem_core.simulate(scene, motion, duration=motion.end_time)
                out.append(float(np.max(result.peak_theta)))
                over.append(bool(result.overturned))
            except dem_core.SimulationUnstable:
                out.append(np.nan)
                over.append(True)
    return np.array(out), np.array(over)


def main(argv=None):
    parser = argparse.ArgumentParser(description=__doc__.splitlines()[0])
    parser.add_argument("--scene", choices=list(SCENES), default="column")
    parser.add_argument("--factors", type=float, nargs="+", default=[1.0, 10.0, 100.0])
    args = parser.parse_args(argv)
    scene = SCENES[args.scene]()
    runs = {}
    for factor in args.factors:
        started = time.perf_counter()
        runs[factor] = peaks(scene, factor)
        print(f"{args.scene}: {factor:g} x K_n done in {time.perf_counter() - started:.0f} s", flush=True)
    standing = np.all([~over for _, over in runs.values()], axis=0)
    stiffest = runs[max(args.factors)]
    print(f"{args.scene}, {len(standing)} members, {standing.sum()} standing at every stiffness")
    for factor, (peak, over) in runs.items():
        ratio = np.median(peak[standing] / stiffest[0][standing])
        print(f"  {factor:g} x K_n = {factor * dem_core.ContactParameters().kn:.0e}: overturned {over.sum()}, median "
              f"peak {np.median(peak[standing]):.5f} rad, median ratio to the stiffest {ratio:.4f}, agrees on "
              f"overturning with it {np.mean(over == stiffest[1]):.0%}")


if __name__ == "__main__":
    main()
