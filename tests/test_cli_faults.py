"""The command line under bad input and faults: each probe runs the real entry point (``python -m dem_core``) in a
subprocess and expects its exit status, one line naming the input at fault, and never a traceback.

Faults of the file system that a test run as root cannot make (a read-only file system, a full disk) are made by a
prelude that patches the operating-system calls (``os.mkdir``, ``os.open``, ``open``) for one folder before the
entry point runs; an unstable run by a prelude that has ``Simulation.result`` raise after a real run."""

import json
import os
import re
import signal
import subprocess
import sys
import textwrap
import time
from pathlib import Path

import pandas as pd
import pytest

COLUMN = textwrap.dedent("""
    [scene]
    builder = "column"
    n_drums = 2
    [excitation]
    kind = "harmonic"
    frequency = 1.0
    pga = 2.0
    [simulation]
    duration = 0.5
""")
SWEEP = COLUMN + textwrap.dedent("""
    [sweep.excitation]
    pga = [1.0, 2.0]
""")

#: runs ``python -m dem_core`` after the patch given as the ``-c`` program's source
RUN_MODULE = "\nimport runpy\nrunpy.run_module('dem_core', run_name='__main__', alter_sys=True)\n"

#: the folder named by the first argument is on a read-only file system (as a user, not root, meets it)
READ_ONLY = textwrap.dedent("""
    import builtins, errno, io, os, sys
    READ_ONLY = os.path.abspath(sys.argv.pop(1))
    real_mkdir, real_os_open, real_open = os.mkdir, os.open, builtins.open

    def _inside(path):
        if not isinstance(path, (str, os.PathLike)):
            return False
        path = os.path.abspath(os.fspath(path))
        return path == READ_ONLY or path.startswith(READ_ONLY + os.sep)

    def _refuse(path):
        raise OSError(errno.EROFS, os.strerror(errno.EROFS), os.fspath(path))

    def mkdir(path, *args, **options):
        if _inside(path):
            if os.path.exists(path):
                raise FileExistsError(errno.EEXIST, os.strerror(errno.EEXIST), os.fspath(path))
            _refuse(path)
        return real_mkdir(path, *args, **options)

    def os_open(path, flags, *args, **options):
        if _inside(path) and flags & (os.O_WRONLY | os.O_RDWR | os.O_CREAT):
            _refuse(path)
        return real_os_open(path, flags, *args, **options)

    def open_(file, mode="r", *args, **options):
        if _inside(file) and any(c in mode for c in "wax+"):
            _refuse(file)
        return real_open(file, mode, *args, **options)

    os.mkdir, os.open, builtins.open, io.open = mkdir, os_open, open_, open_
""") + RUN_MODULE

#: files written under the folder named by the first argument fill the disk after the number of bytes of the second
FULL_DISK = textwrap.dedent("""
    import builtins, errno, io, os, sys
    FULL = os.path.abspath(sys.argv.pop(1))
    LEFT = [int(sys.argv.pop(1))]
    real_open = builtins.open

    class Filling:
        def __init__(self, file):
            self._file = file

        def write(self, data):
            if len(data) > LEFT[0]:
                self._file.write(data[:LEFT[0]])
                self._file.flush()
                LEFT[0] = 0
                raise OSError(errno.ENOSPC, os.strerror(errno.ENOSPC))
            LEFT[0] -= len(data)
            return self._file.write(data)

        def __getattr__(self, name):
            return getattr(self._file, name)

        def __enter__(self):
            return self

        def __exit__(self, *exc):
            self._file.close()

        def __iter__(self):
            return iter(self._file)

    def open_(file, mode="r", *args, **options):
        opened = real_open(file, mode, *args, **options)
        if isinstance(file, (str, os.PathLike)) and any(c in mode for c in "wax+"):
            path = os.path.abspath(os.fspath(file))
            if path.startswith(FULL + os.sep):
                return Filling(opened)
        return opened

    builtins.open = io.open = open_
""") + RUN_MODULE

#: the run goes to its end and then stops as unstable at its last output, the result up to there kept
UNSTABLE = textwrap.dedent("""
    from dem_core.simulation import Simulation, SimulationUnstable
    real_result = Simulation.result

    def result(self):
        result = real_result(self)
        raise SimulationUnstable(
            f"simulation stopped at t = {result.t[-1]:.6g} s (step 9, dt = 1e-05 s): the blocks gained energy that "
            "neither gravity nor the ground supplied; reduce dt below 1e-05 s or check the contact parameters. "
            f"The result up to t = {result.t[-1]:.6g} s is in this error's .partial", result)

    Simulation.result = result
""") + RUN_MODULE

#: an error nobody foresaw, in the ``records`` command
UNEXPECTED = textwrap.dedent("""
    import dem_core.cli.records as command

    def records(*args):
        raise RuntimeError("a fault nobody foresaw\\nits second line")

    command.run = records
""") + RUN_MODULE


def command_line(*args, cwd, prelude=None, timeout=180, env=None):
    """``python -m dem_core ARGS`` (after ``prelude``, a patch of the process, if given) in ``cwd``."""
    command = [sys.executable, *(["-c", prelude] if prelude else ["-m", "dem_core"]), *map(str, args)]
    return subprocess.run(command, check=False, cwd=cwd, capture_output=True, text=True, timeout=timeout,
                          env={**os.environ, **(env or {})})


def error_line(done, status: int, *names) -> str:
    """The one error line of a finished command, checked: exit ``status``, no traceback anywhere, exactly one line
    on stderr other than warnings and notes, and ``names`` in it."""
    printed = done.stdout + done.stderr
    assert "Traceback" not in printed, printed
    assert done.returncode == status, printed
    lines = [line for line in done.stderr.splitlines() if not line.startswith(("warning: ", "note: "))]
    assert len(lines) == 1, done.stderr
    for name in names:
        assert name in lines[0], lines[0]
    return lines[0]


@pytest.fixture
def scene(tmp_path):
    path = tmp_path / "column.toml"
    path.write_text(COLUMN)
    return path


# --- output folders and files ----------------------------------------------------------------------

def test_a_run_into_the_folder_of_another_scene_is_refused_naming_it(tmp_path, scene):
    """A run into a folder that holds the run of another scene is refused (exit status 2), naming that scene,
    and leaves the folder as it was; with --overwrite the folder holds this run's files alone."""
    other = tmp_path / "other.toml"
    other.write_text(COLUMN.replace("pga = 2.0", "pga = 1.0"))
    out = tmp_path / "out"
    assert command_line("run", scene, "--out", out, cwd=tmp_path).returncode == 0
    before = {p.name: p.stat().st_mtime_ns for p in out.iterdir()}
    assert {"rotations.png", "time_history.csv", "summary.json"} <= set(before)
    refused = command_line("run", other, "--out", out, "--no-plots", cwd=tmp_path)
    line = error_line(refused, 2, "--out", str(scene.resolve()), "--overwrite")
    assert line.startswith("error: ")
    assert {p.name: p.stat().st_mtime_ns for p in out.iterdir()} == before
    replaced = command_line("run", other, "--out", out, "--no-plots", "--format", "parquet", "--overwrite",
                            cwd=tmp_path)
    assert replaced.returncode == 0, replaced.stderr
    assert sorted(p.name for p in out.iterdir()) == ["interfaces.csv", "metrics.csv", "scene.json", "summary.json",
                                                     "time_history.parquet"]
    summary = json.loads((out / "summary.json").read_text())
    assert summary["scene"] == str(other.resolve()) and summary["status"] == "complete"


def test_rerunning_a_scene_into_its_folder_replaces_its_results_whole(tmp_path, scene):
    """The same scene run again into its folder replaces the earlier run's files whole, saying so: no figure or
    time history of the earlier run is left beside the new files."""
    out = tmp_path / "out"
    assert command_line("run", scene, "--out", out, cwd=tmp_path).returncode == 0
    again = command_line("run", scene, "--out", out, "--no-plots", "--format", "parquet", cwd=tmp_path)
    assert again.returncode == 0 and "Traceback" not in again.stderr
    assert "replaced whole" in again.stderr
    assert sorted(p.name for p in out.iterdir()) == ["interfaces.csv", "metrics.csv", "scene.json", "summary.json",
                                                     "time_history.parquet"]
    assert json.loads((out / "summary.json").read_text())["files"] == ["summary.json", "time_history.parquet",
                                                                       "metrics.csv", "interfaces.csv", "scene.json"]


@pytest.mark.parametrize("argv", [["run", "{scene}", "--out", "taken"],
                                  ["run", "{scene}", "--out", "taken/results"],
                                  ["sweep", "{sweep}", "--out", "taken/sweep", "--workers", "1"],
                                  ["animate", "{scene}", "--out", "taken/movies/run.gif"],
                                  ["spectrum", "el_centro_1940", "--out", "taken/spectra.png"]])
def test_an_output_path_at_or_under_a_file_is_refused_before_the_run(argv, tmp_path, scene):
    """``--out`` naming a file, or a path under a file, is refused (exit status 2) before anything runs, naming
    the option and the file in the way."""
    (tmp_path / "taken").write_text("a file, not a folder\n")
    (tmp_path / "sweep.toml").write_text(SWEEP)
    argv = [a.format(scene=scene, sweep=tmp_path / "sweep.toml") for a in argv]
    done = command_line(*argv, cwd=tmp_path)
    error_line(done, 2, "--out", "taken", "is a file, not a folder")
    assert "contact law" not in done.stdout and "runs over" not in done.stdout


@pytest.mark.parametrize("argv", [["run", "{scene}", "--out", "{folder}"],
                                  ["sweep", "{sweep}", "--out", "{folder}", "--workers", "1"],
                                  ["animate", "{scene}", "--out", "{folder}/run.gif"],
                                  ["spectrum", "el_centro_1940", "--out", "{folder}/spectra.png"]])
def test_an_output_folder_on_a_read_only_file_system_is_refused_before_the_run(argv, tmp_path, scene):
    """An output folder that cannot be written in (a read-only file system) is refused at once (exit status 2),
    naming the option, the folder and the system's reason, not after the whole simulation."""
    folder = tmp_path / "mounted"
    folder.mkdir()
    (tmp_path / "sweep.toml").write_text(SWEEP)
    argv = [a.format(scene=scene, sweep=tmp_path / "sweep.toml", folder=folder) for a in argv]
    done = command_line(folder, *argv, cwd=tmp_path, prelude=READ_ONLY)
    error_line(done, 2, "--out", str(folder), "Read-only file system")
    assert "contact law" not in done.stdout
    assert list(folder.iterdir()) == []


def test_a_full_disk_leaves_no_truncated_file_and_says_which(tmp_path, scene):
    """A disk that fills while the time history is written: one line naming the file and the system's reason (exit
    status 1), no truncated time_history.csv nor temporary file, and summary.json saying the results are
    incomplete."""
    out = tmp_path / "out"
    scene.write_text(COLUMN.replace("duration = 0.5", "duration = 1.0"))
    done = command_line(out, 6000, "run", scene, "--out", out, "--no-plots", cwd=tmp_path, prelude=FULL_DISK)
    error_line(done, 1, str(out / "time_history.csv"), "No space left on device", "incomplete")
    assert sorted(p.name for p in out.iterdir()) == ["summary.json"]
    assert json.loads((out / "summary.json").read_text())["status"] == "incomplete"


def test_a_full_disk_while_writing_parquet_leaves_no_partial_file(tmp_path, scene, capsys, monkeypatch):
    """As above, in this process, for the Parquet writer failing halfway (pyarrow writes past Python's open)."""
    from dem_core.cli import main

    def fills_the_disk(frame, path, **options):
        Path(path).write_bytes(b"PAR1 and half a table")
        raise OSError(28, "No space left on device")

    monkeypatch.setattr(pd.DataFrame, "to_parquet", fills_the_disk)
    out = tmp_path / "out"
    assert main(["run", str(scene), "--out", str(out), "--format", "parquet", "--no-plots"]) == 1
    err = capsys.readouterr().err
    assert len(err.splitlines()) == 1 and "Traceback" not in err
    assert f"cannot write {out / 'time_history.parquet'}: No space left on device" in err
    assert sorted(p.name for p in out.iterdir()) == ["summary.json"]


def test_save_run_figures_creates_its_folder(tmp_path):
    from dem_core import excitation, scenes, simulate
    from dem_core.pictures.plots import save_run_figures

    result = simulate(scenes.column(2), excitation.harmonic(pga=2.0, frequency=1.0), duration=0.2)
    written = save_run_figures(result, tmp_path / "new" / "figures")
    assert written and all(p.read_bytes()[:4] == b"\x89PNG" for p in written)


# --- runs that stop, settings the run refuses --------------------------------------------------------

def test_an_unstable_run_writes_what_it_reached_marked_stopped(tmp_path, scene):
    """A run that loses stability: exit status 3, one error line saying why and where the partial results are, and
    summary.json with status "stopped" and the reason (not Python's ``.partial``)."""
    out = tmp_path / "out"
    done = command_line("run", scene, "--out", out, "--no-plots", cwd=tmp_path, prelude=UNSTABLE)
    line = error_line(done, 3, "gained energy", str(out), "stopped")
    assert ".partial" not in line
    summary = json.loads((out / "summary.json").read_text())
    assert summary["status"] == "stopped" and "gained energy" in summary["stop_reason"]
    assert ".partial" not in summary["stop_reason"]
    assert (out / "time_history.csv").is_file()


def test_a_run_that_ends_at_its_first_overturn_is_complete_and_says_where_it_ended(overturning_scene_file, tmp_path):
    """Where a run ended at its first overturn (``Result.info["ended_at_overturn"]``) is written under that name
    in summary.json beside ``status`` "complete": never under a name that reads as a loss of stability."""
    from dem_core import cli

    assert cli.main(["run", str(overturning_scene_file), "--out", str(tmp_path / "out"), "--no-plots"]) == 0
    summary = json.loads((tmp_path / "out" / "summary.json").read_text())
    assert summary["status"] == "complete" and summary["stop_reason"] is None and "stopped" not in summary
    assert re.fullmatch(r"(block 'drum\d' overturned|the stack drum1..drum2 tipped past its base) at t = [\d.]+ s",
                        summary["ended_at_overturn"]), summary["ended_at_overturn"]
    assert summary["end_time_s"] < 3.0


@pytest.mark.parametrize("command", [("stiffness", "--factors", "1"), ("ramp", "--rate", "20")])
def test_a_run_that_stops_unstable_inside_a_study_command_exits_3(command, tmp_path, scene):
    """``stiffness`` and ``ramp`` write nothing of a run that lost stability: exit status 3 (as ``run``), one line
    saying why."""
    done = command_line(command[0], scene, *command[1:], cwd=tmp_path, prelude=UNSTABLE)
    assert ".partial" not in error_line(done, 3, "gained energy")


def test_an_extreme_ground_motion_is_blamed_and_nothing_written(tmp_path, scene):
    """pga = 1e6 m/s^2 (a mistake of units or scale): refused naming the motion, and no results that look whole."""
    scene.write_text(COLUMN.replace("pga = 2.0", "pga = 1e6"))
    out = tmp_path / "out"
    done = command_line("run", scene, "--out", out, "--no-plots", cwd=tmp_path)
    error_line(done, 2, "pga", "50 g")
    assert not (out / "summary.json").exists()


@pytest.mark.parametrize("value", ["-0.5", "0"])
def test_an_output_step_that_is_not_positive_is_one_line_naming_it(value, tmp_path, scene):
    scene.write_text(COLUMN.replace("duration = 0.5", f"duration = 0.5\noutput_dt = {value}"))
    done = command_line("run", scene, "--out", tmp_path / "out", cwd=tmp_path)
    error_line(done, 2, "output_dt", "column.toml")


@pytest.mark.parametrize("value", ["inf", "nan", "-1"])
def test_a_duration_that_is_not_positive_and_finite_is_refused_naming_the_option(value, tmp_path, scene):
    done = command_line("run", scene, "--duration", value, "--out", tmp_path / "out", cwd=tmp_path)
    error_line(done, 2, "--duration", value)
    assert not (tmp_path / "out").exists()


@pytest.mark.parametrize("value", ["0", "-0.5"])
def test_a_ramp_rate_that_is_not_positive_is_refused_naming_the_option(value, tmp_path, scene):
    error_line(command_line("ramp", scene, "--rate", value, cwd=tmp_path), 2, "--rate", value)


@pytest.mark.parametrize("value", ["-1", "0"])
def test_fewer_than_one_sweep_worker_is_refused_at_once(value, tmp_path):
    """No worker could ever start a run: refused at once (exit status 2) naming the option, not a wait."""
    (tmp_path / "sweep.toml").write_text(SWEEP)
    done = command_line("sweep", "sweep.toml", "--out", "out", "--workers", value, cwd=tmp_path, timeout=60)
    error_line(done, 2, "--workers", value)


def test_threshold_says_which_key_its_parameter_sets(tmp_path):
    """A scene file that gives ``amplitude`` under the default ``--parameter pga``: the error says that the
    option set ``pga`` and which key of the file stands in its way."""
    (tmp_path / "column.toml").write_text(COLUMN.replace("pga = 2.0", "amplitude = 0.05"))
    done = command_line("threshold", "column.toml", "--low", "1", "--high", "5", cwd=tmp_path)
    error_line(done, 2, "amplitude", "--parameter pga sets [excitation] pga",
               "the scene file gives amplitude: use --parameter amplitude or remove it")


# --- sweeps: saved runs that cannot be read, Ctrl-C ----------------------------------------------------

@pytest.mark.parametrize("content", [b"", b"PAR1 cut short"])
def test_a_saved_run_that_cannot_be_read_is_run_again_with_a_note(content, tmp_path):
    (tmp_path / "sweep.toml").write_text(SWEEP)
    command = ["sweep", "sweep.toml", "--out", "out", "--workers", "1", "--no-progress"]
    assert command_line(*command, cwd=tmp_path).returncode == 0
    damaged = min((tmp_path / "out" / "runs").glob("*.parquet"))
    damaged.write_bytes(content)
    done = command_line(*command, cwd=tmp_path)
    assert done.returncode == 0 and "Traceback" not in done.stderr, done.stderr
    assert f"{damaged.name}" in done.stderr and "cannot be read" in done.stderr and "run again" in done.stderr
    table = pd.read_parquet(tmp_path / "out" / "results.parquet")
    assert len(table) == 2 and set(table.status) == {"ok"}
    assert len(pd.read_parquet(damaged)) == 1


def _interrupt(command, cwd, started) -> subprocess.CompletedProcess:
    """Start ``python -m dem_core COMMAND`` in its own process group, wait until ``started()``, then press Ctrl-C
    (SIGINT to the group, as a terminal sends it) and return what it did."""
    process = subprocess.Popen([sys.executable, "-u", "-m", "dem_core", *map(str, command)], cwd=cwd,
                               start_new_session=True, stdout=subprocess.PIPE, stderr=subprocess.PIPE, text=True)
    try:
        deadline = time.time() + 120
        while not started() and process.poll() is None and time.time() < deadline:
            time.sleep(0.02)
        assert process.poll() is None, "it ended before it could be interrupted"
        os.killpg(process.pid, signal.SIGINT)
        out, err = process.communicate(timeout=60)
    finally:
        if process.poll() is None:
            os.killpg(process.pid, signal.SIGKILL)
            process.wait()
    return subprocess.CompletedProcess(process.args, process.returncode, out, err)


def test_ctrl_c_during_a_sweep_says_what_was_saved_and_the_rerun_resumes(tmp_path):
    """Ctrl-C during a sweep: exit status 130 and one line with the runs saved and how to resume; the same command
    again runs only the rest."""
    # Eight runs of equal cost (none rocks), each long enough (explicit, 30 s) for Ctrl-C to land midway.
    (tmp_path / "sweep.toml").write_text(SWEEP.replace("duration = 0.5", 'duration = 30.0\nintegrator = "explicit"')
                                         .replace("pga = [1.0, 2.0]", "pga = [0.5, 0.6, 0.7, 0.8, 0.9, 1.0, 1.1, 1.2]"))
    command = ["sweep", "sweep.toml", "--out", "out", "--workers", "1", "--no-progress"]
    runs = tmp_path / "out" / "runs"
    done = _interrupt(command, tmp_path, lambda: any(runs.glob("*.parquet")))
    line = error_line(done, 130, "runs saved in out", "run the same command again to resume")
    saved = {p.name: p.stat().st_mtime_ns for p in runs.glob("*.parquet")}
    assert line == f"interrupted: {len(saved)} of 8 runs saved in out; run the same command again to resume"
    assert 1 <= len(saved) < 8
    again = command_line(*command, cwd=tmp_path)
    assert again.returncode == 0, again.stderr
    assert len(pd.read_parquet(tmp_path / "out" / "results.parquet")) == 8
    assert {name: (runs / name).stat().st_mtime_ns for name in saved} == saved


def test_ctrl_c_during_a_run_is_one_line_and_leaves_the_folder_as_it_was(tmp_path, scene):
    """Ctrl-C while the compiled kernel runs: exit status 130 and one line, the process alive to say it (an
    interrupt raised inside the kernel's call back into Python would end it with a segmentation fault)."""
    scene.write_text(COLUMN.replace("duration = 0.5", "duration = 1000.0"))
    out = tmp_path / "out"
    started = time.time()
    done = _interrupt(["run", scene, "--out", out, "--no-plots", "--integrator", "explicit"], tmp_path,
                      lambda: out.is_dir() and time.time() > started + 4)
    error_line(done, 130, "interrupted: the run was stopped before its results were written", str(out))
    assert list(out.iterdir()) == []


# --- the last resort --------------------------------------------------------------------------------

def test_an_unexpected_error_is_one_line_asking_for_a_report(tmp_path):
    done = command_line("records", cwd=tmp_path, prelude=UNEXPECTED)
    error_line(done, 1, "RuntimeError: a fault nobody foresaw", "unexpected: please report",
               "DEM_CORE_DEBUG=1")
    debug = command_line("records", cwd=tmp_path, prelude=UNEXPECTED, env={"DEM_CORE_DEBUG": "1"})
    assert debug.returncode == 1 and "Traceback" in debug.stderr


# --- numbers on the command line, in this process ----------------------------------------------------

@pytest.mark.parametrize("argv, option", [
    (["run", "{scene}", "--duration", "1e400"], "--duration"),
    (["run", "{scene}", "--animate", "run.gif", "--exaggerate", "inf"], "--exaggerate"),
    (["animate", "{scene}", "--fps", "1000"], "--fps"),
    (["animate", "{scene}", "--speed", "inf"], "--speed"),
    (["animate", "{scene}", "--speed", "1e-9"], "--speed"),
    (["sweep", "{scene}", "--out", "out", "--workers", "1.5"], "--workers"),
    (["threshold", "{scene}", "--low", "0", "--high", "5"], "--low"),
    (["threshold", "{scene}", "--low", "5", "--high", "1"], "--low"),
    (["threshold", "{scene}", "--low", "1", "--high", "inf"], "--high"),
    (["threshold", "{scene}", "--low", "1", "--high", "5", "--tolerance", "0"], "--tolerance"),
    (["threshold", "{scene}", "--low", "1", "--high", "5", "--scan", "1"], "--scan"),
    (["ramp", "{scene}", "--rate", "nan"], "--rate"),
    (["spectrum", "el_centro_1940", "--damping", "nan"], "--damping"),
    (["spectrum", "el_centro_1940", "--damping", "1"], "--damping"),
    (["stiffness", "{scene}", "--factors", "1", "inf"], "--factors"),
    (["stiffness", "{scene}", "--factors", "0"], "--factors"),
])
def test_every_number_is_checked_before_any_run(argv, option, tmp_path, scene, capsys, monkeypatch):
    """A number out of range, infinite or NaN is refused (exit status 2) before anything runs, in one line naming
    its option."""
    from dem_core import cli
    from dem_core.analyses import convergence, spectra, thresholds

    def no_run(*args, **options):
        pytest.fail("a run started")

    for module in (thresholds, convergence):
        monkeypatch.setattr(module, "simulate", no_run)
    monkeypatch.setattr(cli.single_run, "simulate", no_run)
    monkeypatch.setattr(cli.progress, "simulate", no_run)
    monkeypatch.setattr(spectra, "response_spectrum", no_run)
    monkeypatch.chdir(tmp_path)
    assert cli.main([a.format(scene=scene) for a in argv]) == 2
    err = capsys.readouterr().err
    assert len(err.splitlines()) == 1 and err.startswith("error: ") and option in err, err


@pytest.mark.parametrize("argv, said", [
    (["run", "scene.toml", "--integrater", "moreau"], "--integrater moreau (did you mean '--integrator'?)"),
    (["run", "scene.toml", "--ouput=x"], "--ouput=x (did you mean '--out'?)"),
    (["run", "scene.toml", "-integrater", "moreau"], "-integrater moreau (did you mean '--integrator'?)"),
    (["run", "scene.toml", "-help"], "-help (did you mean '--help'?)"),  # not -h with the argument "elp"
    (["fragility", "scene.toml", "-out", "o"],
     "-out (did you mean '--out'?); the following arguments are required: --out"),
    (["run", "--", "-scene.toml"], None),  # after --, a scene file's name
    (["run", "scene.toml", "--out", "-my results"], None),  # a value with a space
    (["fragility", "scene.toml", "--out", "o", "--disclocation", "5"],
     "--disclocation 5 (did you mean '--dislocation'?)"),
])
def test_a_mistyped_option_is_refused_with_the_nearest_option_of_its_command(argv, said, capsys, tmp_path,
                                                                            monkeypatch):
    """The nearest of the command's own options is suggested, compared without their dashes (one dash too few
    finds it too, before argparse reads a single dash and a word as a short option and its argument); a word after
    ``--`` and a value with a space are arguments, here a scene file that is not there."""
    from dem_core import cli

    monkeypatch.chdir(tmp_path)
    assert cli.main(argv) == 2
    err = capsys.readouterr().err
    if said is None:
        assert "unrecognized" not in err and "no such scene file" in err, err
    else:
        assert f"unrecognized arguments: {said} (see dem-core {argv[0]} --help)" in err


@pytest.mark.parametrize("argv, prog", [
    (["run", "scene.toml", "--bogus"], "dem-core run"),
    (["animate", "scene.toml", "--bogus"], "dem-core animate"),
    (["records", "--bogus"], "dem-core records"),
    (["--bogus", "records"], "dem-core"),
])
def test_an_unknown_option_points_at_the_help_that_lists_the_options_there(argv, prog, capsys):
    """An option a command does not have is refused in one line that sends the user to that command's --help,
    where its options are listed; one given before the command, to the top level's."""
    from dem_core import cli

    assert cli.main(argv) == 2
    assert capsys.readouterr().err.strip().endswith(f"unrecognized arguments: --bogus (see {prog} --help)")
