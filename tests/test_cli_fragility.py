"""dem-core fragility: the suite of records scaled to stripes, the fits printed and written, bad records refused."""

import json
import textwrap

import numpy as np
import pandas as pd

from dem_core.cli import main

COLUMN = textwrap.dedent("""
    [scene]
    builder = "column"
    n_drums = 3
    width = 1.0
    height = 4.0
    [excitation]
    kind = "record"
    source = "el_centro_1940"
    [simulation]
    integrator = "moreau"
""")


def _scene(tmp_path):
    path = tmp_path / "column.toml"
    path.write_text(COLUMN)
    return str(path)


def test_fragility_writes_fits_counts_runs_figure_and_settings(tmp_path, capsys):
    out = tmp_path / "fragility"
    status = main(["fragility", _scene(tmp_path), "--records", "el_centro_1940", "kalamata_1986", "--levels", "3",
                   "--max", "9", "--states", "0.2", "1.0", "--duration", "27", "--out", str(out)])
    printed = capsys.readouterr().out
    assert status == 0
    assert "2 record(s) x 3 PGA levels from 3 to 9 m/s^2 (6 runs), integrator moreau" in printed
    assert "peak |theta|/alpha >= 0.2:" in printed and "overturning:" in printed
    fits = pd.read_csv(out / "fragility.csv")
    assert fits["state"].tolist() == [0.2, 1.0] and (fits["runs"] == 6).all()
    counts = pd.read_csv(out / "counts.csv")
    assert len(counts) == 6 and (counts["runs"] == 2).all()
    runs = pd.read_csv(out / "runs.csv")
    assert sorted(set(runs["record"])) == ["el_centro_1940", "kalamata_1986"]
    np.testing.assert_allclose(sorted(set(runs["level"])), [3.0, 6.0, 9.0])
    overturned = runs["overturned"].astype(bool)
    for state in (0.2, 1.0):  # the counts are the runs' own damage, state by state
        hit = overturned if state >= 1 else overturned | (runs["damage_ratio"] >= state)
        assert fits.loc[fits["state"] == state, "exceeded"].item() == hit.sum()
    facts = json.loads((out / "study.json").read_text())
    assert facts["runs"] == 6 and facts["simulation"]["integrator"] == "moreau" and facts["duration_s"] == 27.0
    assert (out / "fragility.png").stat().st_size > 0


def test_a_folder_of_text_records_is_a_suite(tmp_path, capsys):
    folder = tmp_path / "records"
    folder.mkdir()
    t = np.arange(0.0, 2.0, 0.01)
    for name, frequency in (("north", 2.0), ("south", 3.0)):
        np.savetxt(folder / f"{name}.txt", np.column_stack([t, np.sin(2 * np.pi * frequency * t)]))
    (folder / "notes.md").write_text("not a record")
    out = tmp_path / "out"
    assert main(["fragility", _scene(tmp_path), "--suite", str(folder), "--units", "g", "--levels", "2",
                 "--out", str(out)]) == 0
    assert sorted(set(pd.read_csv(out / "runs.csv")["record"])) == ["north", "south"]


def test_a_record_that_cannot_be_read_is_named(tmp_path, capsys):
    assert main(["fragility", _scene(tmp_path), "--records", str(tmp_path / "missing.at2"), "--out",
                 str(tmp_path / "out")]) == 2
    error = capsys.readouterr().err
    assert error.startswith("error: record ") and "missing.at2" in error and "Traceback" not in error


def test_an_empty_records_folder_is_refused(tmp_path, capsys):
    (tmp_path / "empty").mkdir()
    assert main(["fragility", _scene(tmp_path), "--suite", str(tmp_path / "empty"), "--out",
                 str(tmp_path / "out")]) == 2
    assert capsys.readouterr().err == (f"error: --suite: {tmp_path / 'empty'}: no record in it: a suite folder holds "
                                       f"record files (.at2, .txt, .dat, .csv) and optionally records.csv\n")
    assert not (tmp_path / "out").exists()


def test_the_gpu_is_refused_before_anything_runs(tmp_path, capsys):
    assert main(["fragility", _scene(tmp_path), "--device", "gpu", "--out", str(tmp_path / "out")]) == 2
    captured = capsys.readouterr()
    assert captured.out == "" and captured.err.startswith("error: --device:") and "CUDA" in captured.err


def test_a_duration_that_cuts_a_records_strong_motion_is_refused_naming_it(tmp_path, capsys):
    """Mexico City's strong motion (5-95% of its Arias intensity) lasts from 40 to 77 s: 25 s of it would count
    every stripe as standing."""
    out = tmp_path / "out"
    assert main(["fragility", _scene(tmp_path), "--records", "kalamata_1986", "mexico_city_1985", "--duration", "25",
                 "--out", str(out)]) == 2
    captured = capsys.readouterr()
    assert captured.out == "" and not out.exists()
    assert captured.err.startswith("error: --duration: 25 s of mexico_city_1985 stop before the end of its strong "
                                   "motion (39.7 to 76.5 s")


def test_stripes_of_spectral_acceleration_need_a_usable_period(tmp_path, capsys):
    common = ["fragility", _scene(tmp_path), "--records", "el_centro_1940", "--out", str(tmp_path / "out")]
    assert main([*common, "--im", "sa"]) == 2
    assert "--im sa: give the period with --period" in capsys.readouterr().err
    assert main([*common, "--im", "sa", "--period", "0.02"]) == 2
    assert capsys.readouterr().err.startswith("error: --period: el_centro_1940: a period of 0.02 s is under 4")
    assert main([*common, "--period", "1"]) == 2
    assert "--period is the period of --im sa" in capsys.readouterr().err
    assert not (tmp_path / "out").exists()


def test_residual_states_are_fitted_and_written_after_a_rest(tmp_path, capsys):
    out = tmp_path / "out"
    assert main(["fragility", _scene(tmp_path), "--records", "kalamata_1986", "el_centro_1940", "--levels", "3",
                 "--max", "9", "--dislocation", "1", "5", "--tilt", "0.002", "--rest", "4", "--out", str(out)]) == 0
    printed = capsys.readouterr().out
    assert "residual dislocation >= 1 mm:" in printed and "residual tilt >= 0.002 rad:" in printed
    fits = pd.read_csv(out / "fragility.csv")
    assert list(zip(fits["measure"], fits["state"])) == [("peak", 0.1), ("peak", 0.3), ("peak", 0.5), ("peak", 1.0),
                                                         ("dislocation", 1.0), ("dislocation", 5.0), ("tilt", 0.002)]
    runs = pd.read_csv(out / "runs.csv")
    assert {"residual_dislocation_mm", "residual_tilt_rad", "at_rest"} <= set(runs.columns)
    assert json.loads((out / "study.json").read_text())["rest"] == 4.0


def test_residual_states_with_a_duration_are_refused_naming_it(tmp_path, capsys):
    assert main(["fragility", _scene(tmp_path), "--records", "kalamata_1986", "--levels", "2", "--tilt", "0.01",
                 "--duration", "27", "--out", str(tmp_path / "out")]) == 2
    error = capsys.readouterr().err
    assert error.startswith("error: --duration: residual states are read after each whole record and --rest s at "
                            "rest; leave out the duration, or give --rest 0") and error.count("\n") == 1
