"""The figures the README quotes from the comparison report, read from the report's own tables: a figure that
drifts from its source fails here, naming both.  Timings are left out (they are the machine's, not the code's).

Each claim is the text the README must hold, made from ``reports/`` as the report makes its scoreboard
(``scoreboard.csv``), its ensembles (``ensembles.csv``) and its cases (``results.csv``)."""

from pathlib import Path

import numpy as np
import pandas as pd
import pytest

REPOSITORY = Path(__file__).resolve().parents[1]
REPORTS = REPOSITORY / "reports"


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


def _usual(table: pd.DataFrame, engine: str, board: pd.DataFrame) -> pd.DataFrame:
    from comparisons.report.scoreboard import usual_steps

    return table[(table.engine == engine) & (table.step == usual_steps([engine])[engine])]


def quantile_of_standing(ensembles, board, ensemble: str, engine: str, q: float) -> float:
    """The ``q`` quantile of |peak error| over the members of ``ensemble`` whose reference stands (the scoreboard's
    members), at the engine's usual step."""
    rows = _usual(ensembles[ensembles.ensemble == ensemble], engine, board)
    return float(np.quantile(np.abs(rows[~rows.reference_overturned.astype(bool)].error), q))


def case_error(results, case: str, engine: str, step: str, metric: str) -> float:
    rows = results[(results.case == case) & (results.engine == engine) & (results.step == step)
                   & (results.settings == "{}") & (results.metric == metric)]
    assert len(rows) == 1, f"results.csv: {case}, {engine}, {step}, {metric}: {len(rows)} rows"
    return float(rows.error.iloc[0])


def claims(board, ensembles, results) -> list:
    """``(what, text)``: each figure the README quotes, as the README words it."""
    right = {e: (int(board.loc[e, "right"]), int(board.loc[e, "judged"])) for e in board.index}
    said = []
    for engine in ("dem-moreau", "dem", "pybullet", "pymunk", "mujoco"):
        r, j = right[engine]
        said.append((f"{engine}: verdicts", f"right in all {j}" if r == j else f"right in {r} of {j}"))
    said += [
        ("dem-moreau: rocking ensemble", f"median |peak error| {percent(board.loc['dem-moreau', 'rocking_median'])}"),
        ("dem-moreau: sliding ensemble", f"sliding ensemble {percent(board.loc['dem-moreau', 'sliding_median'])}"),
        ("dem: rocking ensemble", f"median |peak error| {percent(board.loc['dem', 'rocking_median'])}"),
        ("dem-overlap: rocking ensemble", f"rocking ensemble median error "
                                          f"{percent(board.loc['dem-overlap', 'rocking_median'])}"),
        ("pymunk: sliding ensemble", f"sliding ensemble median error {percent(board.loc['pymunk', 'sliding_median'])}"),
        ("mujoco: sliding ensemble", f"not for sliding: ensemble median error "
                                     f"{percent(board.loc['mujoco', 'sliding_median'])}, 90th percentile "
                                     f"{percent(quantile_of_standing(ensembles, board, 'sliding_records', 'mujoco', 0.9))}"),
        ("dem-overlap: rocking onset", f"rocking onset {percent(-case_error(results, 'onset_ramp', 'dem-overlap', 'auto/1', 'onset_acceleration'), 1)} early"),
    ]
    for engine in ("dem-moreau", "dem", "dem-overlap"):
        said.append((f"{engine}: overturning spectra", f"overturns when the rocking equation does at "
                     f"{percent(board.loc[engine, 'overturn_agreement'], 3)} of the spectra's points"))
    return said


def test_every_figure_the_readme_quotes_from_the_report_is_the_reports(readme, board, ensembles, results):
    missing = [f"{what}: the README should say {text!r}" for what, text in claims(board, ensembles, results)
               if _words(text) not in readme]
    assert missing == [], "\n".join(missing)
