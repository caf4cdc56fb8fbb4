"""Rerunning a scene at stiffer contacts: the table, and the convergence it shows on a record."""

import pytest

import dem_core
from dem_core import excitation, scenes
from dem_core.cli import main
from dem_core.analyses.convergence import stiffness_convergence


def test_table_matches_direct_runs_and_shows_the_peak_settling():
    scene = scenes.block(1.0, 6.0)
    motion = excitation.record("northridge_1994", pga=4.0)
    table = stiffness_convergence(scene, motion, 15.0, factors=(100.0, 1.0, 10.0))
    assert list(table.factor) == [1.0, 10.0, 100.0]
    direct = dem_core.simulate(scene, motion, 15.0)
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
    assert "largest relative change" in capsys.readouterr().out
    assert main(["stiffness", str(scene), "--factors", "0"]) == 2
