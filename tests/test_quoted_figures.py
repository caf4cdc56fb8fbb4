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


@pytest.fixture(scope="module")
def ensembles() -> pd.DataFrame:
    return pd.read_csv(REPORTS / "ensembles.csv")


@pytest.fixture(scope="module")
def results() -> pd.DataFrame:
    return pd.read_csv(REPORTS / "results.csv")


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
    for engine in ("dem-moreau", "dem", "pybullet", "pymunk", "mujoco"):
        right, judged = int(board.loc[engine, "right"]), int(board.loc[engine, "judged"])
        said.append((f"{engine}: verdicts", f"right in all {judged}" if right == judged else
                     f"right in {right} of {judged}"))
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
