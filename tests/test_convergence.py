"""Rerunning a scene at stiffer contacts: the table, the convergence it shows on a record, and the verdict on
each measure (within 5%, or an absolute floor for tiny values)."""

import numpy as np
import pandas as pd
import pytest

import dem_core
from dem_core import excitation, scenes
from dem_core.cli import main
from dem_core.analyses.convergence import LABELS, agree, stiffness_convergence, verdicts


def test_table_matches_direct_runs_and_shows_the_peak_settling():
    scene = scenes.block(1.0, 6.0)
    motion = excitation.record("northridge_1994", pga=4.0)
    table = stiffness_convergence(scene, motion, 15.0, factors=(100.0, 1.0, 10.0))
    assert list(table.factor) == [1.0, 10.0, 100.0]
    direct = dem_core.simulate(scene, motion, 15.0, integrator="explicit")
    assert table.max_peak_abs_theta_rad.iloc[0] == direct.peak_theta.max()
    assert table["change:max_peak_abs_theta_rad"].iloc[-1] == 0.0
    # measured +113% and +31% from the stiffest run (see tests/test_rocking.py for the rocking equation)
    change = table["change:max_peak_abs_theta_rad"].abs()
    assert change.iloc[0] > change.iloc[1] > 0.0
    assert table.dt_s.iloc[0] == pytest.approx(10.0 * table.dt_s.iloc[2], rel=0.05)


def test_stiffness_command(tmp_path, capsys):
    scene = tmp_path / "block.toml"
    scene.write_text('[scene]\nbuilder = "block"\nwidth = 1.0\nheight = 6.0\n'
                     '[excitation]\nkind = "sine_pulse"\namplitude = 4.0\nduration = 0.6\n')
    assert main(["stiffness", str(scene), "--factors", "1", "4", "--duration", "3"]) == 0
    out = capsys.readouterr().out
    assert "each measure at K_n x 1 against x 4, the stiffest: converged when it changes by at most 5%" in out
    for label in LABELS.values():
        assert f"  {label}: " in out
    assert "largest relative change" not in out
    assert main(["stiffness", str(scene), "--factors", "0"]) == 2


def issue_table():
    """The table of issue 22: total sliding 3.91 mm at K_n, 1.29 mm at 100 K_n (2.0 mm at 10 K_n)."""
    return pd.DataFrame({"factor": [1.0, 10.0, 100.0], "kn": [2e11, 2e12, 2e13],
                         "max_peak_abs_theta_rad": [0.0346, 0.0350, 0.0351],
                         "total_sliding_m": [3.91e-3, 2.0e-3, 1.29e-3],
                         "mean_rocking_rad": [2.0e-4, 5.0e-4, 9.0e-4],
                         "overturn_time_s": [np.nan, np.nan, np.nan]})


def test_each_measure_gets_a_verdict_with_an_absolute_floor():
    found = {v.measure: v for v in verdicts(issue_table())}
    sliding = found["total_sliding_m"]
    assert sliding.change == pytest.approx(2.031, abs=1e-3) and not sliding.converged
    assert sliding.agrees_from == 10.0  # 2.0 mm against 1.29 mm: 0.71 mm apart, under the 1 mm floor
    assert found["max_peak_abs_theta_rad"].converged  # 1.4%
    rocking = found["mean_rocking_rad"]
    assert abs(rocking.change) > 0.5 and rocking.converged  # +350% of a tiny value, but 0.0007 rad: the floor
    assert found["overturn_time_s"].converged  # no overturn at any stiffness
    assert agree("overturn_time_s", 5.0, 5.08) and not agree("overturn_time_s", np.nan, 5.0)


def test_stiffness_verdicts_name_the_measure_its_values_and_what_to_do():
    from dem_core.cli.stiffness import verdict_lines

    lines = verdict_lines(issue_table())
    text = "\n".join(lines)
    assert lines[0] == ("each measure at K_n x 1 against x 100, the stiffest: converged when it changes by at most 5%, "
                        "or by less than 0.001 rad of rotation, 1 mm of sliding, 0.1 s of overturn time")
    assert ("  total sliding (summed over the interfaces): 3.91 mm at x 1, 2 mm at x 10, 1.29 mm at x 100\n"
            "    not converged at x 1 (+203.1%, +2.62 mm); it agrees from x 10: rerun at a stiffer K_n ([contact] "
            "kn = 2e+12) or treat this measure as uncertain") in text
    assert "  peak rotation (the largest peak |theta| of any block): 0.0346 rad at x 1" in text
    assert "    converged: x 1 within 5% of x 100 (-1.4%, -0.0005 rad)" in text
    assert ("    converged: x 1 differs from x 100 by -77.8%, but only by -0.0007 rad, less than the 0.001 rad floor"
            in text)
    assert ("  overturn time: none at x 1, none at x 10, none at x 100\n"
            "    converged: no overturn at any stiffness") in text
    stiff = issue_table().assign(total_sliding_m=[3.91e-3, 2.9e-3, 1.29e-3])
    lines = verdict_lines(stiff)
    assert any("the two stiffest runs disagree too: treat this measure as uncertain" in line for line in lines)
