"""The command line runs a scene file and writes results and figures, prints accelerations in m/s^2
with g in brackets, takes --duration wherever it runs a scene, shows progress only on a terminal, and
fails cleanly on bad input."""

import json
import re
import subprocess
import sys
import textwrap

import pandas as pd
import pytest

import dem_core
from dem_core import cli
from dem_core.analyses import thresholds
from dem_core.cli import main

ACCELERATION = r"-?\d[\d.e+-]* m/s\^2 \(-?\d[\d.e+-]* g\)"


def test_run_writes_tables_summary_and_figures(tmp_path, capsys):
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
    assert main(["run", str(scene), "--out", str(out), "--format", "parquet", "--relative-rotations"]) == 0
    printed = capsys.readouterr().out
    assert re.search(f"ground motion: el_centro_1940 x[\\d.]+, PGA {ACCELERATION}", printed)
    assert "figures: rotations.png, displacements.png, sliding.png" in printed
    history = pd.read_parquet(out / "time_history.parquet")
    assert set(history["block"]) == {"drum1", "drum2", "drum3"}
    assert history["t"].max() >= 3.0
    metrics = pd.read_csv(out / "metrics.csv")
    assert list(metrics["block"]) == ["drum1", "drum2", "drum3"]
    summary = json.loads((out / "summary.json").read_text())
    assert summary["dt_s"] < summary["stability_limit_s"]
    for name in ("rotations.png", "displacements.png", "sliding.png"):
        assert (out / name).read_bytes()[:8] == b"\x89PNG\r\n\x1a\n"


def test_bad_scene_file_is_reported_with_its_name(tmp_path, capsys):
    scene = tmp_path / "bad.toml"
    scene.write_text("[scene]\nbuilder = 'column'\nn_drums = -2\n")
    assert main(["run", str(scene), "--out", str(tmp_path / "o")]) == 2
    err = capsys.readouterr().err
    assert "bad.toml" in err and "n_drums" in err


def test_module_entry_point_lists_records_with_their_pga_in_one_unit():
    done = subprocess.run([sys.executable, "-m", "dem_core", "records"], capture_output=True, text=True, check=True)
    lines = done.stdout.splitlines()
    assert len(lines) == len(dem_core.records.BUNDLED)
    assert lines[0].startswith("el_centro_1940     PGA 2.75 m/s^2 (0.281 g)")
    for line in lines:
        assert re.search(f"PGA {ACCELERATION}, ", line), line
        assert line.count("PGA") == 1


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
    assert re.search(f"overturning threshold: amplitude = {ACCELERATION}, between [\\d.]+ and [\\d.]+ m/s\\^2", out)
    assert re.search(f"  amplitude = {ACCELERATION}: overturning", out)
    assert main(["ramp", str(scene), "--duration", "8"]) == 0
    out = capsys.readouterr().out
    assert re.search(f"starts rocking +{ACCELERATION}", out)
    assert main(["threshold", str(scene), "--parameter", "amplitdue", "--low", "1", "--high", "2"]) == 2
    assert "amplitdue" in capsys.readouterr().err


def test_threshold_units_follow_the_varied_parameter_and_duration_overrides_the_file(tmp_path, capsys,
                                                                                   monkeypatch):
    scene = tmp_path / "harmonic.toml"
    scene.write_text(COLUMN.replace('kind = "sine_pulse"\namplitude = 4.0\nduration = 0.8',
                                    'kind = "harmonic"\npga = 2.0\nfrequency = 1.0'))
    durations = []

    def overturns_above_3_m_s2(scene, motion, **options):
        durations.append(options["duration"])
        return type("Run", (), {"overturned": motion.horizontal.peak_acceleration > 3.0})()

    monkeypatch.setattr(thresholds, "simulate", overturns_above_3_m_s2)
    assert main(["threshold", str(scene), "--low", "1", "--high", "6", "--duration", "2.5"]) == 0
    assert set(durations) == {2.5}
    assert re.search(f"overturning threshold: pga = {ACCELERATION}, between", capsys.readouterr().out)
    assert main(["threshold", str(scene), "--parameter", "frequency", "--low", "0.5", "--high", "3"]) == 0
    assert durations[-1] == 4.0  # the file's duration
    assert re.search(r"frequency = [\d.]+ Hz: ", capsys.readouterr().out)


def test_animate_and_spectrum_commands_write_their_files(tmp_path, capsys):
    scene = tmp_path / "column.toml"
    scene.write_text(COLUMN)
    movie = tmp_path / "column.gif"
    assert main(["animate", str(scene), "--out", str(movie), "--duration", "1", "--fps", "10",
                 "--exaggerate", "20"]) == 0
    assert movie.read_bytes()[:6] == b"GIF89a"
    assert (tmp_path / "column_snapshots.png").is_file()
    printed = capsys.readouterr()
    assert "(11 frames, 1.1 s at 10 frames/s, rotations and displacements x 20)" in printed.out
    assert printed.err == ""  # no progress bar when stderr is not a terminal
    assert main(["animate", str(scene), "--out", str(movie), "--exaggerate", "0"]) == 2
    figure = tmp_path / "spectra.png"
    assert main(["spectrum", "el_centro_1940", "kalamata_1986", "--out", str(figure)]) == 0
    table = pd.read_csv(figure.with_suffix(".csv"))
    assert set(table.record) == {"el_centro_1940 x1", "kalamata_1986 x1"}
    out = capsys.readouterr().out
    assert re.search(f"el_centro_1940 x1: PGA {ACCELERATION}, peak PSA {ACCELERATION} at T = [\\d.]+ s, "
                     r"peak SD [\d.]+ m", out)
    assert main(["spectrum", "no_such_record"]) == 2


def test_progress_shows_on_a_terminal(tmp_path, capsys, monkeypatch):
    scene = tmp_path / "column.toml"
    scene.write_text(COLUMN)
    monkeypatch.setattr(cli, "_interactive", lambda: True)
    assert main(["animate", str(scene), "--out", str(tmp_path / "c.gif"), "--duration", "0.4", "--fps", "10"]) == 0
    assert "frames: 100%" in capsys.readouterr().err


@pytest.mark.parametrize("command", ["run", "animate", "threshold", "ramp", "stiffness"])
def test_every_command_that_runs_a_scene_takes_a_duration(command, capsys):
    with pytest.raises(SystemExit):
        main([command, "--help"])
    assert "--duration" in capsys.readouterr().out


def test_warnings_print_as_one_line_a_user_reads(monkeypatch, capsys):
    """The long-run warning printed as Python's 'cli.py:206: RuntimeWarning: ...' and the source line."""
    import warnings

    def warn(args):
        warnings.warn("a long run: 1.7e+08 steps; expect about 4.6 minutes", RuntimeWarning)
        return 0

    monkeypatch.setattr(cli, "_spectrum", warn)
    assert main(["spectrum", "el_centro_1940"]) == 0
    assert capsys.readouterr().err == "warning: a long run: 1.7e+08 steps; expect about 4.6 minutes\n"


@pytest.mark.parametrize("argv", [["animate", "--out", "anim"], ["animate", "--out", "movie.avi"],
                                  ["run", "--animate", "run.png", "--no-plots"]])
def test_an_animation_name_without_gif_or_mp4_is_refused_before_the_run(argv, tmp_path, capsys, monkeypatch):
    """An animation name without .gif or .mp4 is refused (exit status 2, the reason on stderr) before the
    simulation starts."""
    monkeypatch.chdir(tmp_path)
    monkeypatch.setattr(cli, "simulate", lambda *a, **k: pytest.fail("the run started"))
    assert main(argv) == 2
    assert "must end in .gif or .mp4" in capsys.readouterr().err


def test_mp4_without_ffmpeg_is_refused_before_the_run(tmp_path, capsys, monkeypatch):
    from dem_core.pictures import animation

    monkeypatch.chdir(tmp_path)
    monkeypatch.setattr(animation, "can_write_mp4", lambda: False)
    monkeypatch.setattr(cli, "simulate", lambda *a, **k: pytest.fail("the run started"))
    assert main(["animate", "--out", "run.mp4"]) == 2
    assert "writing MP4 needs ffmpeg" in capsys.readouterr().err
