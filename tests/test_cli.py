"""The command line runs a scene file and writes results and figures, prints accelerations in m/s^2
with g in brackets, takes --duration wherever it runs a scene, shows progress only on a terminal, and
fails cleanly on bad input."""

import json
import math
import os
import re
import subprocess
import sys
import textwrap
from pathlib import Path

import numpy as np
import pandas as pd
import pytest

import dem_core
from dem_core import cli
from dem_core.analyses import thresholds
from dem_core.cli import main
from dem_core.inputs.suites import load_suite
from dem_core.pictures import SLIP_IN_MM_BELOW

REPOSITORY = Path(__file__).resolve().parents[1]

ACCELERATION = r"-?\d[\d.e+-]* m/s\^2 \(-?\d[\d.e+-]* g\)"


def _says_the_unconverged_steps(printed: str, summary: dict) -> None:
    """The run's printout counts its contact solves that ended short of their tolerance, as summary.json does, and
    says nothing of them where there are none."""
    unconverged = summary["unconverged_steps"]
    said = f"contact solve: {unconverged:,} solves in {summary['steps']:,} steps ended short" in printed
    assert said == (unconverged > 0)


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
    assert summary["integrator"] == "moreau" and summary["restitution"] == 0.0  # the defaults
    assert re.search(r"Moreau-Jean integrator .* impacts: restitution 0$", printed, re.MULTILINE)
    assert re.search(r"simulated 3 s in [\d.]+ s \(setting up and compiling the engine: [\d.]+ s\)", printed)
    # each interface's sliding once in interfaces.csv; metrics.csv's per-block column adds a block's joints
    interfaces = pd.read_csv(out / "interfaces.csv")
    assert list(interfaces.interface) == ["base/drum1", "drum1/drum2", "drum2/drum3"]
    assert interfaces.sliding_m.sum() == pytest.approx(summary["total_sliding_m"], rel=1e-12, abs=1e-15)
    assert "sliding_m" not in metrics and "sliding_at_its_joints_m" in metrics
    assert summary["total_sliding_m"] < SLIP_IN_MM_BELOW
    assert f", total sliding {1e3 * summary['total_sliding_m']:.4g} mm, " in printed
    joint = dict(zip(interfaces.interface, interfaces.sliding_m))
    assert metrics.sliding_at_its_joints_m[1] == pytest.approx(joint["drum1/drum2"] + joint["drum2/drum3"])
    assert "interfaces.csv" in summary["files"]
    _says_the_unconverged_steps(printed, summary)
    for name in ("rotations.png", "displacements.png", "sliding.png"):
        assert (out / name).read_bytes()[:8] == b"\x89PNG\r\n\x1a\n"


def test_bad_scene_file_is_reported_with_its_name(tmp_path, capsys):
    scene = tmp_path / "bad.toml"
    scene.write_text("[scene]\nbuilder = 'column'\nn_drums = -2\n")
    assert main(["run", str(scene), "--out", str(tmp_path / "o")]) == 2
    err = capsys.readouterr().err
    assert "bad.toml" in err and "n_drums" in err


def test_module_entry_point_lists_the_demonstration_suite_with_each_pga_in_one_unit():
    done = subprocess.run([sys.executable, "-m", "dem_core", "records"], capture_output=True, text=True, check=True)
    suite = load_suite()
    lines = done.stdout.splitlines()
    assert lines[0] == f"suite demonstration: {len(suite)} records" and len(lines) == len(suite) + 1
    assert lines[1].startswith("el_centro_1940     PGA 2.75 m/s^2 (0.281 g), PGV ")
    for line, entry in zip(lines[1:], suite.records, strict=True):
        assert line.startswith(entry.name) and line.endswith(entry.source), line
        assert re.search(f"PGA {ACCELERATION}, PGV ", line) and line.count("PGA") == 1 + entry.source.count("PGA")


def test_records_lists_a_folder_and_writes_its_table(tmp_path, capsys):
    folder = tmp_path / "suite"
    folder.mkdir()
    np.savetxt(folder / "one.txt", np.sin(np.arange(400) * 0.05))
    (folder / "records.csv").write_text("file,dt,magnitude,source\none.txt,0.01,6.1,a test\n")
    assert main(["records", str(folder), "--csv", str(tmp_path / "suite.csv")]) == 0
    printed = capsys.readouterr().out.splitlines()
    assert printed[0] == "suite suite: 1 records"
    assert "every 0.01 s (given in records.csv), strong motion " in printed[1] and printed[1].endswith("; M6.1: a test")
    table = pd.read_csv(tmp_path / "suite.csv")
    assert list(table["name"]) == ["one"] and table.loc[0, "pgv_m_s"] > 0


def test_records_names_a_suite_it_cannot_read_in_one_line(tmp_path, capsys):
    folder = tmp_path / "suite"
    folder.mkdir()
    np.savetxt(folder / "one.txt", np.sin(np.arange(400) * 0.05))
    assert main(["records", str(folder)]) == 2
    error = capsys.readouterr().err
    assert error.count("\n") == 1 and "one.txt" in error and "records.csv's dt column" in error


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
                 "--scan", "6", "--tolerance", "0.05"]) == 0
    out = capsys.readouterr().out
    assert re.search(f"overturning threshold: amplitude = {ACCELERATION}, between [\\d.]+ and [\\d.]+ m/s\\^2", out)
    assert re.search(f"  amplitude = {ACCELERATION}( to {ACCELERATION} \\(\\d+ runs\\))?: overturning", out)
    assert main(["ramp", str(scene), "--duration", "8"]) == 0
    out = capsys.readouterr().out
    # each onset with its criterion, and the static uplift of the column as one block to set it against
    assert re.search(f"starts rocking +{ACCELERATION} +criterion: a block's rotation passes theta_cr/30 = "
                     r"0.0055 rad \(theta_cr = 0.165 rad, the scene's slenderness\)", out)
    assert re.search(r"starts sliding .* criterion: an interface slips more than 0.0001 m", out)
    assert re.search(f"static uplift acceleration g b/h = {ACCELERATION} \\(the column as one rigid block, "
                     r"b/h = 0.167\)", out)
    uplift = float(re.search(r"g b/h = ([\d.]+) m/s\^2", out).group(1))
    assert uplift == pytest.approx(dem_core.scenes.column(2).gravity * 0.5 / 3.0, rel=5e-3)  # 1 m by 6 m
    assert main(["threshold", str(scene), "--parameter", "amplitdue", "--low", "1", "--high", "2"]) == 2
    assert "amplitdue" in capsys.readouterr().err


def test_threshold_units_follow_the_varied_parameter_and_duration_overrides_the_file(tmp_path, capsys,
                                                                                   monkeypatch):
    scene = tmp_path / "harmonic.toml"
    scene.write_text(COLUMN.replace('kind = "sine_pulse"\namplitude = 4.0\nduration = 0.8',
                                    'kind = "harmonic"\npga = 2.0\nfrequency = 1.0'))
    durations = []

    def overturns_above_3_m_s2(scene, motion_at, scales, event, **options):
        durations.append(options["duration"])
        return [motion_at(s).horizontal.peak_acceleration > 3.0 for s in scales]

    monkeypatch.setattr(thresholds, "batch_outcomes", overturns_above_3_m_s2)
    assert main(["threshold", str(scene), "--low", "1", "--high", "6", "--duration", "2.5"]) == 0
    assert set(durations) == {2.5}
    assert re.search(f"overturning threshold: pga = {ACCELERATION}, between", capsys.readouterr().out)
    assert main(["threshold", str(scene), "--parameter", "frequency", "--low", "0.5", "--high", "3"]) == 0
    assert durations[-1] == 4.0  # the file's duration
    assert re.search(r"frequency = [\d.]+ Hz to [\d.]+ Hz \(\d+ runs\): no overturning", capsys.readouterr().out)


def test_animate_and_spectrum_commands_write_their_files(tmp_path, capsys):
    scene = tmp_path / "column.toml"
    scene.write_text(COLUMN)
    movie = tmp_path / "column.gif"
    assert main(["animate", str(scene), "--out", str(movie), "--duration", "1", "--fps", "10",
                 "--exaggerate", "20"]) == 0
    assert movie.read_bytes()[:6] == b"GIF89a"
    assert (tmp_path / "column_snapshots.png").is_file()
    printed = capsys.readouterr()
    assert ("(11 frames, 1.1 s at 10 frames/s, rotations and displacements x 20, each block's on what it rests on)"
            in printed.out)
    assert re.search(r"simulated 1 s in [\d.]+ s", printed.out)
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
    monkeypatch.setattr(cli.single_run, "interactive", lambda: True)
    assert main(["animate", str(scene), "--out", str(tmp_path / "c.gif"), "--duration", "0.4", "--fps", "10"]) == 0
    assert "frames: 100%" in capsys.readouterr().err


@pytest.mark.parametrize("command", ["run", "animate", "threshold", "ramp", "stiffness", "fragility"])
def test_every_command_that_runs_a_scene_takes_a_duration_and_defaults_to_the_bundled_scene(command, capsys):
    from dem_core.cli.arguments import DEFAULT_SCENE

    with pytest.raises(SystemExit):
        main([command, "--help"])
    shown = " ".join(capsys.readouterr().out.split())
    assert "--duration" in shown
    assert "[scene]" in shown and f"default the bundled {DEFAULT_SCENE}" in shown.replace("default: the", "default the")


def test_warnings_print_as_one_line_a_user_reads(monkeypatch, capsys):
    """The long-run warning printed as Python's 'cli.py:206: RuntimeWarning: ...' and the source line."""
    import warnings

    def warn(args):
        warnings.warn("a long run: 1.7e+08 steps; expect about 4.6 minutes", RuntimeWarning)
        return 0

    monkeypatch.setattr(cli.spectrum, "run", warn)
    assert main(["spectrum", "el_centro_1940"]) == 0
    assert capsys.readouterr().err == "warning: a long run: 1.7e+08 steps; expect about 4.6 minutes\n"


@pytest.mark.parametrize("argv", [["animate", "--out", "anim"], ["animate", "--out", "movie.avi"],
                                  ["run", "--animate", "run.png", "--no-plots"]])
def test_an_animation_name_without_gif_or_mp4_is_refused_before_the_run(argv, tmp_path, capsys, monkeypatch):
    """An animation name without .gif or .mp4 is refused (exit status 2, the reason on stderr) before the
    simulation starts."""
    monkeypatch.chdir(tmp_path)
    monkeypatch.setattr(cli.single_run, "simulate", lambda *a, **k: pytest.fail("the run started"))
    assert main(argv) == 2
    assert "must end in .gif or .mp4" in capsys.readouterr().err


def test_mp4_without_ffmpeg_is_refused_before_the_run(tmp_path, capsys, monkeypatch):
    from dem_core.pictures import animation

    monkeypatch.chdir(tmp_path)
    monkeypatch.setattr(animation, "can_write_mp4", lambda: False)
    monkeypatch.setattr(cli.single_run, "simulate", lambda *a, **k: pytest.fail("the run started"))
    assert main(["animate", "--out", "run.mp4"]) == 2
    assert "writing MP4 needs ffmpeg" in capsys.readouterr().err


def parsers():
    """(name, parser) of dem-core and of each of its commands."""
    import argparse

    parser = cli.parser()
    commands = next(a for a in parser._actions if isinstance(a, argparse._SubParsersAction))
    return [("dem-core", parser), *commands.choices.items()]


@pytest.mark.parametrize("name, parser", parsers())
def test_every_option_says_its_default_in_help(name, parser):
    """Every option that takes a value and may be left out says in --help what it is then: its default, or what it
    falls back to ("default: from the file or the record")."""
    import argparse

    formatter = parser._get_formatter()
    for action in parser._actions:
        if isinstance(action, (argparse._HelpAction, argparse._SubParsersAction)) or action.nargs == 0:
            continue
        if action.required or (not action.option_strings and action.nargs not in ("?", "*")):
            continue
        text = formatter._expand_help(action)
        assert "default" in text, f"{name} {action.option_strings or action.dest}: {text!r}"
    assert parser.format_help()  # every help string formats (a stray % would raise)


def test_threshold_searches_as_the_library_does_by_default(tmp_path, capsys, monkeypatch):
    """Left to its defaults the command runs the scales the library runs by default (a scan in steps of 2%, each
    change refined to 0.5%); --absolute-step is the library's absolute_step; --scan excludes --step."""
    scene = tmp_path / "harmonic.toml"
    scene.write_text(COLUMN.replace('kind = "sine_pulse"\namplitude = 4.0\nduration = 0.8',
                                    'kind = "harmonic"\npga = 2.0\nfrequency = 1.0'))
    ran = []

    def overturns_above_3_m_s2(scene, motion_at, scales, event, **options):
        peaks = [motion_at(s).horizontal.peak_acceleration for s in scales]
        ran.extend(peaks)
        return [peak > 3.0 for peak in peaks]

    monkeypatch.setattr(thresholds, "batch_outcomes", overturns_above_3_m_s2)
    monkeypatch.setattr(cli.threshold, "compile_first", lambda *args: None)

    def library(**options):
        ran.clear()
        thresholds.overturning_threshold(dem_core.scenes.column(2), lambda pga: dem_core.excitation.harmonic(
            pga=pga, frequency=1.0), 1.0, 6.0, **options)
        return list(ran)

    for argv, options in (([], {}), (["--absolute-step", "0.05"], {"absolute_step": 0.05})):
        expected = library(**options)
        ran.clear()
        assert main(["threshold", str(scene), "--low", "1", "--high", "6", *argv]) == 0
        assert ran == pytest.approx(expected, rel=1e-12)
    assert len(expected) > 90  # from 1 to 6 in steps of at most 2% and 0.05 m/s^2
    out = capsys.readouterr().out
    assert "runs, each 2% above the last, at most 0.05 m/s^2 (0.0051 g), then each change refined to 0.5%" in out
    below, above = map(float, re.search(r"overturning threshold: pga = .*, between ([\d.]+) and ([\d.]+) m/s\^2",
                                        out).groups())
    assert below <= 3.0 < above and above - below <= 0.005 * above  # refined to the library's 0.5%
    assert main(["threshold", str(scene), "--low", "1", "--high", "6", "--scan", "5", "--step", "0.1"]) == 2
    assert "--scan 5 gives evenly spaced values: leave out --step" in capsys.readouterr().err


def test_a_reader_that_stops_reading_ends_the_listing_quietly():
    """``dem-core records | head -1``: the listing stops when the pipe closes, with no error on stderr and the
    status a shell gives a command stopped by SIGPIPE."""
    read_end, write_end = os.pipe()
    os.close(read_end)  # a reader gone before the first line: every write meets a closed pipe
    done = subprocess.run([sys.executable, "-m", "dem_core", "records"], stdout=write_end, stderr=subprocess.PIPE,
                          text=True)
    os.close(write_end)
    assert done.returncode == 141 and done.stderr == ""


def test_records_say_where_each_sampling_interval_comes_from(capsys):
    assert main(["records"]) == 0
    lines = {line.split()[0]: line for line in capsys.readouterr().out.splitlines()[1:]}
    assert "every 0.01 s (stated in the file's header)" in lines["el_centro_1940"]
    assert "every 0.02 s (from its time column)" in lines["northridge_1994"]
    assert ("every 0.01 s (not stated in the file, which has no time column: dem_core's reading; the file's name "
            "says 0.02 s, see dem_core/data/records/SOURCES.md)") in lines["kalamata_1986"]


def test_a_slow_engine_setup_is_announced_timed_and_recorded(tmp_path, capsys, monkeypatch):
    """Compiling the engine (half a minute the first time) says so while it goes on and how long it took, and
    summary.json's compile_time_s is that run's setup, not the kernel's cached load alone."""
    import time

    from dem_core.simulation import Simulation

    scene = tmp_path / "column.toml"
    scene.write_text(COLUMN.replace("duration = 4.0", "duration = 0.5"))
    real = Simulation.__init__

    def slow(self, *args, **options):
        time.sleep(0.5)  # as a first compilation would, slower
        real(self, *args, **options)

    monkeypatch.setattr(Simulation, "__init__", slow)
    monkeypatch.setattr(cli.progress, "COMPILE_NOTICE_S", 0.2)
    assert main(["run", str(scene), "--out", str(tmp_path / "out"), "--no-plots"]) == 0
    printed = capsys.readouterr()
    assert printed.err.splitlines()[:2] == [cli.progress.COMPILING, "done in 1 s"] or \
        printed.err.splitlines()[:2] == [cli.progress.COMPILING, "done in 0 s"]
    summary = json.loads((tmp_path / "out" / "summary.json").read_text())
    assert summary["compile_time_s"] >= 0.5
    assert re.search(r"simulated 0.5 s in [\d.]+ s \(setting up and compiling the engine: 0.[5-9]\d s\)",
                     printed.out)
    monkeypatch.setattr(Simulation, "__init__", real)
    monkeypatch.setattr(cli.progress, "COMPILE_NOTICE_S", 60.0)
    assert main(["run", str(scene), "--out", str(tmp_path / "out"), "--no-plots"]) == 0
    assert cli.progress.COMPILING not in capsys.readouterr().err  # a quick setup says nothing


def test_the_integrator_option_replaces_the_scene_files(tmp_path, capsys):
    """``run --integrator moreau`` on the bundled default (explicit in its file) steps it by Moreau-Jean and says
    so; a scene whose contact law Moreau-Jean cannot take is refused naming the law."""
    assert main(["run", "--integrator", "moreau", "--duration", "0.5", "--no-plots", "--out",
                 str(tmp_path / "m")]) == 0
    assert "Moreau-Jean integrator" in capsys.readouterr().out
    assert json.loads((tmp_path / "m" / "summary.json").read_text())["integrator"] == "moreau"
    overlap = tmp_path / "overlap.toml"
    overlap.write_text("[scene]\nbuilder = 'column'\nn_drums = 2\n\n[contact]\nlaw = 'overlap_area'\n\n"
                       "[excitation]\nkind = 'sine_pulse'\namplitude = 1.0\nduration = 0.5\n")
    assert main(["run", str(overlap), "--integrator", "moreau", "--out", str(tmp_path / "o")]) == 2
    assert "'overlap_area'" in capsys.readouterr().err


#: each command that runs scenes, with the arguments that run it on a scene file ("{scene}", "{out}")
RUNNING_COMMANDS = {
    "run": ["run", "{scene}", "--out", "{out}", "--no-plots"],
    "animate": ["animate", "{scene}", "--out", "{out}/a.gif"],
    "threshold": ["threshold", "{scene}", "--parameter", "amplitude", "--low", "1", "--high", "2"],
    "ramp": ["ramp", "{scene}"],
    "sweep": ["sweep", "{sweep}", "--out", "{out}"],
    "fragility": ["fragility", "{scene}", "--out", "{out}", "--levels", "2", "--records", "el_centro_1940",
                  "--duration", "27"],  # the scene file's 4 s would cut the record's strong motion: refused
}


@pytest.mark.parametrize("command", RUNNING_COMMANDS)
def test_every_command_that_runs_scenes_takes_the_integrator_and_its_runs_use_it(command, tmp_path, capsys,
                                                                                  monkeypatch):
    """The same option, choices and default in every command; what it names is what the command's runs get (the
    engine's first run, or the run itself, is caught and stopped as Ctrl-C would stop it)."""
    with pytest.raises(SystemExit):
        main([command, "--help"])
    assert "{explicit,moreau}" in capsys.readouterr().out
    scene = tmp_path / "column.toml"
    scene.write_text(COLUMN)
    sweep = tmp_path / "sweep.toml"
    sweep.write_text(COLUMN + "\n[sweep.excitation]\namplitude = [1.0, 2.0]\n")
    seen = []

    def caught(*args, **options):
        seen.append(options.get("integrator", (args[2] if len(args) > 2 else {}).get("integrator")))
        raise KeyboardInterrupt

    for module in (cli.threshold, cli.ramp, cli.fragility, cli.sweep):
        monkeypatch.setattr(module, "compile_first", caught)
    monkeypatch.setattr(cli.single_run, "simulate", caught)
    argv = [a.format(scene=scene, sweep=sweep, out=tmp_path / "out") for a in RUNNING_COMMANDS[command]]
    assert main([*argv, "--integrator", "moreau"]) == 130
    assert seen == ["moreau"]


@pytest.mark.parametrize("quiet", [False, True])
@pytest.mark.parametrize("command", ["threshold", "stiffness", "fragility"])
def test_no_progress_turns_off_the_bar_over_a_commands_runs(command, quiet, tmp_path, monkeypatch):
    """The bar's lines in a log are noise to a script that reads what a command prints: ``--no-progress`` turns
    them off (the bar is caught as it is made, and the command stopped as Ctrl-C would stop it)."""
    scene = tmp_path / "column.toml"
    scene.write_text(COLUMN)
    module = getattr(cli, command)
    monkeypatch.setattr(module, "compile_first", lambda *args: None)
    asked = []

    def bar(**options):
        asked.append(options.get("disable", False))
        raise KeyboardInterrupt

    monkeypatch.setattr(module, "progress_bar", bar)
    argv = [a.format(scene=scene, out=tmp_path / "out")
            for a in RUNNING_COMMANDS.get(command, ["stiffness", "{scene}"])]
    assert main([*argv, *["--no-progress"] * quiet]) == 130
    assert asked == [quiet]


def test_stiffness_with_no_progress_shows_no_bar_over_a_runs_steps_either(tmp_path, monkeypatch):
    """Each of stiffness' runs is long and has a bar of its own over its steps on a terminal: off too."""
    scene = tmp_path / "column.toml"
    scene.write_text(COLUMN)
    seen = []
    monkeypatch.setattr(cli.stiffness, "compile_first", lambda *args: None)
    monkeypatch.setattr(cli.stiffness, "simulate_options",
                        lambda settings, progress=True: seen.append(progress) or settings)
    monkeypatch.setattr(cli.stiffness, "stiffness_convergence", lambda *args, **options: (_ for _ in ()).throw(
        KeyboardInterrupt))
    assert main(["stiffness", str(scene), "--no-progress"]) == 130
    assert main(["stiffness", str(scene)]) == 130
    assert seen == [False, True]


def test_the_stiffness_check_runs_the_explicit_integrator_and_says_so(tmp_path, capsys, monkeypatch):
    scene = tmp_path / "column.toml"
    scene.write_text(COLUMN.replace("[simulation]", "[simulation]\nintegrator = 'moreau'"))
    seen = []
    monkeypatch.setattr(cli.stiffness, "compile_first", lambda scene, motion, settings: seen.append(settings))
    monkeypatch.setattr(cli.stiffness, "stiffness_convergence", lambda *args, **options: (_ for _ in ()).throw(
        KeyboardInterrupt))
    assert main(["stiffness", str(scene)]) == 130
    assert seen[0]["integrator"] == "explicit"
    assert "this check is the explicit core's" in capsys.readouterr().out


def test_threshold_runs_the_bundled_scene_when_given_none(capsys):
    assert main(["threshold", "--low", "1.5", "--high", "2", "--scan", "2", "--tolerance", "0.2"]) == 0
    assert "no overturning up to pga = 2 m/s^2" in capsys.readouterr().out


def test_run_prints_the_peak_as_a_share_of_the_critical_angle(tmp_path, capsys):
    """The printout's peak |theta|/alpha is the damage ratio a fragility study counts (its result's, written)."""
    assert main(["run", "--out", str(tmp_path / "out"), "--no-plots", "--duration", "8"]) == 0
    printed = capsys.readouterr().out
    found = re.search(r"peak \|theta\| ([\d.e-]+) rad \(peak \|theta\|/alpha ([\d.e-]+), alpha the critical angle",
                      printed)
    peak, ratio = float(found.group(1)), float(found.group(2))
    metrics = pd.read_csv(tmp_path / "out" / "metrics.csv")
    assert peak == pytest.approx(metrics["peak_abs_theta_rad"].max(), rel=1e-3)
    column_alpha = math.atan(1.0 / 6.0)  # the bundled 1 x 6 m column's critical angle
    assert ratio == pytest.approx(peak / column_alpha, rel=2e-3)
    summary = json.loads((tmp_path / "out" / "summary.json").read_text())
    _says_the_unconverged_steps(printed, summary)


def test_a_runs_solves_left_short_of_their_tolerance_are_said_or_nothing():
    """The line on Moreau-Jean's unconverged solves, from its result's counts; none where no solve was left short or
    under central differences, which has no such solve."""
    from types import SimpleNamespace

    from dem_core.cli.run import _solver_lines

    assert _solver_lines(SimpleNamespace(info={"unconverged_steps": 32, "steps": 53710}, dt=1e-3)) == [
        "contact solve: 32 solves in 53,710 steps ended short of their tolerance after the sweeps a part allows; "
        "such a solve is kept where its last sweep (after up to 2,000 more) changed no velocity by more than 0.1 g "
        "times the part's length, else the part is taken again at half its length, and a run whose retries fail too "
        "stops with an error. The run finished, so each solve it kept met that bound, not the tolerance; the same run "
        "at half the step ([simulation] dt = 0.0005) shows how far its measures are from converged, these solves "
        "included (unconverged_steps in summary.json; docs/method.md 1.8)"]
    assert _solver_lines(SimpleNamespace(info={"unconverged_steps": 0, "steps": 53710}, dt=1e-3)) == []
    assert _solver_lines(SimpleNamespace(info={"steps": 53710}, dt=1e-3)) == []


def test_without_a_terminal_a_commands_bar_over_its_runs_writes_a_line_now_and_then(monkeypatch, capsys):
    """In a log or a CI pipe the bar is a line every LOG_EVERY_S s, with the share done and the time left from the
    rate so far, and a last line at the end."""
    from dem_core.cli import progress

    monkeypatch.setattr(progress, "interactive", lambda: False)
    assert isinstance(progress.progress_bar(total=1), progress.ProgressLines)
    clock = iter([0.0, 5.0, 12.0, 12.0, 20.0, 31.0])
    bar = progress.ProgressLines(total=8, desc="runs", unit="run", clock=lambda: next(clock))
    bar.update()      # 5 s: too soon for a line
    bar.update()      # 12 s: 2 of 8 in 12 s, 6 left at that rate
    bar.update(3)     # 20 s: too soon
    bar.set_postfix_str("pga = 3 m/s^2")
    bar.close()       # 31 s: the end
    assert capsys.readouterr().err.splitlines() == ["runs: 2 of 8 (25.0%), 12 s, about 36 s left",
                                                    "runs: 5 of 8 (62.5%), 31 s; pga = 3 m/s^2"]


def test_a_resumed_bar_counts_what_was_done_and_takes_its_rate_from_what_it_does(capsys):
    from dem_core.cli import progress

    clock = iter([0.0, 12.0, 12.0])
    with progress.ProgressLines(total=8, initial=4, desc="sweep", unit="run", clock=lambda: next(clock)) as bar:
        bar.update(2)  # 12 s: 2 run here in 12 s, 2 left at that rate
    with progress.ProgressLines(total=8, disable=True, clock=lambda: 99.0) as quiet:
        quiet.update(8)
    assert capsys.readouterr().err.splitlines() == ["sweep: 6 of 8 (75.0%), 12 s, about 12 s left"]


def test_a_bar_weighted_by_each_runs_work_writes_its_share_not_a_count(capsys):
    """dem-core stiffness weighs each run by the square root of its stiffness factor (its length in steps), and its
    bar's format shows its share, no count: a line of "4.16 of 14.2 runs" would read as a count."""
    from dem_core.cli import progress

    clock = iter([0.0, 12.0, 12.0])
    shares = "{desc}: {percentage:3.0f}%|{bar}|"
    with progress.ProgressLines(total=1.0 + 10**0.5 + 10.0, desc="runs", bar_format=shares,
                                clock=lambda: next(clock)) as bar:
        bar.update(1.0 + 10**0.5)
    assert capsys.readouterr().err.splitlines() == ["runs: 29.4%, 12 s, about 29 s left"]


def test_every_key_of_summary_json_is_explained_in_cli_md(overturning_scene_file, tmp_path):
    """docs/cli.md's table of summary.json explains every key that runs of an overturning column write under either
    integrator, and no other key but the one these runs cannot write (a step asked beyond the stability limit)."""
    written = set()
    for integrator in ("moreau", "explicit"):
        out = tmp_path / integrator
        argv = ["run", str(overturning_scene_file), "--out", str(out), "--no-plots", "--integrator", integrator]
        assert main(argv) == 0
        written |= set(json.loads((out / "summary.json").read_text()))
    page = (REPOSITORY / "docs" / "cli.md").read_text()
    table = page[page.index("### summary.json, key by key"):]
    table = table[:table.index("\n\n", table.index("| --- |"))]
    explained = set(re.findall(r"`([a-z_]+)`", "\n".join(line.split("|")[1] for line in table.splitlines()[4:])))
    assert written <= explained, f"summary.json keys docs/cli.md does not explain: {sorted(written - explained)}"
    assert explained - written == {"beyond_stability_limit"}, sorted(explained - written)
