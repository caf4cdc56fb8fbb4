"""Parametric sweeps: points, sweep files, parallel runs that resume, record failures, and run on Dask."""

import textwrap

import numpy as np
import pandas as pd
import pytest

import dem_core
from dem_core import excitation, scenes
from dem_core.analyses.sweep import RunSpec, Sweep, SweepError, load_sweep, run_id, run_sweep

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
    assert run_id({"a": np.float64(1.0).item(), "b": 2}) == run_id({"b": 2, "a": 1.0})


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
    history = pd.read_parquet(tmp_path / "out" / "histories" / f"{row.run_id}.parquet")
    assert history.theta.abs().max() == pytest.approx(direct.peak_theta.max(), rel=0.05)


def test_failing_point_is_recorded_and_the_sweep_goes_on(tmp_path):
    sweep = Sweep(block_under_pulse, {"mu": [0.7, -1.0], "amplitude": [2.0, 8.0]})
    table = run_sweep(sweep, tmp_path, workers=2, progress=False)
    failed = table[table.mu == -1.0]
    assert set(failed.status) == {"failed"} and failed.error.str.contains("friction").all()
    assert set(table[table.mu == 0.7].status) == {"ok"}


def test_restarted_sweep_skips_finished_runs(tmp_path):
    first = Sweep(block_under_pulse, {"mu": [0.7], "amplitude": [2.0, 8.0]})
    run_sweep(first, tmp_path, workers=1, progress=False)
    done = {p.name: p.stat().st_mtime_ns for p in (tmp_path / "runs").glob("*.parquet")}
    # as if the first sweep had been killed after two of its six runs
    whole = Sweep(block_under_pulse, {"mu": [0.7, 0.3], "amplitude": [2.0, 8.0, 12.0]})
    table = run_sweep(whole, tmp_path, workers=2, progress=False)
    assert len(table) == 6 and set(table.status) == {"ok"}
    for name, mtime in done.items():
        assert (tmp_path / "runs" / name).stat().st_mtime_ns == mtime  # not run again
    assert [(r.mu, r.amplitude) for r in table.itertuples()] == [(p["mu"], p["amplitude"]) for p in whole.points()]


def test_same_sweep_on_a_dask_cluster(tmp_path):
    distributed = pytest.importorskip("distributed")
    sweep = Sweep(block_under_pulse, {"mu": [0.7], "amplitude": [3.0, 8.0]})
    local = run_sweep(sweep, tmp_path / "local", workers=1, progress=False)
    with distributed.LocalCluster(n_workers=2, threads_per_worker=1, processes=True, dashboard_address=None) as cluster:
        remote = run_sweep(sweep, tmp_path / "dask", scheduler=cluster.scheduler_address, progress=False)
    assert set(remote.status) == {"ok"}
    columns = ["run_id", "max_peak_abs_theta_rad", "total_sliding_m", "overturned"]
    pd.testing.assert_frame_equal(local[columns], remote[columns])


def test_sweep_command(tmp_path):
    from dem_core.cli import main

    path = tmp_path / "spec.toml"
    path.write_text(textwrap.dedent(SPEC).replace("time_histories = true", "time_histories = false"))
    assert main(["sweep", str(path), "--out", str(tmp_path / "out"), "--workers", "1", "--no-progress"]) == 0
    assert len(pd.read_parquet(tmp_path / "out" / "results.parquet")) == 4


def test_bundled_example_sweep_file_builds_every_point():
    from pathlib import Path

    sweep = load_sweep(Path(__file__).parents[1] / "examples" / "sweeps" / "column_harmonic.toml")
    points = sweep.points()
    assert len(points) == 10 * 4 * 2
    spec = sweep.build(points[-1])
    assert spec.scene.friction("drum1", "drum2") == 0.7 and spec.simulation["duration"] == 10.0


def test_sweep_killed_midway_resumes_without_losing_runs(tmp_path):
    import os
    import signal
    import subprocess
    import sys
    import time

    spec = tmp_path / "spec.toml"
    spec.write_text(SPEC.replace("time_histories = true", "time_histories = false")
                    .replace("duration = 1.0", "duration = 4.0")
                    .replace("pga = [3.0, 6.0]", "pga = [1.0, 2.0, 3.0, 4.0, 5.0, 6.0]"))
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
