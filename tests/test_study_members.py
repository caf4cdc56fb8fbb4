"""A study's members (dem_core.analyses.study_members): saved as they finish, resumed after Ctrl-C, the same on a
Dask cluster, and a scheduler that cannot be reached named in one line."""

import json
import socket
import warnings

import pandas as pd
import pytest

from dem_core import scenes
from dem_core.analyses import cluster, study_members, thresholds
from dem_core.analyses.fragility_study import fragility_study, stripes
from dem_core.analyses.study_members import LOST, MembersInterrupted
from dem_core.cli import main
from dem_core.inputs.excitation import sine_pulse

BLOCK = scenes.block(0.6, 3.0)
RECORDS = {f"pulse {period:g} s": sine_pulse(1.0, period) for period in (0.4, 0.6, 0.9)}
LEVELS = stripes(4, 8.0)
OPTIONS = {"duration": 2.0, "integrator": "moreau", "samples": 50}
#: the columns that say what a run did (not how long it took)
OUTCOME = ["record", "level", "member", "status", "overturned", "damage_ratio", "max_peak_abs_theta_rad"]


def _study(**options):
    with warnings.catch_warnings():
        warnings.simplefilter("ignore", RuntimeWarning)  # three records: fewer than advised
        return fragility_study(BLOCK, RECORDS, LEVELS, (0.5, 1.0), **OPTIONS, **options)


def test_a_logged_study_is_resumed_without_running_again(tmp_path):
    whole = _study()
    first = _study(log=tmp_path / "members.jsonl")
    again = _study(log=tmp_path / "members.jsonl")
    assert first.resumed == 0 and again.resumed == len(again.runs) == 12 and again.device == "resumed from the log"
    pd.testing.assert_frame_equal(whole.runs[OUTCOME], again.runs[OUTCOME], check_dtype=False)
    pd.testing.assert_frame_equal(whole.table(), again.table())


def test_ctrl_c_keeps_the_finished_members_and_the_rerun_gives_the_same_study(tmp_path):
    """Ctrl-C once 5 members finished: each was logged as it ended, the rest run on resuming, and the study is the
    uninterrupted one."""
    log = tmp_path / "members.jsonl"

    pressed = []

    def stop(done, total):  # Ctrl-C, once
        if done >= 5 and not pressed:
            pressed.append(done)
            raise KeyboardInterrupt

    with pytest.raises(MembersInterrupted) as stopped:
        _study(log=log, progress=stop, threads=1)
    saved = stopped.value.saved
    assert 5 <= saved < 12 and len(log.read_text().splitlines()) == saved
    with log.open("a") as handle:
        handle.write('{"digest": "torn')  # a crash in the middle of a line
    resumed = _study(log=log, threads=1)
    assert resumed.resumed == saved
    pd.testing.assert_frame_equal(_study().runs[OUTCOME], resumed.runs[OUTCOME], check_dtype=False)


@pytest.mark.slow
def test_the_same_study_on_a_dask_cluster_of_two_workers(tmp_path):
    distributed = pytest.importorskip("distributed")
    here = _study()
    with cluster.local_cluster(2) as dask:
        there = _study(scheduler=dask.scheduler_address, log=tmp_path / "members.jsonl")
        onset = thresholds.onset_threshold(BLOCK, _pulse, 0.5, 8.0, step=0.25, duration=1.5,
                                           scheduler=dask.scheduler_address)
        with distributed.Client(dask) as client:  # no profiler, not even in a worker its nanny started again
            client.restart()
            assert not any(client.run(lambda dask_worker: "profile" in dask_worker.periodic_callbacks).values())
    assert there.device.startswith("Dask cluster of 2 workers")
    pd.testing.assert_frame_equal(here.runs[OUTCOME], there.runs[OUTCOME], check_dtype=False)
    pd.testing.assert_frame_equal(here.table(), there.table())
    assert onset == thresholds.onset_threshold(BLOCK, _pulse, 0.5, 8.0, step=0.25, duration=1.5)


def _pulse(amplitude):
    return sine_pulse(amplitude, 0.6)


def test_a_scheduler_that_cannot_be_reached_is_one_line(tmp_path, capsys, monkeypatch):
    monkeypatch.setattr(cluster, "CONNECT_TIMEOUT", 1.0)
    out = tmp_path / "out"
    assert main(["fragility", "--records", "kalamata_1986", "--levels", "2", "--scheduler", "tcp://127.0.0.1:9",
                 "--out", str(out)]) == 2
    said = capsys.readouterr().err.splitlines()
    errors = [line for line in said if line.startswith("error:")]
    assert errors == [said[-1]] and "Traceback" not in "".join(said)
    assert said[-1].startswith("error: --scheduler: the Dask scheduler tcp://127.0.0.1:9 cannot be reached within 1 s")


BLOCK_UNDER_PULSE = """
[scene]
builder = "block"
width = 0.6
height = 3.0
[excitation]
kind = "sine_pulse"
amplitude = 4.0
duration = 0.6
[simulation]
duration = 2.0
integrator = "moreau"
"""


def test_threshold_writes_its_runs_and_answer_and_resumes_from_its_log(tmp_path, capsys):
    scene = tmp_path / "block.toml"
    scene.write_text(BLOCK_UNDER_PULSE)
    out = tmp_path / "out"
    command = ["threshold", str(scene), "--parameter", "amplitude", "--low", "2", "--high", "12", "--step", "0.2",
               "--out", str(out)]
    assert main(command) == 0
    first = capsys.readouterr().out
    answer = json.loads((out / "threshold.json").read_text())
    runs = pd.read_csv(out / "runs.csv")
    assert answer["criterion"] == "overturning" and answer["runs"] == len(runs) == len(
        (out / "members.jsonl").read_text().splitlines())
    assert f"overturning threshold: amplitude = {answer['threshold']:.4g} m/s^2" in first
    assert runs.loc[runs["overturning"] == "yes", "amplitude"].min() == answer["above"]
    assert main(command) == 0
    assert capsys.readouterr().out == first
    assert len((out / "members.jsonl").read_text().splitlines()) == answer["runs"]  # nothing ran again


def test_a_local_cluster_takes_a_free_port_for_its_http_server_without_a_warning():
    """distributed's scheduler serves HTTP on 8787 unless told otherwise, and warns where another cluster holds it."""
    distributed = pytest.importorskip("distributed")
    with socket.socket() as held:
        try:
            held.bind(("", 8787))
            held.listen()
        except OSError:
            pass  # held already
        with warnings.catch_warnings():
            warnings.simplefilter("error")
            with cluster.local_cluster(1, processes=False) as dask:
                assert dask.scheduler.http_server.port != 8787
                # no profiler to deadlock a Python 3.11 worker whose task starts threads; distributed's default has it
                assert [w for w in dask.workers.values() if "profile" in w.periodic_callbacks] == []
    with distributed.LocalCluster(n_workers=1, processes=False, dashboard_address=None,
                                  scheduler_kwargs={"dashboard_address": ":0"}) as default:
        assert all("profile" in w.periodic_callbacks for w in default.workers.values())


@pytest.mark.slow
def test_a_task_lost_on_the_cluster_fails_its_members_alone_and_is_not_logged(tmp_path):
    pytest.importorskip("distributed")
    log = tmp_path / "members.jsonl"

    def flaky(result):
        if result.peak_theta.max() > 0.02:
            raise RuntimeError("a worker fault")
        return {}

    with cluster.local_cluster(1, processes=False) as dask:
        done = study_members.run_members(BLOCK, [sine_pulse(a, 0.5) for a in (1.0, 2.0, 8.0)], 1.0, [[0], [1], [2]],
                                         log=log, scheduler=dask.scheduler_address, measures=flaky,
                                         integrator="moreau")
    assert list(done.table["status"]) == ["ok", "ok", LOST] and "a worker fault" in done.table["error"][2]
    assert len(log.read_text().splitlines()) == 2
