"""How many of its arrays' elements a GPU thread reads and writes in a member's step, counted without a GPU.

    python -m comparisons kernel-accesses --scene column --integrator moreau [--amplitude 3] [--windows 100 200]

The GPU kernel's code (:data:`~dem_core.engine._members.SERIAL`, the kernel's own loop on one thread) runs as Python
under ``NUMBA_DISABLE_JIT`` and numba's CUDA simulator (the command sets both in a process of its own), for one
member of the device check's scene (:data:`~comparisons.benchmarks.record_members.SCENES`) under a sine pulse of 0.5
s and ``--amplitude`` times g tan(alpha), its packed arrays (``batch_gpu.pack``) wrapped so that every element read
or written is counted, by array.  It prints, for each window of ``--windows`` steps in turn, the reads and writes a
step (and, by Moreau-Jean, the passes by statuses and Gauss-Seidel sweeps a step) and the peak |theta| at its end,
then the bytes the last window touched of the member's arrays, and its accesses a step by array.

A read counted here stands for a load of the compiled kernel, which keeps some values in registers (fewer loads) and
adds the loads of the registers it spills and of the arrays not counted: the motion's samples (about four a step),
and the member's row of them and its status (once a chunk).
"""

import argparse
import math
import os
import subprocess
import sys
from collections import Counter

from dem_core.cli.arguments import WORKERS

#: what the counting process must run under
UNCOMPILED = {"NUMBA_DISABLE_JIT": "1", "NUMBA_ENABLE_CUDASIM": "1"}
#: the default windows (steps), per integrator: the first at the pulse's start, the next once the block rocks
WINDOWS = {"explicit": (1000, 2000), "moreau": (100, 200)}
#: arrays shown in the last window's table
ARRAYS_SHOWN = 12
#: s of the member's run: room for the windows (the block's steps are 6e-5 s, the column's 1e-3 s)
DURATION = 2.0


def arguments(parser: argparse.ArgumentParser) -> None:
    """The options of its subcommand of ``python -m comparisons``."""
    from .record_members import SCENES

    parser.add_argument("--scene", choices=tuple(SCENES), default="block")
    parser.add_argument("--integrator", choices=tuple(WINDOWS), default="explicit")
    parser.add_argument("--amplitude", type=float, default=3.0, help="the pulse's peak over g tan(alpha) (default 3)")
    parser.add_argument("--windows", type=WORKERS, nargs="+", default=None,
                        help="steps of each window in turn (default 1000 2000 explicit, 100 200 Moreau-Jean)")


class _Counted:
    """Every element read and written through the arrays :meth:`wrap` returns, by array name."""

    def __init__(self):
        import numpy as np

        self.reads, self.writes = Counter(), Counter()
        self.touched = {}  # element address: its array's name and the element's bytes
        counted = self

        def record_elements(array, key) -> int:
            """Record the elements ``array[key]`` names; returns how many."""
            part = np.ndarray.__getitem__(array, key)
            if not isinstance(part, np.ndarray):  # one element: its own address
                index = key if isinstance(key, tuple) else (key,)
                offset = sum((i % n) * stride for i, n, stride in zip(index, array.shape, array.strides))
                counted.touched[array.__array_interface__["data"][0] + offset] = array.name, array.itemsize
                return 1
            start = part.__array_interface__["data"][0]
            for index in np.ndindex(part.shape):  # a slice filled: the kernel's loop over its elements
                counted.touched[start + sum(i * stride for i, stride in zip(index, part.strides))] = (array.name,
                                                                                                     array.itemsize)
            return part.size

        class Array(np.ndarray):
            """An array that counts its elements read and written under its ``name``."""

            def __array_finalize__(self, obj):
                self.name = getattr(obj, "name", "?")

            def __getitem__(self, key):
                got = super().__getitem__(key)
                if not isinstance(got, np.ndarray):  # an element; a view (a member's, a row) reads nothing yet
                    counted.reads[self.name] += record_elements(self, key)
                return got

            def __setitem__(self, key, value):
                counted.writes[self.name] += record_elements(self, key)
                super().__setitem__(key, value)

        self.array = Array

    def wrap(self, arrays, kind: str):
        """``arrays`` (a named tuple of the batch's) with each array counted as ``kind.field``."""
        wrapped = []
        for field, array in zip(arrays._fields, arrays):
            view = array.view(self.array)
            view.name = f"{kind}.{field}"
            wrapped.append(view)
        return type(arrays)(*wrapped)

    def clear(self) -> None:
        """Forget what was counted."""
        self.reads.clear()
        self.writes.clear()
        self.touched.clear()


def _count(args) -> None:
    """Run the member through ``args.windows`` and print what :func:`run` says, in this process (uncompiled)."""
    import numpy as np

    from dem_core import batch_gpu
    from dem_core.engine._members import RUNNING, SERIAL
    from dem_core.engine.state import SOLVER_SWEEPS, STATUS_PASSES, STEP
    from dem_core.inputs.excitation import sine_pulse
    from dem_core.inputs.records import G_STANDARD
    from dem_core.simulation import Simulation

    from .record_members import SCENES

    build, tan_alpha = SCENES[args.scene]
    windows = args.windows or WINDOWS[args.integrator]
    run = Simulation(build(), sine_pulse(args.amplitude * G_STANDARD * tan_alpha, 0.5), DURATION,
                     integrator=args.integrator)
    motions = batch_gpu._motions([run])
    packed = batch_gpu.pack([run], motions)
    counted = _Counted()
    kinds = {"model": batch_gpu.written_out(packed.model), "settings": packed.settings, "state": packed.state,
             "outputs": batch_gpu.written_out(packed.outputs), "scratch": batch_gpu.written_out(packed.scratch)}
    arrays = {kind: counted.wrap(part, kind) for kind, part in kinds.items()}
    sizes = {f"{kind}.{field}": array[0].nbytes for kind, part in kinds.items() for field, array in
             zip(part._fields, part)}
    # the outputs are written a row per output, not a step's working set
    working = [name for name in sizes if not name.startswith("outputs.")]
    print(f"{args.scene}, {args.integrator}: dt {run.dt:.6g} s, a sine pulse of {args.amplitude:g} g tan(alpha) and "
          f"0.5 s", flush=True)
    step = 0
    counters = np.asarray(arrays["state"].counters)[0]
    for window in windows:
        counted.clear()
        passes_before, sweeps_before = counters[STATUS_PASSES], counters[SOLVER_SWEEPS]
        SERIAL[packed.integrator](arrays["model"], arrays["settings"], arrays["state"], arrays["outputs"],
                                  arrays["scratch"], motions.samples(step, window), packed.motion, window,
                                  packed.status)
        taken = int(counters[STEP]) - step
        step += taken
        theta = np.abs(np.asarray(arrays["state"].pos)[0, 1:, 2]).max()
        work = (f"{(counters[STATUS_PASSES] - passes_before) / taken:.3g} passes by statuses and "
                f"{(counters[SOLVER_SWEEPS] - sweeps_before) / taken:.3g} sweeps a step; "
                if args.integrator == "moreau" else "")
        print(f"steps {step - taken} to {step}: {sum(counted.reads.values()) / taken:.0f} reads and "
              f"{sum(counted.writes.values()) / taken:.0f} writes a step; {work}peak |theta| {theta:.2g} rad at the "
              f"end", flush=True)
        if packed.status[0, 0] != RUNNING:
            print(f"the run ended: status {packed.status[0].tolist()}")
            break
    accesses = counted.reads + counted.writes
    elements = Counter(name for name, _ in counted.touched.values())
    touched = sum(size for name, size in counted.touched.values() if name in working)
    print(f"the last window touched {touched:,} B of the member's arrays but its outputs, in "
          f"{sum(1 for name in working if name in elements)} of its {len(working)} arrays of "
          f"{sum(sizes[name] for name in working):,} B")
    print("its accesses a step by array (reads and writes; of all), the elements touched and the array's bytes:")
    for name, n in accesses.most_common(ARRAYS_SHOWN):
        print(f"  {name:28s} {n / taken:8.0f} {n / sum(accesses.values()):6.1%} {elements[name]:7,d} "
              f"{sizes[name]:9,d} B")


def run(args: argparse.Namespace) -> None:
    """Count in a process of its own under :data:`UNCOMPILED` (numba reads them at its import)."""
    if not math.isfinite(args.amplitude):
        raise SystemExit(f"kernel-accesses: --amplitude {args.amplitude}: give a finite multiple of g tan(alpha)")
    if all(os.environ.get(name) == value for name, value in UNCOMPILED.items()):
        _count(args)
        return
    command = [sys.executable, "-m", "comparisons", "kernel-accesses", "--scene", args.scene, "--integrator",
               args.integrator, "--amplitude", repr(args.amplitude)]
    if args.windows:
        command += ["--windows", *(str(w) for w in args.windows)]
    done = subprocess.run(command, env={**os.environ, **UNCOMPILED}, check=False)
    if done.returncode:
        raise SystemExit(done.returncode)
