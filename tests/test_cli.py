"""The command line runs a scene file and writes results and figures; bad input fails cleanly."""

import json
import subprocess
import sys
import textwrap

import pandas as pd

from dem_core.cli import main


def test_run_writes_tables_summary_and_figures(tmp_path):
    scene = tmp_path / "col.toml"
    scene.write_text(textwrap.dedent("""
        [scene]
        builder = "column"
        n_drums = 3
        [excitation]
        kind = "record"
        source = "el_centro_1940"
        pga = 2.0
        [simulation]
        duration = 3.0
    """))
    out = tmp_path / "out"
    assert main(["run", str(scene), "--out", str(out), "--format", "parquet"]) == 0
    history = pd.read_parquet(out / "time_history.parquet")
    assert set(history["block"]) == {"drum1", "drum2", "drum3"}
    assert history["t"].max() >= 3.0
    metrics = pd.read_csv(out / "metrics.csv")
    assert list(metrics["block"]) == ["drum1", "drum2", "drum3"]
    summary = json.loads((out / "summary.json").read_text())
    assert summary["dt_s"] < summary["stability_limit_s"]
    for name in ("rotations.png", "displacements.png"):
        assert (out / name).read_bytes()[:8] == b"\x89PNG\r\n\x1a\n"


def test_bad_scene_file_is_reported_with_its_name(tmp_path, capsys):
    scene = tmp_path / "bad.toml"
    scene.write_text("[scene]\nbuilder = 'column'\nn_drums = -2\n")
    assert main(["run", str(scene), "--out", str(tmp_path / "o")]) == 2
    err = capsys.readouterr().err
    assert "bad.toml" in err and "n_drums" in err


def test_module_entry_point_lists_records():
    done = subprocess.run([sys.executable, "-m", "dem_core", "records"], capture_output=True, text=True, check=True)
    assert "el_centro_1940" in done.stdout


COLUMN = textwrap.dedent("""
    [scene]
    builder = "column"
    n_drums = 2
    [excitation]
    kind = "sine_pulse"
    amplitude = 4.0
    duration = 0.8
    [simulation]
    duration = 4.0
""")


def test_threshold_and_ramp_commands_print_their_findings(tmp_path, capsys):
    scene = tmp_path / "column.toml"
    scene.write_text(COLUMN)
    assert main(["threshold", str(scene), "--parameter", "amplitude", "--low", "1", "--high", "12",
                 "--tolerance", "0.05"]) == 0
    out = capsys.readouterr().out
    assert "overturning threshold: amplitude = " in out
    assert main(["ramp", str(scene), "--duration", "8"]) == 0
    out = capsys.readouterr().out
    assert "rocking starts" in out and "m/s^2" in out
    assert main(["threshold", str(scene), "--parameter", "amplitdue", "--low", "1", "--high", "2"]) == 2
    assert "amplitdue" in capsys.readouterr().err


def test_animate_and_spectrum_commands_write_their_files(tmp_path):
    scene = tmp_path / "column.toml"
    scene.write_text(COLUMN)
    movie = tmp_path / "column.gif"
    assert main(["animate", str(scene), "--out", str(movie), "--duration", "1", "--fps", "10"]) == 0
    assert movie.read_bytes()[:6] == b"GIF89a"
    assert (tmp_path / "column_snapshots.png").is_file()
    figure = tmp_path / "spectra.png"
    assert main(["spectrum", "el_centro_1940", "kalamata_1986", "--out", str(figure)]) == 0
    table = pd.read_csv(figure.with_suffix(".csv"))
    assert set(table.record) == {"el_centro_1940 x1", "kalamata_1986 x1"}
    assert main(["spectrum", "no_such_record"]) == 2
