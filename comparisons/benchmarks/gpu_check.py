"""The GPU path measured on the machine it runs on: the device check, one table, within a time budget.

    python -m comparisons gpu-check [--budget 450] [--out DIR]

Run it first on a machine with an NVIDIA GPU (``.ci/gpu-check`` installs the carried wheels and runs it).  Its
sections, in this order unless ``--sections`` names others, each printing its lines as it ends, and each stopped
where the budget's end comes first (the table says which were cut):

1. device: the GPU, its compute capability, the driver, the versions of numpy, numba and numba-cuda, and each
   integrator's kernel as compiled for this GPU (registers and local memory per thread).
2. scaling: the block by central differences and the column by Moreau-Jean (2 s of El Centro) on a few
   multiprocessors, a block of threads on each, a block of fewer threads on each (whose members' working sets fit
   its L1 cache) and (the block) as many threads as they hold: the time of one thread's step at each load, which
   says whether the kernel waits on latency, on bandwidth, or on where its reads find their bytes.
3. agreement: ``--sample`` members of the 1 x 6 m block by central differences and of the 8-drum column by
   Moreau-Jean (the issue's marked cases) under El Centro, scaled evenly from 1.2 to 3 times g tan(alpha), on the
   GPU and on the CPU's threads.  A member whose CPU run moves by less than 1e-10 when its scale moves by 1e-12 is
   not chaotic, and its GPU peak must be within 1e-9 of the CPU's; the medians of the peak theta/alpha over the
   members must lie within each other's 90% bootstrap intervals (members drawn again).  And how many times as long
   a GPU thread takes for a member's step as a CPU core, the ratio that ``simulate_batch(device="auto")`` rests on.
   The CPU's side is taken from ``--cpu-reference`` where that file was run ahead for this code and these members
   (``python -m comparisons gpu-reference``; its line names the machine it ran on); a case it lacks is put off to
   ``agreement-other`` where that section runs later, and otherwise runs here, the CPU's kernels compiled first
   (minutes on a fresh machine).
4. throughput: the block (``--block-members``, 65,536) and the column (``--column-members``, 4,096) under
   ``--duration`` s of El Centro, at the integrator's automatic step: the kernels' member-steps per second, the
   members' set-up and the whole batch's time (the set-up, the packing of the members' arrays, their copies to
   and from the GPU and the kernel), and, with ``--cpu-members``, the CPU's threads on as many of the same members.
   The issue's marked cases run here; the other two (``throughput-other``) run last.
5. fragility: the committed study (examples/studies/fragility.py: the bundled default column, the demonstration
   suite's 40 motions x 40 stripes, each followed by 10 s at rest, Moreau-Jean) on the GPU: its time and its
   overturning median.
6. fine scan: the first overturn of each of record_overturning's 28 systems (examples/studies/record_overturning.py:
   columns of 1 to 3 drums and colonnades of 1, 2, 3 and 5 drums under the four records), every 0.02 m/s^2 from
   its lowest PGA to its cap, one GPU batch a system: the time, and ``fine_scan.csv`` in ``--out``.
7. agreement-other: the agreement of the cases put off and of the block by Moreau-Jean and the column by central
   differences (the GPU's slowest case by far).
8. throughput-other: the block by Moreau-Jean and the column by central differences, as in 4.

The issue's marks (H100 or H200): the block by central differences at least 1e10 member-steps/s; the column's 4,096
members by Moreau-Jean in at most 10 s; the fragility study in at most 60 s; the fine scan in at most 10 minutes.
"""

import argparse
import importlib
import os
import sys
import time
import traceback
from importlib import metadata
from pathlib import Path

import numpy as np
import pandas as pd

import dem_core
from dem_core import scenes
from dem_core.analyses.study_members import MembersInterrupted
from dem_core.batch import BatchInterrupted, simulate_batch
from dem_core.batch_gpu import gpu_available, run_members
from dem_core.cli.arguments import SECONDS, WORKERS
from dem_core.gpu_kernels import ENVIRONMENT, load_named_kernels
from dem_core.engine.settings import INTEGRATORS
from dem_core.engine.state import STEP
from dem_core.simulation import Simulation, set_up_scene

from . import gpu_reference
from .gpu_reference import STEADY, cpu_side, members_key, peaks
from .record_members import MARKED_CASES, OTHER_CASES, RECORD, SCENES, ignore_the_cut_strong_motion, motions

STUDIES = Path(__file__).resolve().parents[2] / "examples" / "studies"
#: a steady member's GPU peak is within this (relative) of its CPU peak
AGREEMENT = 1e-9
#: the sections in the order they run: what decides the kernel's design first, the marked cases' agreement, the
#: issue's marks, then the other cases (the column by central differences is the GPU's slowest by far)
SECTION_ORDER = ("device", "scaling", "agreement", "throughput", "fragility", "fine", "agreement-other",
                 "throughput-other")
#: s of every run under --smoke (the record's whole length otherwise, where a study runs it)
SMOKE_DURATION = 0.05
#: motions of the fragility study's suite run under --smoke
SMOKE_RECORDS = 2
#: the issue's marks
MARKS = {"block explicit member-steps/s": 1e10, "column moreau batch s": 10.0, "fragility s": 60.0,
         "fine scan s": 600.0}


def arguments(parser: argparse.ArgumentParser) -> None:
    """The options of its subcommand of ``python -m comparisons``."""
    parser.add_argument("--budget", type=float, default=450.0, help="s for every section together (default 450)")
    parser.add_argument("--out", default=".",
                        help="folder for fine_scan.csv and each section's gpu_check_<section>.csv (default: here)")
    parser.add_argument("--sample", type=WORKERS, default=gpu_reference.SAMPLE,
                        help=f"members of each agreement check (default {gpu_reference.SAMPLE})")
    parser.add_argument("--cpu-reference", default=None,
                        help="the agreement's CPU side run ahead (`python -m comparisons gpu-reference`): its cases "
                             "are taken where they are for this code and these members; a marked case it lacks is "
                             "put off to agreement-other where that runs later, and run here otherwise")
    parser.add_argument("--block-members", type=int, default=65536)
    parser.add_argument("--column-members", type=int, default=4096)
    parser.add_argument("--cpu-members", type=int, default=0,
                        help="members of the CPU's throughput beside the GPU's (default 0: none; the CPU's threaded "
                             "kernel compiles first, minutes on a fresh machine; the agreement section measures a GPU "
                             "thread against a CPU core in any case)")
    parser.add_argument("--duration", type=SECONDS, default=gpu_reference.DURATION,
                        help=f"s of El Centro (default {gpu_reference.DURATION:g})")
    parser.add_argument("--stripes", type=int, default=None, help="the fragility study's stripes (default its own)")
    parser.add_argument("--systems", type=int, default=None, help="the fine scan's first N systems (default all)")
    parser.add_argument("--fine-step", type=float, default=None, help="m/s^2 (default the study's 0.02)")
    parser.add_argument("--smoke", action="store_true",
                        help="two members a case, 0.05 s each: the check itself tested under numba's CUDA simulator")
    parser.add_argument("--sections", nargs="+", choices=SECTION_ORDER, default=list(SECTION_ORDER),
                        help="the sections to run, in the order given (default: all, in the order above)")


class OverBudget(KeyboardInterrupt):
    """Raised from a batch's progress when the check's budget is spent: the batch stops as Ctrl-C stops it."""


class Clock:
    """The check's budget: ``left()`` s, and ``progress`` for a batch, which stops it at the budget's end."""

    def __init__(self, budget: float):
        self.end = time.perf_counter() + budget

    def left(self) -> float:
        return self.end - time.perf_counter()

    def progress(self, done: int, total: int) -> None:
        if self.left() <= 0:
            raise OverBudget


def _line(section: str, item: str, value: str, mark: str = "") -> None:
    print(f"| {section:16s} | {item:50s} | {value:44s} | {mark:16s} |", flush=True)


def _marked(name: str, value: float, higher_is_better: bool = False) -> str:
    target = MARKS[name]
    met = value >= target if higher_is_better else value <= target
    return f"{'met' if met else 'NOT met'} ({target:g})"


def device_section(args, clock: Clock) -> None:
    from numba import cuda

    from dem_core.engine._members import KERNELS

    _line("device", "GPU", gpu_available() or "none found by numba-cuda")
    for name in ("numpy", "numba", "numba-cuda"):
        _line("device", name, _version(name))
    if not cuda.is_available():
        return
    device = cuda.get_current_device()
    _line("device", "compute capability", ".".join(str(c) for c in device.compute_capability))
    try:
        driver = cuda.cudadrv.driver.driver.get_version()
        _line("device", "CUDA driver", ".".join(str(v) for v in driver))
    except Exception as error:  # noqa: BLE001 (the simulator has no driver)
        _line("device", "CUDA driver", type(error).__name__)
    ahead = load_named_kernels()
    _line("device", "kernels", f"{', '.join(ahead)} compiled ahead, from {os.environ[ENVIRONMENT]}" if ahead
          else "compiled here, at the first batch")
    for name, kernel in zip(INTEGRATORS, KERNELS):
        began = time.perf_counter()
        simulate_batch(scenes.block(1.0, 6.0), motions(1.0 / 6.0, 1), 0.01, device="gpu", integrator=name)
        _line("device", f"{name} kernel: first batch (its build), s", f"{time.perf_counter() - began:.1f}")
        try:
            built = next(iter(kernel.overloads.values()))
            _line("device", f"{name} kernel, per thread",
                  f"{built.regs_per_thread} registers, {built.local_mem_per_thread} B local memory")
        except Exception as error:  # noqa: BLE001 (the simulator compiles nothing)
            _line("device", f"{name} kernel, per thread", type(error).__name__)


def _version(name: str) -> str:
    try:
        return metadata.version(name)
    except metadata.PackageNotFoundError:
        return "-"


def _median_interval(values: np.ndarray, rng, samples: int = 2000) -> tuple:
    drawn = rng.choice(values, size=(samples, len(values)), replace=True)
    medians = np.median(drawn, axis=1)
    return float(np.median(values)), float(np.quantile(medians, 0.05)), float(np.quantile(medians, 0.95))


def _cpu_reference(path) -> dict:
    """The cases by key of ``--cpu-reference`` (:func:`gpu_reference.load`), with a line naming the machine they
    ran on; none where it is not given, and none with a line saying why where it cannot be used."""
    if path is None:
        return {}
    try:
        cases, made = gpu_reference.load(path)
    except ValueError as error:
        _line("agreement", "CPU reference not used", str(error))
        return {}
    _line("agreement", "CPU reference", f"{path}: run on {made['machine']}, numpy {made['numpy']}, "
          f"numba {made['numba']}")
    return cases


def agreement_section(args, clock: Clock, section: str = "agreement", cases=MARKED_CASES) -> None:
    """Each of ``cases`` on the GPU against its CPU side: from ``args.reference`` (:func:`_cpu_reference`) where it
    has the case; else, in ``agreement`` where ``agreement-other`` runs after it (``args.other_later``), put off to
    that section (``args.put_off``), since the CPU's kernels would compile first, minutes of device time ahead of
    the issue's marks; else run here.  Its lines carry ``section``'s name."""
    rng = np.random.default_rng(0)
    for name, integrator in cases:
        cpu = args.reference.get(members_key(name, integrator, args.sample, args.duration))
        if cpu is None and section == "agreement" and args.other_later:
            args.put_off.append((name, integrator))
            _line(section, f"{name}, {integrator}: put off to agreement-other",
                  "no CPU reference for this code and these members (python -m comparisons gpu-reference)")
            continue
        build, tan_alpha = SCENES[name]
        alpha = float(np.arctan(tan_alpha))
        gpu = simulate_batch(build(), motions(tan_alpha, args.sample), args.duration, device="gpu",
                             integrator=integrator, progress=clock.progress, **gpu_reference.OPTIONS)
        if cpu is not None:
            where = f"run ahead ({cpu['device']})"
        else:
            cpu = cpu_side(name, integrator, args.sample, args.duration, progress=clock.progress)
            where = "run here" + (" (the reference is for other code or members)" if args.reference else "")
        on_gpu, on_cpu, moved = peaks(gpu, alpha), np.array(cpu["peaks"]), np.array(cpu["nudged"])
        steady = np.abs(moved - on_cpu) <= STEADY * np.abs(on_cpu)
        within = int(np.sum(np.abs(on_gpu - on_cpu)[steady] <= AGREEMENT * np.abs(on_cpu)[steady]))
        g, c = _median_interval(on_gpu, rng), _median_interval(on_cpu, rng)
        overlap = g[1] <= c[0] <= g[2] and c[1] <= g[0] <= c[2]
        _line(section, f"{name}, {integrator}: the CPU's side", where)
        _line(section, f"{name}, {integrator}: steady members within 1e-9",
              f"{within} of {int(steady.sum())} (of {len(on_cpu)})",
              "met" if within == int(steady.sum()) else "NOT met")
        _line(section, f"{name}, {integrator}: median theta/alpha GPU, CPU",
              f"{g[0]:.4f} ({g[1]:.4f}-{g[2]:.4f}), {c[0]:.4f}", "met" if overlap else "NOT met")
        _line(section, f"{name}, {integrator}: a GPU thread's step against a CPU core's",
              f"{_thread_against_core(gpu, cpu):.3g} times as long")


def _thread_against_core(gpu, cpu: dict) -> float:
    """How many times as long a GPU thread takes for a member's step as a CPU core, from one batch of the same
    members on each (``cpu``: :func:`gpu_reference.cpu_side`'s): the GPU's members run at once (its time is its
    longest member's), the CPU's on its threads, a member each at a time (its time is all their steps over its
    threads)."""
    steps = np.array(cpu["steps"], float)
    return (gpu.wall_time_s / steps.max()) / (cpu["wall_time_s"] * cpu["threads"] / steps.sum())


def _set_up_members(scene, integrator: str, tan_alpha: float, members: int, duration: float) -> list:
    """``members`` runs of ``scene`` under the record's :func:`motions` for ``duration`` s, set up on the CPU as a
    batch sets them up (the scene's set-up shared) and not yet stepped."""
    shared = set_up_scene(scene, integrator=integrator)
    return [Simulation(scene, motion, duration, scene_set_up=shared, integrator=integrator)
            for motion in motions(tan_alpha, members)]


def throughput_section(args, clock: Clock, cases=MARKED_CASES) -> list:
    rows = []
    for name, integrator in cases:
        build, tan_alpha = SCENES[name]
        members = args.block_members if name == "block" else args.column_members
        if clock.left() <= 0:
            _line("throughput", f"{name}, {integrator}", "not run: the budget is spent")
            continue
        scene = build()
        began = time.perf_counter()
        runs = _set_up_members(scene, integrator, tan_alpha, members, args.duration)
        set_up = time.perf_counter() - began
        cut = ""
        try:
            kernel = run_members(runs, progress=clock.progress)
        except OverBudget:
            kernel, cut = time.perf_counter() - began - set_up, " (cut at the budget)"
        whole = time.perf_counter() - began  # with the members' packing and their copies to and from the GPU
        steps = sum(int(run.state.counters[STEP]) for run in runs)
        rate = steps / kernel
        cpu_rate, versus = np.nan, "the CPU not run (--cpu-members 0)"
        if args.cpu_members:
            cpu = simulate_batch(scene, motions(tan_alpha, args.cpu_members), args.duration, device="cpu",
                                 integrator=integrator)
            cpu_rate = cpu.table["steps"].sum() / cpu.wall_time_s
            versus = f"{rate / cpu_rate:.2f} of {cpu.device}"
        mark = ""
        if name == "block" and integrator == "explicit":
            mark = _marked("block explicit member-steps/s", rate, higher_is_better=True)
        if name == "column" and integrator == "moreau":
            mark = _marked("column moreau batch s", whole)
        _line("throughput", f"{name}, {integrator}, M={members}: member-steps/s",
              f"{rate:.3g}{cut}", mark)
        _line("throughput", f"{name}, {integrator}: set-up s, kernel s, all s; GPU/CPU",
              f"{set_up:.1f}, {kernel:.1f}, {whole:.1f}; {versus}")
        rows.append({"scene": name, "integrator": integrator, "members": members, "member_steps": steps,
                     "set_up_s": set_up, "kernel_s": kernel, "whole_s": whole, "cut": bool(cut),
                     "cpu_member_steps_per_s": cpu_rate})
    return rows


#: the scaling section's cases and their loads: (threads a block, blocks a multiprocessor).  At 64 threads a block, a
#: block on a few multiprocessors, one on each and as many as they hold at 255 registers a thread (four); and one
#: block a multiprocessor of fewer threads, whose members' working sets (docs/performance.md, "What a thread's step
#: waits on") fit its L1 cache
SCALING = {("block", "explicit"): ((64, 1 / 32), (16, 1), (64, 1), (64, 4)),
           ("column", "moreau"): ((64, 1 / 32), (8, 1), (64, 1))}
#: s of El Centro in each of the scaling section's batches
SCALING_DURATION = 2.0


def scaling_section(args, clock: Clock) -> list:
    """Each case of :data:`SCALING` at each of its loads: the time of one thread's step.  The same time at every
    load says a thread waits on its own chain of memory accesses (latency); a time that grows with the load says
    the threads share a limit (bandwidth); one that falls where a multiprocessor's members' working sets fit its L1
    cache says the reads wait on the L2 cache or the memory beyond it."""
    from numba import cuda

    from dem_core.batch_gpu import cuda_launcher

    sms = getattr(cuda.get_current_device(), "MULTIPROCESSOR_COUNT", 1)  # none on the simulator's device
    duration = SMOKE_DURATION if args.smoke else SCALING_DURATION
    rows = []
    for (name, integrator), loads in SCALING.items():
        build, tan_alpha = SCENES[name]
        scene = build()
        for threads, blocks in loads:
            members = 2 if args.smoke else round(blocks * sms * threads)
            runs = _set_up_members(scene, integrator, tan_alpha, members, duration)
            kernel = run_members(runs, progress=clock.progress, launcher=cuda_launcher(threads))
            steps = sum(int(run.state.counters[STEP]) for run in runs) / members
            _line("scaling", f"{name}, {integrator}, M={members}, {threads} a block, {sms} multiprocessors",
                  f"{kernel / steps * 1e6:.3g} us a step a thread")
            rows.append({"scene": name, "integrator": integrator, "members": members, "threads_per_block": threads,
                         "multiprocessors": sms, "steps_per_member": steps, "kernel_s": kernel})
    return rows


def _study(name: str):
    if str(STUDIES) not in sys.path:
        sys.path.insert(0, str(STUDIES))
    return importlib.import_module(name)


def fragility_section(args, clock: Clock) -> None:
    from dem_core.analyses.fragility_study import fragility_study, stripes
    from dem_core.cli import default_scene_path
    from dem_core.inputs.scene_file import load

    study = _study("fragility")
    records = study.suite()
    if args.smoke:  # the suite's first two motions
        records = dict(list(records.items())[:SMOKE_RECORDS])
    levels = stripes(args.stripes or study.LEVELS, study.TOP)
    began = time.perf_counter()
    try:
        done = fragility_study(load(default_scene_path()).scene, records, levels, study.STATES, device="gpu",
                               duration=SMOKE_DURATION if args.smoke else None, progress=clock.progress,
                               residual=None if args.smoke else study.RESIDUAL, **study.OPTIONS)
    except (BatchInterrupted, MembersInterrupted):  # a study's members stop as its batches do
        _line("fragility", f"{len(records) * len(levels)} runs", "cut at the budget's end", "NOT met")
        return
    took = time.perf_counter() - began
    _line("fragility", f"{len(done.runs)} runs ({done.device[:30]})", f"{took:.1f} s", _marked("fragility s", took))
    _line("fragility", "overturning median, m/s^2 (90% band)", study.median_text(done.fits[1.0]))


def fine_section(args, clock: Clock) -> None:
    study = _study("record_overturning")
    step = args.fine_step or study.FINE_STEP
    systems = [(record, kind, n, scene) for record in dem_core.records.BUNDLED
               for kind, n, scene in study.study_scenes()][:args.systems]
    rows, began = [], time.perf_counter()
    for record, kind, n, scene in systems:
        pgas = np.arange(study.LOW, study.CAP[record] + step / 2, step)
        motion_at = study.motion(record, study.COMPONENT.get(record))
        try:
            batch = simulate_batch(scene, [motion_at(p) for p in pgas], SMOKE_DURATION if args.smoke else None,
                                   device="gpu", output_dt=0.05,
                                   progress=clock.progress)
        except BatchInterrupted:
            break
        table = batch.table
        overturned = table["overturned"].to_numpy(bool) & (table["status"] == "ok").to_numpy()
        rows.append({"kind": kind, "n_drums": n, "record": record, "runs": len(pgas),
                     "unstable": int((table["status"] != "ok").sum()),
                     "first_overturn_pga": float(pgas[overturned][0]) if overturned.any() else np.nan,
                     "wall_time_s": batch.wall_time_s})
    took = time.perf_counter() - began
    out = Path(args.out) / "fine_scan.csv"
    pd.DataFrame(rows).to_csv(out, index=False)
    finished = f"{len(rows)} of {len(systems)} systems"
    _line("fine scan", f"{finished}, {sum(r['runs'] for r in rows)} runs, {step:g} m/s^2",
          f"{took:.1f} s", _marked("fine scan s", took) if len(rows) == len(systems) else "NOT met (cut)")
    _line("fine scan", "first overturns", f"in {out}")


SECTIONS = {"device": device_section, "agreement": agreement_section, "throughput": throughput_section,
            "throughput-other": lambda args, clock: throughput_section(args, clock, OTHER_CASES),
            "agreement-other": lambda args, clock: agreement_section(args, clock, "agreement-other",
                                                                     [*args.put_off, *OTHER_CASES]),
            "fragility": fragility_section, "fine": fine_section, "scaling": scaling_section}


def run(args: argparse.Namespace) -> None:
    """Run with the options of :func:`arguments` and print the table."""
    if not gpu_available():
        raise SystemExit("gpu-check: numba-cuda finds no GPU here (nothing to check; tests/test_cuda_build.py builds "
                         "the kernels for sm_90 without one)")
    if args.smoke:
        args.sample = args.block_members = args.column_members = args.cpu_members = args.stripes = 2
        args.duration, args.systems, args.fine_step = SMOKE_DURATION, 1, 1.0
    Path(args.out).mkdir(parents=True, exist_ok=True)
    load_named_kernels()  # before any section: the throughput's batches are launched without simulate_batch
    clock = Clock(args.budget)
    ignore_the_cut_strong_motion()
    print(f"gpu-check, budget {args.budget:g} s, {args.duration:g} s of {RECORD}", flush=True)
    _line("section", "item", "value", "issue's mark")
    order = list(dict.fromkeys(args.sections))
    args.reference = _cpu_reference(args.cpu_reference) if {"agreement", "agreement-other"} & set(order) else {}
    args.other_later = ("agreement" in order and "agreement-other" in order
                        and order.index("agreement-other") > order.index("agreement"))
    args.put_off = []
    for name in order:
        began = time.perf_counter()
        try:
            rows = SECTIONS[name](args, clock)
        except (OverBudget, BatchInterrupted, MembersInterrupted):
            _line(name, "cut at the budget's end", "")
            continue
        except Exception as error:  # noqa: BLE001 (one section's failure leaves the others' lines)
            traceback.print_exc()
            _line(name, "FAILED (its traceback above)", f"{type(error).__name__}: {error}"[:44])
            continue
        if rows:
            pd.DataFrame(rows).to_csv(Path(args.out) / f"gpu_check_{name}.csv", index=False)
        _line(name, "section's wall time", f"{time.perf_counter() - began:.1f} s")
