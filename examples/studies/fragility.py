"""Fragility curves of the 8-drum column (6 m x 1 m, the bundled default scene: friction 0.7, corner law) under
the four bundled records, each scaled to 256 PGA stripes from 1/256 g to 1 g: 1,024 runs, one batch on every
core (:func:`dem_core.analyses.fragility_study.fragility_study`), Moreau-Jean at its automatic step.

Damage states: peak |theta|/alpha of 0.1, 0.3 and 0.5 (alpha the column's critical angle) and overturning.  The
same study at half the step on every fourth stripe checks that the fits do not depend on the step.
"""

import time

from _study import markdown_table, out_dir, write_readme

from dem_core import excitation
from dem_core.analyses.fragility_study import fragility_study, machine, stripes, write_study
from dem_core.cli import default_scene_path
from dem_core.inputs.records import BUNDLED, G_STANDARD
from dem_core.inputs.scene_file import load

NAME = "fragility"
LEVELS = 256
STATES = (0.1, 0.3, 0.5, 1.0)
OPTIONS = {"integrator": "moreau"}
#: the check: half Moreau-Jean's automatic step (1e-3 s) on every CHECK_EVERY-th stripe
CHECK_DT, CHECK_EVERY = 5e-4, 4


def state_label(state: float) -> str:
    return "overturning" if state >= 1.0 else f"peak \\|theta\\|/alpha >= {state:g}"


def main():
    started = time.perf_counter()
    scene = load(default_scene_path()).scene
    records = {name: excitation.record(name) for name in BUNDLED}
    levels = stripes(LEVELS, G_STANDARD)
    study = fragility_study(scene, records, levels, STATES, **OPTIONS)
    write_study(study, out_dir(NAME), "8-drum column, four bundled records x 256 PGA levels",
                {"scene": default_scene_path().name, "simulation": OPTIONS})
    check = fragility_study(scene, records, levels[CHECK_EVERY - 1::CHECK_EVERY], STATES, **OPTIONS, dt=CHECK_DT)
    rows, inside_band = [], 0
    for state in STATES:
        fit, other = study.fits[state], check.fits[state]
        low, high = fit.median_band
        inside = low <= other.median <= high
        inside_band += inside
        rows.append([state_label(state), f"{fit.median:.3g} ({low:.3g} to {high:.3g})",
                     f"{fit.beta:.2f} ({fit.beta_band[0]:.2f} to {fit.beta_band[1]:.2f})",
                     f"{int(fit.exceed.sum())} of {int(fit.runs.sum())}",
                     f"{other.median:.3g}, {'inside' if inside else 'OUTSIDE'} the band"])
    table = markdown_table(["damage state", "median PGA, m/s^2 (90% band)", "beta (90% band)", "runs exceeding",
                            f"median at dt = {CHECK_DT:g} s, every {CHECK_EVERY}th stripe"], rows)
    per_record = study.runs.groupby("record")["overturned"].mean()
    findings = [
        f"{len(study.runs)} runs in {study.wall_time_s:.0f} s ({study.device}; {machine()}); "
        f"{int((study.runs['status'] != 'ok').sum())} did not finish.",
        "Share of runs that overturned, by record, over the stripes from 1/256 g to 1 g: "
        + ", ".join(f"{name} {share:.0%}" for name, share in per_record.items()) + ".",
        f"The column starts to rock at g b/h = {G_STANDARD / 6.0:.2f} m/s^2 (b/h = 1/6).",
        f"The check at dt = {CHECK_DT:g} s ({len(check.runs)} runs, {check.wall_time_s:.0f} s): {inside_band} of "
        f"{len(STATES)} medians inside the 90% band of the study at the automatic step.",
    ]
    write_readme(NAME, "Fragility of the 8-drum column under the bundled records", findings,
                 [("fragility.png", "Probability of exceedance against PGA: each state's lognormal with its "
                   "bootstrap 90% band, and the observed fraction at each stripe (four runs)")],
                 started, "fragility.py", resumes=False, tables=[*table, ""])


if __name__ == "__main__":
    main()
