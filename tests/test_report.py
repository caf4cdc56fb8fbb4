"""The comparison report's presentation, without running it: the committed report is current (its digest is that
of the sources its numbers come from), the scoreboard counts what its definitions say, a consensus case that
cannot be judged for every engine has no reference, and the figures' words are plain."""

import json

import matplotlib.pyplot as plt
import numpy as np
import pandas as pd
import pytest

from comparisons.cases import catalogue
from comparisons.harness import overturning_spectra
from comparisons.report import figures, provenance, verdicts
from comparisons.report.scoreboard import scoreboard

COMMITTED = provenance.REPOSITORY / "reports"


def test_committed_report_is_current():
    """The digest reports/digest.json records is that of the sources in the checkout (the engine, its inputs,
    the adapters, the cases, the references, the harness): an edit to any of them makes the committed numbers
    stale until the report is made again."""
    recorded = provenance.recorded_digest(COMMITTED)
    current, files = provenance.source_digest()
    advice = "run `python -m comparisons report` and commit reports/"
    assert recorded is not None, f"reports/{provenance.DIGEST_FILE} is missing: {advice}"
    if recorded != current:
        listed = json.loads((COMMITTED / provenance.DIGEST_FILE).read_text(encoding="utf-8")).get("files", [])
        added, gone = sorted(set(files) - set(listed)), sorted(set(listed) - set(files))
        changes = "".join(f"; {what}: {', '.join(names)}" for what, names in (("new", added), ("gone", gone)) if names)
        pytest.fail(f"reports/ is stale: it was made from sources with digest {recorded[:12]}, the checkout's are "
                    f"{current[:12]}{changes}. {advice}.")


def test_digest_covers_the_sources_and_nothing_else(tmp_path):
    files = provenance.source_files()
    assert "dem_core/simulation.py" in files and "comparisons/harness/consensus.py" in files
    assert any(f.startswith("dem_core/engine/") for f in files)
    assert any(f.startswith("dem_core/data/records/") for f in files)
    assert any(f.startswith("comparisons/cases/") for f in files)
    assert any(f.startswith("comparisons/references/") for f in files)
    for name in files:  # documentation, tests, the report's layout and compiled files never count
        assert not name.startswith(("docs/", "tests/", "comparisons/report/", "reports/", "README"))
        assert "__pycache__" not in name and not name.endswith((".pyc", ".md"))


def test_digest_changes_with_a_source_and_not_with_anything_else(tmp_path):
    for name in ("dem_core/engine/step.py", "dem_core/simulation.py", "comparisons/harness/runs.py",
                 "dem_core/data/records/SOURCES.md", "docs/method.md", "README.md", "comparisons/report/page.py",
                 "tests/test_x.py"):
        (tmp_path / name).parent.mkdir(parents=True, exist_ok=True)
        (tmp_path / name).write_text("x = 1\n")
    before, files = provenance.source_digest(tmp_path)
    assert files == ["comparisons/harness/runs.py", "dem_core/engine/step.py", "dem_core/simulation.py"]
    for name in ("docs/method.md", "README.md", "comparisons/report/page.py", "tests/test_x.py",
                 "dem_core/data/records/SOURCES.md"):
        (tmp_path / name).write_text("changed\n")
    (tmp_path / "comparisons/harness/__pycache__").mkdir()
    (tmp_path / "comparisons/harness/__pycache__/runs.cpython-311.pyc").write_bytes(b"\0")
    assert provenance.source_digest(tmp_path)[0] == before
    (tmp_path / "dem_core/simulation.py").write_text("x = 2\n")
    assert provenance.source_digest(tmp_path)[0] != before


def test_digest_file_round_trip(tmp_path):
    made = {"digest": "ab" * 32, "commit": "c" * 40, "modified": [], "digest_files": ["dem_core/simulation.py"]}
    provenance.write_digest(tmp_path, made)
    assert provenance.recorded_digest(tmp_path) == "ab" * 32
    assert json.loads((tmp_path / provenance.DIGEST_FILE).read_text())["files"] == ["dem_core/simulation.py"]
    assert provenance.recorded_digest(tmp_path / "nowhere") is None


# --- the scoreboard ------------------------------------------------------------------------------------------

USUAL = {"a": "auto/1", "b": "0.001"}


def _verdicts():
    """Four verdict rows: a is right on 3 of 3 referenced rows (fastest on 2), b on 1 of 2 (it did not run the
    spectrum; fastest on 1); the colonnade-like row has no reference and counts for neither."""
    return pd.DataFrame([
        {"name": "c1", "has_reference": True, "engines": ("a", "b"), "right": ("a", "b"), "fastest": "b"},
        {"name": "c2", "has_reference": True, "engines": ("a", "b"), "right": ("a",), "fastest": "a"},
        {"name": "s1", "has_reference": True, "engines": ("a",), "right": ("a",), "fastest": "a"},
        {"name": "none", "has_reference": False, "engines": ("a", "b"), "right": (), "fastest": None},
    ])


def _ensembles():
    rows = []
    for engine, step, errors in (("a", "auto/1", (0.01, -0.03, 0.02, 9.0)), ("a", "auto/4", (0.5, 0.5, 0.5, 0.5)),
                                 ("b", "0.001", (0.10, 0.20, -0.30, 0.0))):
        for k, error in enumerate(errors):  # the fourth member's reference overturns: not judged on its peak
            rows.append({"ensemble": "rock", "engine": engine, "step": step, "settings": "{}", "error": error,
                         "reference_overturned": k == 3})
        rows.append({"ensemble": "slide", "engine": engine, "step": step, "settings": "{}",
                     "error": 0.004 if engine == "a" else -0.006, "reference_overturned": False})
    return pd.DataFrame(rows)


def _spectra():
    rows = []
    for engine, step, outcomes in (("a", "auto/1", (1, 1, 0, 0)), ("a", "auto/2", (0, 0, 0, 0)),
                                   ("b", "0.001", (1, 0, 0, 0))):
        for k, overturned in enumerate(outcomes):
            rows.append({"spectrum": "s1" if k < 2 else "s2", "engine": engine, "step": step,
                         "overturned": bool(overturned), "reference_overturned": k < 2})
    return pd.DataFrame(rows)


def _results():
    rows = []
    for case, times in (("c1", {"a": 1.0, "b": 2.0}), ("c2", {"a": 3.0, "b": 4.0}), ("c3", {"a": 5.0, "b": 9.0})):
        for engine, wall in times.items():
            for metric in ("peak", "rms"):  # two metrics of one run count once
                rows.append({"case": case, "engine": engine, "step": USUAL[engine], "settings": "{}",
                             "status": "ok", "metric": metric, "wall_time_s": wall})
            rows.append({"case": case, "engine": engine, "step": "fine", "settings": "{}", "status": "ok",
                         "metric": "peak", "wall_time_s": 100.0})
    rows.append({"case": "c1", "engine": "b", "step": "0.001", "settings": '{"iterations": 30}', "status": "ok",
                 "metric": "peak", "wall_time_s": 50.0})
    return pd.DataFrame(rows)


def test_scoreboard_counts_what_its_definitions_say():
    board = scoreboard(_verdicts(), _ensembles(), _spectra(), _results(), ensemble_kinds={"rock": "rocking",
                       "slide": "sliding"}, engines=["a", "b"], usual=USUAL).set_index("engine")
    assert board.loc["a", ["right", "judged", "fastest"]].tolist() == [3, 3, 2]
    assert board.loc["b", ["right", "judged", "fastest"]].tolist() == [1, 2, 1]
    # medians at the usual step over the members whose reference stands: a 0.01, 0.02, 0.03; b 0.1, 0.2, 0.3
    assert board.loc["a", "rocking_median"] == pytest.approx(0.02)
    assert board.loc["b", "rocking_median"] == pytest.approx(0.2)
    assert board.loc["a", "sliding_median"] == pytest.approx(0.004)
    assert board.loc["b", "sliding_median"] == pytest.approx(0.006)
    # overturning: every point of every spectrum at the usual step; a agrees on 4 of 4, b on 3 of 4
    assert board.loc["a", "overturn_agreement"] == 1.0 and board.loc["a", "overturn_points"] == 4
    assert board.loc["b", "overturn_agreement"] == pytest.approx(0.75)
    # run time: the median of the case runs at the usual step and default settings (a 1, 3, 5; b 2, 4, 9)
    assert board.loc["a", "median_wall_time_s"] == pytest.approx(3.0)
    assert board.loc["b", "median_wall_time_s"] == pytest.approx(4.0)
    assert board.loc["b", "case_runs"] == 3


def test_scoreboard_without_ensembles_or_spectra():
    board = scoreboard(_verdicts(), pd.DataFrame(), pd.DataFrame(), _results(), ensemble_kinds={},
                       engines=["a", "b"], usual=USUAL)
    assert board.rocking_median.isna().all() and board.overturn_agreement.isna().all()
    assert (board.overturn_points == 0).all() and board.right.tolist() == [3, 1]


# --- no reference ----------------------------------------------------------------------------------------------

def _consensus_rows(missing_for=("pymunk", "mujoco")):
    """Harness rows of the colonnade: dem, dem-overlap and pybullet judged against a consensus, the engines in
    ``missing_for`` without one (only one other engine converged)."""
    rows = []
    for engine, step, error, wall in (("dem", "auto/1", -0.05, 1.0), ("dem-overlap", "auto/1", 0.33, 0.5),
                                      ("pybullet", "0.0005", -0.03, 2.0), ("pymunk", "0.001", 0.15, 0.8),
                                      ("mujoco", "0.001", -0.12, 0.9)):
        none = engine in missing_for
        for metric, err in (("peak_rotation", error), ("overturn_mismatch", 0.0)):
            rows.append({"case": "colonnade_mexico", "engine": engine, "step": step, "settings": "{}",
                         "status": "ok", "metric": metric, "value": 0.1, "error": np.nan if none else err,
                         "wall_time_s": wall, "dt": 1e-3, "reference": np.nan if none else 0.12,
                         "reference_uncertainty": np.nan if none else (0.079 if metric == "peak_rotation" else 0.0),
                         "reference_members": "mujoco" if none else "pymunk, mujoco",
                         "no_reference": "1 other engine(s) converged" if none else np.nan})
    return pd.DataFrame(rows)


def test_a_consensus_missing_for_some_engine_is_no_reference():
    verdict = verdicts.case_verdict(_consensus_rows(), catalogue.case("colonnade_mexico"))
    assert not verdict["has_reference"] and verdict["short_reference"] == "no reference"
    assert verdict["right"] == [] and verdict["fastest"] is None
    assert "No reference" in verdict["text"] and "inf%" not in verdict["text"]
    assert "pymunk: 1 other engine(s) converged" in verdict["text"]


def test_a_consensus_for_every_engine_judges_them():
    verdict = verdicts.case_verdict(_consensus_rows(missing_for=()), catalogue.case("colonnade_mexico"))
    assert verdict["has_reference"] and verdict["short_reference"] == "consensus, +-8%"
    assert verdict["right"] == ["dem", "pybullet"] and verdict["fastest"].engine == "dem"
    assert "inf%" not in verdict["text"] and "up to 7.9%" in verdict["text"]


def test_a_closed_form_case_always_has_a_reference():
    table = pd.DataFrame([{"case": "newmark", "engine": "dem", "step": "auto/1", "settings": "{}", "status": "ok",
                           "metric": "max_slip", "error": 0.001, "wall_time_s": 0.1, "dt": 1e-3}])
    verdict = verdicts.case_verdict(table, catalogue.case("newmark"))
    assert verdict["has_reference"] and verdict["right"] == ["dem"]



def test_a_verdict_names_its_metric_once_with_its_article():
    table = pd.DataFrame([{"case": "impact_slip", "engine": "dem-moreau", "step": "auto/1", "settings": "{}",
                           "status": "ok", "metric": "joint_slip_m", "error": 5e-8, "wall_time_s": 0.1, "dt": 1e-3}])
    text = verdicts.case_verdict(table, catalogue.case("impact_slip"))["text"]
    assert "on the largest slip of any joint" in text and "the the" not in text


# --- figures' words --------------------------------------------------------------------------------------------

def test_figure_words_are_plain():
    assert figures.error_label("peak_rotation") == "peak rotation |error| (%)"
    assert figures.error_label("drift_m") == "horizontal drift |error| (m)"
    assert figures.spectrum_label(overturning_spectra.spectrum("spectrum_sine_1_5x6")) == "sine pulse, 1.5 x 6 m block"
    assert figures.run_label("0.001", '{"iterations": 30}') == "0.001, 30 iterations"
    assert figures.run_label("auto/1, 10 x K_n", '{"kn_factor": 10}') == "auto/1, 10 x K_n"


def test_point_labels_never_overlap(tmp_path):
    fig, ax = plt.subplots(figsize=(4, 3))
    xs = [1.0, 1.01, 1.02, 1.03, 2.0, 4.0]
    ys = [1.0, 1.0, 1.01, 1.0, 2.0, 3.0]
    ax.scatter(xs, ys)
    figures.plain_log(ax)
    fig.tight_layout()
    placed = figures.label_points(ax, xs, ys, [f"label {k}" for k in range(len(xs))])
    assert 3 <= placed < len(xs)  # the clustered points cannot all be labelled
    renderer = fig.canvas.get_renderer()
    boxes = [t.get_window_extent(renderer) for t in ax.texts]
    assert len(boxes) == placed
    assert not any(a.overlaps(b) for i, a in enumerate(boxes) for b in boxes[i + 1:])
    figures.save(fig, tmp_path / "labels.png", layout=False)
