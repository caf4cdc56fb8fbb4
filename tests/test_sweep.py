"""Parametric sweeps: points, sweep files, parallel runs that resume, record failures, and run on Dask."""

import json
import os
import signal
import subprocess
import sys
import textwrap
import time
from dataclasses import dataclass
from pathlib import Path

import numpy as np
import pandas as pd
import pytest

import dem_core
from dem_core import excitation, scenes
from dem_core.analyses.cluster import local_cluster
from dem_core.analyses.sweep import RunSpec, Sweep, SweepError, load_sweep, run_id, run_sweep
from dem_core.engine.result import BLOCK_MEASURES
from dem_core.inputs.excitation import Component, GroundMotion

SPEC = """
[scene]
builder = "block"
width = 0.5
height = 2.0
[excitation]
kind = "harmonic"
frequency = 1.0
pga = 1.0
[simulation]
duration = 1.0
[sweep]
time_histories = true
[sweep.excitation]
frequency = {start = 1.0, stop = 2.0, num = 2}
pga = [3.0, 6.0]
"""


def block_under_pulse(params):
    """Module-level, hence picklable into worker processes."""
    scene = scenes.block(0.5, 2.0, friction=params["mu"])
    return RunSpec(scene, excitation.sine_pulse(params["amplitude"], 0.5), {"duration": 1.0, "output_dt": 0.01})


def test_grid_and_zip_points():
    grid = Sweep(block_under_pulse, {"a": [1, 2], "b": [10, 20, 30]})
    assert len(grid.points()) == 6 and grid.points()[1] == {"a": 1, "b": 20}
    zipped = Sweep(block_under_pulse, {"a": [1, 2], "b": [10, 20]}, mode="zip")
    assert zipped.points() == [{"a": 1, "b": 10}, {"a": 2, "b": 20}]
    with pytest.raises(SweepError, match="as many values"):
        Sweep(block_under_pulse, {"a": [1, 2], "b": [10]}, mode="zip")


def test_run_id_is_the_whole_run_not_the_varied_values():
    one = block_under_pulse({"mu": 0.7, "amplitude": np.float64(2.0)})
    assert run_id(one) == run_id(block_under_pulse({"amplitude": 2.0, "mu": 0.7}))
    shorter = RunSpec(one.scene, one.excitation, {**one.simulation, "duration": 0.5})
    stiffer = RunSpec(one.scene.replace(contact=dem_core.ContactParameters(kn=4e10)), one.excitation, one.simulation)
    assert len({run_id(one), run_id(shorter), run_id(stiffer)}) == 3


def test_sweep_file_values_and_errors(tmp_path):
    path = tmp_path / "spec.toml"
    path.write_text(SPEC)
    sweep = load_sweep(path)
    assert sweep.parameters == {"excitation.frequency": [1.0, 2.0], "excitation.pga": [3.0, 6.0]}
    assert sweep.time_histories
    path.write_text(SPEC.replace("pga = [3.0, 6.0]", "pgaa = [3.0, 6.0]"))
    with pytest.raises(SweepError, match=r"spec.toml.*pgaa"):
        load_sweep(path)
    path.write_text(SPEC.replace("pga = [3.0, 6.0]", "pga = {from = 1}"))
    with pytest.raises(SweepError, match=r"\[sweep.excitation\] pga"):
        load_sweep(path)


def test_sweep_matches_direct_runs_and_writes_histories(tmp_path):
    path = tmp_path / "spec.toml"
    path.write_text(SPEC)
    table = run_sweep(load_sweep(path), tmp_path / "out", workers=2, progress=False)
    assert len(table) == 4 and set(table.status) == {"ok"}
    assert (tmp_path / "out" / "results.parquet").is_file()
    row = table[(table["excitation.frequency"] == 2.0) & (table["excitation.pga"] == 6.0)].iloc[0]
    direct = dem_core.simulate(scenes.block(0.5, 2.0), excitation.harmonic(pga=6.0, frequency=2.0), duration=1.0)
    assert row.max_peak_abs_theta_rad == direct.peak_theta.max()  # same code, same numbers
    block = direct.metrics().iloc[0]  # the block's measures in the columns a batch's rows have
    for measure in BLOCK_MEASURES:
        np.testing.assert_array_equal(row[f"{measure}[block]"], block[measure])
    assert row.max_peak_displacement_m == block.peak_abs_displacement_m
    history = pd.read_parquet(tmp_path / "out" / "histories" / f"{row.run_id}.parquet")
    assert history.theta.abs().max() == pytest.approx(direct.peak_theta.max(), rel=0.05)


def test_failing_point_is_recorded_and_the_sweep_goes_on(tmp_path):
    sweep = Sweep(block_under_pulse, {"mu": [0.7, -1.0], "amplitude": [2.0, 8.0]})
    table = run_sweep(sweep, tmp_path, workers=2, progress=False)
    failed = table[table.mu == -1.0]
    assert set(failed.status) == {"failed"} and failed.error.str.contains("friction").all()
    assert set(table[table.mu == 0.7].status) == {"ok"}


def test_restarted_sweep_skips_finished_runs(tmp_path):
    whole = Sweep(block_under_pulse, {"mu": [0.7, 0.3], "amplitude": [2.0, 8.0, 12.0]})
    run_sweep(whole, tmp_path, workers=2, progress=False)
    runs = sorted((tmp_path / "runs").glob("*.parquet"))
    for lost in runs[2:]:  # as if the sweep had been killed after two of its six runs
        lost.unlink()
    done = {p.name: p.stat().st_mtime_ns for p in runs[:2]}
    table = run_sweep(whole, tmp_path, workers=2, progress=False)
    assert len(table) == 6 and set(table.status) == {"ok"}
    for name, mtime in done.items():
        assert (tmp_path / "runs" / name).stat().st_mtime_ns == mtime  # not run again
    assert [(r.mu, r.amplitude) for r in table.itertuples()] == [(p["mu"], p["amplitude"]) for p in whole.points()]


@pytest.mark.slow
def test_same_sweep_on_a_dask_cluster(tmp_path):
    pytest.importorskip("distributed")
    sweep = Sweep(block_under_pulse, {"mu": [0.7], "amplitude": [3.0, 8.0]})
    local = run_sweep(sweep, tmp_path / "local", workers=1, progress=False)
    with local_cluster(2) as cluster:
        remote = run_sweep(sweep, tmp_path / "dask", scheduler=cluster.scheduler_address, progress=False)
    assert set(remote.status) == {"ok"}
    columns = ["run_id", "max_peak_abs_theta_rad", "total_sliding_m", "overturned"]
    pd.testing.assert_frame_equal(local[columns], remote[columns])


def test_sweep_command_writes_its_progress_as_lines_in_a_log(tmp_path, monkeypatch, capsys):
    from dem_core.cli import main, progress

    monkeypatch.setattr(progress, "interactive", lambda: False)
    path = tmp_path / "spec.toml"
    path.write_text(textwrap.dedent(SPEC).replace("time_histories = true", "time_histories = false"))
    assert main(["sweep", str(path), "--out", str(tmp_path / "out"), "--workers", "1"]) == 0
    assert len(pd.read_parquet(tmp_path / "out" / "results.parquet")) == 4
    assert "sweep: 4 of 4 (100.0%)" in capsys.readouterr().err


def test_bundled_example_sweep_file_builds_every_point():
    from pathlib import Path

    sweep = load_sweep(Path(__file__).parents[1] / "examples" / "sweeps" / "column_harmonic.toml")
    points = sweep.points()
    assert len(points) == 10 * 4 * 2
    spec = sweep.build(points[-1])
    assert spec.scene.friction("drum1", "drum2") == 0.7 and spec.simulation["duration"] == 10.0


@pytest.mark.slow
def test_sweep_killed_midway_resumes_without_losing_runs(tmp_path):
    spec = tmp_path / "spec.toml"
    # Twelve runs of equal cost (none rocks), each long enough (explicit, 40 s) for the kill to land midway.
    spec.write_text(SPEC.replace("time_histories = true", "time_histories = false")
                    .replace("duration = 1.0", 'duration = 40.0\nintegrator = "explicit"')
                    .replace("pga = [3.0, 6.0]", "pga = [0.5, 0.75, 1.0, 1.25, 1.5, 1.75]"))
    out = tmp_path / "out"
    command = [sys.executable, "-m", "dem_core", "sweep", str(spec), "--out", str(out), "--workers", "1",
               "--no-progress"]
    process = subprocess.Popen(command, start_new_session=True, stdout=subprocess.DEVNULL, stderr=subprocess.DEVNULL)
    deadline = time.time() + 120
    while len(list((out / "runs").glob("*.parquet"))) < 3 and time.time() < deadline and process.poll() is None:
        time.sleep(0.05)
    os.killpg(process.pid, signal.SIGKILL)  # the command and its worker, at once
    process.wait()
    before = {p.name: p.stat().st_mtime_ns for p in (out / "runs").glob("*.parquet")}
    assert 3 <= len(before) < 12
    assert subprocess.run(command, check=False, capture_output=True).returncode == 0
    table = pd.read_parquet(out / "results.parquet")
    assert len(table) == 12 and table.run_id.is_unique and set(table.status) == {"ok"}
    for name, mtime in before.items():
        assert (out / "runs" / name).stat().st_mtime_ns == mtime


# --- stale and mixed results ---------------------------------------------------------------------

QUIET_SPEC = SPEC.replace("time_histories = true", "time_histories = false").replace("pga = [3.0, 6.0]",
                                                                                    "pga = [0.5, 1.0]")


def test_rerun_after_editing_the_base_file_is_refused_then_overwritten(tmp_path):
    """A sweep file whose base settings changed is refused in the folder of its former self, naming the change;
    with overwrite it runs again and results.parquet reports the new settings."""
    path = tmp_path / "spec.toml"
    path.write_text(QUIET_SPEC.replace("duration = 1.0", "duration = 2.0"))
    first = run_sweep(load_sweep(path), tmp_path / "out", workers=1, progress=False)
    assert first.end_time_s.round(2).tolist() == [2.0] * 4
    path.write_text(QUIET_SPEC)
    with pytest.raises(SweepError, match=r"holds the results of another sweep \(the same parameter values, but "
                                         r"\[simulation\] duration: 2\.0 -> 1\.0 changed since\).*--overwrite"):
        run_sweep(load_sweep(path), tmp_path / "out", workers=1, progress=False)
    table = run_sweep(load_sweep(path), tmp_path / "out", workers=1, progress=False, overwrite=True)
    assert table.end_time_s.round(2).tolist() == [1.0] * 4
    assert pd.read_parquet(tmp_path / "out" / "results.parquet").end_time_s.round(2).tolist() == [1.0] * 4
    spec = json.loads((tmp_path / "out" / "sweep.json").read_text())
    assert spec["tables"]["simulation"]["duration"] == 1.0 and len(spec["runs"]) == 4


def test_another_sweep_into_the_same_folder_is_refused_not_mixed(tmp_path):
    """Another sweep into a folder that holds one is refused, naming both; with overwrite only its own runs
    are left in results.parquet and runs/."""
    first = Sweep(block_under_pulse, {"mu": [0.7, 0.5], "amplitude": [1.0, 2.0]})
    run_sweep(first, tmp_path, workers=2, progress=False)
    other = Sweep(block_under_pulse, {"mu": [0.6], "amplitude": [1.0, 2.0, 3.0]})
    with pytest.raises(SweepError, match=r"another sweep \(4 runs over mu = \[0\.7, 0\.5\]; amplitude = "
                                         r"\[1\.0, 2\.0\], where this sweep has 3 over mu = \[0\.6\]"):
        run_sweep(other, tmp_path, workers=2, progress=False)
    table = run_sweep(other, tmp_path, workers=2, progress=False, overwrite=True)
    assert len(table) == 3 and len(pd.read_parquet(tmp_path / "results.parquet")) == 3
    assert len(list((tmp_path / "runs").glob("*.parquet"))) == 3


def test_cli_refuses_a_folder_of_another_sweep(tmp_path, capsys):
    from dem_core.cli import main

    path = tmp_path / "spec.toml"
    path.write_text(QUIET_SPEC)
    command = ["sweep", str(path), "--out", str(tmp_path / "out"), "--workers", "1", "--no-progress"]
    assert main(command) == 0
    path.write_text(QUIET_SPEC.replace("pga = [0.5, 1.0]", "pga = [0.5]"))
    assert main(command) == 2
    assert "holds the results of another sweep" in capsys.readouterr().err
    assert main([*command, "--overwrite"]) == 0
    assert len(pd.read_parquet(tmp_path / "out" / "results.parquet")) == 2


def test_cli_duration_sets_every_run_and_is_part_of_their_identity(tmp_path, capsys):
    """--duration replaces the file's [simulation] duration at every point; a resumed sweep says how many runs
    were already done; the end counts the runs in words; a rerun with another --duration is refused, not mixed."""
    from dem_core.cli import main

    path = tmp_path / "spec.toml"
    path.write_text(QUIET_SPEC)
    out = tmp_path / "out"
    command = ["sweep", str(path), "--out", str(out), "--workers", "1", "--no-progress", "--duration", "0.5"]
    assert main(command) == 0
    printed = capsys.readouterr().out
    assert "4 runs over excitation.frequency, excitation.pga on 1 local worker(s), each run for 0.5 s" in printed
    assert f"4 runs: 4 ok; results in {out}/results.parquet" in printed
    assert "already done" not in printed
    assert pd.read_parquet(out / "results.parquet").end_time_s.round(3).tolist() == [0.5] * 4
    assert json.loads((out / "sweep.json").read_text())["tables"]["simulation"]["duration"] == 0.5
    next((out / "runs").glob("*.parquet")).unlink()  # as if the sweep had been stopped before its last run
    assert main(command) == 0
    assert f"3 of 4 runs already done in {out}; running 1" in capsys.readouterr().out
    assert main(command) == 0
    assert f"all 4 runs already done in {out}; nothing to run" in capsys.readouterr().out
    assert main([*command[:-1], "0.25"]) == 2  # runs of 0.5 s are not mixed with runs of 0.25 s
    assert "[simulation] duration: 0.5 -> 0.25" in capsys.readouterr().err
    varied = tmp_path / "varied.toml"
    varied.write_text(QUIET_SPEC + "[sweep.simulation]\nduration = [0.5, 1.0]\n")
    assert main(["sweep", str(varied), "--out", str(tmp_path / "o2"), "--duration", "0.5"]) == 2
    assert "varies simulation.duration" in capsys.readouterr().err


def test_run_counts_in_words():
    from dem_core.cli.sweep import run_counts

    assert run_counts(16, {"ok": 15, "failed": 1}) == "16 runs: 15 ok, 1 failed"
    assert run_counts(3, {"failed": 1, "unstable": 1, "ok": 1}) == "3 runs: 1 ok, 1 unstable, 1 failed"
    assert run_counts(1, {"ok": 1}) == "1 run: 1 ok"


# --- failures ------------------------------------------------------------------------------------

def test_failing_first_point_of_a_sweep_file_is_a_failed_row(tmp_path):
    """A point whose scene cannot be built, even the first, is a failed row with its error and 0 attempts;
    the other points run."""
    path = tmp_path / "spec.toml"
    path.write_text(QUIET_SPEC.replace("[sweep.excitation]", "[sweep.scene]\nfriction = [-0.1, 0.7]\n"
                                                             "[sweep.excitation]"))
    table = run_sweep(load_sweep(path), tmp_path / "out", workers=2, progress=False)
    assert len(table) == 8
    failed = table[table["scene.friction"] == -0.1]
    assert set(failed.status) == {"failed"} and failed.error.str.contains("friction must be >= 0").all()
    assert set(table[table["scene.friction"] == 0.7].status) == {"ok"}
    assert table.attempts.dtype.kind == "i" and set(failed.attempts) == {0}  # never run: 0, an integer


def test_sweep_file_with_a_value_of_the_wrong_type_is_refused_at_once(tmp_path):
    path = tmp_path / "spec.toml"
    path.write_text(QUIET_SPEC.replace("pga = [0.5, 1.0]", 'pga = [0.5, "1.0"]'))
    with pytest.raises(SweepError, match=r"spec\.toml: \[excitation\] pga: expected a finite number, got the string "
                                         r"'1\.0'.*at the point"):
        load_sweep(path)


@dataclass(frozen=True, eq=False)
class KillsItsWorker(Component):
    """Ground motion whose evaluation SIGKILLs the process running the simulation: always, or only
    while the file ``once`` does not exist (it is created first)."""

    once: str = ""
    end_time = 0.2
    peak_acceleration = 0.0

    def acceleration(self, t):
        if not self.once or not os.path.exists(self.once):
            if self.once:
                Path(self.once).touch()
            os.kill(os.getpid(), signal.SIGKILL)
        return np.zeros_like(np.asarray(t, dtype=float))

    velocity = displacement = acceleration


@dataclass(frozen=True)
class SometimesKillsItsWorker:
    """Sweep build: case "dies" kills its worker on every attempt, "dies_once" on the first only."""

    folder: str

    def __call__(self, params):
        case = params["case"]
        if case == "dies":
            motion = GroundMotion(KillsItsWorker())
        elif case == "dies_once":
            motion = GroundMotion(KillsItsWorker(str(Path(self.folder) / "killed_once")))
        else:
            motion = excitation.harmonic(pga=0.5 if case == "ok" else 0.6, frequency=1.0)
        return RunSpec(scenes.block(0.5, 2.0), motion, {"duration": 0.2})


def test_a_dead_worker_fails_only_its_own_run_after_one_retry(tmp_path):
    """A worker killed during a run fails that run alone, after one retry; the other runs finish and
    results.parquet has every row."""
    sweep = Sweep(SometimesKillsItsWorker(str(tmp_path)), {"case": ["ok", "dies", "dies_once", "also_ok"]})
    table = run_sweep(sweep, tmp_path / "out", workers=2, progress=False)
    assert list(table.case) == ["ok", "dies", "dies_once", "also_ok"]
    assert list(table.status) == ["ok", "failed", "ok", "ok"] and list(table.attempts) == [1, 2, 2, 1]
    assert "killed by SIGKILL on each of 2 attempts" in table.error[1]
    assert len(pd.read_parquet(tmp_path / "out" / "results.parquet")) == 4


def _children(pid: int) -> list:
    """Live (not zombie) processes whose parent is ``pid``."""
    found = []
    for stat in Path("/proc").glob("[0-9]*/stat"):
        try:
            fields = stat.read_text().rsplit(")", 1)[1].split()
        except OSError:
            continue
        if int(fields[1]) == pid and fields[0] != "Z":
            found.append(int(stat.parent.name))
    return found


def _alive(pid: int) -> bool:
    try:
        return Path(f"/proc/{pid}/stat").read_text().rsplit(")", 1)[1].split()[0] != "Z"
    except OSError:
        return False


@pytest.mark.skipif(not Path("/proc/self/stat").exists(), reason="reads /proc")
def test_killing_the_sweep_ends_its_workers(tmp_path):
    """Killing the sweep's process with SIGKILL ends its worker processes too."""
    spec = tmp_path / "spec.toml"
    spec.write_text(QUIET_SPEC.replace("duration = 1.0", "duration = 60.0")
                    .replace("frequency = {start = 1.0, stop = 2.0, num = 2}", "frequency = [1.0, 1.5, 2.0, 2.5]"))
    command = [sys.executable, "-m", "dem_core", "sweep", str(spec), "--out", str(tmp_path / "out"), "--workers", "2",
               "--no-progress"]
    process = subprocess.Popen(command, start_new_session=True, stdout=subprocess.DEVNULL, stderr=subprocess.DEVNULL)
    try:
        deadline = time.time() + 60
        while len(_children(process.pid)) < 2 and time.time() < deadline and process.poll() is None:
            time.sleep(0.05)
        workers = _children(process.pid)
        assert len(workers) == 2
        os.kill(process.pid, signal.SIGKILL)  # the parent only
        process.wait()
        deadline = time.time() + 10
        while any(_alive(w) for w in workers) and time.time() < deadline:
            time.sleep(0.05)
        assert not any(_alive(w) for w in workers)
    finally:
        for pid in [process.pid, *_children(process.pid)]:
            try:
                os.kill(pid, signal.SIGKILL)
            except ProcessLookupError:
                pass


def block_under_el_centro(params):
    """A point that runs the first ``duration`` s of El Centro, whose strong motion ends at 26.3 s."""
    return RunSpec(scenes.block(0.5, 2.0), excitation.record("el_centro_1940", pga=params["pga"]),
                   {"duration": params["duration"], "output_dt": 0.05})


def test_a_sweep_that_cuts_a_records_strong_motion_says_so_once_naming_it(tmp_path):
    cut = Sweep(block_under_el_centro, {"pga": [0.5, 1.0], "duration": [0.2]})
    with pytest.warns(RuntimeWarning, match="the strong motion is cut: 0.2 s of el_centro_1940 stop") as said:
        run_sweep(cut, tmp_path / "out", workers=1, progress=False)
    assert sum("strong motion" in str(w.message) for w in said) == 1
