"""Command line: ``dem-core COMMAND`` (also ``python -m dem_core COMMAND``), one module per command.

* ``run [SCENE.toml]``: run a scene file (default: the bundled 8-drum column
  under the 1940 El Centro record), write results and plots (below);
  ``--animate run.gif`` adds an animation and a snapshot strip;
* ``sweep SPEC.toml --out DIR``: a parametric sweep (:mod:`dem_core.analyses.sweep`) on
  this machine's cores or, with ``--scheduler ADDRESS``, on a Dask cluster; ``--duration``
  sets every run's simulated time (part of what identifies a run, so a resumed sweep never
  mixes durations); a resumed sweep says how many runs were already done, and the end
  counts the runs in words ("16 runs: 15 ok, 1 failed");
* ``threshold [SCENE.toml]``: the smallest PGA (or other excitation parameter)
  that overturns the scene, or starts it rocking or sliding, by the search of
  :mod:`dem_core.analyses.thresholds` with its defaults (a scan in steps of 2%, ``--step``, capped
  at ``--absolute-step``, or ``--scan N`` evenly spaced values; each change refined to 0.5%,
  ``--tolerance``);
* ``ramp SCENE.toml --rate 0.5``: rocking, sliding and overturning
  accelerations under a monotonic ramp, each with its criterion (rocking: a rotation above
  theta_cr/30), and for a single block or column its static uplift acceleration g b/h;
* ``animate SCENE.toml --out run.gif``: run and animate (GIF or MP4, at most 5000 frames);
  ``--exaggerate K`` draws each block's motion on what it rests on K times larger, so that a
  block rocking on a corner still stands on it;
* ``fragility [SCENE.toml] --out DIR``: fragility curves of the scene under a record suite (``--suite``, the
  bundled demonstration suite by default, or ``--records``) scaled to ``--levels`` stripes of PGA, PGV or Sa(T),
  the runs in batches on every core or on a Dask cluster (``--scheduler``), each saved as it ends so that the same
  command resumes, lognormals fitted to the damage states together with bands drawn by record
  (:mod:`dem_core.analyses.fragility_study`), written as CSV files and a figure;
* ``spectrum RECORD ... --out spectra.png``: elastic response spectra;
* ``stiffness SCENE.toml``: the run again at 10 and 100 times the contact stiffness, to see
  whether the answer depends on it: each measure named, its value at each stiffness and a
  verdict (converged when it changes by at most 5% from the stiffest run, or by less than
  1 mm of sliding, 0.001 rad of rotation, 0.1 s of overturn time; otherwise what to do);
* ``select [SUITE] --ec8 B --ag 2.4 --out DIR`` (or ``--scenario M R VS30 MECHANISM``): the records of a suite that
  best match a target spectrum, each scaled to it, written as a suite (:mod:`dem_core.analyses.target_spectra`);
* ``records [SUITE]``: a record suite's motions (:mod:`dem_core.inputs.suites`; the bundled demonstration suite
  by default), with their intensities, where each one's sampling interval comes from and what is known of their
  earthquakes.

Every command that runs a scene compiles the engine first; that takes a few minutes the first
time (numba caches it for later runs) and is announced on stderr when it takes more than 2 s
("compiling the engine (once, a few minutes; cached for later runs) ...", then "done in N s").  ``run`` and
``animate`` print the time simulated and the wall time it took ("simulated 53.72 s in 8.96 s").
``--help`` of every command shows every option's default.

``run`` writes into the output folder:

* ``time_history.csv`` (or ``.parquet``): one row per output time and block
  (t, block, x, y, theta, x_rel, base_x, base_y);
* ``metrics.csv``: per block peak |theta|, residual displacement, ``sliding_at_its_joints_m`` (the
  slip accumulated at the block's interfaces, below and above it, added: each interface counts for
  both its blocks, so adding this column over the blocks counts every joint twice), mean |theta|,
  overturn;
* ``interfaces.csv``: per interface ("drum1/drum2", "base/drum1") the slip accumulated there over the
  run, ``sliding_m``; the column adds up to the total sliding;
* ``summary.json``: the scene file (``scene``), whether the run is whole (``status``: "complete";
  "stopped" when the run lost stability, with ``stop_reason``, the files then holding the run up to
  ``end_time_s``; "incomplete" while the files are written, so a folder left by Ctrl-C or a full
  disk says so), where a run that stops at its first overturn ended (``ended_at_overturn``: "block
  'drum3' overturned at t = 4.2 s"; the run is complete there), the files written (``files``),
  scene-level measures and run facts (time step and stability limit, steps, ``compile_time_s``: the
  seconds this run took to set up and compile its engine or load it from numba's cache, and the run's
  wall time ``run_time_s``);
* ``rotations.png``, ``displacements.png``, ``sliding.png`` (and ``epistyles.png`` for colonnades).

A folder that holds an earlier run of the same scene file has it replaced whole (its files are
deleted once the new run has finished, before the new ones are written; the command says so); a
folder that holds another scene's run is refused, naming that scene, unless ``--overwrite``.

Output paths are checked before any run starts (created, writable, not a file where a folder
belongs), and every number on the command line is checked for finiteness, sign and range; an error
is one line naming the option.  Each file is written under a temporary name (``NAME.partial``) and
renamed when complete: a full disk or Ctrl-C leaves no truncated file that looks whole
(:mod:`dem_core.output_files`).

Exit status: 0 done; 1 failed (a sweep with failed runs, a file that could not be written, an
unexpected error); 2 refused input (an option, a scene or sweep file, an output path); 3 a run that
stopped unstable (``run`` and ``animate`` still write what it reached, marked so); 130 interrupted
by Ctrl-C, with one line saying what was saved (for a sweep, how many runs, and that the same
command resumes).  No error prints a traceback: an unexpected one is a line ending "unexpected:
please report"; ``DEM_CORE_DEBUG=1`` shows its traceback.

Accelerations are printed in m/s^2 with g in brackets, ``PGA 2.75 m/s^2 (0.281 g)``; every other
quantity in SI units (sliding in mm where the stiffness command compares small values).  Long work
(frames, the runs of a search) shows a progress bar with an estimate of the time left when stderr is
a terminal, and nothing otherwise (CI, logs).
"""

import argparse
import os
import sys
import warnings

from ..output_files import OutputPathError, OutputWriteError
from . import animate, fragility, ramp, records, run, select, spectrum, stiffness, sweep, threshold
from .arguments import ArgumentError, Parser, default_scene_path
from .console import Refused, one_line, show_warning
from .interrupts import INTERRUPTS

#: the commands, each a module of this package that declares its options (``add``) and runs (``run``)
COMMANDS = {"run": run, "sweep": sweep, "threshold": threshold, "ramp": ramp, "animate": animate,
            "fragility": fragility, "spectrum": spectrum, "stiffness": stiffness, "records": records,
            "select": select}
__all__ = ["COMMANDS", "default_scene_path", "main", "parser"]
#: exit status of a command stopped by Ctrl-C (128 + SIGINT, as shells report it)
INTERRUPTED = 130
#: exit status when the reader of the output went away (a closed pipe, as in ``| head``): a shell's for SIGPIPE
PIPE_CLOSED = 141
#: environment variable that lets an unexpected error show its traceback
DEBUG = "DEM_CORE_DEBUG"


def main(argv=None) -> int:
    """Run the command line ``argv`` (default ``sys.argv[1:]``) and return its exit status: 0 done; 1 failed (a
    sweep with failed runs, a file that could not be written, an unexpected error); 2 refused input (an option,
    a scene file, an output path); 3 a run that stopped unstable (its results up to there are written and
    marked so); 130 interrupted by Ctrl-C; 141, silently, when the reader of its output went away (``| head``).
    Every error is one line on stderr, never a traceback (set
    ``DEM_CORE_DEBUG=1`` to see the traceback of an unexpected one)."""
    try:
        args = parser().parse_args(argv)
    except ArgumentError as exc:
        print(f"error: {exc}", file=sys.stderr)
        return 2
    args.on_interrupt = lambda: "nothing was written"
    try:
        with warnings.catch_warnings(), INTERRUPTS.installed():
            warnings.showwarning = show_warning
            status = COMMANDS[args.command].run(args)
            sys.stdout.flush()  # a reader gone before the buffered output is met here, not at the interpreter's exit
            return status
    except KeyboardInterrupt:
        print(f"interrupted: {args.on_interrupt()}", file=sys.stderr)
        return INTERRUPTED
    except BrokenPipeError:
        os.dup2(os.open(os.devnull, os.O_WRONLY), sys.stdout.fileno())  # the exit's flush must not fail again
        return PIPE_CLOSED
    except (Refused, OutputPathError) as exc:
        print(f"error: {exc}", file=sys.stderr)
        return 2
    except OutputWriteError as exc:
        print(f"error: {exc}{_after_write_error(args)}", file=sys.stderr)
        return 1
    except Exception as exc:  # noqa: BLE001 - the last resort: a user never gets a traceback
        if os.environ.get(DEBUG, "") not in ("", "0"):
            raise
        print(f"error: {one_line(exc)} (unexpected: please report; rerun with {DEBUG}=1 for the traceback)",
              file=sys.stderr)
        return 1


def _after_write_error(args) -> str:
    """What a failed write left, for the commands that say more than the file that failed."""
    note = getattr(args, "after_write_error", None)
    return f"; {note()}" if note else ""


def parser() -> argparse.ArgumentParser:
    """The command line's parser: each command's options, declared by its module (:data:`COMMANDS`)."""
    top = Parser(prog="dem-core", description="Seismic response of stone columns and colonnades (native 2D DEM: "
                 "rigid contacts by Moreau-Jean time stepping, or the thesis' soft contacts).",
                 epilog="Exit status: 0 done, 1 failed, 2 refused input, 3 a run that "
                 "stopped unstable, 130 interrupted (Ctrl-C).  Each command's --help shows its options and "
                 f"their defaults.  No error shows a traceback; set {DEBUG}=1 to see that of an unexpected one.")
    sub = top.add_subparsers(dest="command", required=True)
    for command in COMMANDS.values():
        command.add(sub)
    return top
