"""Fragility curves of the 8-drum column (6 m x 1 m, the bundled default scene: friction 0.7, corner law) under the
bundled demonstration suite (40 motions: the 4 bundled records, 28 stochastic and 8 near-fault synthetic motions;
docs/records.md), each scaled to 40 PGA stripes from 0.05 g to 2 g and followed by 10 s of ground at rest: 1,600
runs on every core (:func:`dem_core.analyses.fragility_study.fragility_study`), Moreau-Jean at its automatic step.

Damage states: peak |theta|/alpha of 0.1, 0.3 and 0.5 (alpha the column's critical angle) and overturning, fitted
together (one dispersion, ordered medians: :mod:`dem_core.analyses.nested_fragility`); and what the runs leave, the
residual dislocation of a drum over the one below (1, 5 and 20 mm) and the residual tilt (0.002 and 0.01 rad),
each measure's states fitted together; every band drawn by record, beside each state's IDA-style estimate.  Every
fourth stripe is run again at the automatic step and at half of it, to check that the fits do not depend on the
step.
"""

import math
import time

from _study import markdown_table, out_dir, write_readme

from dem_core.analyses.fragility_study import (STILL_SPEED, fragility_study, state_label, state_parts, stripes,
                                               write_study)
from dem_core.analyses.run_identity import machine
from dem_core.cli import default_scene_path
from dem_core.inputs.records import G_STANDARD
from dem_core.inputs.scene_file import load
from dem_core.inputs.suites import DEFAULT_SUITE, load_suite

NAME = "fragility"
LEVELS, TOP = 40, 2.0 * G_STANDARD
STATES = (0.1, 0.3, 0.5, 1.0)
RESIDUAL = {"dislocation": (1.0, 5.0, 20.0), "tilt": (0.002, 0.01)}
OPTIONS = {"integrator": "moreau"}
#: the check: every CHECK_EVERY-th stripe at Moreau-Jean's automatic step (1e-3 s) and at CHECK_DT
CHECK_DT, CHECK_EVERY = 5e-4, 4


def suite() -> dict:
    """{name: GroundMotion} of the study's suite."""
    return load_suite(DEFAULT_SUITE).motions()


def median_text(fit) -> str:
    if math.isnan(fit.median):
        return f"no median ({fit.note})"
    low, high = fit.median_band
    return f"{fit.median:.3g} = {fit.median / G_STANDARD:.3g} g ({low:.3g} to {high:.3g})"


def ida_text(study, state) -> str:
    median, beta, reached = study.ida[state]
    if math.isnan(median):
        return f"{reached} of {len(study.settings['records'])} records reached it"
    return f"{median:.3g}, beta {beta:.2f} ({reached} of {len(study.settings['records'])} records)"


def kind(name: str) -> str:
    """A suite record's kind by its name: recorded, stochastic or near-fault."""
    return next((k for k in ("stochastic", "near_fault") if name.startswith(k)), "recorded").replace("_", "-")


def fit_rows(study, coarse, fine) -> tuple[list, int]:
    """The table's rows, one per state, and how many of the fine step's medians fell inside the coarse bands."""
    rows, inside_band = [], 0
    for state, fit in study.fits.items():
        low, high = coarse.fits[state].median_band
        inside = low <= fine.fits[state].median <= high
        inside_band += inside
        rows.append([state_label(state).replace("|", "\\|"), median_text(fit),
                     f"{fit.beta:.2f} ({fit.beta_band[0]:.2f} to {fit.beta_band[1]:.2f})",
                     f"{int(fit.exceed.sum())} of {int(fit.runs.sum())}", ida_text(study, state),
                     median_text(coarse.fits[state]),
                     median_text(fine.fits[state]) + (", inside" if inside else ", outside")])
    return rows, inside_band


def main():
    started = time.perf_counter()
    scene = load(default_scene_path()).scene
    records = suite()
    levels = stripes(LEVELS, TOP)
    study = fragility_study(scene, records, levels, STATES, residual=RESIDUAL, **OPTIONS)
    write_study(study, out_dir(NAME), f"8-drum column, the {DEFAULT_SUITE} suite ({len(records)} motions) x "
                f"{LEVELS} PGA levels", {"scene": default_scene_path().name, "suite": DEFAULT_SUITE,
                                         "simulation": OPTIONS})
    subset = levels[CHECK_EVERY - 1::CHECK_EVERY]
    coarse = fragility_study(scene, records, subset, STATES, residual=RESIDUAL, **OPTIONS)
    fine = fragility_study(scene, records, subset, STATES, residual=RESIDUAL, **OPTIONS, dt=CHECK_DT)
    rows, inside_band = fit_rows(study, coarse, fine)
    table = markdown_table(["damage state", "median PGA, m/s^2 (90% band, records drawn again)",
                            "beta, common to the measure's states (90% band)", "runs exceeding",
                            "IDA-style median, m/s^2 (records that reached it)",
                            f"every {CHECK_EVERY}th stripe: median at 1e-3 s", f"and at {CHECK_DT:g} s"], rows)
    measures = study.intensity_measures()
    best = measures.loc[measures["beta"].idxmin(), "measure"]
    measure_rows = [[row["measure"], f"{row['beta']:.2f}",
                     *(f"{row[f'median_{state:g}']:.3g}" for state in STATES)] for _, row in measures.iterrows()]
    measure_table = markdown_table(["intensity measure", "common beta", *(f"median, {state_label(s)}".replace(
        "|", "\\|") for s in STATES)], measure_rows)
    finished = study.runs[study.runs["status"] == "ok"]
    fell = finished["overturned"].astype(bool)
    by_kind = fell.groupby(finished["record"].map(kind)).mean()
    never = [name for name in records if not fell[finished["record"] == name].any()]
    moving = study.still_moving()
    counted = [kind(name) for name in records]
    kinds = ", ".join(f"{counted.count(k)} {k}" for k in ("recorded", "stochastic", "near-fault"))
    family = {measure: [s for s in study.fits if state_parts(s)[0] == measure] for measure in ("peak", *RESIDUAL)}
    findings = [
        f"The fits rest on {len(records)} records ({kinds}): "
        "the bands are drawn by record (each drawn record with all its stripes). Each measure's states are fitted "
        "together, with one dispersion and ordered medians, so their curves cannot cross.",
        f"Which intensity measure predicts the column's peak damage best (second table: the peak states fitted "
        f"together to every run at its own value of the measure; the smaller the common dispersion, the more "
        f"efficient the measure): {best}. The dimensionless rocking measures PGA/(g tan alpha) and PGV/(p R) (the "
        "column as one rigid block) are, for one column, PGA and PGV divided by constants: the same dispersions, "
        "with medians that studies of other columns can compare.",
        f"{len(study.runs)} runs in {study.wall_time_s:.0f} s ({study.device}; {machine()}); "
        f"{int((study.runs['status'] != 'ok').sum())} did not finish; each run is its motion and then "
        f"{study.settings['rest']:g} s of ground at rest, after which {moving} of the {int((~fell).sum())} standing "
        f"runs still moved faster than {STILL_SPEED:g} m/s, rocking still (the residual measures leave a column's "
        "rocking as one body out).",
        "Share of runs that overturned, by kind of motion, over the stripes from 0.05 g to 2 g: " + ", ".join(
            f"{k} {share:.0%}" for k, share in by_kind.items()) + f". Motions that never overturned it up to 2 g: "
        f"{', '.join(never) if never else 'none'}.",
        f"The column starts to rock at g tan(alpha) = {G_STANDARD * math.tan(scene.rocking_slenderness):.2f} m/s^2.",
        "Residual states against peak ones: " + "; ".join(
            f"{state_label(s)} has its median at {study.fits[s].median:.3g} m/s^2" for s in
            (family["dislocation"][0], family["tilt"][0]) if math.isfinite(study.fits[s].median)) + f", against "
        f"{study.fits[0.3].median:.3g} m/s^2 for a peak |theta|/alpha of 0.3.",
        f"The check on every {CHECK_EVERY}th stripe ({len(coarse.runs)} runs at each step; {coarse.wall_time_s:.0f} s "
        f"at 1e-3 s, {fine.wall_time_s:.0f} s at {CHECK_DT:g} s): {inside_band} of {len(study.fits)} medians at "
        f"{CHECK_DT:g} s inside the 90% band of the same stripes at 1e-3 s.",
    ]
    write_readme(NAME, f"Fragility of the 8-drum column under the {DEFAULT_SUITE} suite", findings,
                 [("fragility.png", "Probability of exceedance against PGA, a panel per damage measure: each state's "
                   "lognormal with its 90% bootstrap band (records drawn again), and the observed fraction at each "
                   f"stripe ({len(records)} runs)")],
                 started, "fragility.py", resumes=False, tables=[*table, "", *measure_table, ""])


if __name__ == "__main__":
    main()
