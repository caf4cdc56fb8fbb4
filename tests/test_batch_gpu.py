"""The batch's GPU path (dem_core.batch_gpu, engine/_members.py): its kernel's code, compiled for one CPU thread,
gives each member the run simulate gives bit for bit, under either integrator; the CUDA kernel itself, run by
numba's CUDA simulator in a process of its own, gives simulate_batch's rows on the CPU; and what the GPU cannot
take is refused naming it."""

import json
import os
import re
import subprocess
import sys
import tracemalloc
from pathlib import Path

import numpy as np
import pandas as pd
import pytest

import dem_core
from dem_core import ContactParameters, scenes, simulate_batch
from dem_core.batch_gpu import (_hand_back, _motions, check_members, gpu_available, pack, run_members, serial_launcher,
                                written_out)
from dem_core.inputs.connectors import OAK_POLOS, titanium_bar
from dem_core.inputs.excitation import record, scaled, sine_pulse
from dem_core.simulation import Simulation, set_up_scene

REPOSITORY = Path(__file__).resolve().parents[1]
EL_CENTRO = record("el_centro_1940")


def _assert_same_run(cpu, gpu):
    """Bit for bit: outputs, peaks, overturns, slips, steps and why the run stopped."""
    assert np.array_equal(cpu.t, gpu.t)
    for name in ("x", "y", "theta", "base_x", "base_y", "peak_theta", "slip_history"):
        assert np.array_equal(getattr(cpu, name), getattr(gpu, name)), name
    assert np.array_equal(cpu.overturn_time, gpu.overturn_time, equal_nan=True)
    assert cpu.interface_slip == gpu.interface_slip
    for key in ("steps", "ended_at_overturn", "substepped_steps", "tipped_stacks", "pair_lists",
                "narrow_phase_per_step"):
        assert cpu.info.get(key) == gpu.info.get(key), key
    assert np.array_equal(cpu.connector_history, gpu.connector_history)
    assert (cpu.connectors is None) == (gpu.connectors is None)
    if cpu.connectors is not None:
        pd.testing.assert_frame_equal(cpu.connectors, gpu.connectors)


CASES = {
    # a rocking block thrown by one-sine pulses below and above its overturning amplitude's neighbourhood
    "block under pulses": (scenes.block(1.0, 6.0), [sine_pulse(a, 1.0) for a in (1.5, 2.5)], 3.0, {}),
    # scaled copies of one record (sampled once, scaled per member): rocking, and an overturn that stops the run
    "block under El Centro": (scenes.block(1.0, 6.0), [scaled(EL_CENTRO, f) for f in (1.0, 3.0)], 8.0, {}),
    "block on a moving base": (scenes.block(1.0, 6.0), [scaled(EL_CENTRO, 1.2)], 4.0,
                               {"ground_motion": "moving_base"}),
    "8-drum column": (scenes.column(), [scaled(EL_CENTRO, 2.0)], 1.0, {}),
    # the collapse, taken in substeps past alpha
    "8-drum column to the end": (scenes.column(), [scaled(EL_CENTRO, 4.0)], 6.0, {"stop_at_overturn": False}),
    "colonnade": (scenes.colonnade(), [scaled(EL_CENTRO, 2.0)], 1.0, {}),
    "64 blocks: 9 columns of 7 drums and an epistyle": (scenes.colonnade(n_columns=9, n_drums=7),
                                                         [sine_pulse(4.0, 0.3)], 0.3, {}),
    "overlap-area law": (scenes.stack([(0.8, 1.0), (0.6, 0.8)], contact=ContactParameters(law="overlap_area")),
                         [sine_pulse(4.0, 0.5)], 1.5, {}),
    # Moreau-Jean's stage: rocking and an overturn, a moving base, a column, a colonnade through its collapse
    "Moreau-Jean, block under El Centro": (scenes.block(1.0, 6.0), [scaled(EL_CENTRO, f) for f in (1.0, 3.0)], 8.0,
                                           {"integrator": "moreau"}),
    "Moreau-Jean, block on a moving base": (scenes.block(1.0, 6.0), [scaled(EL_CENTRO, 1.2)], 4.0,
                                            {"ground_motion": "moving_base", "integrator": "moreau"}),
    "Moreau-Jean, 8-drum column": (scenes.column(), [scaled(EL_CENTRO, 2.0)], 6.0, {"integrator": "moreau"}),
    "Moreau-Jean, colonnade to its collapse": (scenes.colonnade(), [scaled(EL_CENTRO, 5.0)], 10.0,
                                               {"integrator": "moreau", "stop_at_overturn": False}),
    # connectors: titanium bars at every joint of the column (they yield), oak poles with their clearance
    "8-drum column with titanium bars": (scenes.column(connectors=[(titanium_bar(), "all")]),
                                         [scaled(EL_CENTRO, 3.0)], 6.0, {"integrator": "explicit"}),
    "Moreau-Jean, 8-drum column with titanium bars and oak poles": (
        scenes.column(connectors=[(titanium_bar(), "capital"), (OAK_POLOS, "all")]), [scaled(EL_CENTRO, 3.0)], 6.0,
        {"integrator": "moreau"}),
}
#: members of one batch under either contact law (each law's buffers beside the other's)
BOTH_LAWS = [scenes.stack([(0.8, 1.0), (0.6, 0.8)], contact=ContactParameters(law=law))
             for law in ("corner", "overlap_area")]


@pytest.mark.parametrize("case", CASES)
def test_the_gpu_kernels_code_gives_each_member_the_run_simulate_gives(case):
    scene, motions, duration, options = CASES[case]
    options = {"integrator": "explicit", **options}
    runs = [Simulation(scene, motion, duration, **options) for motion in motions]
    run_members(runs, launcher=serial_launcher())
    for motion, run in zip(motions, runs):
        _assert_same_run(dem_core.simulate(scene, motion, duration, **options), run.result())


def test_members_under_either_contact_law_share_a_batch():
    motion = sine_pulse(4.0, 0.5)
    runs = [Simulation(scene, motion, 1.0, integrator="explicit") for scene in BOTH_LAWS]
    run_members(runs, launcher=serial_launcher())
    for scene, run in zip(BOTH_LAWS, runs):
        _assert_same_run(dem_core.simulate(scene, motion, 1.0, integrator="explicit"), run.result())


def test_the_device_checks_members_scale_one_record_sampled_once_for_them_all():
    """The benchmarks' members (record_members.motions) scale one record, so that a batch samples it once."""
    from comparisons.benchmarks.record_members import SCENES, motions

    build, tan_alpha = SCENES["block"]
    runs = [Simulation(build(), motion, 0.05) for motion in motions(tan_alpha, 4)]
    assert len(_motions(runs).units) == 1


def test_a_batch_holds_one_blank_and_one_shared_model_for_its_members_until_its_kernel_runs():
    """Every member starts with blank outputs and scratch (most of a member's bytes: 2.4 GB and 0.8 GB for 4,096
    columns of 20 s), and members of one scene set up once share its model, so packing a batch makes one member's
    blank and model, not the batch's: here 774 KB and the 40 members' stacked settings and state, 7 KB each, 3.5%
    of 40 blanks, where stacked blanks would be all of them; written out for the kernel, every member's rows are
    that blank and model."""
    scene = scenes.column()
    shared = set_up_scene(scene, integrator="moreau")
    runs = [Simulation(scene, scaled(EL_CENTRO, f), 20.0, integrator="moreau", scene_set_up=shared)
            for f in np.linspace(1.0, 3.0, 40)]
    tracemalloc.start()
    members = pack(runs, _motions(runs))
    peak = tracemalloc.get_traced_memory()[1]
    tracemalloc.stop()
    blank = [a[0] for part in (members.outputs, members.scratch) for a in part]
    assert peak < 0.1 * len(runs) * sum(a.nbytes for a in blank)
    for part in (members.model, members.outputs, members.scratch):
        for a, whole in zip(part, written_out(part)):
            assert whole.flags.c_contiguous and whole.flags.writeable and whole.shape == (len(runs),) + a[0].shape
            assert all(np.array_equal(row, a[0], equal_nan=True) for row in whole)
    assert all(np.shares_memory(a, own) for a, own in zip(members.model, shared.arrays) if own.size)
    apart = [Simulation(scene, scaled(EL_CENTRO, f), 1.0, integrator="moreau") for f in (1.0, 2.0)]
    assert all(a.flags.writeable for a in pack(apart, _motions(apart)).model)  # each its own set-up: stacked


def test_a_batch_hands_each_run_its_rows_of_the_outputs_it_fetched_without_copying_them():
    """The outputs a batch fetches from its kernel are most of its bytes (2.4 GB for 4,096 columns of 20 s): each run
    is handed its rows of them as views, so that handing 40 columns back allocates their states (7 KB each; 1.8% of
    the outputs traced in all) and not their outputs again (577 KB each).  A batch stopped before its launcher
    first wrote the outputs out leaves each run as it was set up.  (A kept history holds a copy of its own: the
    simulator's test.)"""
    scene = scenes.column()
    shared = set_up_scene(scene, integrator="moreau")
    runs = [Simulation(scene, scaled(EL_CENTRO, f), 20.0, integrator="moreau", scene_set_up=shared)
            for f in np.linspace(1.0, 3.0, 40)]
    members = pack(runs, _motions(runs))
    _hand_back(runs, members, 0.0)
    assert all(run.outputs is None for run in runs)
    members.outputs = written_out(members.outputs)  # as the kernel's launcher leaves them
    tracemalloc.start()
    _hand_back(runs, members, 0.0)
    peak = tracemalloc.get_traced_memory()[1]
    tracemalloc.stop()
    fetched = sum(a.nbytes for a in members.outputs)
    assert peak < 0.1 * fetched
    for m, run in enumerate(runs):
        assert all(np.shares_memory(own, whole[m]) for own, whole in zip(run.outputs, members.outputs) if own.size)


#: convex outlines (m) with a flat bottom, and a flat top where a block rests on them: 5 and 5, and 4 and 6 vertices
PENTAGON = [(-0.5, 0.0), (0.5, 0.0), (0.6, 0.25), (0.5, 0.5), (-0.5, 0.5)]
HOUSE = [(-0.4, 0.5), (0.4, 0.5), (0.4, 0.8), (0.0, 1.0), (-0.4, 0.8)]
SQUARE = [(-0.5, 0.0), (0.5, 0.0), (0.5, 0.5), (-0.5, 0.5)]
HEXAGON = [(-0.4, 0.5), (0.4, 0.5), (0.5, 0.7), (0.4, 0.9), (-0.4, 0.9), (-0.5, 0.7)]


def _two_blocks(lower, upper):
    """A block on a block on the ground, under the overlap-area law (which clips their polygons)."""
    return dem_core.Scene((dem_core.Block("lower", np.array(lower)), dem_core.Block("upper", np.array(upper))),
                          dem_core.Block("base", np.array([(-5.0, -1.0), (5.0, -1.0), (5.0, 0.0), (-5.0, 0.0)])),
                          contact=ContactParameters(law="overlap_area"))


def test_a_member_whose_polygons_are_larger_than_member_0s_has_room_in_the_batchs_scratch():
    """Members of one shape (bodies, vertices in all) may differ in their largest polygon: the overlap-area law's
    clipping has room for the largest of any member (member 1's hexagon, 2 x 6 + 2 points, where member 0's
    largest has 5 and left room for 12); and members of different polygons run as simulate runs them.  (Here no
    clipped overlap of a resting pair needs more than 10 points, so only the room tells the two sizings apart.)"""
    motion = sine_pulse(4.0, 0.5)
    members = [_two_blocks(PENTAGON, HOUSE), _two_blocks(SQUARE, HEXAGON)]
    runs = [Simulation(scene, motion, 1.0, integrator="explicit") for scene in members]
    assert pack(runs, _motions(runs)).scratch.clip_x.shape[-1] == 2 * 6 + 2
    run_members(runs, launcher=serial_launcher())
    for scene, run in zip(members, runs):
        _assert_same_run(dem_core.simulate(scene, motion, 1.0, integrator="explicit"), run.result())


def test_a_member_whose_store_fills_is_run_again_on_the_cpu(monkeypatch):
    """A member's store of retired slips is as large as the largest its batch starts with; a member that fills it
    stops and is run again from its start by the CPU's driver, which grows it."""
    from dem_core.engine import state as state_module

    scene, motion, options = scenes.colonnade(), scaled(EL_CENTRO, 5.0), {"integrator": "moreau",
                                                                          "stop_at_overturn": False}
    alone = dem_core.simulate(scene, motion, 10.0, **options)
    monkeypatch.setattr(state_module, "RETIRED_PER_BODY", 0)  # one retired slip
    run = Simulation(scene, motion, 10.0, **options)
    run_members([run], launcher=serial_launcher())
    assert run.state.capacities[1] > 1
    _assert_same_run(alone, run.result())


def test_an_unstable_member_stops_alone_and_says_where():
    """A member beyond its stability limit stops with the CPU's error; the other member runs to its end."""
    scene = scenes.block(1.0, 6.0)
    with pytest.warns(RuntimeWarning, match="times the stability limit"):
        runs = [Simulation(scene, sine_pulse(2.5, 1.0), 1.0, dt=d, enforce_stability_limit=False,
                           integrator="explicit") for d in (5e-5, 1e-3)]
    run_members(runs, launcher=serial_launcher())
    runs[0].result()
    with pytest.raises(dem_core.SimulationUnstable) as gpu:
        runs[1].result()
    with pytest.raises(dem_core.SimulationUnstable) as cpu, pytest.warns(RuntimeWarning):
        dem_core.simulate(scene, sine_pulse(2.5, 1.0), 1.0, dt=1e-3, enforce_stability_limit=False,
                          integrator="explicit")
    assert str(gpu.value) == str(cpu.value)


def test_what_the_gpu_kernel_cannot_take_is_refused_naming_the_member():
    block = Simulation(scenes.block(1.0, 6.0), sine_pulse(2.0, 0.5), 0.1, integrator="explicit")
    moreau = Simulation(scenes.block(1.0, 6.0), sine_pulse(2.0, 0.5), 0.1, integrator="moreau")
    with pytest.raises(ValueError, match="member 1 runs integrator 'moreau', member 0 'explicit'"):
        check_members([block, moreau])
    with pytest.raises(ValueError, match="member 1's scene has"):
        check_members([block, Simulation(scenes.stack([(1.0, 3.0), (1.0, 3.0)]), sine_pulse(2.0, 0.5), 0.1,
                                         integrator="explicit")])


@pytest.mark.skipif(bool(gpu_available()), reason="a GPU is here")
def test_without_a_gpu_auto_runs_on_the_cpu_and_gpu_is_refused():
    batch = simulate_batch(scenes.block(1.0, 6.0), [sine_pulse(2.0, 0.5)], 0.1, device="auto", threads=1)
    assert batch.device == "cpu, 1 thread"
    with pytest.raises(ValueError, match="numba-cuda finds no CUDA GPU"):
        simulate_batch(scenes.block(1.0, 6.0), [sine_pulse(2.0, 0.5)], 0.1, device="gpu")


def test_the_gpu_refused_without_numba_cuda_says_to_install_the_extra(monkeypatch):
    """numba's own numba.cuda imports without the GPU extra: the refusal names what is missing."""
    import dem_core.batch as batch_module

    monkeypatch.setattr(batch_module, "gpu_available", lambda: "")
    monkeypatch.setattr(batch_module, "numba_cuda_installed", lambda: False)
    with pytest.raises(ValueError, match=r"numba-cuda, the GPU extra, is not installed \(pip install -e '\.\[gpu\]'"):
        simulate_batch(scenes.block(1.0, 6.0), [sine_pulse(2.0, 0.5)], 0.1, device="gpu")
    monkeypatch.setattr(batch_module, "numba_cuda_installed", lambda: True)
    with pytest.raises(ValueError, match="numba-cuda finds no CUDA GPU here"):
        simulate_batch(scenes.block(1.0, 6.0), [sine_pulse(2.0, 0.5)], 0.1, device="gpu")


#: run by numba's CUDA simulator (with the CPU's JIT off, so that the simulator's arrays reach the stages): the
#: CUDA kernels through simulate_batch, two members of a block (a pulse and a scaled record) and a stack of three by
#: central differences, and two members of the stack by Moreau-Jean; and one member's blank written out on the
#: device for five
SIMULATED = """
import json, sys
import numpy as np
from numba import cuda
from dem_core.batch_gpu import _repeated_on_device
from dem_core.inputs.excitation import sine_pulse
MOREAU_MOTIONS = [sine_pulse(6.0, 0.1), sine_pulse(9.0, 0.08)]
BARRED = lambda: scenes.column(3, connectors=[(titanium_bar(), "all"), (OAK_POLOS, "capital")])
import dem_core
from dem_core import scenes, simulate_batch
from dem_core.inputs.connectors import OAK_POLOS, titanium_bar
from dem_core.inputs.excitation import record, scaled, sine_pulse
from dem_core.batch import GPU_MEMBERS_PER_THREAD
assert GPU_MEMBERS_PER_THREAD > 1
few = simulate_batch(scenes.block(1.0, 6.0), [sine_pulse(3.0, 0.2)], 0.01, device="auto", threads=1,
                     integrator="explicit")
seen = []
dem_core.batch.GPU_MEMBERS_PER_THREAD = 2  # two members on one thread fill the simulated GPU
block = simulate_batch(scenes.block(1.0, 6.0), [sine_pulse(3.0, 0.2), scaled(record("el_centro_1940"), 4.0)], 0.1,
                       device="auto", threads=1, histories=[1], measures=lambda result: {"outputs": len(result.t)},
                       progress=lambda done, total: seen.append((done, total)), integrator="explicit")
stack = simulate_batch(scenes.stack([(0.8, 1.0), (0.7, 0.9), (0.6, 0.8)]), [sine_pulse(6.0, 0.1)], 0.01,
                       device="gpu", integrator="explicit")
def interrupt(done, total):
    raise KeyboardInterrupt
try:  # the short pulse's member ends within the first chunk, the other does not
    simulate_batch(scenes.block(1.0, 6.0), [sine_pulse(3.0, 0.005), sine_pulse(3.0, 0.2)], device="gpu",
                   progress=interrupt, integrator="explicit")
except dem_core.batch.BatchInterrupted as stopped:
    finished = stopped.partial.table["member"].tolist()
moreau = simulate_batch(scenes.stack([(0.8, 1.0), (0.7, 0.9), (0.6, 0.8)]), MOREAU_MOTIONS, 0.05, device="gpu",
                        integrator="moreau")
bars = simulate_batch(BARRED(), MOREAU_MOTIONS[:1], 0.03, device="gpu", integrator="moreau")
blank = np.arange(6.0).reshape(2, 3)
json.dump({"repeated": [np.array_equal(row, blank) for row in _repeated_on_device(blank, 5, cuda).copy_to_host()],
           "devices": [few.device, block.device, stack.device, moreau.device, bars.device], "finished": finished,
           "kept": list(block.histories), "progress": seen[-1], "kept_owns": block.histories[1].theta.base.ndim == 3,
           **{name: batch.table.drop(columns="wall_time_s").to_dict("list")
              for name, batch in (("block", block), ("stack", stack), ("moreau", moreau), ("bars", bars))}},
          sys.stdout)
"""


def test_the_cuda_kernel_under_the_simulator_gives_the_cpus_rows():
    env = dict(os.environ, NUMBA_ENABLE_CUDASIM="1", NUMBA_DISABLE_JIT="1", PYTHONPATH=str(REPOSITORY))
    done = subprocess.run([sys.executable, "-c", SIMULATED], capture_output=True, text=True, env=env, timeout=600)
    assert done.returncode == 0, done.stderr[-3000:]
    simulated = json.loads(done.stdout)
    # auto takes the GPU for a batch of many members per CPU thread, not for one member
    assert simulated["devices"] == ["cpu, 1 thread"] + ["gpu, CUDA simulator"] * 4
    assert simulated["kept"] == [1] and simulated["progress"] == [2, 2]
    # theta is a slice of the kept run's outputs: its base is them, (rows, bodies, 3), if they are its own, and the
    # batch's (members, rows, bodies, 3) if they are a view (memory cannot be compared across the JSON)
    assert simulated["kept_owns"]
    assert simulated["finished"] == [0]  # Ctrl-C: the member that ended is handed back
    assert simulated["repeated"] == [True] * 5  # one member's blank written out on the device, doubling its rows
    block = simulate_batch(scenes.block(1.0, 6.0), [sine_pulse(3.0, 0.2), scaled(EL_CENTRO, 4.0)], 0.1, device="cpu",
                           measures=lambda result: {"outputs": len(result.t)},
                           integrator="explicit").table.drop(columns="wall_time_s")
    stack = simulate_batch(scenes.stack([(0.8, 1.0), (0.7, 0.9), (0.6, 0.8)]), [sine_pulse(6.0, 0.1)], 0.01,
                           device="cpu", integrator="explicit").table.drop(columns="wall_time_s")
    moreau = simulate_batch(scenes.stack([(0.8, 1.0), (0.7, 0.9), (0.6, 0.8)]),
                            [sine_pulse(6.0, 0.1), sine_pulse(9.0, 0.08)], 0.05, device="cpu",
                            integrator="moreau").table.drop(columns="wall_time_s")
    # a column held by titanium bars at its joints and an oak pole at its capital (section 1.12's connectors)
    bars = simulate_batch(scenes.column(3, connectors=[(titanium_bar(), "all"), (OAK_POLOS, "capital")]),
                          [sine_pulse(6.0, 0.1)], 0.03, device="cpu", integrator="moreau").table
    assert "peak_connector_shear_N" in bars.columns and bars["peak_connector_shear_N"][0] > 0.0
    for name, cpu in (("block", block), ("stack", stack), ("moreau", moreau),
                      ("bars", bars.drop(columns="wall_time_s"))):
        gpu = simulated[name]
        assert list(gpu) == list(cpu.columns)
        for column in cpu.columns:
            if cpu[column].dtype.kind == "f":
                np.testing.assert_allclose(np.array(gpu[column], float), cpu[column].to_numpy(float), rtol=1e-9,
                                           atol=0.0, err_msg=f"{name} {column}")
            else:
                assert gpu[column] == cpu[column].tolist(), f"{name} {column}"
    # the pulses lifted the blocks (a block at rest settles on its springs by about 1e-6 rad): not a comparison of rest
    assert max(block["max_peak_abs_theta_rad"]) > 1e-4 and max(moreau["max_peak_abs_theta_rad"]) > 1e-4


def _device_check(tmp_path, *options) -> subprocess.CompletedProcess:
    """``python -m comparisons gpu-check --smoke OPTIONS`` (two members a case, 0.05 s each) through numba's CUDA
    simulator, its files in ``tmp_path``."""
    env = dict(os.environ, NUMBA_ENABLE_CUDASIM="1", NUMBA_DISABLE_JIT="1", PYTHONPATH=str(REPOSITORY))
    return subprocess.run([sys.executable, "-m", "comparisons", "gpu-check", "--smoke", "--out", str(tmp_path),
                           *options], capture_output=True, text=True, env=env, timeout=600, cwd=tmp_path, check=False)


def test_the_device_check_runs_every_section_under_the_simulator(tmp_path):
    """Every section prints its lines, in the order ``--sections`` gives, none fails, and the fine scan writes its
    table."""
    order = ("device", "throughput", "fragility", "fine", "agreement", "agreement-other", "throughput-other", "scaling")
    done = _device_check(tmp_path, "--sections", *order)
    assert done.returncode == 0, done.stderr[-3000:]
    ended = [done.stdout.find(f"| {section:16s} | section's wall time") for section in order]
    assert -1 not in ended and ended == sorted(ended), done.stdout
    assert "FAILED" not in done.stdout and "cut at" not in done.stdout, done.stdout + done.stderr[-3000:]
    assert "| agreement        | column, moreau: put off to agreement-other" in done.stdout  # no reference
    assert "| agreement-other  | column, moreau: steady members within 1e-9" in done.stdout
    scanned = pd.read_csv(tmp_path / "fine_scan.csv")
    assert len(scanned) == 1 and scanned["runs"][0] > 1


@pytest.mark.slow
def test_the_device_check_takes_the_cpus_side_run_ahead_where_it_is_for_its_members(tmp_path):
    """``gpu-reference`` run here (compiled) at the smoke check's members: the check under the simulator takes each
    case's CPU side from it, naming the machine, and its members agree; a case whose key is not the file's is put off
    to agreement-other and compared there once, and a file that is not a reference is named and not used (with no
    agreement-other to come, the marked cases' CPU side runs in agreement)."""
    from comparisons.__main__ import main
    from comparisons.benchmarks import gpu_reference
    from comparisons.benchmarks.record_members import CASES, MARKED_CASES
    from dem_core.analyses.run_identity import machine

    reference = tmp_path / "agreement.json"
    main(["gpu-reference", "--sample", "2", "--duration", "0.05", "--out", str(reference)])
    cases, made = gpu_reference.load(reference)
    assert len(cases) == len(CASES) and made["machine"] == machine()
    done = _device_check(tmp_path, "--cpu-reference", str(reference), "--sections", "agreement", "agreement-other")
    assert done.returncode == 0, done.stderr[-3000:]
    for name, integrator in CASES:
        section = "agreement" if (name, integrator) in MARKED_CASES else "agreement-other"
        assert f"| {section:16s} | {name}, {integrator}: the CPU's side" in done.stdout
        # in 0.05 s only the explicit members rise above round-off; Moreau-Jean's peaks there move with the nudge
        steady = "2 of 2" if integrator == "explicit" else "0 of 0"
        assert re.search(rf"\| {name}, {integrator}: steady members within 1e-9 +\| {steady} \(of 2\) +\| met",
                         done.stdout), done.stdout
    assert done.stdout.count("run ahead (cpu, ") == len(CASES), done.stdout
    assert done.stdout.count(f"run on {machine()}, numpy ") == 1, done.stdout

    written = json.loads(reference.read_text(encoding="utf-8"))
    written["cases"][0]["key"] = "another"
    reference.write_text(json.dumps(written), encoding="utf-8")
    done = _device_check(tmp_path, "--cpu-reference", str(reference), "--sections", "agreement", "agreement-other")
    assert done.returncode == 0, done.stderr[-3000:]
    name, integrator = CASES[0]
    put_off = done.stdout.index(f"| agreement        | {name}, {integrator}: put off to agreement-other")
    ran = re.search(rf"\| agreement-other +\| {name}, {integrator}: the CPU's side +\| run here \(the reference is "
                    rf"for other code or members\)", done.stdout)
    assert ran and put_off < ran.start(), done.stdout
    assert done.stdout.count(f"{name}, {integrator}: the CPU's side") == 1, done.stdout
    assert re.search(rf"\| agreement-other +\| {name}, {integrator}: steady members within 1e-9 +\| (\d) of \1 "
                     rf"\(of 2\) +\| met", done.stdout), done.stdout
    assert done.stdout.count("run ahead (") == len(CASES) - 1, done.stdout

    reference.write_text("{}", encoding="utf-8")
    done = _device_check(tmp_path, "--cpu-reference", str(reference), "--sections", "agreement")
    assert done.returncode == 0 and "is not a CPU reference" in done.stdout, done.stdout + done.stderr[-3000:]
    assert "put off" not in done.stdout and done.stdout.count("run here") == 2, done.stdout  # no agreement-other


def test_the_device_check_cuts_a_study_at_its_budget_and_goes_on(tmp_path):
    """A budget spent during the fragility study (whose members stop with the study's own interruption, not a
    batch's) cuts that section and leaves the next to run: on an H200 it ended the whole check with a traceback."""
    done = _device_check(tmp_path, "--budget", "0", "--sections", "fragility", "fine")
    assert done.returncode == 0 and "Traceback" not in done.stderr, done.stderr[-3000:]
    assert re.search(r"\| fragility +\| \d+ runs +\| cut at the budget's end", done.stdout), done.stdout
    assert "| fine             | section's wall time" in done.stdout, done.stdout
