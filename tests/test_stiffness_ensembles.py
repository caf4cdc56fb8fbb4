"""The stiffness-ensemble summary (comparisons/benchmarks/stiffness_ensembles.py) on ensembles whose answers are
known, and its runs: a batch of the runs simulate gives."""

from pathlib import Path

import numpy as np
import pandas as pd
import pytest

import dem_core
from comparisons.benchmarks.stiffness_ensembles import compare, median_change_interval, peaks, summarise
from comparisons.cases.strong_motion import strong_motion


def _table(**runs):
    """A table as run_ensemble writes it: {run key: (peaks, overturned)}."""
    n = len(next(iter(runs.values()))[0])
    table = pd.DataFrame({"record": ["r"] * n, "scale": np.linspace(1.2, 3.0, n)})
    for key, (peak, over) in runs.items():
        table[f"peak_{key}"], table[f"overturned_{key}"] = peak, over
    return table


def test_a_uniform_ten_percent_rise_is_read_as_ten_percent_by_every_measure():
    stiff = np.linspace(0.01, 0.1, 21)
    line = compare("soft", 1.1 * stiff, np.zeros(21, bool), stiff, np.zeros(21, bool), np.ones(21, bool))
    assert "(+10.0%, 90% interval +10.0% to +10.0%)" in line
    assert "median ratio 1.1000" in line and "geometric mean ratio 1.1000" in line
    assert "median |log ratio| 0.095" in line and "agrees on overturning 100%" in line


def test_the_median_of_peaks_jumps_with_one_member_and_its_interval_says_so():
    # every member the same in both runs except one that crosses the median of a gapped ensemble
    stiff = np.array([0.01, 0.011, 0.012, 0.05, 0.06, 0.07, 0.08])
    soft = stiff.copy()
    soft[4] = 0.011
    low, high = median_change_interval(soft, stiff)
    assert np.median(soft) / np.median(stiff) - 1 == pytest.approx(-0.76, abs=0.01)
    assert low < -0.5 and high == pytest.approx(0.0)


def test_summary_compares_with_the_stiffest_and_the_perturbed_run_with_its_own_stiffness():
    base = np.array([0.02, 0.03, 0.04, 0.165])
    over = np.array([False, False, False, True])
    table = _table(**{"1x": (base * 0.9, over), "100x": (base, over), "1x_perturbed": (base * 0.9 * 1.05, over)})
    lines = summarise(table, "toy")
    assert lines[0] == "toy, 4 members, 3 standing in every run; against 100x K_n:"
    assert "1x K_n = 2e+11" in lines[1] and "median ratio 0.9000" in lines[1]
    assert "median ratio 1.0000" in lines[2]
    assert "amplitudes perturbed" in lines[4] and "median ratio 1.0500" in lines[4]


def test_a_member_that_overturns_in_any_run_leaves_the_peak_measures():
    peak = np.array([0.02, 0.03, 0.165])
    table = _table(**{"1x": (peak, np.array([False, False, True])), "10x": (peak * 2, np.array([False, True, False]))})
    lines = summarise(table)
    assert "1 standing in every run" in lines[0]
    assert "agrees on overturning 33%" in lines[1]


def test_the_ensemble_runs_as_a_batch_of_the_runs_simulate_gives():
    block = dem_core.scenes.block(1.0, 6.0)
    ensemble = [("el_centro_1940", 1.5), ("el_centro_1940", 3.0)]
    peak, over = peaks(block, 1.0, ensemble)
    uplift = block.gravity * np.tan(block.rocking_slenderness)
    for m, (name, scale) in enumerate(ensemble):
        motion = strong_motion(name, scale * uplift)
        alone = dem_core.simulate(block, motion, duration=motion.end_time, integrator="explicit")
        assert peak[m] == np.max(alone.peak_theta) and over[m] == alone.overturned


def test_members_are_written_into_a_new_folder_with_the_stamp_of_the_sources(tmp_path, monkeypatch, capsys):
    """``--members`` makes its folder before the runs (a missing one once lost them to a traceback after) and writes
    the members and, beside them, the digest of the sources they come from and the options that made them."""
    import argparse
    import json

    from comparisons.benchmarks import stiffness_ensembles
    from comparisons.report import provenance

    committed = pd.read_csv(Path(__file__).parents[1] / "reports" / "stiffness_ensembles" / "column.csv")
    made = {}

    def ensemble(scene, factors, n_scales, perturb, name):  # the runs, standing in: the folder exists before them
        made["folder"] = (tmp_path / "new" / "deeper").is_dir()
        return committed

    monkeypatch.setattr(stiffness_ensembles, "run_ensemble", ensemble)
    members = tmp_path / "new" / "deeper" / "column.csv"
    stiffness_ensembles.run(argparse.Namespace(summarise=None, members=str(members), scene="column",
                                               factors=[1.0, 10.0, 100.0], scales=10, perturb=0.001))
    assert made["folder"]
    pd.testing.assert_frame_equal(pd.read_csv(members), committed)
    stamp = json.loads(members.with_suffix(".json").read_text(encoding="utf-8"))
    assert stamp["digest"] == provenance.source_digest()[0]
    assert stamp["options"] == {"scene": "column", "factors": [1.0, 10.0, 100.0], "scales": 10, "perturb": 0.001}
    assert "column" in capsys.readouterr().out
