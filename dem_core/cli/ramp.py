"""``dem-core ramp [SCENE]``: the accelerations at which the scene starts rocking, starts sliding and overturns under
a monotonic ramp (:func:`dem_core.analyses.thresholds.onset_under_ramp`), each with its criterion."""

import math

import numpy as np

from ..analyses.thresholds import ROCKING_FRACTION, SLIP_THRESHOLD, onset_under_ramp
from ..simulation import SimulationUnstable
from .arguments import DEFAULT_SCENE, RATE, SECONDS, add_integrator, default_scene_path, load_or_fail, with_integrator
from .console import acceleration_text, failed_run
from .progress import compile_first, simulate_options


def add(sub):
    ramp = sub.add_parser("ramp", help="rocking, sliding and overturning accelerations under a monotonic ramp, each "
                          "with its criterion",
                          description="Run the scene under a ground acceleration growing at --rate and print the "
                          "accelerations at which it starts rocking (a block's rotation passes theta_cr/30, "
                          "theta_cr the scene's slenderness), starts sliding (an interface slips more than 0.1 mm) "
                          "and overturns, each with its criterion, and, for a single block or column, its static "
                          "uplift acceleration g b/h.")
    ramp.add_argument("scene", nargs="?", help=f"scene file (its [excitation] is ignored); default the bundled "
                      f"{DEFAULT_SCENE}")
    ramp.add_argument("--rate", type=RATE, default=0.5, help="rate at which the ground acceleration grows, m/s^2 per "
                      "s, positive (default: 0.5)")
    ramp.add_argument("--duration", type=SECONDS, help="simulated time in s (default: until the ramp reaches 1 g)")
    add_integrator(ramp)


def run(args) -> int:
    args.scene = args.scene or default_scene_path()
    spec = load_or_fail(args.scene)
    if spec is None:
        return 2
    settings = {k: v for k, v in with_integrator(spec.simulation, args).items() if k not in ("duration", "output_dt")}
    compile_first(spec.scene, None, settings)
    try:
        found = onset_under_ramp(spec.scene, args.rate, args.duration, **simulate_options(settings))
    except (SimulationUnstable, TypeError, ValueError) as exc:
        return failed_run(exc, args.scene)
    theta_cr = spec.scene.rocking_slenderness
    criteria = {
        "starts rocking": f"a block's rotation passes theta_cr/{1 / ROCKING_FRACTION:.0f} = "
                          f"{ROCKING_FRACTION * theta_cr:.3g} rad (theta_cr = {theta_cr:.3g} rad, the scene's "
                          f"slenderness)",
        "starts sliding": f"an interface slips more than {SLIP_THRESHOLD:g} m",
        "overturns": "a block passes its critical angle or falls half its size, or a column tips past its base"}
    print(f"ramp of {args.rate:g} m/s^2 per s, run for {found.result.t[-1]:.4g} s; the ground acceleration when "
          "the scene")
    for what, value in (("starts rocking", found.rocking), ("starts sliding", found.sliding),
                        ("overturns", found.overturning)):
        shown = acceleration_text(value, 4) if np.isfinite(value) else "not reached"
        print(f"  {what:15s} {shown:24s} criterion: {criteria[what]}")
    uplift = _static_uplift(spec.scene, found.result)
    if uplift:
        print(uplift)
    return 0


def _static_uplift(scene, result) -> str:
    """For a scene that is one block, or one stack of blocks (a column), the line giving its static uplift
    acceleration g b/h (b/h = tan of the critical angle: the stack as one rigid body), to set the rocking onset
    against; '' for other scenes."""
    stacks = [c for c in result.columns if set(c.blocks) == set(result.names)]
    if not stacks:
        return ""
    what = "the block" if len(result.names) == 1 else "the column as one rigid block"
    ratio = math.tan(stacks[0].critical_angle)
    return (f"for comparison, the static uplift acceleration g b/h = {acceleration_text(scene.gravity * ratio, 3)} "
            f"({what}, b/h = {ratio:.3g}): a corner starts to lift there; rocking counts from the rotation above")
