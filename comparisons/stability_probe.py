"""How far the native core's estimated stability limit is from the real one.

For a few scenes, runs at ``dt = factor x stability_limit`` for growing
factors and prints where the run first stops with a stability error (the
energy, speed and overlap checks of :func:`dem_core.simulate`).  The ratio
is the margin the default safety factor relies on.

    python -m comparisons.stability_probe
"""

import argparse

import numpy as np

import dem_core
from dem_core import excitation, scenes, stability


def probe_cases():
    strong = excitation.record("el_centro_1940", pga=6.0)
    return [
        ("Housner block 0.25 x 1.0 m, free rocking", scenes.block(0.25, 1.0, tilt=0.05236), None, 3.0),
        ("8-drum column, El Centro at 6 m/s^2", scenes.column(8), strong, 3.0),
        ("3-column colonnade (b), El Centro at 6 m/s^2", scenes.colonnade(3, 3, epistyle="b"), strong, 3.0),
    ]


def first_failure(scene, motion, duration, factors):
    """Smallest factor of the stability limit at which the run stops unstable (inf if none)."""
    for f in factors:
        try:
            dem_core.simulate(scene, motion, duration=duration, safety=f)
        except dem_core.SimulationUnstable:
            return f
    return np.inf


def main(argv=None):
    parser = argparse.ArgumentParser(description=__doc__.splitlines()[0])
    parser.add_argument("--factors", default="1,1.25,1.5,2,2.5,3,4", help="comma-separated multiples of the limit")
    args = parser.parse_args(argv)
    factors = [float(f) for f in args.factors.split(",")]
    print(f"{'case':48s} {'limit (s)':>10s} {'first unstable factor':>22s}")
    for name, scene, motion, duration in probe_cases():
        limit = stability.stability_limit(scene)
        fail = first_failure(scene, motion, duration, factors)
        print(f"{name:48s} {limit:10.3e} {fail:22.2f}")
    print(f"default safety factor: {dem_core.simulation.DEFAULT_SAFETY}")


if __name__ == "__main__":
    main()
