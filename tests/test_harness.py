"""The comparison harness on the quick set: each engine within its band on each case, the native core
ahead where it is ahead today (accuracy, not wall time), and a report whose page and figures are whole."""

import html.parser
import re

import pandas as pd
import pytest

from comparisons import cases
from comparisons.harness import run_harness
from comparisons.report import write_report
from comparisons.stress import stiffness_sweep

# |error| bands at each engine's usual step (the native core's automatic one, 1e-3 s for the others);
# the comments give the measured values (python -m comparisons report --quick)
BANDS = {
    ("free_rocking", "quarter_period"): {"dem": 0.015, "pymunk": 0.015, "pybullet": 0.015, "mujoco": 0.01},
    # measured dem 0.91%, pymunk 0.61%, pybullet 0.54%, mujoco 0.08%
    ("free_rocking", "peak_decay"): {"dem": 0.03, "pymunk": 0.10, "pybullet": 0.15, "mujoco": 0.05},
    # measured dem 2.0%, pymunk 6.5%, pybullet 9.1%, mujoco 2.7%
    ("newmark", "max_slip"): {"dem": 0.01, "pymunk": 0.01, "pybullet": 0.01, "mujoco": 0.01},
    # measured dem 2.7e-4, pymunk 3.7e-6, pybullet 1.3e-5, mujoco 6.8e-7
    ("sine_pulse", "peak_rotation"): {"dem": 0.05, "pymunk": 0.05, "pybullet": 0.05, "mujoco": 0.05},
    # measured dem 1.3%, pymunk 0.4%, pybullet -1.8%, mujoco 0.6%
    ("record_sliding", "max_slip"): {"dem": 0.03, "pymunk": 0.03, "pybullet": 0.03, "mujoco": 0.03},
    # measured dem -1.9e-4, pymunk 5.4e-5, pybullet 4.2e-5, mujoco 8.0e-5
    ("record_sliding", "rms_slip"): {"dem": 0.03, "pymunk": 0.03, "pybullet": 0.03, "mujoco": 0.08},
    # measured dem 0.9%, pymunk 0.4%, pybullet 0.4%, mujoco 3.8%
    ("statics", "drift_m"): {"dem": 1e-9, "pymunk": 1e-3, "pybullet": 1e-3, "mujoco": 1e-9},
    # measured dem 2.7e-15 m, pymunk 2.4e-4 m, pybullet 2.1e-4 m, mujoco 1.9e-17 m
}
# where the native core at its automatic step is more accurate today than an engine at 1e-3 s
AHEAD = [
    ("free_rocking", "peak_decay", "pymunk"), ("free_rocking", "peak_decay", "pybullet"),
    ("free_rocking", "peak_decay", "mujoco"), ("sine_pulse", "peak_rotation", "pybullet"),
    ("statics", "drift_m", "pymunk"), ("statics", "drift_m", "pybullet"),
]


@pytest.fixture(scope="module")
def quick_table():
    return run_harness(quick=True, progress=False)


def _error(table, case, metric, engine):
    step = "auto/1" if engine == "dem" else "0.001"
    row = table[(table.case == case) & (table.metric == metric) & (table.engine == engine) & (table.step == step)]
    assert len(row) == 1 and row.status.iloc[0] == "ok", (case, metric, engine)
    return abs(float(row.error.iloc[0]))


def test_every_quick_run_finished(quick_table):
    assert set(quick_table.case) == {c.name for c in cases.all_cases() if c.quick}
    assert set(quick_table.status) == {"ok"}
    assert (quick_table.wall_time_s > 0).all()


@pytest.mark.parametrize("case, metric", list(BANDS))
def test_each_engine_within_its_band(quick_table, case, metric):
    for engine, band in BANDS[(case, metric)].items():
        assert _error(quick_table, case, metric, engine) < band, engine


@pytest.mark.parametrize("case, metric, engine", AHEAD)
def test_native_core_stays_ahead_where_it_is_ahead(quick_table, case, metric, engine):
    assert _error(quick_table, case, metric, "dem") < _error(quick_table, case, metric, engine)


def test_errors_fall_with_the_time_step_where_the_engines_converge(quick_table):
    for engine, coarse, fine in (("pymunk", "0.001", "0.00025"), ("mujoco", "0.001", "0.00025"),
                                 ("dem", "auto/1", "auto/4")):
        rows = quick_table[(quick_table.case == "free_rocking") & (quick_table.metric == "peak_decay")
                           & (quick_table.engine == engine)].set_index("step")
        assert abs(rows.error[fine]) < abs(rows.error[coarse]), engine


class _Links(html.parser.HTMLParser):
    def __init__(self):
        super().__init__()
        self.images, self.links = [], []

    def handle_starttag(self, tag, attrs):
        attrs = dict(attrs)
        if tag == "img":
            self.images.append(attrs["src"])
        if tag == "a":
            self.links.append(attrs["href"])


def test_report_page_and_its_figures_are_whole(tmp_path):
    some = [c for c in cases.all_cases() if c.name in ("free_rocking", "newmark")]
    table = run_harness(quick=True, cases=some, engines=("dem", "mujoco"), progress=False)
    stress = pd.DataFrame(stiffness_sweep(quick=True, progress=False) + [
        {"test": "column, growing dt", "engine": "dem", "setting": "1 x limit", "status": "ok", "metric": "e",
         "value": 0.0, "wall_time_s": 0.1}])
    index = write_report(table, stress, tmp_path, quick=True, run_time_s=1.0)
    page = index.read_text()
    assert page.startswith("<!DOCTYPE html>") and page.rstrip().endswith("</html>")
    parser = _Links()
    parser.feed(page)
    # a Pareto and a convergence figure per case, a stability map per stress test, K_n figure
    assert len(parser.images) == 2 * 2 + 2 + 1
    for src in parser.images + parser.links:
        assert (tmp_path / src).is_file(), src
    for src in parser.images:
        assert (tmp_path / src).read_bytes()[:8] == b"\x89PNG\r\n\x1a\n"
    verdicts = re.findall(r'<p class="verdict">(.*?)</p>', page)
    assert len(verdicts) == 2 and all("Most accurate" in v for v in verdicts)
    assert "Stability map" in page
