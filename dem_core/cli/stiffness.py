"""``dem-core stiffness [SCENE]``: the scene run again at stiffer contacts, and whether each measure converged
(:mod:`dem_core.analyses.convergence`)."""

import math

import numpy as np

from ..analyses.convergence import FLOORS, MEASURES, RELATIVE_TOLERANCE, stiffness_convergence, verdicts
from ..simulation import SimulationUnstable
from .arguments import DEFAULT_SCENE, POSITIVE, SECONDS, add_no_progress, scene_and_settings
from .console import failed_run, percent
from .progress import compile_first, progress_bar, simulate_options


#: what ``dem-core stiffness --help`` says the command does
DESCRIPTION = ("Run the scene at each multiple of its contact stiffness K_n and print the measures (peak rotation, "
               "total sliding, mean rocking, overturn time) at each, with a verdict for each: converged when the "
               "smallest multiple is within 5% of the stiffest, or within 1 mm of sliding, 0.001 rad of rotation, "
               "0.1 s of overturn time; otherwise from which multiple it agrees, and what to do.  The check is the "
               "explicit integrator's, whose contacts have a stiffness: it runs that integrator whatever the scene "
               "file's [simulation] says (Moreau-Jean's rigid contacts have none).")


def add(sub):
    stiffness = sub.add_parser("stiffness", description=DESCRIPTION,
                               help="rerun a scene file at stiffer contacts and judge whether each measure converged")
    stiffness.add_argument("scene", nargs="?", help=f"scene file; default the bundled {DEFAULT_SCENE}")
    stiffness.add_argument("--factors", type=POSITIVE, nargs="+", default=[1.0, 10.0, 100.0],
                           help="multiples of the scene's K_n, each positive (default: 1 10 100)")
    stiffness.add_argument("--duration", type=SECONDS, help="simulated time in s (default: from the file or the "
                           "record)")
    add_no_progress(stiffness)


def run(args) -> int:
    loaded = scene_and_settings(args)
    if loaded is None:
        return 2
    _, spec, settings = loaded
    settings.pop("dt", None)  # each stiffness takes its own automatic step
    if settings.get("integrator") not in (None, "explicit"):
        print(f"note: the scene file's integrator is {settings['integrator']!r}; this check is the explicit core's, "
              "whose answers depend on the contact stiffness: it runs the explicit integrator")
    settings["integrator"] = "explicit"
    compile_first(spec.scene, spec.excitation, settings)
    # a run's length grows as the square root of the stiffness (the step shrinks so): the bar counts that
    bar = progress_bar(total=sum(math.sqrt(max(f, 0.0)) for f in args.factors), desc="runs",
                       bar_format="{desc}: {percentage:3.0f}%|{bar}| [{elapsed}<{remaining}{postfix}]",
                       disable=args.no_progress)

    def on_run(factor, result):
        bar.set_postfix_str(f"K_n x {factor:g} done")
        bar.update(math.sqrt(max(factor, 0.0)))

    try:
        table = stiffness_convergence(spec.scene, spec.excitation, factors=args.factors, on_run=on_run,
                                      **simulate_options(settings, progress=not args.no_progress))
    except (SimulationUnstable, TypeError, ValueError) as exc:
        return failed_run(exc)
    finally:
        bar.close()
    shown = table[["factor", "kn", "dt_s", "run_time_s", *MEASURES]].rename(columns={"kn": "kn_N/m^2"})
    print(shown.to_string(index=False, float_format="%.4g"))
    for line in verdict_lines(table):
        print(line)
    return 0


def verdict_lines(table) -> list:
    """The lines that judge each measure of a stiffness table: its name, its value at each factor, and whether it
    converged (:func:`dem_core.analyses.convergence.verdicts`), with what to do when it did not."""
    found = verdicts(table)
    if len(table) < 2:
        return ["one stiffness only: nothing to compare (give two --factors or more)"]
    lowest, stiffest = found[0].factors[0], found[0].factors[-1]
    floors = ", ".join(f"{_measure_text(value, unit)} of {what}" for what, value, unit in (
        ("rotation", FLOORS["max_peak_abs_theta_rad"], "rad"), ("sliding", FLOORS["total_sliding_m"], "m"),
        ("overturn time", FLOORS["overturn_time_s"], "s")))
    lines = [f"each measure at K_n x {lowest:g} against x {stiffest:g}, the stiffest: converged when it changes by "
             f"at most {percent(RELATIVE_TOLERANCE)}, or by less than {floors}"]
    kn = dict(zip(table.factor, table.kn))
    for v in found:
        values = ", ".join(f"{_measure_text(value, v.unit)} at x {factor:g}" for factor, value in
                           zip(v.factors, v.values))
        lines.append(f"  {v.label}: {values}")
        if all(np.isnan(value) for value in v.values):
            lines.append("    converged: " + ("no overturn at any stiffness" if v.measure == "overturn_time_s" else
                                             "not measured"))
            continue
        if np.isnan(v.values[0]) != np.isnan(v.values[-1]):
            change = "an overturn at one stiffness and none at the other"
        else:
            relative = f"{v.change:+.1%}, " if np.isfinite(v.change) else ""
            change = f"{relative}{_measure_text(v.difference, v.unit, signed=True)}"
        if v.converged and np.isfinite(v.change) and abs(v.change) > RELATIVE_TOLERANCE:
            floor = _measure_text(FLOORS[v.measure], v.unit)
            lines.append(f"    converged: x {lowest:g} differs from x {stiffest:g} by {v.change:+.1%}, but only by "
                         f"{_measure_text(v.difference, v.unit, signed=True)}, less than the {floor} floor")
        elif v.converged:
            within = percent(RELATIVE_TOLERANCE) if np.isfinite(v.change) else "the floor"
            lines.append(f"    converged: x {lowest:g} within {within} of x {stiffest:g} ({change})")
        elif v.agrees_from < stiffest:
            lines.append(f"    not converged at x {lowest:g} ({change}); it agrees from x {v.agrees_from:g}: rerun at "
                         f"a stiffer K_n ([contact] kn = {kn[v.agrees_from]:.3g}) or treat this measure as uncertain")
        else:
            lines.append(f"    not converged ({change} at x {lowest:g}), and the two stiffest runs disagree too: treat "
                         f"this measure as uncertain, or rerun stiffer still ([contact] kn)")
    return lines


def _measure_text(value: float, unit: str, signed: bool = False) -> str:
    """A measure as the stiffness command prints it: lengths in mm below 1 m, "none" for NaN (no overturn)."""
    if not np.isfinite(value):
        return "none"
    sign = "+" if signed else ""
    if unit == "m" and abs(value) < 1.0:
        return f"{1e3 * value:{sign}.3g} mm"
    return f"{value:{sign}.4g} {unit}"
