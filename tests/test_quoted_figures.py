"""The figures the README and docs quote from the comparison report, read from the report's own tables: a figure
that drifts from its source fails here, naming both.  Timings are left out (they are the machine's, not the
code's).

The README's engine table and its figures of the column ensemble are made from ``reports/`` as the report makes its
scoreboard (``scoreboard.csv``), its ensembles (``ensembles.csv``, ``column_ensemble.csv``) and its cases
(``results.csv``), the thesis' failure PGAs from the thesis_tables study (``reports/studies/thesis_tables``);
docs/validation.md's ensemble table and spectra agreement from ``ensembles.csv`` and ``spectra.csv``; the
README's joint slips and docs/cli.md's peak of the default run from the runs themselves."""

from pathlib import Path

import numpy as np
import pandas as pd
import pytest

from comparisons.harness.column_ensemble import summarise_pairs

REPOSITORY = Path(__file__).resolve().parents[1]
REPORTS = REPOSITORY / "reports"
#: the thesis_tables study's band: a failure PGA within this fraction of the thesis' value is reproduced
THESIS_BAND = 0.2


def _words(text: str) -> str:
    return " ".join(text.replace("\\|", "|").split())


@pytest.fixture(scope="module")
def readme() -> str:
    return _words((REPOSITORY / "README.md").read_text(encoding="utf-8"))


@pytest.fixture(scope="module")
def board() -> pd.DataFrame:
    return pd.read_csv(REPORTS / "scoreboard.csv").set_index("engine")


def percent(share: float, digits: int = 2) -> str:
    """``share`` as the report writes a percentage: ``digits`` significant figures."""
    return f"{100 * share:.{digits}g}%"


def _usual(table: pd.DataFrame, engine: str) -> pd.DataFrame:
    from comparisons.report.scoreboard import usual_steps

    return table[(table.engine == engine) & (table.step == usual_steps([engine])[engine])]


def quantile_of_standing(ensembles, ensemble: str, engine: str, q: float) -> float:
    """The ``q`` quantile of |peak error| over the members of ``ensemble`` whose reference stands (the scoreboard's
    members), at the engine's usual step."""
    rows = _usual(ensembles[ensembles.ensemble == ensemble], engine)
    return float(np.quantile(np.abs(rows[~rows.reference_overturned.astype(bool)].error), q))


def case_error(results, case: str, engine: str, step: str, metric: str) -> float:
    """The error of one run of ``results.csv`` (the step's label names the settings of a stiffer run)."""
    rows = results[(results.case == case) & (results.engine == engine) & (results.step == step)
                   & ((results.settings == "{}") | results.step.str.contains("K_n")) & (results.metric == metric)]
    assert len(rows) == 1, f"results.csv: {case}, {engine}, {step}, {metric}: {len(rows)} rows"
    return float(rows.error.iloc[0])


def claims(board, ensembles, results) -> list:
    """``(what, text)``: each figure the README quotes, as the README words it."""
    def median(engine, kind):
        return percent(board.loc[engine, f"{kind}_median"])

    def agreement(engine):
        share = percent(board.loc[engine, "overturn_agreement"], 3)
        return f"overturns when the rocking equation does at {share} of the spectra's points"

    said = []
    #: where the README gives each engine's verdicts: the words before them (its row of the table, or its sentence)
    before = {"dem-moreau": "1e-3 s steps) |", "dem": "with `dem-core stiffness` |", "pymunk": "`pymunk` (1e-3 s) |",
              "mujoco": "`mujoco` (or `dem-moreau`) |", "pybullet": "PyBullet is"}
    for engine, words in before.items():
        right, judged = int(board.loc[engine, "right"]), int(board.loc[engine, "judged"])
        said.append((f"{engine}: verdicts", f"{words} right in all {judged}" if right == judged else
                     f"{words} right in {right} of {judged}"))
    onset = -case_error(results, "onset_ramp", "dem-overlap", "auto/1", "onset_acceleration")
    column = [abs(case_error(results, "column_record", "dem", step, "peak_rotation"))
              for step in ("auto/1", "auto/1, 10 x K_n")]
    colonnade = max(abs(case_error(results, "colonnade_mexico", "dem", step, "peak_rotation"))
                    for step in ("auto/1", "auto/1, 10 x K_n", "auto/1, 100 x K_n"))
    drift = [1e3 * case_error(results, "statics", engine, "0.001", "drift_m") for engine in ("pymunk", "pybullet")]
    mujoco_p90 = quantile_of_standing(ensembles, "sliding_records", "mujoco", 0.9)
    pairs = summarise_pairs(pd.read_csv(REPORTS / "column_ensemble.csv")).set_index(["run", "against"])
    column_step = pairs.loc[("dem-moreau 1e-3 s", "dem-moreau 2.5e-4 s"), "typical_difference"]
    thesis = pd.read_parquet(REPORTS / "studies" / "thesis_tables" / "results.parquet")
    overlap = thesis[(thesis.law_name == "overlap_area") & thesis.thesis.notna()]
    within = int((np.abs(overlap.smallest / overlap.thesis - 1.0) <= THESIS_BAND).sum())
    said += [
        ("dem-overlap: the thesis' failure PGAs", f"({within} of {len(overlap)} within {THESIS_BAND:.0%},"),
        ("dem-moreau: fastest", f"the fastest right engine in {int(board.loc['dem-moreau', 'fastest'])}"),
        ("dem-moreau: ensembles", (f"median |peak error| {median('dem-moreau', 'rocking')}, sliding ensemble "
                                   f"{median('dem-moreau', 'sliding')}")),
        ("dem-moreau: spectra", f"sliding ensemble {median('dem-moreau', 'sliding')}; {agreement('dem-moreau')}"),
        ("dem: rocking ensemble and spectra", f"median |peak error| {median('dem', 'rocking')}; {agreement('dem')}"),
        ("dem: the column and the colonnade against the consensus",
         (f"within {percent(column[0])} of the other engines' consensus at the default K_n and {percent(column[1])} "
          f"at 10 x K_n, the colonnade under Mexico City within {percent(colonnade)} at 1, 10 and 100 x K_n")),
        ("dem-overlap", (f"rocking ensemble median error {median('dem-overlap', 'rocking')}, "
                         f"{agreement('dem-overlap')}, rocking onset {percent(onset, 1)} early")),
        ("pymunk: sliding ensemble", f"sliding ensemble median error {median('pymunk', 'sliding')}"),
        ("statics: drift at rest", f"pymunk and PyBullet drift {drift[0]:.2g} and {drift[1]:.2g} mm"),
        ("dem-moreau: the column ensemble's step", (f"its top drum's peak moves by {percent(column_step)} typically "
                                                    "from 1e-3 to 2.5e-4 s")),
        ("mujoco: sliding ensemble", (f"not for sliding: ensemble median error {median('mujoco', 'sliding')}, "
                                      f"90th percentile {percent(mujoco_p90)}")),
    ]
    return said


def test_every_figure_the_readme_quotes_from_the_report_is_the_reports(readme, board, ensembles, results):
    missing = [f"{what}: the README should say {text!r}" for what, text in claims(board, ensembles, results)
               if _words(text) not in readme]
    assert missing == [], "\n".join(missing)


@pytest.mark.slow
def test_the_joint_slips_the_readme_quotes_are_the_default_runs(readme):
    """The README's slips of the bundled default's joints (20 s of El Centro as recorded, the largest joint's
    kinematic travel): Moreau-Jean's and PyBullet's, both rigid, and the explicit core's, run again here."""
    import adapters
    import dem_core
    from dem_core import excitation, scenes

    motion = excitation.record("el_centro_1940")

    def largest_mm(result) -> float:
        return 1e3 * max(result.interface_slip.get(tuple(pair), 0.0) for pair in result.interfaces)

    moreau, explicit = (largest_mm(dem_core.simulate(scenes.column(8), motion, 20.0, integrator=integrator))
                        for integrator in ("moreau", "explicit"))
    pybullet = largest_mm(adapters.simulate(scenes.column(8), motion, 20.0, engine="pybullet"))
    said = (f"Moreau-Jean's joints slip at most {moreau:.2g} mm and PyBullet's, also rigid, at most {pybullet:.2g} mm; "
            f"the explicit core's up to {explicit:.1g} mm")
    assert _words(said) in readme


def test_the_default_runs_peak_that_cli_md_quotes_is_the_runs():
    from dem_core.cli import default_scene_path
    from dem_core.cli.single_run import simulated
    from dem_core.inputs.scene_file import load

    spec = load(default_scene_path())
    result, _ = simulated(spec, dict(spec.simulation))
    cli_md = _words((REPOSITORY / "docs" / "cli.md").read_text(encoding="utf-8"))
    assert f"the default run rocks to about {float(np.max(result.peak_theta)):.1g} rad" in cli_md


@pytest.mark.slow
def test_what_validation_md_says_of_the_default_runs_step_is_the_runs(validation):
    """The bundled default by Moreau-Jean at 1e-3, 5e-4 and 2.5e-4 s, and at 1e-3 s with every contact solve
    converged: its peak over alpha and its total sliding."""
    import dem_core
    from dem_core.cli import default_scene_path
    from dem_core.inputs.scene_file import load

    spec = load(default_scene_path())
    runs = [dem_core.simulate(spec.scene, spec.excitation, **{**spec.simulation, "dt": dt, "integrator": "moreau"})
            for dt in (1e-3, 5e-4, 2.5e-4)]
    peaks = [run.damage_ratio for run in runs]
    slides = [1e3 * run.total_sliding for run in runs]
    short = 100 * (1 - peaks[0] / peaks[2])
    said = (f"peaks of {peaks[0]:.3f}, {peaks[1]:.3f} and {peaks[2]:.3f} alpha and total sliding of {slides[0]:.2f}, "
            f"{slides[1]:.2f} and {slides[2]:.2f} mm: the run's peak at 1e-3 s is {short:.0f}% under its value at "
            f"2.5e-4 s")
    assert _words(said) in validation, said
    times = TIMES[round(slides[0] / slides[2])]
    assert f"is {times} it" in validation
    converged = _with_every_solve_converged(spec)
    unconverged = runs[0].info["unconverged_steps"]
    assert converged.info["unconverged_steps"] == 0
    still = TIMES[round(1e3 * converged.total_sliding / slides[2])]
    said = (f"ended short of their tolerance in {unconverged} of its steps. With every solve converged (a hundredth "
            f"of the tolerance and up to {CONVERGED_SWEEPS} sweeps), the run at 1e-3 s peaks at "
            f"{converged.damage_ratio:.3f} alpha, {100 * (1 - converged.damage_ratio / peaks[2]):.0f}% under, and "
            f"slides {1e3 * converged.total_sliding:.2f} mm, still {still} "
            f"the sliding at 2.5e-4 s")
    assert _words(said) in validation, said
    assert converged.damage_ratio > peaks[0], "validation.md: the unsettled solves held back part of the peak"


#: a ratio as validation.md words it
TIMES = {2: "twice", 3: "three times", 4: "four times"}
#: the sweeps allowed to the converged run of validation.md's default step (its tolerance a hundredth of the default)
CONVERGED_SWEEPS = 5000


def _with_every_solve_converged(spec):
    """The bundled default by Moreau-Jean at 1e-3 s, its contact solves held to a hundredth of their tolerance with
    up to :data:`CONVERGED_SWEEPS` Gauss-Seidel sweeps a step."""
    from dem_core.simulation import Simulation

    run = Simulation(spec.scene, spec.excitation, **{**spec.simulation, "dt": 1e-3, "integrator": "moreau"})
    run.settings = run.settings.replace(max_sweeps=CONVERGED_SWEEPS,
                                        solver_tolerance=run.settings.solver_tolerance / 100)
    run.advance()
    return run.result()


#: validation.md's ensemble table: its engines, as it labels them
ENSEMBLE_TABLE = {"dem": "dem (auto/1)", "dem-moreau": "dem-moreau (auto/1)", "dem-overlap": "dem-overlap (auto/1)",
                  "pymunk": "pymunk (1e-3 s)", "pybullet": "PyBullet (1e-3 s)", "mujoco": "MuJoCo (1e-3 s)"}


def _two_figures(share: float) -> str:
    """A share as a percentage of two significant figures, without an exponent (140%, 1%, 0.29%)."""
    return f"{float(f'{100 * share:.2g}'):g}%"


def test_validation_mds_ensemble_table_is_the_reports(ensembles):
    """Per engine at its usual step: the rocking ensemble's median and 90th percentile |peak error| over the
    members whose reference stands, the share of members where it overturns when the rocking equation does, and
    the sliding ensemble's median and 90th percentile."""
    validation = _words((REPOSITORY / "docs" / "validation.md").read_text(encoding="utf-8"))
    for engine, label in ENSEMBLE_TABLE.items():
        cells = []
        for name in ("rocking_records", "sliding_records"):
            members = _usual(ensembles[ensembles.ensemble == name], engine)
            standing = np.abs(members[~members.reference_overturned.astype(bool)].error)
            cells += [_two_figures(np.median(standing)), _two_figures(np.quantile(standing, 0.9))]
            if name == "rocking_records":
                agree = np.mean(members.overturned.astype(bool) == members.reference_overturned.astype(bool))
                cells.append(f"{100 * agree:.3g}%")
        row = _words(f"| {label} | " + " | ".join(cells) + " |")
        assert row in validation, f"docs/validation.md's ensemble table should have the row {row!r}"


def test_validation_mds_agreement_on_the_overturning_spectra_is_the_reports():
    """Per engine at its usual step, the share of each overturning spectrum's points where it overturns when the
    rocking equation does, in validation.md's order of the spectra."""
    spectra = pd.read_csv(REPORTS / "spectra.csv")
    order = ("spectrum_sine_1x6", "spectrum_rectangular_1x6", "spectrum_sine_1_5x6", "spectrum_rectangular_1_5x6")
    parts = []
    for engine in ("dem-moreau", "dem", "dem-overlap", "pymunk", "pybullet", "mujoco"):
        mine = _usual(spectra, engine)
        shares = [np.mean(mine[mine.spectrum == name].overturned.astype(bool)
                          == mine[mine.spectrum == name].reference_overturned.astype(bool)) for name in order]
        parts.append(f"{ENSEMBLE_TABLE[engine].split(' (')[0]} " + ", ".join(_two_figures(x) for x in shares))
    sentence = _words("Agreement at the usual steps (sine and rectangular, 1 x 6 m then 1.5 x 6 m): "
                      + "; ".join(parts) + ".")
    assert sentence in _words((REPOSITORY / "docs" / "validation.md").read_text(encoding="utf-8")), sentence


@pytest.fixture(scope="module")
def validation() -> str:
    return _words((REPOSITORY / "docs" / "validation.md").read_text(encoding="utf-8"))


#: the free-rocking cases of the four slender blocks, and the squat one
SLENDER_ROCKING = ("free_rocking", "free_rocking_large", "free_rocking_slender", "free_rocking_slender_large")
SQUAT_ROCKING = "free_rocking_squat"
PULSES = ("sine_pulse", "sine_pulse_strong", "sine_pulse_slender", "cosine_pulse")
NEWMARK = ("newmark", "newmark_low", "newmark_high")
#: the engines of validation.md's free-rocking sentence, in its order, as it names them
SIDE_BY_SIDE = {"dem-moreau": "native, Moreau-Jean", "dem": "native, explicit corner law", "mujoco": "MuJoCo",
                "pymunk": "pymunk", "pybullet": "PyBullet", "dem-overlap": "native, overlap-area law"}


def _usual_error(results, case: str, engine: str, metric: str) -> float:
    from comparisons.report.scoreboard import usual_steps

    return case_error(results, case, engine, usual_steps([engine])[engine], metric)


def _largest(results, cases, engine: str, metric: str) -> str:
    return _two_figures(max(abs(_usual_error(results, case, engine, metric)) for case in cases))


def _more_or_less(error: float) -> str:
    return f"{_two_figures(abs(error))} {'more' if error > 0 else 'less'}"


def validation_claims(board, results) -> list:
    """``(what, text)``: each figure docs/validation.md quotes from the report's cases and scoreboard."""
    dem = lambda case, metric: _usual_error(results, case, "dem", metric)  # noqa: E731
    said = [("the corner law: free-rocking quarter periods", "free-rocking quarter periods within "
             f"{_largest(results, SLENDER_ROCKING + (SQUAT_ROCKING,), 'dem', 'quarter_period')} of the rocking equation"),
            ("the corner law: peaks after five impacts", f"peaks after five impacts within "
             f"{_largest(results, SLENDER_ROCKING, 'dem', 'peak_decay')} on the four slender blocks, and "
             f"{_two_figures(abs(dem(SQUAT_ROCKING, 'peak_decay')))} on the squat one"),
            ("the corner law: onset", f"rocking onset under a ramp within "
             f"{_two_figures(abs(dem('onset_ramp', 'onset_acceleration')))};"),
            ("the corner law: stacked blocks", "Psycharis' stacked blocks' first impact within "
             f"{_two_figures(abs(dem('stacked_blocks', 'impact_time')))};"),
            ("the corner law: pulses", f"one-sine and one-cosine pulses within "
             f"{_largest(results, PULSES, 'dem', 'peak_rotation')} of the peak;"),
            ("the corner law: Newmark", f"Newmark's sliding pulses within {_largest(results, NEWMARK, 'dem', 'max_slip')} "
             "of the rigid-plastic slip"),
            ("the overlap-area law: onset", "rocking onset "
             f"{percent(-_usual_error(results, 'onset_ramp', 'dem-overlap', 'onset_acceleration'), 1)} early"),
            ("the overlap-area law: rocking ensemble", "In the report's rocking ensemble its median |peak error| is "
             f"{percent(board.loc['dem-overlap', 'rocking_median'])}")]
    free = {e: [_two_figures(abs(_usual_error(results, "free_rocking", e, m))) for m in ("quarter_period", "peak_decay")]
            for e in SIDE_BY_SIDE}
    newmark = max(abs(_usual_error(results, "newmark", e, "max_slip")) for e in SIDE_BY_SIDE)
    *first, last = [peaks for _, peaks in free.values()]
    said.append(("the engines side by side: free rocking and Newmark",
                 "first impact within " + ", ".join(f"{free[e][0]} ({name})" for e, name in SIDE_BY_SIDE.items())
                 + "; peaks after five impacts within " + ", ".join(first) + f" and {last}; Newmark's sliding pulse "
                 f"within {_two_figures(newmark)} in all"))

    def verdicts(engine):
        right, judged = int(board.loc[engine, "right"]), int(board.loc[engine, "judged"])
        return f"in all {judged}" if right == judged else f"in {right} of {judged}"

    judged = int(board.judged.max())
    cases = int(board.case_runs.max())
    said += [("the report's verdicts", f"Of the page's {judged} verdicts ({cases} cases, 2 ensembles, "
              f"{judged - cases - 2} overturning spectra;"),
             ("the report's verdicts per engine",
              f"`dem-moreau` is right {verdicts('dem-moreau')} and the fastest right engine in "
              f"{int(board.loc['dem-moreau', 'fastest'])}, `dem` {verdicts('dem')}"),
             ("the report's verdicts of the other engines",
              f"MuJoCo {verdicts('mujoco')}, pymunk {verdicts('pymunk')}, PyBullet {verdicts('pybullet')} (the other "
              f"engines refuse the {judged - int(board.loc['pymunk', 'judged'])} cases with connectors) and "
              f"`dem-overlap` {verdicts('dem-overlap')}")]
    scenes = {}
    for case in ("column_record", "colonnade_mexico"):
        rows = [results[(results.case == case) & (results.engine == "dem") & (results.step == step)
                        & (results.metric == "peak_rotation")].iloc[0]
                for step in ("auto/1", "auto/1, 10 x K_n", "auto/1, 100 x K_n")]
        scenes[case] = (f"{rows[0].reference:.3g} rad +-{rows[0].reference_uncertainty:.0%}",
                        [_more_or_less(row.error) for row in rows], rows[0].reference_members)
    (column, column_errors, members), (colonnade, colonnade_errors, _) = scenes.values()
    said.append(("the multi-block scenes against the consensus",
                 f"The column's peak is {column} by the consensus that judges `dem` ({members}); `dem` gives "
                 f"{column_errors[0]} at its default K_n, {column_errors[1]} at 10 x K_n and {column_errors[2]} at "
                 f"100 x K_n. The colonnade's is {colonnade} by the same consensus; `dem` gives "
                 f"{colonnade_errors[0]}, {colonnade_errors[1]} and {colonnade_errors[2]}."))
    pairs = summarise_pairs(pd.read_csv(REPORTS / "column_ensemble.csv")).set_index(["run", "against"])
    step = pairs.loc[("dem-moreau 1e-3 s", "dem-moreau 2.5e-4 s")]
    explicit = pairs.loc[("dem-moreau 1e-3 s", "dem automatic step")]
    said.append(("the column ensemble", f"Moreau-Jean's 1e-3 s is {_two_figures(step.typical_difference)} from its "
                 f"2.5e-4 s typically (90% interval {_two_figures(step.interval_low)} to "
                 f"{_two_figures(step.interval_high)}) and {_two_figures(explicit.typical_difference)} from the explicit "
                 f"core, over the {int(step.compared)} runs that stand and rock in both;"
                 + (" every run agrees on overturning" if pairs.overturn_agreement.min() == 1.0 else "")))
    return said


def test_every_figure_validation_md_quotes_from_the_report_is_the_reports(validation, board, results):
    missing = [f"{what}: docs/validation.md should say {text!r}" for what, text in validation_claims(board, results)
               if _words(text) not in validation]
    assert missing == [], "\n".join(missing)


def test_validation_mds_threshold_check_is_the_record_overturning_studys(validation):
    """The smallest overturning PGA of the 1-drum column (friction 2) under each bundled record, by the rocking
    equation, Moreau-Jean and the explicit core: by the 2% scan, and by either search (the scan or the fine
    0.02 m/s^2 scan), from the study's ``rigid_check.parquet``."""
    import test_thresholds

    check = pd.read_parquet(REPORTS / "studies" / "record_overturning" / "rigid_check.parquet").set_index("record")
    either = {run: np.minimum(check[f"{run}_smallest"], check[f"{run}_fine"]) for run in ("rigid", "moreau", "explicit")}
    off = {run: either[run] / either["rigid"] - 1.0 for run in ("moreau", "explicit")}
    worst = off["moreau"].abs().idxmax()
    scan = check.loc[worst]
    said = [f"under El Centro and Northridge within {test_thresholds.RECORD_OVERTURN_BAND:.0%}",
            f"The explicit core at the default K_n 2e11 is within {_two_figures(off['explicit'].abs().max())} under all "
            f"four; Moreau-Jean within {_two_figures(off['moreau'].drop(worst).abs().max())} under three and "
            f"{_two_figures(off['moreau'][worst])} high under {worst.split('_')[0].capitalize()}",
            f"from {either['rigid'][worst]:.2f} m/s^2 up",
            f"With the 2% scan alone the rocking equation gives {scan.rigid_smallest:.1f}, Moreau-Jean "
            f"{scan.moreau_smallest:.1f} and the explicit core {scan.explicit_smallest:.1f} "
            f"(+{scan.explicit_smallest / scan.rigid_smallest - 1:.0%}); with the fine scan "
            f"{either['rigid'][worst]:.2f}, {either['moreau'][worst]:.2f} and {either['explicit'][worst]:.2f}"]
    missing = [text for text in said if _words(text) not in validation]
    assert missing == [], "docs/validation.md should say:\n" + "\n".join(missing)


def test_validation_mds_converged_bands_are_the_catalogues(validation):
    from comparisons.cases.catalogue import MOREAU_CONVERGED_BANDS

    quarter, peaks = (MOREAU_CONVERGED_BANDS[m]["dem-moreau"] for m in ("quarter_period", "peak_decay"))
    said = (f"free rocking within {_two_figures(quarter)} on the quarter period and {_two_figures(peaks)} on the peaks "
            "after five impacts")
    assert _words(said) in validation, said


def test_validation_mds_luck_of_a_single_record_run_is_the_rocking_equations(validation):
    """The rigid monolith's peak under El Centro's strong motion at 2.75 and 2.76 m/s^2, by the rocking equation."""
    from comparisons.cases.strong_motion import strong_motion, window
    from comparisons.references import analytical
    from comparisons.references.rocking_equation import rocking_response

    block = analytical.RockingBlock.from_size(1.0, 6.0)
    start, end = window("el_centro_1940")
    peaks = [rocking_response(block, strong_motion("el_centro_1940", pga), end - start).peak / block.alpha
             for pga in (2.75, 2.76)]
    said = f"El Centro at 2.75 and 2.76 m/s^2 take the rigid monolith's peak from {peaks[0]:.3f} to {peaks[1]:.3f} alpha"
    assert _words(said) in validation, said


@pytest.mark.slow
def test_validation_mds_rectangular_boundary_against_housner_is_the_rocking_equations(validation):
    """The largest difference, over each rectangular spectrum's columns, between the rocking equation's overturning
    boundary and Housner's linearised 1/(1 - exp(-p t_d))."""
    from comparisons.harness import overturning_spectra

    worst = []
    for name in ("spectrum_rectangular_1x6", "spectrum_rectangular_1_5x6"):
        spec = overturning_spectra.spectrum(name)
        worst.append(max(abs(overturning_spectra.reference_transitions(spec, column)[0][0]
                             / overturning_spectra.closed_form_rectangular(column) - 1.0) for column in spec.columns))
    said = (f"the rocking equation's boundary is within {_two_figures(worst[0])} (1 x 6 m) and {_two_figures(worst[1])} "
            "(1.5 x 6 m) of Housner's linearised")
    assert _words(said) in validation, said


def _kn(setting: str) -> str:
    """``kn = 1e+07`` as validation.md writes it: ``1e7``."""
    return f"{float(setting.removeprefix('kn = ')):.0e}".replace("e+0", "e").replace("e+", "e")


def _listed(items) -> str:
    items = list(items)
    return ", ".join(items[:-1]) + f" and {items[-1]}" if len(items) > 1 else "".join(items)


def stability_claim(stability: pd.DataFrame) -> str:
    """What docs/validation.md says of the explicit core's stability map: its step and verdict at each contact
    stiffness of the free-rocking sweep, and where it stops on the time-step ladder (both cases)."""
    sweep = stability[(stability.test == "free rocking, contact stiffness") & (stability.engine == "dem")]
    steps = sweep[sweep.metric == "dt_s"]
    root_kn = np.sqrt(steps.setting.str.removeprefix("kn = ").astype(float).to_numpy())
    assert np.ptp(steps.value.to_numpy() * root_kn) < 1e-9 * steps.value.iloc[0] * root_kn[0], "dt is not ~ 1/sqrt(K_n)"
    decay = sweep[sweep.metric == "peak_decay"].set_index("setting")
    parts = []
    stopped = [_kn(k) for k in decay.index[decay.status == "stopped"]]
    if stopped:
        parts.append(f"stops with an error at {_listed(stopped)}")
    wrong = decay[decay.status == "silently wrong"]
    if len(wrong):
        parts.append(f"finishes silently wrong at {_listed(map(_kn, wrong.index))} (peaks after five impacts off by "
                     f"{_listed(_two_figures(abs(v)) for v in wrong.value)})")
    ok = decay[decay.status == "ok"]
    if len(ok):
        parts.append(f"is within {_two_figures(ok.value.abs().max())} of the rocking equation's peaks from "
                     f"{_kn(ok.index[0])} to {_kn(ok.index[-1])}")
    ladder = stability[stability.test.str.endswith("at growing dt") & (stability.engine == "dem")]
    by_step = ladder.groupby("setting", sort=False).status.agg(lambda s: s.iloc[0] if s.nunique() == 1 else "mixed")
    factor = lambda settings: _listed(s.removesuffix(" x limit") for s in settings)  # noqa: E731
    return (f"The explicit core (`dem`) on the free-rocking block: its automatic step falls as 1/sqrt(K_n), from "
            f"{steps.value.iloc[0]:.2g} s at K_n = {_kn(steps.setting.iloc[0])} N/m^2 to {steps.value.iloc[-1]:.2g} s "
            f"at {_kn(steps.setting.iloc[-1])}; it " + "; it ".join(parts) + ". On free rocking and Newmark's pulse "
            f"it is ok at {factor(by_step.index[by_step == 'ok'])} x its stability limit and stops with an error at "
            f"{factor(by_step.index[by_step == 'stopped'])} x.")


def test_validation_mds_stability_map_is_the_reports(validation):
    said = stability_claim(pd.read_csv(REPORTS / "stability.csv"))
    assert _words(said) in validation, f"docs/validation.md should say {said!r}"


#: the stiffness ensembles' members (``python -m comparisons stiffness-ensembles --members``), per scene
STIFFNESS_ENSEMBLES = REPORTS / "stiffness_ensembles"


def test_the_stiffness_ensembles_are_current():
    """Each stiffness ensemble's members were run from the sources the checkout holds (the report's digest)."""
    import json

    from comparisons.report import provenance

    current, _ = provenance.source_digest()
    for scene in ("column", "colonnade"):
        stamp = json.loads((STIFFNESS_ENSEMBLES / f"{scene}.json").read_text(encoding="utf-8"))
        assert stamp["digest"] == current, (
            f"reports/stiffness_ensembles/{scene}.csv is stale: run `python -m comparisons stiffness-ensembles "
            f"--scene {scene} --perturb 0.001 --members reports/stiffness_ensembles/{scene}.csv`")


def test_validation_mds_stiffness_table_is_the_stiffness_ensembles(validation):
    """validation.md's table of the stiffness ensembles, each cell made from the members' peaks as
    ``comparisons.benchmarks.stiffness_ensembles.measures`` measures them, and its count of members."""
    from comparisons.benchmarks.stiffness_ensembles import compared

    tables = {scene: pd.read_csv(STIFFNESS_ENSEMBLES / f"{scene}.csv") for scene in ("column", "colonnade")}
    found = {scene: compared(table) for scene, table in tables.items()}

    def change(m):
        return f"{m['change']:+.1%} ({m['change_low']:+.0%} to {m['change_high']:+.0%})"

    rows = {
        "median peak at 1 x K_n (90% interval of the change)": lambda f: change(f["1x"]),
        "the same at 10 x K_n": lambda f: change(f["10x"]),
        "member by member at 1 x: median ratio, geometric mean (standard error)":
            lambda f: f"{f['1x']['median_ratio']:.4f}, {f['1x']['geometric_mean']:.3f} ({f['1x']['standard_error']:.1%})",
        "typical member change at 1 x / 10 x (median \\|log ratio\\|)":
            lambda f: f"{_two_figures(f['1x']['typical_change'])} / {_two_figures(f['10x']['typical_change'])}",
        "amplitudes 0.1% higher at 1 x: typical member change, geometric mean (standard error)":
            lambda f: (f"{_two_figures(f['1x_perturbed']['typical_change'])}, "
                       f"{f['1x_perturbed']['geometric_mean']:.3f} ({f['1x_perturbed']['standard_error']:.1%})"),
        "agreement on overturning at 1 x": lambda f: f"{f['1x']['agreement']:.0%}",
    }
    missing = []
    for label, cell in rows.items():
        row = _words(f"| {label} | " + " | ".join(cell(f) for f in found.values()) + " |")
        if row not in validation:
            missing.append(row)
    fell = {scene: table[table.filter(like="overturned_").any(axis=1)] for scene, table in tables.items()}
    members = {len(table) for table in tables.values()}
    standing = sorted({len(tables[scene]) - len(fell[scene]) for scene in tables})
    mexico = sorted({int((fallen.record == "mexico_city_1985").sum()) for fallen in fell.values()})
    others = sorted({len(fallen) for fallen in fell.values()})
    said = (f"On the {members.pop()} members ({' or '.join(map(str, standing))} standing in every run; the "
            f"{' or '.join(map(str, others))} others overturn in some run, {' or '.join(map(str, mexico))} of them "
            "under Mexico City)" if len(members) == 1 else "the scenes' ensembles have the same members")
    if _words(said) not in validation:
        missing.append(said)
    assert missing == [], "docs/validation.md should say:\n" + "\n".join(missing)


def test_what_validation_md_reads_from_the_stiffness_table_is_so():
    """The words under the table: the column's typical member change at 1 x K_n is less than twice the 0.1%
    amplitude change's; the colonnade's at 1 x more than twice the amplitude change's and at 10 x more than it;
    every geometric mean at 1 x within two standard errors of 1."""
    from comparisons.benchmarks.stiffness_ensembles import compared

    column, colonnade = (compared(pd.read_csv(STIFFNESS_ENSEMBLES / f"{scene}.csv")) for scene in ("column", "colonnade"))
    assert column["1x"]["typical_change"] < 2.0 * column["1x_perturbed"]["typical_change"]
    assert colonnade["1x"]["typical_change"] > 2.0 * colonnade["1x_perturbed"]["typical_change"]
    assert colonnade["10x"]["typical_change"] > colonnade["1x_perturbed"]["typical_change"]
    for found in (column, colonnade):
        assert abs(np.log(found["1x"]["geometric_mean"])) < 2.0 * found["1x"]["standard_error"]
