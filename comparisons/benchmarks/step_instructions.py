"""How many instructions a member's step takes, counted on the CPU with valgrind, and what that many allows a GPU.

    python -m comparisons step-instructions --scene block --integrator explicit [--amplitude 2.1] [--duration 20]

One member of the device check's scene (:data:`~comparisons.benchmarks.record_members.SCENES`) runs under El Centro
scaled to ``--amplitude`` times g tan(alpha) for ``--duration`` s: here, timed (the least of :data:`TIMED` runs),
then in a process of its own under valgrind's callgrind, which counts the instructions executed while the driver
steps the member (``callgrind_control -i on`` before :meth:`~dem_core.simulation.Simulation.advance`, ``-i off``
after; the count also holds ``advance``'s Python between its chunks, and not the record's samples, made before:
:class:`_SampledAhead`).  It prints the instructions a step, the time a step on a core of this machine (the driver
built for it), and how many member-steps a second a GPU could take at that many instructions a step if it issued
:data:`GPUS`' instructions a second, every lane of every warp busy.

The count is of the CPU's build of the one step driver (x86-64), whose stages the GPU kernels compile for another
instruction set, so it measures the step's length, not a GPU's instructions exactly: a GPU's load is an instruction
where x86-64 folds it into the arithmetic, its 64-bit integer arithmetic and float64 division take several, an
x86-64 vector instruction may do the work of two to four of a thread's, and a GPU fuses a multiply and an add.  The
rate it gives a GPU is an estimate, at peak issue.  The counted build is for the CPU valgrind presents, which may
lack some of this machine's instructions; numba builds the driver for it once (minutes) and caches it.
"""

import argparse
import contextlib
import math
import os
import re
import shutil
import subprocess
import sys
import tempfile
import time
from pathlib import Path

import numpy as np

from dem_core.cli.arguments import POSITIVE, SECONDS
from dem_core.engine.settings import STATUS_OVERTURNED
from dem_core.inputs.excitation import MotionSequence
from dem_core.simulation import Simulation

from .record_members import MIDDLE, RECORD, SCENES, ignore_the_cut_strong_motion, motion

#: GPU: (multiprocessors, instructions each issues a cycle for its threads (4 schedulers x 32 lanes), boost clock
#: in Hz), NVIDIA's figures for the SXM parts
GPUS = {"H100 or H200 (SXM)": (132, 4 * 32, 1.98e9)}
#: the option of the process valgrind runs, which steps the member with the counting on and says its steps
COUNTED = "--counted"
#: s for valgrind's process, and for ``callgrind_control`` to reach it
VALGRIND_TIMEOUT, CONTROL_TIMEOUT = 3600.0, 60.0
#: runs timed here, the least taken
TIMED = 3
#: the valgrind tool and the options of the counting process: counting off until the member's steps begin
VALGRIND = ("valgrind", "--tool=callgrind", "--instr-atstart=no")


def arguments(parser: argparse.ArgumentParser) -> None:
    """The options of its subcommand of ``python -m comparisons``."""
    parser.add_argument("--scene", choices=tuple(SCENES), default="block")
    parser.add_argument("--integrator", choices=("explicit", "moreau"), default="explicit")
    parser.add_argument("--amplitude", type=POSITIVE, default=MIDDLE,
                        help=f"the record's peak over g tan(alpha) (default {MIDDLE:g}, the device check's middle "
                             "member)")
    parser.add_argument("--duration", type=SECONDS, default=20.0, help="s of the record (default 20)")
    parser.add_argument(COUNTED, action="store_true", help=argparse.SUPPRESS)


class _SampledAhead(Simulation):
    """A run that makes its ground samples for the whole run once it is set up, and hands each chunk a copy of their
    columns, the same values under a single motion: the record's sampling, which the host does for a GPU thread,
    then falls outside the steps timed and counted."""

    def __init__(self, *args, **options):
        self.ahead = None
        super().__init__(*args, **options)
        if isinstance(self.excitation, MotionSequence):
            raise TypeError("step-instructions samples a single motion ahead, not a sequence's events")
        self.ahead = super()._samples(0, self.settings.last_step)

    def _samples(self, first: int, steps: int) -> np.ndarray:
        if self.ahead is None:
            return super()._samples(first, steps)
        return np.ascontiguousarray(self.ahead[:, first:first + steps + 2])


def _member(args) -> _SampledAhead:
    """The member's run, set up and not yet stepped."""
    build, tan_alpha = SCENES[args.scene]
    return _SampledAhead(build(), motion(tan_alpha, args.amplitude), args.duration, integrator=args.integrator)


def _stepped(args, around=None, repeats: int = 1) -> tuple:
    """``(steps, s)``: the member stepped through its run, the least time of ``repeats`` runs, ``around`` (a context
    manager, or None) about the steps alone: each run's set-up, outside it, compiles the driver or loads it from
    numba's cache."""
    took = math.inf
    for _ in range(repeats):
        run = _member(args)
        with around or contextlib.nullcontext():
            began = time.perf_counter()
            run.advance()
            took = min(took, time.perf_counter() - began)
    if run.step < run.settings.last_step:
        why = "it overturned" if run.status == STATUS_OVERTURNED else f"status {run.status}"
        print(f"note: the member's run ended at step {run.step:,} of {run.settings.last_step:,} ({why})", flush=True)
    return run.step, took


class _Counting:
    """valgrind's counting on for this process while the context lasts."""

    def __enter__(self):
        self._switch("on")

    def __exit__(self, *exc):
        self._switch("off")

    @staticmethod
    def _switch(state: str) -> None:
        try:
            done = subprocess.run(["callgrind_control", "-i", state, str(os.getpid())], capture_output=True,
                                  text=True, timeout=CONTROL_TIMEOUT, check=False)
        except (OSError, subprocess.TimeoutExpired) as error:
            raise SystemExit(f"step-instructions: callgrind_control -i {state} failed ({error})") from None
        if done.returncode or "Error" in done.stdout:  # it exits 0 where it finds no such process
            raise SystemExit(f"step-instructions: callgrind_control -i {state} did not reach this process, which "
                             f"valgrind's callgrind should run: {done.stdout.strip()[-300:]}")


def _counted(args) -> tuple:
    """``(instructions, steps, CPU)``: the instructions the member's steps took, counted by callgrind in a process
    of its own, its steps, and the CPU the driver was built for there (the one valgrind presents)."""
    with tempfile.TemporaryDirectory() as folder:
        out = Path(folder) / "callgrind.out"
        command = [*VALGRIND, f"--callgrind-out-file={out}", sys.executable, "-m", "comparisons",
                   "step-instructions", "--scene", args.scene, "--integrator", args.integrator, "--amplitude",
                   repr(args.amplitude), "--duration", repr(args.duration), COUNTED]
        try:
            done = subprocess.run(command, capture_output=True, text=True, timeout=VALGRIND_TIMEOUT, check=False)
        except subprocess.TimeoutExpired:
            raise SystemExit(f"step-instructions: the process under valgrind ran past {VALGRIND_TIMEOUT:g} s") from None
        said = re.search(r"^counted steps (\d+) built for (\S+)$", done.stdout, re.MULTILINE)
        totals = re.search(r"^totals: (\d+)$", out.read_text(), re.MULTILINE) if out.is_file() else None
        if done.returncode or said is None or totals is None:
            raise SystemExit(f"step-instructions: the process under valgrind failed (exit {done.returncode}):\n"
                             f"{done.stderr[-2000:]}")
        return int(totals.group(1)), int(said.group(1)), said.group(2)


def run(args: argparse.Namespace) -> None:
    """Time the member here, count it under valgrind, and print what the count allows a GPU."""
    ignore_the_cut_strong_motion()
    if args.counted:
        from llvmlite import binding

        steps, _ = _stepped(args, _Counting())
        print(f"counted steps {steps} built for {binding.get_host_cpu_name()}", flush=True)
        return
    missing = [tool for tool in ("valgrind", "callgrind_control") if shutil.which(tool) is None]
    if missing:
        raise SystemExit(f"step-instructions: {' and '.join(missing)} not found: it counts with valgrind's callgrind "
                         "(apt-get install valgrind)")
    from importlib import metadata

    from dem_core.analyses.run_identity import machine

    version = subprocess.run(["valgrind", "--version"], capture_output=True, text=True, check=False).stdout.strip()
    print(f"{version}, numba {metadata.version('numba')}", flush=True)
    steps, took = _stepped(args, repeats=TIMED)
    print(f"{args.scene} by {args.integrator}, {args.duration:g} s of {RECORD} at {args.amplitude:g} g tan(alpha): "
          f"{steps:,} steps, {took / steps * 1e9:.0f} ns a step on {machine()} (the driver built for it)",
          flush=True)
    print("counting under valgrind (the first count on a machine compiles the driver for the CPU valgrind presents, "
          "for minutes under valgrind; numba's cache keeps it)", flush=True)
    instructions, counted, cpu = _counted(args)
    if counted != steps:
        raise SystemExit(f"step-instructions: the counted run took {counted:,} steps, the timed one {steps:,}")
    per_step = instructions / steps
    print(f"{per_step:,.0f} instructions a step (x86-64, the driver built for {cpu}; {instructions:,} in all)")
    for gpu, (multiprocessors, lanes, clock) in GPUS.items():
        issued = multiprocessors * lanes * clock
        print(f"{gpu}: {issued:.4g} instructions a second at peak issue, so at most {issued / per_step:.3g} "
              f"member-steps a second at this many a step")
