"""Calibrate the default contact damping ratio against Housner's impact loss.

Free rocking of a rectangular block released from ``theta0``: the native core's
peak angles after each of the first ``n`` impacts are compared with Housner's
``theta_n`` (docs/method.md 4.2), and the rocking damping ratio ``zeta_r`` of the
overlap-area law (:class:`dem_core.ContactParameters`, the other contact parameters
at their defaults) that minimises the largest relative error is found by bounded
scalar minimisation.  The table ``dem_core.contact.HOUSNER_DAMPING`` (``zeta_r`` per
slenderness, blocks 2 m tall released from 0.2 alpha) is what this script prints; it
also prints the Housner block's own ``zeta_r`` and its peak errors at other steps.

    python -m comparisons calibrate-damping
"""

import argparse

import numpy as np
from scipy.optimize import minimize_scalar

import dem_core
from comparisons.cases.measures import peaks_between_crossings
from comparisons.references import analytical
from dem_core import scenes
from dem_core.engine.model import compile_model

#: the calibration runs at a time step converged for the impacts (a tenth of the stability limit):
#: the model's own energy loss, not the discretisation's, is matched to Housner's
CALIBRATION_STEP = 0.1


def simulated_peaks(width, height, theta0, n_impacts, contact, step=CALIBRATION_STEP):
    """Peak |theta| before the first impact and after each of the next ``n_impacts``, with
    dt = ``step`` x the stability limit, or the automatic dt when ``step`` is None."""
    block = analytical.RockingBlock.from_size(width, height)
    duration = 1.5 * analytical.housner_period(block, theta0) * (n_impacts + 2) / 2.0
    scene = scenes.block(width, height, tilt=theta0, contact=contact)
    dt = None if step is None else step * dem_core.stability.stability_limit(compile_model(scene))
    result = dem_core.simulate(scene, duration=duration, dt=dt, output_dt=1e-9)
    return peaks_between_crossings(result.theta[:, 0], n_impacts + 1)


def peak_errors(width, height, theta0, n_impacts, contact, step=CALIBRATION_STEP):
    """Relative errors of the peaks after impacts 1..n against Housner (``step`` as in :func:`simulated_peaks`)."""
    block = analytical.RockingBlock.from_size(width, height)
    reference = analytical.housner_peaks(block, theta0, n_impacts)[1:]
    sim = simulated_peaks(width, height, theta0, n_impacts, contact, step)[1:]
    if len(sim) < n_impacts:
        return np.full(n_impacts, np.inf)
    return sim / reference - 1.0


#: N/m^2, the overlap-area law's default K_n: the stiffness the damping is calibrated at unless told
OVERLAP_KN = dem_core.contact.DEFAULT_STIFFNESS["overlap_area"]


def calibrate(width=0.25, height=1.0, theta0=0.05236, n_impacts=5, kn=OVERLAP_KN):
    def worst(zeta):
        cp = dem_core.ContactParameters(law="overlap_area", kn=kn, rocking_damping_ratio=zeta)
        return float(np.max(np.abs(peak_errors(width, height, theta0, n_impacts, cp))))

    # the objective is not smooth (peaks jump between output samples): grid first, then refine locally
    grid = np.arange(0.05, 2.5, 0.05)
    start = grid[int(np.argmin([worst(z) for z in grid]))]
    res = minimize_scalar(worst, bounds=(start - 0.05, start + 0.05), method="bounded", options={"xatol": 1e-3})
    return res.x, res.fun


def arguments(parser: argparse.ArgumentParser) -> None:
    """The options of its subcommand of ``python -m comparisons``."""
    parser.add_argument("--kn", type=float, default=OVERLAP_KN)
    parser.add_argument("--alphas", default="0.06,0.08,0.10,0.125,0.15,0.175,0.2,0.25,0.3,0.35,0.4")


def run(args: argparse.Namespace) -> None:
    """Run with the options of :func:`arguments` and print the results."""
    print(f"HOUSNER_DAMPING at kn = {args.kn:.3g} N/m^2 (blocks 2 m tall released from 0.2 alpha):")
    for alpha in (float(a) for a in args.alphas.split(",")):
        height = 2.0
        zeta, err = calibrate(height * np.tan(alpha), height, 0.2 * alpha, 5, kn=args.kn)
        print(f"    ({alpha}, {zeta:.3f}),  # worst peak error over 5 impacts {err:.2%}")
    zeta, err = calibrate(0.25, 1.0, 0.05236, 5, kn=args.kn)
    print(f"0.25 x 1.0 m block from 0.05236 rad alone: zeta = {zeta:.3f}, worst peak error {err:.2%}")
    contact = dem_core.ContactParameters(law="overlap_area", kn=args.kn, rocking_damping_ratio=zeta)
    for step in (0.8, 0.4, 0.2, None):
        errors = peak_errors(0.25, 1.0, 0.05236, 5, contact, step)
        where = "at the automatic dt" if step is None else f"at dt = {step} x the stability limit"
        print(f"  with that zeta {where}: peak errors {np.round(100 * errors, 2)} %")

