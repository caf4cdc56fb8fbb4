"""The comparison report on its quick set (what ``python -m comparisons report --quick`` runs): each engine
within the bands its cases, ensembles and spectra declare, the native core ahead where :data:`AHEAD`
says it is, a consensus that leaves the judged engine out, and a page whose figures and links are whole, whose
headers are plain words, which states its commit and its sources digest, and which opens with the scoreboard."""

import html.parser
import re
import shutil
import sys
import warnings

import matplotlib.pyplot as plt
import numpy as np
import pandas as pd
import pytest

from comparisons.__main__ import make_report
from comparisons.cases import catalogue as cases
from comparisons.cases.case import ENGINES, EXACT_RELATIVE
from comparisons.harness import column_ensemble, consensus, ensembles, overturning_spectra
from comparisons.harness.engines import USUAL_STEP, step_label
from comparisons.report import figures, provenance, verdicts

pytestmark = pytest.mark.slow  # the whole module

#: where the native core at its automatic step is more accurate than an engine at 1e-3 s (a test fails if it falls
#: behind)
AHEAD = [
    ("free_rocking", "peak_decay", "pymunk"), ("free_rocking", "peak_decay", "pybullet"),
    ("free_rocking", "peak_decay", "mujoco"), ("sine_pulse", "peak_rotation", "pybullet"),
    ("statics", "drift_m", "pymunk"), ("statics", "drift_m", "pybullet"),
]
QUICK_CASES = [c for c in cases.all_cases() if c.quick]
QUICK_ENSEMBLES = [e for e in ensembles.all_ensembles() if e.quick]
QUICK_SPECTRA = [s for s in overturning_spectra.all_spectra() if s.quick]


@pytest.fixture(scope="module")
def quick_report(tmp_path_factory):
    """The whole quick report, made once: ``(index.html, {part: table})``."""
    return make_report(quick=True, out=tmp_path_factory.mktemp("report"), progress=False)


@pytest.fixture(scope="module")
def quick_table(quick_report):
    return quick_report[1]["cases"]


def _usual(table, case, metric, engine):
    row = table[(table.case == case) & (table.metric == metric) & (table.engine == engine)
                & (table.step == step_label(engine, USUAL_STEP[engine])) & (table.settings == "{}")]
    assert len(row) == 1 and row.status.iloc[0] == "ok", (case, metric, engine)
    return float(row.error.iloc[0])


def test_every_quick_run_finished(quick_table):
    assert set(quick_table.case) == {c.name for c in QUICK_CASES}
    assert set(quick_table.engine) == set(ENGINES)
    assert set(quick_table.status) == {"ok"}
    assert (quick_table.wall_time_s > 0).all()


@pytest.mark.parametrize("case, metric, engine", [(c, m, e) for c in QUICK_CASES for m in c.bands
                                                  for e in c.bands[m]], ids=lambda x: getattr(x, "name", x))
def test_each_engine_within_its_band(quick_table, case, metric, engine):
    error = _usual(quick_table, case.name, metric, engine)
    assert case.within_band(metric, engine, error), (error, case.band(metric, engine))


@pytest.mark.parametrize("case, metric, engine", AHEAD)
def test_native_core_stays_ahead_where_it_is_ahead(quick_table, case, metric, engine):
    assert abs(_usual(quick_table, case, metric, "dem")) < abs(_usual(quick_table, case, metric, engine))


def test_errors_fall_with_the_time_step_where_the_engines_converge(quick_table):
    for engine, coarse, fine in (("pymunk", "0.001", "0.00025"), ("mujoco", "0.001", "0.00025"),
                                 ("dem", "auto/1", "auto/4")):
        rows = quick_table[(quick_table.case == "free_rocking") & (quick_table.metric == "peak_decay")
                           & (quick_table.engine == engine)].set_index("step")
        assert abs(rows.error[fine]) < abs(rows.error[coarse]), engine


@pytest.mark.parametrize("ens", QUICK_ENSEMBLES, ids=lambda e: e.name)
def test_ensemble_statistics_within_their_bands(quick_report, ens):
    summary = ensembles.summarise(quick_report[1]["ensembles"].query("ensemble == @ens.name"))
    assert len(summary) == len(ENGINES) and (summary.members == len(ens.members())).all()
    for _, row in summary.iterrows():
        for metric in set(ens.bands) & {"median_error", "p90_error"}:
            assert row[metric] <= ens.band(metric, row.engine), (row.engine, metric, row[metric])
        assert row.overturn_agreement >= ens.band("overturn_agreement", row.engine), row.engine


@pytest.mark.parametrize("spec", QUICK_SPECTRA, ids=lambda s: s.name)
def test_overturning_spectrum_agreement_within_its_band(quick_report, spec):
    summary = overturning_spectra.summarise(quick_report[1]["spectra"].query("spectrum == @spec.name"))
    assert len(summary) == len(ENGINES)
    for _, row in summary.iterrows():
        assert row.agreement >= spec.band("agreement", row.engine), (row.engine, row.agreement)


#: the largest typical member difference of the column's top-drum peak between Moreau-Jean at 1e-3 s and at 2.5e-4 s
#: on the quick column ensemble: measured 1.4% (8 runs; 6 standing and rocking), the full ensemble's in the report
COLUMN_STEP_BAND = 0.05


def test_moreau_jeans_step_converges_on_the_column_ensemble(quick_report):
    """The 8-drum column under the bundled records: halving Moreau-Jean's step twice changes the top drum's peak by
    a few percent typically, less at each halving, and no run's overturning."""
    table = quick_report[1]["column ensemble"]
    members = column_ensemble.members(column_ensemble.QUICK_SCALES)
    assert len(table) == len(members) * len(column_ensemble.RUNS)
    pairs = column_ensemble.summarise_pairs(table).set_index(["run", "against"])
    coarse = pairs.loc[("dem-moreau 1e-3 s", "dem-moreau 2.5e-4 s")]
    half = pairs.loc[("dem-moreau 5e-4 s", "dem-moreau 2.5e-4 s")]
    assert coarse.compared >= len(members) // 2
    assert coarse.typical_difference < COLUMN_STEP_BAND
    assert half.typical_difference < coarse.typical_difference
    assert coarse.overturn_agreement == half.overturn_agreement == 1.0


def test_rectangular_pulse_boundary_is_housners_closed_form_in_the_small_angle_limit():
    """The rocking equation's boundary comes within its linearisation of 1 / (1 - exp(-p t_d)): measured 0.1%
    to 0.3% on the 1 x 6 m monolith (the closed form ignores sin(alpha - theta) - (alpha - theta))."""
    spec = overturning_spectra.spectrum("spectrum_rectangular_quick")
    for column in spec.columns:
        (boundary, impacts), = overturning_spectra.reference_transitions(spec, column)
        assert impacts == 0  # it overturns before any impact
        assert boundary == pytest.approx(overturning_spectra.closed_form_rectangular(column), rel=0.005)


def _answers(values: dict):
    """Harness rows of a consensus case: each engine's finest and next-finest peak (rad)."""
    rows = []
    for engine, (finest, following) in values.items():
        for (step, settings), value in ((consensus.FINEST[engine], finest), (consensus.NEXT_FINEST[engine], following)):
            rows.append({"case": "c", "engine": engine, "step": step_label(engine, step, settings),
                         "settings": consensus.settings_label(settings), "metric": "peak_rotation", "value": value,
                         "status": "ok", "error": np.nan})
    return pd.DataFrame(rows)


def test_consensus_leaves_the_judged_engine_and_its_family_out():
    rows = _answers({"dem": (0.50, 0.50), "dem-overlap": (0.10, 0.10), "pymunk": (0.40, 0.41),
                     "pybullet": (0.42, 0.43), "mujoco": (0.44, 0.60)})
    judged = consensus.judge(rows)
    dem = judged[(judged.engine == "dem") & (judged.step == step_label("dem", 1, {"kn_factor": 100}))].iloc[0]
    # mujoco moved 36% between its two finest runs: not converged, so it does not vote
    assert dem.reference_members == "pymunk, pybullet" and dem.reference == pytest.approx(0.41)
    assert dem.reference_uncertainty == pytest.approx(0.015 / 0.41)
    pymunk = consensus.consensus(consensus.finest_answers(rows, "peak_rotation"), "peak_rotation", "pymunk")
    assert not pymunk.exists and "spread" in pymunk.reason  # dem 0.5, dem-overlap 0.1, pybullet 0.42


def test_no_reference_without_two_converged_other_engines():
    rows = _answers({"dem": (0.50, 0.50), "pymunk": (0.40, 0.80), "mujoco": (0.44, 0.44)})
    ref = consensus.consensus(consensus.finest_answers(rows, "peak_rotation"), "peak_rotation", "mujoco")
    assert not ref.exists and ref.members == ("dem",)


def test_errors_below_the_floor_are_exact_and_not_ranked():
    assert verdicts.describe(1.3e-14, "max_slip") == f"exact (below {EXACT_RELATIVE:g})"
    assert verdicts.describe(0.0123, "peak_decay") == "1.2%"
    assert verdicts.describe(2.4e-4, "drift_m") == "0.00024 m"
    table = pd.DataFrame([{"case": "newmark", "engine": e, "step": s, "settings": "{}", "status": "ok",
                           "metric": "max_slip", "error": err, "wall_time_s": w, "dt": 1e-3}
                          for e, s, err, w in (("pymunk", "0.001", 1.3e-14, 0.2), ("mujoco", "0.001", 2e-9, 0.1),
                                               ("dem", "auto/1", 2e-4, 0.05))])
    text = verdicts.case_verdict(table, cases.case("newmark"))["text"]
    assert "times smaller" not in text and "Exact (error below 1e-06, not ranked): mujoco, pymunk" in text
    assert "Fastest of them: dem" in text


def test_a_title_cut_at_the_figure_edge_is_refused(tmp_path):
    fig, ax = plt.subplots(figsize=(3, 2))
    ax.set_title("a stability-map title far longer than the narrow figure it was given to sit above " * 2)
    with pytest.raises(figures.FigureTextCut, match="edge"):
        figures.save(fig, tmp_path / "cut.png")
    fig, ax = plt.subplots(figsize=(3, 2))
    figures.title(ax, "a stability-map title far longer than the narrow figure it was given to sit above " * 2)
    figures.save(fig, tmp_path / "whole.png")


def test_a_pareto_figure_whose_runs_all_lie_on_the_exact_floor_draws_without_a_warning(tmp_path):
    """Every run exact (error 0): the points share the floor's value, and the axis spans a decade either side of it
    rather than matplotlib widening a singular range with a warning."""
    runs = pd.DataFrame({"engine": ["dem", "pymunk"], "error": [0.0, 0.0], "wall_time_s": [0.1, 0.3],
                         "step": ["0.001", "0.001"], "settings": ["{}", "{}"]})
    with warnings.catch_warnings():
        warnings.simplefilter("error")
        figures.pareto_figure(runs, "newmark", "max_slip", tmp_path / "pareto.png")
    assert (tmp_path / "pareto.png").stat().st_size > 0


def test_a_log_axis_whose_data_share_one_value_spans_a_decade_either_side(tmp_path):
    """A stiffness sweep whose time step is the same at every K_n (a fixed-step integrator) draws a flat line on
    a log axis; ``plain_log`` gives it a decade either side, in every figure, without matplotlib's warning."""
    kn = [1e6, 1e8, 1e10]
    rows = pd.DataFrame({"setting": [f"kn = {k:.0e}" for k in kn for _ in range(3)],
                         "metric": ["quarter_period", "peak_decay", "dt_s"] * 3,
                         "value": [0.01, 0.02, 1e-3] * 3, "status": "ok"})
    with warnings.catch_warnings():
        warnings.simplefilter("error")
        figures.stiffness_figure(rows, tmp_path / "stiffness.png")
        fig, ax = plt.subplots()
        ax.plot(kn, [1e-3] * 3)
        figures.plain_log(ax)
    assert ax.get_ylim() == pytest.approx((1e-4, 1e-2))
    assert (tmp_path / "stiffness.png").stat().st_size > 0


class _Page(html.parser.HTMLParser):
    def __init__(self):
        super().__init__()
        self.images, self.links, self.headers, self._in_th = [], [], [], False

    def handle_starttag(self, tag, attrs):
        attrs = dict(attrs)
        if tag == "img":
            self.images.append(attrs["src"])
        if tag == "a":
            self.links.append(attrs["href"])
        self._in_th = tag == "th"

    def handle_data(self, data):
        if self._in_th and data.strip():
            self.headers.append(data.strip())

    def handle_endtag(self, tag):
        self._in_th = False


def test_report_page_and_its_figures_are_whole(quick_report):
    index, _ = quick_report
    out = index.parent
    page = index.read_text()
    assert page.startswith("<!DOCTYPE html>") and page.rstrip().endswith("</html>")
    parser = _Page()
    parser.feed(page)
    # per case a Pareto and a convergence figure, per ensemble two, per spectrum one, and the two overviews
    n_figures = 2 * len(QUICK_CASES) + 2 * len(QUICK_ENSEMBLES) + len(QUICK_SPECTRA) + 2
    assert len([s for s in parser.images if not s.startswith("stability")]) == n_figures
    for src in parser.images + [link for link in parser.links if not link.startswith("#")]:
        assert (out / src).is_file(), src
    for src in parser.images:
        assert (out / src).read_bytes()[:8] == b"\x89PNG\r\n\x1a\n"
    verdict_texts = re.findall(r'<p class="verdict">(.*?)</p>', page)
    # one per case, ensemble and spectrum, and the column ensemble's
    assert len(verdict_texts) == len(QUICK_CASES) + len(QUICK_ENSEMBLES) + len(QUICK_SPECTRA) + 1
    assert '<section id="column_ensemble">' in page and "column_ensemble.csv" in parser.links
    assert not any("times smaller than the next" in v for v in verdict_texts)
    assert not [h for h in parser.headers if re.fullmatch(r"[a-z0-9]+(_[a-z0-9]+)+", h)], "snake_case header"
    assert "Glossary" in page and "auto/N" in page and "Stability map" in page
    assert re.search(r"commit <code>[0-9a-f]{40}</code>", page)
    assert any("studies/" in link for link in parser.links)


def test_report_opens_with_its_provenance_and_the_scoreboard(quick_report):
    """Title, one line naming the commit and the sources digest (written to digest.json), then the scoreboard;
    errors in percent, never an infinite uncertainty; a screenshot of the first screen where Chromium is."""
    index, _ = quick_report
    page = index.read_text()
    body = page[page.index("<body>"):]
    assert re.match(r'<body>\s*<h1>[^<]+</h1>\s*<p class="prov">', body)
    assert body.index('<section id="scoreboard">') < body.index('<section id="verdicts">')
    assert body.index('<section id="scoreboard">') < body.index("Six engines")
    recorded = provenance.recorded_digest(index.parent)
    assert recorded and f"sources digest <code>{recorded[:12]}</code>" in body
    board = body[body.index('<table class="score">'):body.index("</table>")]
    assert board.count("<tr>") == 1 + len(ENGINES) and all(f"<td>{e}</td>" in board for e in ENGINES)
    assert re.search(r"\d+ of \d+", board) and "%" in board
    assert "inf%" not in page and "nan%" not in page
    if shutil.which("chromium"):
        assert (index.parent / "first_screen.png").read_bytes()[:8] == b"\x89PNG\r\n\x1a\n"


def test_the_harness_bars_show_on_a_terminal_and_are_silent_in_a_log(capsys, monkeypatch):
    """The report in a log (stderr not a terminal) writes no bar; on a terminal its bars show unless progress is off."""
    from comparisons.harness.progress import terminal_bar

    assert list(terminal_bar(range(3), progress=True, desc="cases")) == [0, 1, 2]
    assert capsys.readouterr().err == ""
    monkeypatch.setattr(sys.stderr, "isatty", lambda: True)
    list(terminal_bar(range(3), progress=False, desc="cases"))
    assert capsys.readouterr().err == ""
    list(terminal_bar(range(3), progress=True, desc="cases"))
    assert "cases: 100%" in capsys.readouterr().err
