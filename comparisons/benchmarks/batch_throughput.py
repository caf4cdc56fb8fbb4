"""Batch throughput on this machine: member-runs per second of one scene under many amplitudes of a record, through
``dem_core.simulate_batch`` on one thread and on all, against a loop of ``simulate`` calls and against pymunk on one
process per core, measured in the same run.

Members: the 1 x 6 m block, or the 8-drum column (6 m x 1 m), under ``--duration`` s of the 1940 El Centro record
scaled evenly from 1.2 to 3 times the scene's rocking threshold g tan(alpha) (the spread of the report's
ensembles).  For each scene, integrator and batch size M it prints the wall time, member-runs and member-steps per
second, and the speed-up over one thread.  The loop of ``simulate`` (one thread) runs where M is at most
``--loop-up-to``, and then every member's peak |theta| is compared with the batch's (they are the same runs, bit
for bit).  pymunk (1e-3 s, the report's step) runs the same members on a process per core where M is at most
``--peers-up-to``, beside the batch with ``stop_at_overturn=False``: pymunk runs every member to the end.  Up to
``--loop-up-to`` each timing is the least of ``--repeats``.  Where numba-cuda finds a GPU, the explicit integrator's
members also run there (``device="gpu"``, its wall time including the members' set-up on the CPU), and the line
gives the largest relative difference of a member's peak from the CPU's; the header says when there is none.  Up to
``--loop-up-to`` the GPU kernel's code also runs on one CPU thread (``dem_core.batch_gpu.serial_launcher``), its
members' set-up included, against the batch on one thread: what the GPU path costs a member besides the GPU.

    python -m comparisons batch-throughput [--scenes block column] [--integrators moreau explicit] \
        [--members 1 64 4096 65536] [--duration 20]
"""

import argparse
import math
import os
import time
import warnings
from concurrent.futures import ProcessPoolExecutor

import numba
import numpy as np

import adapters
import dem_core
from dem_core.batch import simulate_batch
from dem_core.batch_gpu import gpu_available, run_members, serial_launcher
from dem_core.simulation import Simulation, set_up_scene

from .record_members import HIGHEST, LOWEST, RECORD, SCENES, motions

def arguments(parser: argparse.ArgumentParser) -> None:
    """The options of its subcommand of ``python -m comparisons``."""
    parser.add_argument("--scenes", nargs="+", choices=tuple(SCENES), default=list(SCENES))
    parser.add_argument("--integrators", nargs="+", choices=dem_core.simulation.INTEGRATORS,
                        default=["moreau", "explicit"])
    parser.add_argument("--members", nargs="+", type=int, default=[1, 64, 4096], help="batch sizes M")
    parser.add_argument("--duration", type=float, default=20.0, help="s of the record")
    parser.add_argument("--loop-up-to", type=int, default=64, help="largest M also run as a loop of simulate")
    parser.add_argument("--peers-up-to", type=int, default=64, help="largest M also run in pymunk")
    parser.add_argument("--repeats", type=int, default=3, help="timings of each M up to --loop-up-to, the least kept")


def _pymunk_peak(scene_name: str, motion, duration: float) -> float:
    scene = SCENES[scene_name][0]()
    return float(np.max(adapters.simulate(scene, motion, duration, engine="pymunk", dt=1e-3).peak_theta))


def _installed(module: str) -> bool:
    try:
        __import__(module)
    except ImportError:
        return False
    return True


def _line(label: str, members: int, wall: float, steps: int, one: float | None) -> str:
    ratio = f"{one / wall:8.2f}" if one else f"{'':8s}"
    return (f"  {label:40s} M={members:<6d} {wall:9.2f} s {members / wall:11.1f} runs/s "
            f"{steps / wall:10.3g} member-steps/s {ratio}")


def run(args: argparse.Namespace) -> None:
    """Run with the options of :func:`arguments` and print the results."""
    warnings.simplefilter("ignore")
    cores, threads, gpu = os.cpu_count(), numba.get_num_threads(), gpu_available()
    print(f"batch throughput: {args.duration:g} s of {RECORD} at {LOWEST:g} to {HIGHEST:g} g tan(alpha); {cores} "
          f"cores, numba {threads} threads; GPU: {gpu or 'none found by numba-cuda'}; MJX: "
          f"{'installed, not run here' if _installed('mujoco.mjx') else 'not installed'}")
    print(f"  {'':40s} {'':8s} {'wall':>11s} {'':>16s} {'':>25s} {'vs 1 thread':>8s}")
    for name in args.scenes:
        build, tan_alpha = SCENES[name]
        scene = build()
        for integrator in args.integrators:
            simulate_batch(scene, motions(tan_alpha, 2), 0.2, integrator=integrator, device="cpu")  # compiled
            if gpu and integrator == "explicit":
                simulate_batch(scene, motions(tan_alpha, 2), 0.2, device="gpu", integrator="explicit")
            for members in args.members:
                _measure(name, scene, integrator, motions(tan_alpha, members), args, threads, gpu)


def _timed(function, repeats: int):
    """(least wall time of ``repeats`` calls of ``function``, s; its last value)."""
    best, value = math.inf, None
    for _ in range(repeats):
        started = time.perf_counter()
        value = function()
        best = min(best, time.perf_counter() - started)
    return best, value


def _gpu_code_on_cpu(scene, members_motions, duration: float) -> list:
    """The members set up as simulate_batch sets them up and run by the GPU kernel's code on one CPU thread."""
    shared = set_up_scene(scene, integrator="explicit")
    runs = [Simulation(scene, motion, duration, scene_set_up=shared, integrator="explicit")
            for motion in members_motions]
    run_members(runs, launcher=serial_launcher())
    return runs


def _measure(name, scene, integrator, members_motions, args, threads, gpu: str) -> None:
    members = len(members_motions)
    repeats = args.repeats if members <= args.loop_up_to else 1
    print(f"{name}, {integrator}, M = {members} (best of {repeats}):", flush=True)
    one, single = _timed(lambda: simulate_batch(scene, members_motions, args.duration, integrator=integrator,
                                                device="cpu", threads=1), repeats)
    steps = int(single.table["steps"].sum())
    print(_line("simulate_batch, 1 thread", members, one, steps, one), flush=True)
    if threads > 1:
        wall, spread = _timed(lambda: simulate_batch(scene, members_motions, args.duration, integrator=integrator,
                                                     device="cpu", threads=threads), repeats)
        same = spread.table["max_peak_abs_theta_rad"].equals(single.table["max_peak_abs_theta_rad"])
        print(_line(f"simulate_batch, {threads} threads", members, wall, steps, one)
              + ("" if same else "  PEAKS DIFFER FROM 1 THREAD"), flush=True)
    if gpu and integrator == "explicit":
        wall, on_gpu = _timed(lambda: simulate_batch(scene, members_motions, args.duration, device="gpu",
                                                                    integrator="explicit"), repeats)
        cpu_peaks = single.table["max_peak_abs_theta_rad"].to_numpy()
        differs = np.max(np.abs(on_gpu.table["max_peak_abs_theta_rad"].to_numpy() - cpu_peaks) / cpu_peaks)
        print(_line(f"simulate_batch, GPU ({gpu})", members, wall, steps, one)
              + f"  peaks within {differs:.1e} (relative) of the CPU's", flush=True)
    if integrator == "explicit" and members <= args.loop_up_to:
        wall, runs = _timed(lambda: _gpu_code_on_cpu(scene, members_motions, args.duration), repeats)
        same = all(float(np.max(r.result().peak_theta)) == p
                   for r, p in zip(runs, single.table["max_peak_abs_theta_rad"]))
        print(_line("GPU kernel's code, 1 CPU thread", members, wall, steps, one)
              + f"  peaks {'identical to' if same else 'DIFFER FROM'} the batch's", flush=True)
    if members <= args.loop_up_to:
        wall, loop = _timed(lambda: [dem_core.simulate(scene, m, args.duration, integrator=integrator)
                                     for m in members_motions], repeats)
        same = all(float(np.max(r.peak_theta)) == p for r, p in zip(loop, single.table["max_peak_abs_theta_rad"]))
        print(_line("loop of simulate, 1 thread", members, wall, steps, one)
              + f"  peaks {'identical to' if same else 'DIFFER FROM'} the batch's", flush=True)
    overturned = int(single.table["overturned"].sum())
    print(f"  {overturned} of {members} members overturned (a run stops there)", flush=True)
    if members <= args.peers_up_to and integrator == args.integrators[0]:
        wall, whole = _timed(lambda: simulate_batch(scene, members_motions, args.duration, integrator=integrator,
                                                    device="cpu", threads=threads, stop_at_overturn=False), repeats)
        print(_line(f"simulate_batch, {threads} threads, to the end", members, wall,
                    int(whole.table["steps"].sum()), one)
              + "  (stop_at_overturn=False, as pymunk below)", flush=True)
        workers = os.cpu_count()
        with ProcessPoolExecutor(workers) as pool:
            list(pool.map(_pymunk_peak, [name] * workers, members_motions[:1] * workers, [0.1] * workers))
            wall, _ = _timed(lambda: list(pool.map(_pymunk_peak, [name] * members, members_motions,
                                                   [args.duration] * members)), repeats)
        print(_line(f"pymunk 1e-3 s, {workers} processes", members, wall, members * math.ceil(args.duration / 1e-3),
                    one), flush=True)
