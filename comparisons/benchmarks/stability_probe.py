"""How far the estimated stability limit of the native core is from the real one.

For a few scenes, runs at ``dt = factor x stability_limit`` for growing
factors, with the limit check off, and prints two factors: the first at
which a mirror-image ground motion stops giving the mirror-image response
(past the limit the scheme chatters, bounded by friction: results are
silently wrong there), and the first at which the run stops with a stability
error (energy, speed and overlap checks).  Up to the estimate both must hold.

    python -m comparisons stability-probe
"""

import argparse
import warnings

import numpy as np

import dem_core
from dem_core import excitation, scenes, stability
from dem_core.engine.model import compile_model

PULSE = (4.0, 0.25)  # one-sine pulse, m/s^2 and s, that sets every scene rocking without overturning it
DURATION = 1.0


def probe_cases():
    return [
        ("Housner block 0.25 x 1.0 m", scenes.block(0.25, 1.0), lambda names: names),
        ("1 x 6 m monolith", scenes.block(1.0, 6.0), lambda names: names),
        ("8-drum column", scenes.column(8), lambda names: names),
        ("3-column colonnade (b)", scenes.colonnade(3, 3, epistyle="b"),
         lambda names: [n.replace("c1_", "c#_").replace("c3_", "c1_").replace("c#_", "c3_")
                        .replace("epistyle1", "e#").replace("epistyle2", "epistyle1").replace("e#", "epistyle2")
                        for n in names]),
    ]


def mirror_asymmetry(scene, mirrored_names, dt):
    """max |theta(motion) + theta(mirrored motion)| over max |theta|, blocks matched by their mirror images."""
    with warnings.catch_warnings():
        warnings.filterwarnings("ignore", message="dt = .* times the stability limit")  # probed on purpose
        runs = [dem_core.simulate(scene, excitation.sine_pulse(sign * PULSE[0], PULSE[1]), duration=DURATION,
                                  dt=dt, output_dt=1e-3, enforce_stability_limit=False, integrator="explicit")
                for sign in (1.0, -1.0)]
    a, b = runs
    if len(a.t) != len(b.t):  # one of the two overturned first
        return np.inf
    order = [b.names.index(n) for n in mirrored_names(list(a.names))]
    return float(np.max(np.abs(a.theta + b.theta[:, order])) / np.max(np.abs(a.theta)))


def arguments(parser: argparse.ArgumentParser) -> None:
    """The options of its subcommand of ``python -m comparisons``."""
    parser.add_argument("--factors", default="0.8,1,1.25,1.5,2,2.5,3,4", help="multiples of the limit")


def run(args: argparse.Namespace) -> None:
    """Run with the options of :func:`arguments` and print the results."""
    factors = [float(f) for f in args.factors.split(",")]
    print(f"{'case':30s} {'limit (s)':>10s} {'asymmetric from':>16s} {'stopped from':>13s}")
    for name, scene, mirrored in probe_cases():
        limit = stability.stability_limit(compile_model(scene))
        asymmetric = stopped = np.inf
        for f in factors:
            try:
                if mirror_asymmetry(scene, mirrored, f * limit) > 1e-9:
                    asymmetric = min(asymmetric, f)
            except dem_core.SimulationUnstable:
                stopped = f
                asymmetric = min(asymmetric, f)
                break
        print(f"{name:30s} {limit:10.3e} {asymmetric:16.2f} {stopped:13.2f}")
    print(f"default: dt = min({dem_core.simulation.DEFAULT_SAFETY} x limit, impact duration / "
          f"{dem_core.simulation.DEFAULT_STEPS_PER_IMPACT})")

