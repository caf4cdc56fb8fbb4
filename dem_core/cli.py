"""Command line: ``dem-core COMMAND`` (also ``python -m dem_core COMMAND``).

* ``run [SCENE.toml]``: run a scene file (default: the bundled 8-drum column
  under the 1940 El Centro record), write results and plots (below);
  ``--animate run.gif`` adds an animation and a snapshot strip;
* ``sweep SPEC.toml --out DIR``: a parametric sweep (:mod:`dem_core.analyses.sweep`) on
  this machine's cores or, with ``--scheduler ADDRESS``, on a Dask cluster; ``--duration``
  sets every run's simulated time (part of what identifies a run, so a resumed sweep never
  mixes durations); a resumed sweep says how many runs were already done, and the end
  counts the runs in words ("16 runs: 15 ok, 1 failed");
* ``threshold SCENE.toml``: the smallest PGA (or other excitation parameter)
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
* ``fragility [SCENE.toml] --out DIR``: fragility curves of the scene under a suite of records (the bundled
  four, ``--records`` or ``--records-dir``) scaled to ``--levels`` stripes of PGA or PGV, all the runs one
  batch on every core, a lognormal per damage state with bootstrap bands
  (:mod:`dem_core.analyses.fragility_study`), written as CSV files and a figure;
* ``spectrum RECORD ... --out spectra.png``: elastic response spectra;
* ``stiffness SCENE.toml``: the run again at 10 and 100 times the contact stiffness, to see
  whether the answer depends on it: each measure named, its value at each stiffness and a
  verdict (converged when it changes by at most 5% from the stiffest run, or by less than
  1 mm of sliding, 0.001 rad of rotation, 0.1 s of overturn time; otherwise what to do);
* ``records``: the bundled accelerograms, with where each one's sampling interval comes from.

Every command that runs a scene compiles the engine first; that takes about half a minute the
first time (numba caches it for later runs) and is announced on stderr when it takes more than
2 s ("compiling the engine (once; cached for later runs) ...", then "done in N s").  ``run`` and
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
  disk says so), the files written (``files``), scene-level measures and run facts (time step and
  stability limit, steps, ``compile_time_s``: the seconds this run took to set up and compile its
  engine or load it from numba's cache, and the run's wall time ``run_time_s``);
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
import json
import math
import os
import re
import sys
import threading
import time
import warnings
from importlib import resources
from pathlib import Path

import numpy as np

from .inputs import records
from .inputs.records import G_STANDARD
from .inputs.scene_file import SceneFileError, load, read_toml
from .output_files import OutputPathError, OutputWriteError, output_file, output_folder, reason, replacing
from .simulation import INTEGRATORS, SimulationUnstable, run_duration

DEFAULT_SCENE = "column_el_centro.toml"


def default_scene_path() -> Path:
    return Path(str(resources.files("dem_core") / "data" / "scenes" / DEFAULT_SCENE))


def acceleration_text(value: float, digits: int = 3) -> str:
    """An acceleration as the command line prints it: ``2.75 m/s^2 (0.281 g)`` (g = 9.80665 m/s^2)."""
    return f"{value:.{digits}g} m/s^2 ({value / G_STANDARD:.{digits}g} g)"


def _interactive() -> bool:
    """Whether progress bars are wanted: stderr is a terminal, not a log file or a CI pipe."""
    return sys.stderr.isatty()


def _progress(**options):
    from tqdm import tqdm

    return tqdm(disable=not _interactive(), **options)


def _simulate_options(settings: dict, *, progress: bool = True) -> dict:
    """The keyword arguments of every ``simulate`` call the command line makes, directly or through
    an analysis: the one place where run-wide options are added.  ``progress``: a bar with the time
    left for each long run, shown only on a terminal (commands that run many short runs have their
    own bar over the runs and pass False).  The progress callback is always given: between a run's
    chunks it raises a Ctrl-C that came while the compiled kernel ran (see :class:`_Interrupts`)."""
    return {**settings, "progress": _progress_callback(progress)}


def _progress_callback(progress: bool = True):
    """``simulate``'s ``progress``: a bar on a terminal (when ``progress``), and the check for a held-back Ctrl-C."""
    bar = _StepProgress() if progress and sys.stderr.isatty() else None

    def report(done: int, total: int):
        INTERRUPTS.check()
        if bar is not None:
            bar(done, total)

    return report


#: s: setting a run up (compiling the engine, or loading it from numba's cache) that takes longer than this is
#: announced while it goes on, and its time printed when it ends (a first run compiles for about half a minute)
COMPILE_NOTICE_S = 2.0
COMPILING = "compiling the engine (once for each integrator; cached for later runs) ..."


class _CompileNotice:
    """A context that prints :data:`COMPILING` on stderr once what it holds has taken :data:`COMPILE_NOTICE_S`,
    and then, at its end, how long it took; ``seconds`` is that time (whether announced or not)."""

    def __init__(self):
        self.seconds = 0.0
        self.shown = False

    def __enter__(self):
        self.started = time.perf_counter()
        self.timer = threading.Timer(COMPILE_NOTICE_S, self._show)
        self.timer.daemon = True
        self.timer.start()
        return self

    def _show(self):
        self.shown = True
        print(COMPILING, file=sys.stderr, flush=True)

    def __exit__(self, *exc):
        self.timer.cancel()
        self.timer.join()
        self.seconds = time.perf_counter() - self.started
        if self.shown and exc[0] is None:
            print(f"done in {self.seconds:.0f} s", file=sys.stderr, flush=True)
        return False


def _prepared_run(scene, excitation, settings: dict):
    """``(dem_core.Simulation, seconds)``: the run of ``simulate(scene, excitation, **settings)`` set up and its
    engine compiled (announced when that takes long, :class:`_CompileNotice`), and the seconds that took."""
    from .simulation import Simulation

    with _CompileNotice() as notice:
        run = Simulation(scene, excitation, **{k: v for k, v in settings.items() if k != "progress"})
    return run, notice.seconds


def _compile_first(scene, excitation, settings: dict) -> None:
    """Compile the engine (or load it from numba's cache) before a command's runs, announced when that takes
    long: a one-step run of ``scene`` is set up.  Whatever it meets (a bad setting, a warning) is left for the
    runs themselves to report."""
    from .simulation import Simulation

    options = {k: v for k, v in settings.items() if k not in ("duration", "output_dt", "progress")}
    try:
        with warnings.catch_warnings():
            warnings.simplefilter("ignore")
            with _CompileNotice():
                Simulation(scene, excitation, duration=1e-9, **options)
    except Exception:  # noqa: BLE001 - the runs report it
        pass


class _Interrupts:
    """Ctrl-C as the command line takes it: ``KeyboardInterrupt`` raised where the program is, except in Python
    code that the compiled kernel calls back (numba loading a constant), where an exception crashes the process
    with a segmentation fault; there the request is only noted, and :meth:`check` raises it at the next safe
    point (between a run's chunks, a quarter of a second apart, and after each run)."""

    def __init__(self):
        self.requested = False

    def handle(self, signum, frame):
        self.requested = True
        if not _called_back_from_compiled_code(frame):
            raise KeyboardInterrupt

    def check(self) -> None:
        """Raise ``KeyboardInterrupt`` if Ctrl-C came and was held back."""
        if self.requested:
            raise KeyboardInterrupt

    def installed(self):
        """A context in which SIGINT goes to :meth:`handle` (in the main thread only: elsewhere Python's own)."""
        import contextlib
        import signal

        self.requested = False
        if threading.current_thread() is not threading.main_thread():
            return contextlib.nullcontext()
        previous = signal.signal(signal.SIGINT, self.handle)
        stack = contextlib.ExitStack()
        stack.callback(signal.signal, signal.SIGINT, previous)
        return stack


INTERRUPTS = _Interrupts()
_PACKAGE = os.path.dirname(os.path.abspath(__file__)) + os.sep


def _called_back_from_compiled_code(frame) -> bool:
    """Whether ``frame`` runs in numba's Python code called straight from a call in this package (its compiled
    code has no Python frames of its own), compilation (``_compile_for_args``) excepted."""
    above = None
    while frame is not None and not frame.f_code.co_filename.startswith(_PACKAGE):
        if frame.f_code.co_name == "_compile_for_args":
            return False
        above, frame = frame, frame.f_back
    return frame is not None and above is not None and f"{os.sep}numba{os.sep}" in above.f_code.co_filename


class _StepProgress:
    """``simulate``'s progress callback as a tqdm bar over simulated seconds; a new bar for each run."""

    def __init__(self):
        self.bar = None

    def __call__(self, done: int, total: int):
        from tqdm import tqdm

        if self.bar is None or done < self.bar.n or total != self.bar.total:
            if self.bar is not None:
                self.bar.close()
            self.bar = tqdm(total=total, desc="simulating", unit="step", unit_scale=True, leave=False)
        self.bar.update(done - self.bar.n)
        if done >= total and self.bar is not None:
            self.bar.close()


class _ArgumentError(Exception):
    """A command line argparse refuses; ``main`` prints it as one line and returns 2."""


class _HelpFormatter(argparse.HelpFormatter):
    """argparse's help with every option's default shown: "(default: X)" is added to the help of an option
    that has a default and whose help does not already say it (an option without one says in its help
    what it falls back to: the scene file, the record)."""

    def _get_help_string(self, action):
        text = action.help or ""
        default = action.default
        if ("default" in text or default is None or default is False or default is argparse.SUPPRESS
                or action.nargs == 0 or not (action.option_strings or action.nargs in ("?", "*"))):
            return text
        shown = " ".join(f"{v:g}" if isinstance(v, float) else str(v) for v in default) \
            if isinstance(default, (list, tuple)) else (f"{default:g}" if isinstance(default, float) else default)
        return f"{text} (default: {shown})".lstrip()


class _Parser(argparse.ArgumentParser):
    """argparse, with an error as one line naming the option (no usage block) returned by ``main`` as 2
    rather than a ``SystemExit`` (``--help`` still exits), and every default shown in ``--help``."""

    def __init__(self, *args, **kwargs):
        kwargs.setdefault("formatter_class", _HelpFormatter)
        super().__init__(*args, **kwargs)

    def error(self, message):
        raise _ArgumentError(f"{message} (see {self.prog} --help)")


def _number(parse, test, requirement: str):
    """An argparse ``type`` that parses with ``parse`` and refuses values failing ``test``: NaN, infinities and
    values out of range never reach a run.  The message names the option: ``argument --rate: must be a positive,
    finite number (m/s^2 per s), got 0``."""
    def check(text):
        try:
            value = parse(text)
        except (TypeError, ValueError):
            raise argparse.ArgumentTypeError(f"expected {requirement}, got {text!r}") from None
        if not test(value):
            raise argparse.ArgumentTypeError(f"must be {requirement}, got {text}")
        return value

    return check


def _finite_positive(value) -> bool:
    return math.isfinite(value) and value > 0


SECONDS = _number(float, _finite_positive, "a positive, finite number of seconds")
POSITIVE = _number(float, _finite_positive, "a positive, finite number")
RATE = _number(float, _finite_positive, "a positive, finite number (m/s^2 per s)")
WORKERS = _number(int, lambda v: v >= 1, "a whole number of at least 1")
#: frames per second of an animation: GIF players honour at most 100
FPS = _number(int, lambda v: 1 <= v <= 100, "a whole number from 1 to 100")
SCALES = _number(int, lambda v: 2 <= v <= 1000, "a whole number from 2 to 1000")
LEVELS = _number(int, lambda v: 2 <= v <= 100_000, "a whole number from 2 to 100000")
STATE = _number(float, lambda v: 0 < v <= 1, "a number above 0 and at most 1")
FRACTION = _number(float, lambda v: 0 < v < 1, "a number between 0 and 1 (both excluded)")
DAMPING = _number(float, lambda v: 0 <= v < 1, "a damping ratio from 0 up to (not including) 1")
#: most frames an animation may have (at 25 frames/s, 200 s of playback): each is held in memory for a GIF
MOST_FRAMES = 5000
#: the files a run writes into its folder (an animation's name is recorded in summary.json)
RUN_FILES = ("summary.json", "time_history.csv", "time_history.parquet", "metrics.csv", "interfaces.csv",
             "rotations.png", "displacements.png", "sliding.png", "epistyles.png", "snapshots.png")
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
        args = _parser().parse_args(argv)
    except _ArgumentError as exc:
        print(f"error: {exc}", file=sys.stderr)
        return 2
    args.on_interrupt = lambda: "nothing was written"
    commands = {"run": _run, "sweep": _sweep, "threshold": _threshold, "ramp": _ramp, "animate": _animate,
                "fragility": _fragility, "spectrum": _spectrum, "stiffness": _stiffness, "records": _records}
    try:
        with warnings.catch_warnings(), INTERRUPTS.installed():
            warnings.showwarning = _show_warning
            status = commands[args.command](args)
            sys.stdout.flush()  # a reader gone before the buffered output is met here, not at the interpreter's exit
            return status
    except KeyboardInterrupt:
        print(f"interrupted: {args.on_interrupt()}", file=sys.stderr)
        return INTERRUPTED
    except BrokenPipeError:
        os.dup2(os.open(os.devnull, os.O_WRONLY), sys.stdout.fileno())  # the exit's flush must not fail again
        return PIPE_CLOSED
    except (_Refused, OutputPathError) as exc:
        print(f"error: {exc}", file=sys.stderr)
        return 2
    except OutputWriteError as exc:
        print(f"error: {exc}{_after_write_error(args)}", file=sys.stderr)
        return 1
    except Exception as exc:  # noqa: BLE001 - the last resort: a user never gets a traceback
        if os.environ.get(DEBUG, "") not in ("", "0"):
            raise
        print(f"error: {_one_line(exc)} (unexpected: please report; rerun with {DEBUG}=1 for the traceback)",
              file=sys.stderr)
        return 1


def _one_line(exc: BaseException) -> str:
    """An exception as the first line of its message, with its type when that says something."""
    text = str(exc).strip().splitlines()[0] if str(exc).strip() else ""
    if isinstance(exc, OSError) and exc.filename:
        return f"{exc.filename}: {reason(exc)}"
    return f"{type(exc).__name__}: {text}" if text else type(exc).__name__


def _after_write_error(args) -> str:
    """What a failed write left, for the commands that say more than the file that failed."""
    note = getattr(args, "after_write_error", None)
    return f"; {note()}" if note else ""


class _Refused(Exception):
    """An output folder that holds results this command will not mix with its own; the message says which."""


def _parser() -> argparse.ArgumentParser:
    parser = _Parser(prog="dem-core", description="Seismic response of stone columns and colonnades (native "
                     "soft-contact DEM).", epilog="Exit status: 0 done, 1 failed, 2 refused input, 3 a run that "
                     "stopped unstable, 130 interrupted (Ctrl-C).  Each command's --help shows its options and "
                     f"their defaults.  No error shows a traceback; set {DEBUG}=1 to see that of an unexpected one.")
    sub = parser.add_subparsers(dest="command", required=True)
    _add_run(sub)
    _add_sweep(sub)
    _add_threshold(sub)
    _add_ramp(sub)
    _add_animate(sub)
    _add_fragility(sub)
    spectrum = sub.add_parser("spectrum", help="elastic response spectra of records")
    spectrum.add_argument("records", nargs="+", help="bundled record names or record files")
    spectrum.add_argument("--damping", type=DAMPING, default=0.05, help="damping ratio, 0 <= damping < 1 "
                          "(default: 0.05)")
    spectrum.add_argument("--out", default="spectra.png", help="figure to write; a .csv beside it holds the values")
    stiffness = sub.add_parser("stiffness", help="rerun a scene file at stiffer contacts and judge whether each "
                               "measure converged",
                               description="Run the scene at each multiple of its contact stiffness K_n and print "
                               "the measures (peak rotation, total sliding, mean rocking, overturn time) at each, "
                               "with a verdict for each: converged when the smallest multiple is within 5% of the "
                               "stiffest, or within 1 mm of sliding, 0.001 rad of rotation, 0.1 s of overturn time; "
                               "otherwise from which multiple it agrees, and what to do.")
    stiffness.add_argument("scene", nargs="?", help=f"scene file; default the bundled {DEFAULT_SCENE}")
    stiffness.add_argument("--factors", type=POSITIVE, nargs="+", default=[1.0, 10.0, 100.0],
                           help="multiples of the scene's K_n, each positive (default: 1 10 100)")
    stiffness.add_argument("--duration", type=SECONDS, help="simulated time in s (default: from the file or the "
                           "record)")
    sub.add_parser("records", help="list the bundled accelerograms: PGA, length, sampling interval and where it "
                   "comes from")
    return parser


def _add_run(sub):
    run = sub.add_parser("run", help="run a scene file and write results and plots",
                         description="Run a scene file and write its results and figures into a folder.  A "
                         "folder that holds an earlier run of the same scene file has that run replaced whole "
                         "(its files are deleted when this run has finished, before its own are written; the "
                         "command says so); a folder that holds the run of another scene is refused, naming it, "
                         "unless --overwrite.  Each file is written whole "
                         "or not at all; summary.json says whether the run is complete, stopped (unstable: the "
                         "files hold the run up to there, and why) or incomplete (interrupted while writing).  "
                         "Files: time_history.csv (or .parquet); metrics.csv, one row per block, whose "
                         "sliding_at_its_joints_m adds the slip of the block's interfaces below and above it (so "
                         "its sum over the blocks counts every joint twice); interfaces.csv, the slip of each "
                         "interface (sliding_m, adding up to the total sliding); summary.json; the figures.")
    run.add_argument("scene", nargs="?", help=f"scene file (TOML); default: the bundled {DEFAULT_SCENE}")
    run.add_argument("--out", help="output folder (default: results/<scene name>), created if need be")
    run.add_argument("--overwrite", action="store_true", help="replace the results of another scene's run in "
                     "--out (its files are deleted before this run's are written); without it such a folder is "
                     "refused")
    run.add_argument("--format", choices=("csv", "parquet"), help="time-history format (default: the file's [output] "
                     "format, else csv)")
    run.add_argument("--duration", type=SECONDS, help="simulated time in s (default: from the file or the record)")
    run.add_argument("--integrator", choices=INTEGRATORS, help="explicit central differences on the contact "
                     "springs, or Moreau-Jean's velocity-level steps on rigid contacts (docs/method.md 1.8; "
                     "default: the file's [simulation] integrator, else explicit)")
    run.add_argument("--no-plots", action="store_true", help="skip the figures")
    run.add_argument("--animate", metavar="FILE", help="also write an animation (.gif or .mp4, relative to --out) "
                     "and snapshots.png (default: none)")
    run.add_argument("--exaggerate", type=POSITIVE, default=1.0, metavar="K",
                     help="draw each block's rotation and displacement on what it rests on K times larger in the "
                     "animation, K > 0 (default: 1); a block rocking on a corner still stands on it")
    run.add_argument("--relative-rotations", action="store_true",
                     help="plot rotations as theta / alpha, alpha the critical angle (column's for drums)")


def _add_sweep(sub):
    sweep = sub.add_parser("sweep", help="run a parametric sweep file; resumes where a previous run stopped",
                           description="Run a parametric sweep.  Each finished run is saved at once in "
                           "OUT/runs/: after Ctrl-C (exit status 130) or a crash, the same command resumes, "
                           "running only what is missing; a saved run that cannot be read is run again.")
    sweep.add_argument("spec", help="sweep file: a scene file with a [sweep] table")
    sweep.add_argument("--out", required=True, help="output folder (results.parquet, runs/, histories/)")
    sweep.add_argument("--workers", type=WORKERS, help="processes on this machine, at least 1 (default: one per "
                       "core)")
    sweep.add_argument("--scheduler", help="address of a running Dask scheduler, e.g. tcp://10.0.0.5:8786 "
                       "(default: none, the runs go to processes on this machine)")
    sweep.add_argument("--retry-failed", action="store_true", help="run again the points that failed before")
    sweep.add_argument("--overwrite", action="store_true", help="delete the results already in --out and run every "
                       "point (without it, another sweep's results there are refused)")
    sweep.add_argument("--duration", type=SECONDS, help="simulated time of every run in s, replacing the file's "
                       "[simulation] duration; part of what identifies a run, so a folder of runs of another "
                       "duration is refused, not mixed (default: the file's, or each record's length)")
    sweep.add_argument("--no-progress", action="store_true", help="no progress bar (there is one only when "
                       "stderr is a terminal anyway)")


def _add_threshold(sub):
    from .analyses.thresholds import SCAN_STEP, TOLERANCE

    threshold = sub.add_parser(
        "threshold", help="smallest excitation value that overturns the scene (or starts it rocking or sliding), "
        "by a fine scan and bisection",
        description="The smallest value of an [excitation] key (the PGA by default) at which the scene overturns, "
        "or starts rocking or sliding: the search of dem_core.analyses.thresholds with its defaults.  Every "
        "value of a scan from --low to --high is run (each the last plus --step of it, the increase capped at "
        "--absolute-step; or --scan evenly spaced values), then every change between neighbouring values "
        "(standing to overturned, and back: the response is not monotonic) is bisected until its bracket is "
        "narrower than --tolerance of its upper end.")
    threshold.add_argument("scene", help="scene file whose [excitation] is scaled")
    threshold.add_argument("--parameter", default="pga", help="the [excitation] key that is varied (default: pga); the "
                           "scene file must not give a key that excludes it (amplitude for pga)")
    threshold.add_argument("--low", type=POSITIVE, required=True, help="lowest value scanned (> 0)")
    threshold.add_argument("--high", type=POSITIVE, required=True, help="highest value scanned (> --low)")
    threshold.add_argument("--criterion", choices=("overturning", "rocking", "sliding"), default="overturning",
                           help="what is searched for (default: overturning): a block overturning; rocking, a "
                           "rotation above theta_cr/30; sliding, an interface slipping more than 0.1 mm")
    threshold.add_argument("--step", type=FRACTION, help="relative step of the scan: each value is the last "
                           f"times (1 + STEP), between 0 and 1 (default: {SCAN_STEP:g})")
    threshold.add_argument("--absolute-step", type=POSITIVE, metavar="STEP", help="largest step of the scan, in "
                           "the unit of --parameter (m/s^2 for pga), positive (default: none, the relative step "
                           "alone)")
    threshold.add_argument("--scan", type=SCALES, metavar="N", help="scan N evenly spaced values instead, 2 to "
                           "1000 (default: none, the steps above); not with --step or --absolute-step")
    threshold.add_argument("--tolerance", type=FRACTION, default=TOLERANCE, help="relative width to which each "
                           "change is refined, between 0 and 1")
    threshold.add_argument("--duration", type=SECONDS, help="simulated time of each run in s (default: from the "
                           "file or the record)")


def _add_ramp(sub):
    ramp = sub.add_parser("ramp", help="rocking, sliding and overturning accelerations under a monotonic ramp, each "
                          "with its criterion",
                          description="Run the scene under a ground acceleration growing at --rate and print the "
                          "accelerations at which it starts rocking (a block's rotation passes theta_cr/30, "
                          "theta_cr the scene's slenderness), starts sliding (an interface slips more than 0.1 mm) "
                          "and overturns, each with its criterion, and, for a single block or column, its static "
                          "uplift acceleration g b/h.")
    ramp.add_argument("scene", help="scene file (its [excitation] is ignored)")
    ramp.add_argument("--rate", type=RATE, default=0.5, help="rate at which the ground acceleration grows, m/s^2 per "
                      "s, positive (default: 0.5)")
    ramp.add_argument("--duration", type=SECONDS, help="simulated time in s (default: until the ramp reaches 1 g)")


def _add_animate(sub):
    anim = sub.add_parser("animate", help="run a scene file and write an animation and snapshots")
    anim.add_argument("scene", nargs="?", help=f"scene file; default the bundled {DEFAULT_SCENE}")
    anim.add_argument("--out", default="animation.gif", help="file to write (.gif or .mp4); snapshots go to "
                      "<name>_snapshots.png beside it.  Both are written whole or not at all")
    anim.add_argument("--duration", type=SECONDS, help="simulated time in s (default: from the file or the record)")
    anim.add_argument("--fps", type=FPS, default=25, help="frames per second, 1 to 100 (default: 25)")
    anim.add_argument("--speed", type=POSITIVE, default=1.0, help="simulated seconds per second of playback, "
                      f"positive (default: 1); the animation may have at most {MOST_FRAMES} frames")
    anim.add_argument("--exaggerate", type=POSITIVE, default=1.0, metavar="K",
                      help="draw each block's rotation and displacement since the start, on what it rests on (the "
                      "base or the block below), K times larger, K > 0 (default: 1); a block rocking on a corner "
                      "still stands on it")


def _add_fragility(sub):
    from .analyses.fragility_study import DEFAULT_STATES, INTENSITY_MEASURES
    from .batch import DEVICES

    fragility = sub.add_parser(
        "fragility", help="fragility curves: the scene under a suite of records scaled to stripes of PGA or PGV",
        description="Run the scene under each record scaled to each of --levels intensities evenly spaced up to "
        "--max (multiple-stripe analysis), all members of one batch on every core, and fit a lognormal fragility "
        "per damage state by maximum likelihood with bootstrap 90% bands (dem_core.analyses.fragility).  A "
        "damage state is a peak |theta|/alpha (alpha the column's critical angle for a drum, else the block's "
        "own); 1 is overturning.  Writes fragility.csv (median and dispersion per state with their "
        "bands), counts.csv (runs and exceedances per level and state), runs.csv (every run's measures), "
        "fragility.png and study.json (the settings, the machine and the wall time).")
    fragility.add_argument("scene", nargs="?", help=f"scene file (its [excitation] is ignored); default the bundled "
                           f"{DEFAULT_SCENE}")
    suite = fragility.add_mutually_exclusive_group()
    suite.add_argument("--records", nargs="+", metavar="RECORD", help="bundled record names or record files (AT2 "
                       "or text) (default: the four bundled records)")
    suite.add_argument("--records-dir", metavar="DIR", help="a folder whose .at2, .txt, .dat and .csv files are the "
                       "suite (default: none, --records)")
    fragility.add_argument("--units", choices=("m/s^2", "g", "cm/s^2"), default="m/s^2", help="units of text "
                           "records (AT2 files state theirs)")
    fragility.add_argument("--im", choices=tuple(INTENSITY_MEASURES), default="pga", help="intensity measure: peak "
                           "ground acceleration (m/s^2) or velocity (m/s) of the horizontal component")
    fragility.add_argument("--levels", type=LEVELS, default=32, help="intensity levels (stripes) per record, 2 to "
                           "100000")
    fragility.add_argument("--max", type=POSITIVE, help="highest level, in the measure's unit; the levels are evenly "
                           "spaced from max/levels to max (default: 1 g of PGA, 1 m/s of PGV)")
    fragility.add_argument("--states", type=STATE, nargs="+", default=list(DEFAULT_STATES),
                           help="damage states as peak |theta|/alpha, each above 0 and at most 1; 1 is overturning")
    fragility.add_argument("--out", required=True, help="output folder, created if need be")
    fragility.add_argument("--duration", type=SECONDS, help="simulated time of each run in s (default: from the "
                           "file, else each record's length)")
    fragility.add_argument("--integrator", choices=INTEGRATORS, help="default: the file's [simulation] integrator, "
                           "else explicit")
    fragility.add_argument("--device", choices=DEVICES, default="auto", help="where the batch runs")
    fragility.add_argument("--threads", type=WORKERS, help="runs at once (default: one per core)")


def _show_warning(message, category, filename, lineno, file=None, line=None):
    """Warnings as a line a user reads ("warning: a long run: ..."), not Python's file, line and source."""
    print(f"warning: {message}", file=sys.stderr if file is None else file, flush=True)


def _records(args=None) -> int:
    from .inputs.excitation import record

    for name, entry in records.BUNDLED.items():
        horizontal = record(name).horizontal
        what = re.sub(r"\s*\(PGA [^)]*\)", "", entry.description)
        print(f"{name:18s} PGA {acceleration_text(horizontal.peak_acceleration)}, {horizontal.end_time:.4g} s "
              f"every {horizontal.dt:.3g} s ({_sampling_source(entry, horizontal.dt)}): {what}")
    return 0


def _sampling_source(entry, dt: float) -> str:
    """Where a bundled record's sampling interval comes from, in words: the AT2 header, the time column, or (for a
    file without either) dem_core's table of bundled records, with the interval the file's name gives if other."""
    if entry.dt is None:
        return "stated in the file's header" if entry.file.lower().endswith(".at2") else "from its time column"
    named = re.search(r"dt[_=]?(\d+(?:\.\d+)?)", entry.file, re.IGNORECASE)
    other = (f"; the file's name says {float(named.group(1)):g} s" if named and
             not math.isclose(float(named.group(1)), dt, rel_tol=1e-6) else "")
    return (f"not stated in the file, which has no time column: dem_core's reading{other}, see "
            f"dem_core/data/records/SOURCES.md")


def _motion_text(motion) -> str:
    """The ground motion's name and, when it has one, its peak horizontal acceleration."""
    peak = motion.horizontal.peak_acceleration
    return f"{motion.name}, PGA {acceleration_text(peak)}" if np.isfinite(peak) and peak > 0 else motion.name


def _run(args) -> int:
    path = Path(args.scene) if args.scene else default_scene_path()
    spec = _load_or_fail(path)
    if spec is None:
        return 2
    if args.exaggerate != 1 and not args.animate:
        print("note: --exaggerate applies to the animation: add --animate run.gif", file=sys.stderr)
    if args.animate and not _movie_name_ok(args.animate, "--animate"):
        return 2
    out = output_folder(Path(args.out) if args.out else Path("results") / path.stem, "--out")
    movie = output_file(out / args.animate, "--animate") if args.animate else None
    previous = _previous_run(out, path, args.overwrite)
    settings = dict(spec.simulation)
    if args.duration is not None:
        settings["duration"] = args.duration
    if args.integrator is not None:
        settings["integrator"] = args.integrator
    fmt = args.format or spec.output.get("format", "csv")
    print(f"scene {path} ({len(spec.scene.blocks)} blocks), ground motion: {_motion_text(spec.excitation)}")
    args.on_interrupt = lambda: f"the run was stopped before its results were written: {out}/ is as it was"
    stopped = ""
    try:
        result, setup = _simulated(spec, settings)
    except SimulationUnstable as exc:
        INTERRUPTS.check()
        result, stopped, setup = exc.partial, _stopped_text(exc), getattr(exc, "setup_s", None)
        if result is None or len(result.t) == 0:
            print(f"error: {stopped}; nothing was written", file=sys.stderr)
            return 3
    except (TypeError, ValueError) as exc:
        print(f"error: {path}: {exc}", file=sys.stderr)
        return 2
    INTERRUPTS.check()
    print(f"peak |theta| {np.max(result.peak_theta):.4g} rad, total sliding {result.total_sliding:.4g} m, "
          f"overturned: {f'yes at t = {result.time_of_overturn:.3f} s' if result.overturned else 'no'}")
    args.on_interrupt = lambda: (f"writing the results into {out}/ was stopped: they are incomplete (summary.json "
                                 "says so); run the same command again")
    args.after_write_error = lambda: f"the results in {out}/ are incomplete"
    for old in previous:
        old.unlink(missing_ok=True)
    summary = _summary(result, path, stopped, setup)
    written = _write(result, out, fmt, summary)
    if not args.no_plots and spec.output.get("plots", True) and len(result.t) > 1:
        from .pictures.plots import save_run_figures  # matplotlib loads only when figures are written

        figures = save_run_figures(result, out, spec.excitation, title=path.stem,
                                   relative_rotations=args.relative_rotations)
        written += [p.name for p in figures]
        print(f"figures: {', '.join(p.name for p in figures)}")
    if movie is not None:
        _write_animation(spec, result, movie, out / "snapshots.png", path.stem, exaggerate=args.exaggerate)
        written += [movie.resolve().relative_to(out.resolve()).as_posix() if _inside(movie, out) else str(movie),
                    "snapshots.png"]
    _write_summary(out, {**summary, "status": "stopped" if stopped else "complete", "files": written})
    if not stopped:
        print(f"results written to {out}/")
        return 0
    print(f"results up to t = {result.t[-1]:.4g} s written to {out}/")
    print(f"error: {stopped}; the results up to t = {result.t[-1]:.6g} s are written to {out}/, marked \"stopped\" "
          "in summary.json", file=sys.stderr)
    return 3


def _stopped_text(exc: SimulationUnstable) -> str:
    """Why a run stopped, without the sentence addressed to Python callers (the result in ``.partial``)."""
    return re.sub(r"\.?\s*The result up to t = \S+ s is in this error's \.partial\.?$", "", str(exc)).strip()


def _failed_run(exc: Exception, culprit: str | None = None) -> int:
    """Print why a run that wrote nothing failed and return the exit status: 3 for a run that lost stability,
    2 for input the engine refused (``TypeError``/``ValueError``, prefixed with ``culprit`` where given)."""
    if isinstance(exc, SimulationUnstable):
        print(f"error: {_stopped_text(exc)}", file=sys.stderr)
        return 3
    print(f"error: {culprit + ': ' if culprit else ''}{exc}", file=sys.stderr)
    return 2


def _simulated(spec, settings: dict):
    """``(result, setup seconds)`` of the scene file ``spec`` run with ``settings``: the engine compiled first
    (announced when that takes long), then the run with a progress bar on a terminal, then what was simulated
    (:func:`_print_run`).  A run that loses stability raises :class:`SimulationUnstable`, with ``setup_s``
    set, after printing what it reached."""
    run, setup = _prepared_run(spec.scene, spec.excitation, settings)
    try:
        result = run.run(_progress_callback()).result()
    except SimulationUnstable as exc:
        exc.setup_s = setup
        if exc.partial is not None and len(exc.partial.t):
            _print_run(run, exc.partial, setup)
        raise
    _print_run(run, result, setup)
    return result, setup


def _print_run(run, result, setup: float) -> None:
    """Two lines: the contact law and time step of ``run``; the time simulated (and of how much, when the run
    ended early), the wall time it took and the time the engine took to set up and compile."""
    info = result.info
    planned = run.settings.last_step * run.dt
    end = float(result.t[-1])
    early = f" of {planned:.4g} s" if end < planned - 1.5 * run.dt else ""
    if info.get("integrator") == "moreau":
        print(f"Moreau-Jean integrator (theta {info.get('theta')}) on the {info.get('contact_law', '?')} law's "
              f"points, rigid contacts; dt = {result.dt:.3g} s, {info.get('steps')} steps; contact solve "
              f"(docs/method.md 1.8): {info.get('status_passes_per_step', float('nan')):.3g} direct passes and "
              f"{info.get('sweeps_per_step', float('nan')):.2g} iterative sweeps a step")
    else:
        print(f"{info.get('contact_law', '?')} contact law, K_n = {info.get('kn', float('nan')):.3g} N/m^2; dt = "
              f"{result.dt:.3g} s (stability limit {info.get('stability_limit_s', float('nan')):.3g} s), "
              f"{info.get('steps')} steps")
    print(f"simulated {end:.4g} s{early} in {run.run_time:.2f} s (setting up and compiling the engine: "
          f"{setup:.2f} s)")


def _previous_run(out: Path, scene: Path, overwrite: bool) -> list:
    """The files of an earlier run in ``out``, to be deleted before this run's are written ([] if none): an
    earlier run of the same scene file is replaced whole (said on stderr); another scene's run, or one whose
    scene is not recorded, raises :class:`_Refused` naming it, unless ``overwrite``."""
    try:
        previous = json.loads((out / "summary.json").read_text())
    except (OSError, ValueError):
        previous = {}
    previous = previous if isinstance(previous, dict) else {}
    listed = previous.get("files") if isinstance(previous.get("files"), list) else []
    names = {*RUN_FILES, *(name for name in listed if isinstance(name, str))}
    files = sorted(p for p in (out / name for name in names) if _inside(p, out) and p.is_file())
    if not files:
        return []
    held = previous.get("scene")
    if isinstance(held, str) and _same_file(held, scene):
        print(f"note: {out}/ holds an earlier run of {scene}: it is replaced whole", file=sys.stderr)
        return files
    what = (f"a run of another scene, {held}" if isinstance(held, str) else
            f"another run, whose scene it does not record ({', '.join(p.name for p in files[:4])})")
    if overwrite:
        print(f"note: --overwrite: {out}/ holds {what}: its files are deleted", file=sys.stderr)
        return files
    raise _Refused(f"--out {out} holds {what}; the results of two runs are not mixed: give another --out, or "
                   "--overwrite to delete them and write this run's")


def _inside(path: Path, folder: Path) -> bool:
    try:
        path.resolve().relative_to(folder.resolve())
    except ValueError:
        return False
    return True


def _same_file(recorded: str, scene: Path) -> bool:
    try:
        return Path(recorded).resolve() == scene.resolve()
    except OSError:
        return False


def _summary(result, scene: Path, stopped: str, setup: float | None = None) -> dict:
    """What summary.json holds: the scene file, whether the run is complete (``status``: "incomplete" until
    every file is written, then "complete", or "stopped" with ``stop_reason``), its measures and run facts;
    ``compile_time_s`` is ``setup``, the seconds this run took to set up and compile its engine (or load it
    from numba's cache), when given."""
    measures = {k: (v.item() if isinstance(v, np.generic) else v) for k, v in result.summary().items()}
    if setup is not None:
        measures["compile_time_s"] = float(setup)
    summary = {"scene": str(scene.resolve()), "status": "incomplete", "stop_reason": stopped or None,
               "end_time_s": float(result.t[-1]), **measures, "blocks": list(result.names)}
    return {k: (None if isinstance(v, float) and not np.isfinite(v) else v) for k, v in summary.items()}


def _write_summary(out: Path, summary: dict) -> None:
    with replacing(out / "summary.json") as tmp:
        tmp.write_text(json.dumps(summary, indent=2))


def _write(result, out: Path, fmt: str, summary: dict) -> list:
    """Write summary.json (status "incomplete" until the caller marks it otherwise), the time history and
    metrics.csv into ``out``, each whole or not at all; returns the names written."""
    _write_summary(out, {**summary, "files": []})
    history = f"time_history.{fmt}"
    with replacing(out / history) as tmp:
        frame = result.to_frame()
        if fmt == "parquet":
            frame.to_parquet(tmp, index=False)
        else:
            frame.to_csv(tmp, index=False)
    with replacing(out / "metrics.csv") as tmp:
        block_metrics(result).to_csv(tmp, index=False)
    with replacing(out / "interfaces.csv") as tmp:
        interface_sliding(result).to_csv(tmp, index=False)
    return ["summary.json", history, "metrics.csv", "interfaces.csv"]


#: the column of metrics.csv that holds the slip summed over a block's interfaces: each interface is counted
#: once for each of its two blocks, so adding the column over the blocks counts every joint twice
#: (``Result.metrics()`` calls it ``sliding_m``)
JOINT_SLIDING = "sliding_at_its_joints_m"


def block_metrics(result):
    """metrics.csv: ``Result.metrics()`` with its per-block sliding named for what it is (:data:`JOINT_SLIDING`:
    the slip accumulated at the block's joints, below and above it, added; the sliding of each joint is in
    interfaces.csv)."""
    return result.metrics().rename(columns={"sliding_m": JOINT_SLIDING})


def interface_sliding(result):
    """interfaces.csv: one row per interface, ``interface`` ("drum1/drum2": its two bodies in the scene's order,
    "base" for the ground) and ``sliding_m``, the slip accumulated there over the run (m; 0 where it did not
    slide, NaN when the engine does not measure it).  The interfaces touching at the start come first, in the
    scene's order, then those that met later and slid; the column adds up to the run's total sliding."""
    import pandas as pd

    slips = result.interface_slip
    pairs = list(dict.fromkeys([*map(tuple, result.interfaces), *(slips or {})]))
    return pd.DataFrame({"interface": [f"{a}/{b}" for a, b in pairs],
                         "sliding_m": [float("nan") if slips is None else float(slips.get(pair, 0.0))
                                       for pair in pairs]}, columns=["interface", "sliding_m"])


def _write_animation(spec, result, movie, strip, title, fps=25, speed=1.0, exaggerate=1.0):
    from .pictures.animation import animate, default_snapshot_times, frame_indices, snapshot_strip

    animate(spec.scene, result, movie, excitation=spec.excitation, fps=fps, speed=speed, title=title,
            exaggerate=exaggerate, progress=_interactive())
    figure = snapshot_strip(spec.scene, result, default_snapshot_times(result), title=title, exaggerate=exaggerate)
    with replacing(strip) as tmp:
        figure.savefig(tmp, dpi=110, format="png")
    frames = len(frame_indices(result, fps, speed))
    shown = (f", rotations and displacements x {exaggerate:g}, each block's on what it rests on"
             if exaggerate != 1 else "")
    print(f"animation written to {movie} ({frames} frames, {frames / fps:.1f} s at {fps} frames/s{shown}), "
          f"snapshots to {strip}")
    if exaggerate != 1 and result.overturned:
        print(f"note: the collapse at {result.time_of_overturn:.2f} s is exaggerated too: its drawing is not to scale")


def _load_or_fail(path):
    try:
        return load(path)
    except SceneFileError as exc:
        print(f"error: {exc}", file=sys.stderr)
        return None


def _sweep(args) -> int:
    from .analyses.sweep import SweepError, load_sweep, run_sweep, saved_runs, with_simulation

    try:
        sweep = load_sweep(args.spec)
        if args.duration is not None:
            sweep = with_simulation(sweep, duration=args.duration)
    except SweepError as exc:
        print(f"error: {args.spec}: {exc}" if str(args.spec) not in str(exc) else f"error: {exc}", file=sys.stderr)
        return 2
    out = output_folder(args.out, "--out")
    points = len(sweep.points())
    where = f"Dask scheduler {args.scheduler}" if args.scheduler else f"{args.workers or 'all'} local worker(s)"
    each = f", each run for {args.duration:g} s (--duration)" if args.duration is not None else ""
    print(f"sweep {args.spec}: {points} runs over {', '.join(sweep.parameters)} on {where}{each}")

    def saved():
        done, total = saved_runs(out)
        return f"{done} of {total or points} runs saved in {out}; run the same command again to resume"

    def on_start(done, total):
        if done == total:
            print(f"all {total} runs already done in {out}; nothing to run")
        elif done:
            again = " (failed ones run again: --retry-failed)" if args.retry_failed else ""
            print(f"{done} of {total} runs already done in {out}{again}; running {total - done}")
        if done < total and args.scheduler is None:
            _compile_first_point(sweep)

    args.on_interrupt = args.after_write_error = saved
    try:
        table = run_sweep(sweep, out, workers=args.workers, scheduler=args.scheduler,
                          progress=False if args.no_progress else None, retry_failed=args.retry_failed,
                          overwrite=args.overwrite, on_start=on_start)
    except SweepError as exc:
        print(f"error: {exc}", file=sys.stderr)
        return 2
    counts = table.status.value_counts().to_dict() if len(table) else {}
    print(f"{_run_counts(len(table), counts)}; results in {out}/results.parquet")
    for _, row in (table[table.status != "ok"].head(5).iterrows() if len(table) else ()):
        print(f"  {row.run_id} {row.status}: {row.error.splitlines()[0] if row.error else ''}")
    return 0 if counts.get("failed", 0) == 0 else 1


def _run_counts(runs: int, counts: dict) -> str:
    """"16 runs: 15 ok, 1 failed": the runs of a sweep by status (ok first, then unstable, failed, others)."""
    order = ["ok", "unstable", "failed", *sorted(set(counts) - {"ok", "unstable", "failed"})]
    parts = [f"{counts[status]} {status}" for status in order if counts.get(status)]
    return f"{runs} run{'s' if runs != 1 else ''}: {', '.join(parts) or 'none'}"


def _compile_first_point(sweep) -> None:
    """Compile the engine in this process before the workers start (they then load it from numba's cache
    rather than each compiling it), with the first point that builds."""
    for params in sweep.points():
        try:
            spec = sweep.build(params)
        except Exception:  # noqa: BLE001 - a point that cannot be built is a failed run of the sweep
            continue
        _compile_first(spec.scene, spec.excitation, spec.simulation)
        return


#: excitation kinds whose ``amplitude`` is an acceleration (a harmonic's is a displacement, m)
PULSES = ("rectangular_pulse", "sine_pulse", "cosine_pulse")
#: SI units of the [excitation] keys a threshold search can vary (``scale`` and unknown keys: none)
PARAMETER_UNITS = {"amplitude": "m", "vertical_amplitude": "m", "frequency": "Hz", "duration": "s",
                   "rate": "m/s^2 per s"}


def _parameter_unit(kind, parameter) -> str:
    """The unit of the [excitation] key ``parameter`` for that ``kind`` of excitation ("" for none)."""
    if parameter in ("pga", "peak") or (parameter == "amplitude" and kind in PULSES):
        return "m/s^2"
    return PARAMETER_UNITS.get(parameter, "")


def _parameter_text(value, unit, digits=4) -> str:
    if unit == "m/s^2":
        return acceleration_text(value, digits)
    return f"{value:.{digits}g} {unit}".rstrip()


def _bisections(width, above, tolerance) -> int:
    """Halvings that bring a bracket of ``width`` below ``tolerance`` times ``above`` (an estimate of
    the runs a search has left, for its progress bar)."""
    if not (tolerance > 0 and above > 0) or width <= tolerance * above:
        return 0
    return math.ceil(math.log2(width / (tolerance * above)))


def _threshold(args) -> int:
    from .analyses.thresholds import SCAN_STEP, onset_threshold, overturning_threshold, scan_grid

    if not args.low < args.high:
        print(f"error: --low {args.low:g} must be below --high {args.high:g}", file=sys.stderr)
        return 2
    if args.scan is not None and (args.step is not None or args.absolute_step is not None):
        given = "--step" if args.step is not None else "--absolute-step"
        print(f"error: --scan {args.scan} gives evenly spaced values: leave out {given}, or --scan",
              file=sys.stderr)
        return 2
    loaded = _threshold_scene(args)
    if loaded is None:
        return 2
    data, spec, motion_at = loaded
    unit = _parameter_unit(data.get("excitation", {}).get("kind"), args.parameter)
    settings = dict(spec.simulation)
    if args.duration is not None:
        settings["duration"] = args.duration
    step = SCAN_STEP if args.step is None else args.step
    search = {"step": step, "absolute_step": args.absolute_step, "scan": args.scan, "tolerance": args.tolerance}
    grid = scan_grid(args.low, args.high, step=step, absolute_step=args.absolute_step, scan=args.scan)
    print(f"searching for {args.criterion}: {args.parameter} from {_parameter_text(args.low, unit)} to "
          f"{_parameter_text(args.high, unit)}: {_scan_text(args, step, unit, len(grid))}, then each change "
          f"refined to {_percent(args.tolerance)} of its value")
    _compile_first(spec.scene, spec.excitation, settings)

    def gap(value):
        """The scan's step near ``value``: the bracket each change starts from."""
        if args.scan is not None:
            return (args.high - args.low) / (args.scan - 1)
        return min(step * value, args.absolute_step or math.inf)

    bar = _progress(total=len(grid) + _bisections(gap(args.high), args.high, args.tolerance), desc="runs",
                    unit="run")

    def on_run(value, happened):
        if happened and not any(h for _, h in runs_so_far):
            bar.total = len(grid) + _bisections(gap(value), value, args.tolerance)
        runs_so_far.append((value, happened))
        bar.set_postfix_str(f"{args.parameter} = {value:.4g} {unit}".rstrip())
        bar.update()

    runs_so_far = []
    args.on_interrupt = lambda: f"the search was stopped after {len(runs_so_far)} run(s); nothing was written"
    options = {**search, "on_run": on_run, **_simulate_options(settings, progress=False)}
    try:
        if args.criterion == "overturning":
            found = overturning_threshold(spec.scene, motion_at, args.low, args.high, **options)
        else:
            found = onset_threshold(spec.scene, motion_at, args.low, args.high, criterion=args.criterion, **options)
    except (SceneFileError, TypeError, ValueError) as exc:
        print(f"error: {exc}", file=sys.stderr)
        return 2
    finally:
        bar.total = bar.n
        bar.close()
    for first, last, count, happened in _outcome_ranges(found.runs):
        values = _parameter_text(first, unit) if count == 1 else \
            f"{_parameter_text(first, unit)} to {_parameter_text(last, unit)} ({count} runs)"
        print(f"  {args.parameter} = {values}: {args.criterion if happened else 'no ' + args.criterion}")
    for value, message in found.failures:
        print(f"  {args.parameter} = {_parameter_text(value, unit)}: failed ({message.splitlines()[0]})")
    if np.isfinite(found.value):
        bracket = f"{found.below:.4g} and {found.above:.4g} {unit}".rstrip()
        print(f"{args.criterion} threshold: {args.parameter} = {_parameter_text(found.value, unit)}, between "
              f"{bracket}{'' if found.monotonic else '; not monotonic: see the runs above'}")
    elif found.above is None:
        print(f"no {args.criterion} up to {args.parameter} = {_parameter_text(args.high, unit)}")
    else:
        print(f"{args.criterion} already at {args.parameter} = {_parameter_text(args.low, unit)}: lower --low")
    return 0


def _scan_text(args, step, unit, runs) -> str:
    """How the threshold command scans, in words: "a scan of 91 runs, each 2% above the last"."""
    if args.scan is not None:
        return f"a scan of {runs} evenly spaced runs"
    cap = f", at most {_parameter_text(args.absolute_step, unit, 3)}" if args.absolute_step is not None else ""
    return f"a scan of {runs} runs, each {_percent(step)} above the last{cap}"


def _percent(fraction: float) -> str:
    """0.02 as "2%", 0.005 as "0.5%"."""
    return f"{100 * fraction:.3g}%"


def _outcome_ranges(runs) -> list:
    """``(first, last, count, happened)`` of each range of consecutive values (sorted) with one outcome."""
    ranges = []
    for value, happened in sorted(runs):
        if ranges and ranges[-1][3] == happened:
            first, _, count, _ = ranges[-1]
            ranges[-1] = (first, value, count + 1, happened)
        else:
            ranges.append((value, value, 1, happened))
    return ranges


def _threshold_scene(args):
    """(the scene file's tables, the scene file, ``motion_at(value)``) of the threshold command, or None after
    printing why the file, or its excitation with ``--parameter`` set to ``--low`` or ``--high``, cannot be
    built; an excitation that cannot be built names the key ``--parameter`` sets."""
    from .analyses.sweep import SceneFileBuild

    try:
        data = read_toml(args.scene)
        build = SceneFileBuild(data, str(args.scene))
        spec = build({})
    except SceneFileError as exc:
        print(f"error: {exc}", file=sys.stderr)
        return None
    key = f"excitation.{args.parameter}"

    def motion_at(value):
        try:
            return build({key: value}).excitation
        except SceneFileError as exc:
            raise SceneFileError(f"{exc} ({_parameter_hint(data, args.scene, args.parameter, value)})") from None

    try:
        motion_at(args.low)
        motion_at(args.high)
    except SceneFileError as exc:
        print(f"error: {exc}", file=sys.stderr)
        return None
    return data, spec, motion_at


def _parameter_hint(data: dict, path, parameter: str, value) -> str:
    """Which key ``--parameter`` sets, and the key of the scene file's [excitation] it cannot stand beside (the
    one whose removal lets the excitation be built), if there is one."""
    from .analyses.sweep import SceneFileBuild

    hint = f"--parameter {parameter} sets [excitation] {parameter}"
    table = data.get("excitation")
    for other in [k for k in table if k not in ("kind", parameter)] if isinstance(table, dict) else []:
        trial = {**data, "excitation": {k: v for k, v in table.items() if k != other}}
        try:
            SceneFileBuild(trial, str(path))({f"excitation.{parameter}": value})
        except Exception:  # noqa: BLE001 - only whether it builds without that key matters
            continue
        return f"{hint}; the scene file gives {other}: use --parameter {other} or remove it"
    return hint


def _ramp(args) -> int:
    from .analyses.thresholds import ROCKING_FRACTION, SLIP_THRESHOLD, onset_under_ramp

    spec = _load_or_fail(args.scene)
    if spec is None:
        return 2
    settings = {k: v for k, v in spec.simulation.items() if k not in ("duration", "output_dt")}
    _compile_first(spec.scene, None, settings)
    try:
        found = onset_under_ramp(spec.scene, args.rate, args.duration, **_simulate_options(settings))
    except (SimulationUnstable, TypeError, ValueError) as exc:
        return _failed_run(exc, args.scene)
    theta_cr = spec.scene.rocking_slenderness
    criteria = {
        "starts rocking": f"a block's rotation passes theta_cr/{1 / ROCKING_FRACTION:.0f} = "
                          f"{ROCKING_FRACTION * theta_cr:.3g} rad (theta_cr = {theta_cr:.3g} rad, the scene's "
                          f"slenderness)",
        "starts sliding": f"an interface slips more than {SLIP_THRESHOLD:g} m",
        "overturns": "a block passes its critical angle or falls half its size, or a column tips past its base"}
    print(f"ramp of {args.rate:g} m/s^2 per s, run for {found.result.t[-1]:.4g} s; the ground acceleration when "
          "the scene")
    for what, value in (("starts rocking", found.rocking), ("starts sliding", found.sliding),
                        ("overturns", found.overturning)):
        shown = acceleration_text(value, 4) if np.isfinite(value) else "not reached"
        print(f"  {what:15s} {shown:24s} criterion: {criteria[what]}")
    uplift = _static_uplift(spec.scene, found.result)
    if uplift:
        print(uplift)
    return 0


def _static_uplift(scene, result) -> str:
    """For a scene that is one block, or one stack of blocks (a column), the line giving its static uplift
    acceleration g b/h (b/h = tan of the critical angle: the stack as one rigid body), to set the rocking onset
    against; '' for other scenes."""
    stacks = [c for c in result.columns if set(c.blocks) == set(result.names)]
    if not stacks:
        return ""
    what = "the block" if len(result.names) == 1 else "the column as one rigid block"
    ratio = math.tan(stacks[0].critical_angle)
    return (f"for comparison, the static uplift acceleration g b/h = {acceleration_text(scene.gravity * ratio, 3)} "
            f"({what}, b/h = {ratio:.3g}): a corner starts to lift there; rocking counts from the rotation above")


def _scene_and_settings(args):
    """(path, scene file, simulate settings with --duration applied) of a command's SCENE argument
    (the bundled default if none), or None after printing why it cannot be read."""
    path = Path(args.scene) if args.scene else default_scene_path()
    spec = _load_or_fail(path)
    if spec is None:
        return None
    settings = dict(spec.simulation)
    if args.duration is not None:
        settings["duration"] = args.duration
    return path, spec, settings


def _animate(args) -> int:
    loaded = _scene_and_settings(args)
    if loaded is None:
        return 2
    path, spec, settings = loaded
    if not _movie_name_ok(args.out, "--out"):
        return 2
    movie = output_file(args.out, "--out")
    try:
        duration = run_duration(spec.excitation, settings.get("duration"))
    except (TypeError, ValueError) as exc:
        print(f"error: {path}: {exc}", file=sys.stderr)
        return 2
    frames = duration * args.fps / args.speed + 1
    if frames > MOST_FRAMES:
        print(f"error: --speed {args.speed:g} at --fps {args.fps}: the animation of {duration:.4g} s would have "
              f"{frames:.3g} frames, more than {MOST_FRAMES}: raise --speed, lower --fps or shorten --duration",
              file=sys.stderr)
        return 2
    settings["output_dt"] = min(settings.get("output_dt", 0.01), args.speed / args.fps)
    print(f"scene {path} ({len(spec.scene.blocks)} blocks), ground motion: {_motion_text(spec.excitation)}")
    args.on_interrupt = lambda: f"nothing was written ({movie} is written whole or not at all)"
    status = 0
    try:
        result, _ = _simulated(spec, settings)
    except SimulationUnstable as exc:
        INTERRUPTS.check()
        result, status = exc.partial, 3
        if result is None or len(result.t) == 0:
            print(f"error: {_stopped_text(exc)}; nothing was written", file=sys.stderr)
            return 3
        print(f"error: {_stopped_text(exc)}; animating up to t = {result.t[-1]:.4g} s", file=sys.stderr)
    except (TypeError, ValueError) as exc:
        print(f"error: {path}: {exc}", file=sys.stderr)
        return 2
    INTERRUPTS.check()
    _write_animation(spec, result, movie, movie.with_name(movie.stem + "_snapshots.png"), path.stem, args.fps,
                     args.speed, args.exaggerate)
    return status


def _movie_name_ok(name: str, option: str) -> bool:
    """Whether an animation file name has a format we write; says why not before any run starts."""
    from .pictures.animation import can_write_mp4

    suffix = Path(name).suffix.lower()
    if suffix == ".gif" or (suffix == ".mp4" and can_write_mp4()):
        return True
    if suffix == ".mp4":
        print(f"error: {option} {name}: writing MP4 needs ffmpeg: install it, or pip install imageio-ffmpeg "
              "(pip install -e .[video]), or write a .gif", file=sys.stderr)
    else:
        print(f"error: {option} {name}: an animation file must end in .gif or .mp4", file=sys.stderr)
    return False


def _spectrum(args) -> int:
    import matplotlib.pyplot as plt
    import pandas as pd
    from matplotlib.figure import Figure

    from .inputs.excitation import record
    from .analyses.spectra import response_spectrum, spectrum_figure

    out = Path(args.out) if Path(args.out).suffix else Path(args.out).with_suffix(".png")
    formats = Figure().canvas.get_supported_filetypes()
    if out.suffix[1:].lower() not in formats:
        print(f"error: --out {out}: the figure's format is taken from its name: end it in one of "
              f"{', '.join('.' + f for f in sorted(formats))}", file=sys.stderr)
        return 2
    output_file(out, "--out")
    table_path = output_file(out.with_suffix(".csv"), "--out")
    try:
        spectra = [response_spectrum(record(name), damping=args.damping) for name in args.records]
    except (OSError, ValueError) as exc:
        print(f"error: {exc}", file=sys.stderr)
        return 2
    figure = spectrum_figure(spectra)
    try:
        with replacing(out) as tmp:
            figure.savefig(tmp, dpi=130, format=out.suffix[1:].lower())
    finally:
        plt.close(figure)
    table = pd.concat([pd.DataFrame({"record": s.name, "period_s": s.periods, "sd_m": s.sd, "psv_m_s": s.psv,
                                     "psa_m_s2": s.psa, "damping": s.damping}) for s in spectra])
    with replacing(table_path) as tmp:
        table.to_csv(tmp, index=False)
    for s in spectra:
        k = int(np.argmax(s.psa))
        print(f"{s.name}: PGA {acceleration_text(s.pga)}, peak PSA {acceleration_text(s.psa[k])} at "
              f"T = {s.periods[k]:.3g} s, peak SD {np.max(s.sd):.3g} m")
    print(f"written {out} and {table_path}")
    return 0


def _stiffness(args) -> int:
    from .analyses.convergence import MEASURES, stiffness_convergence

    loaded = _scene_and_settings(args)
    if loaded is None:
        return 2
    _, spec, settings = loaded
    settings.pop("dt", None)  # each stiffness takes its own automatic step
    _compile_first(spec.scene, spec.excitation, settings)
    # a run's length grows as the square root of the stiffness (the step shrinks so): the bar counts that
    bar = _progress(total=sum(math.sqrt(max(f, 0.0)) for f in args.factors), desc="runs",
                    bar_format="{desc}: {percentage:3.0f}%|{bar}| [{elapsed}<{remaining}{postfix}]")

    def on_run(factor, result):
        bar.set_postfix_str(f"K_n x {factor:g} done")
        bar.update(math.sqrt(max(factor, 0.0)))

    try:
        table = stiffness_convergence(spec.scene, spec.excitation, factors=args.factors, on_run=on_run,
                                      **_simulate_options(settings))
    except (SimulationUnstable, TypeError, ValueError) as exc:
        return _failed_run(exc)
    finally:
        bar.close()
    shown = table[["factor", "kn", "dt_s", "run_time_s", *MEASURES]].rename(columns={"kn": "kn_N/m^2"})
    print(shown.to_string(index=False, float_format="%.4g"))
    for line in _stiffness_verdicts(table):
        print(line)
    return 0


def _stiffness_verdicts(table) -> list:
    """The lines that judge each measure of a stiffness table: its name, its value at each factor, and whether it
    converged (:func:`dem_core.analyses.convergence.verdicts`), with what to do when it did not."""
    from .analyses.convergence import FLOORS, RELATIVE_TOLERANCE, verdicts

    found = verdicts(table)
    if len(table) < 2:
        return ["one stiffness only: nothing to compare (give two --factors or more)"]
    lowest, stiffest = found[0].factors[0], found[0].factors[-1]
    floors = ", ".join(f"{_measure_text(value, unit)} of {what}" for what, value, unit in (
        ("rotation", FLOORS["max_peak_abs_theta_rad"], "rad"), ("sliding", FLOORS["total_sliding_m"], "m"),
        ("overturn time", FLOORS["overturn_time_s"], "s")))
    lines = [f"each measure at K_n x {lowest:g} against x {stiffest:g}, the stiffest: converged when it changes by "
             f"at most {_percent(RELATIVE_TOLERANCE)}, or by less than {floors}"]
    kn = dict(zip(table.factor, table.kn))
    for v in found:
        values = ", ".join(f"{_measure_text(value, v.unit)} at x {factor:g}" for factor, value in
                           zip(v.factors, v.values))
        lines.append(f"  {v.label}: {values}")
        if all(np.isnan(value) for value in v.values):
            lines.append("    converged: " + ("no overturn at any stiffness" if v.measure == "overturn_time_s" else
                                             "not measured"))
            continue
        if np.isnan(v.values[0]) != np.isnan(v.values[-1]):
            change = "an overturn at one stiffness and none at the other"
        else:
            relative = f"{v.change:+.1%}, " if np.isfinite(v.change) else ""
            change = f"{relative}{_measure_text(v.difference, v.unit, signed=True)}"
        if v.converged and np.isfinite(v.change) and abs(v.change) > RELATIVE_TOLERANCE:
            floor = _measure_text(FLOORS[v.measure], v.unit)
            lines.append(f"    converged: x {lowest:g} differs from x {stiffest:g} by {v.change:+.1%}, but only by "
                         f"{_measure_text(v.difference, v.unit, signed=True)}, less than the {floor} floor")
        elif v.converged:
            within = _percent(RELATIVE_TOLERANCE) if np.isfinite(v.change) else "the floor"
            lines.append(f"    converged: x {lowest:g} within {within} of x {stiffest:g} ({change})")
        elif v.agrees_from < stiffest:
            lines.append(f"    not converged at x {lowest:g} ({change}); it agrees from x {v.agrees_from:g}: rerun at "
                         f"a stiffer K_n ([contact] kn = {kn[v.agrees_from]:.3g}) or treat this measure as uncertain")
        else:
            lines.append(f"    not converged ({change} at x {lowest:g}), and the two stiffest runs disagree too: treat "
                         f"this measure as uncertain, or rerun stiffer still ([contact] kn)")
    return lines


def _measure_text(value: float, unit: str, signed: bool = False) -> str:
    """A measure as the stiffness command prints it: lengths in mm below 1 m, "none" for NaN (no overturn)."""
    if not np.isfinite(value):
        return "none"
    sign = "+" if signed else ""
    if unit == "m" and abs(value) < 1.0:
        return f"{1e3 * value:{sign}.3g} mm"
    return f"{value:{sign}.4g} {unit}"



def _fragility(args) -> int:
    from .analyses.fragility_study import DEFAULT_TOP, INTENSITY_MEASURES, fragility_study, state_label, stripes
    from .batch import check_device

    try:
        check_device(args.device)
    except ValueError as exc:
        print(f"error: --device: {exc}", file=sys.stderr)
        return 2
    loaded = _scene_and_settings(args)
    if loaded is None:
        return 2
    path, spec, settings = loaded
    suite = _record_suite(args)
    if suite is None:
        return 2
    out = output_folder(args.out, "--out")
    if args.integrator is not None:
        settings["integrator"] = args.integrator
    duration = settings.pop("duration", None)
    settings.pop("output_dt", None)
    label, unit = INTENSITY_MEASURES[args.im]
    levels = stripes(args.levels, args.max or DEFAULT_TOP[args.im])
    total = len(levels) * len(suite)
    print(f"fragility of {path.name}: {len(suite)} record(s) x {len(levels)} {label} levels from {levels[0]:.4g} to "
          f"{levels[-1]:.4g} {unit} ({total} runs), integrator {settings.get('integrator', 'explicit')}", flush=True)
    _compile_first(spec.scene, next(iter(suite.values())), settings)
    bar = _progress(total=total, desc="runs", unit="run")
    done = [0]

    def on_member(finished, _total):
        done[0] = finished
        bar.update(finished - bar.n)

    args.on_interrupt = lambda: f"stopped after {done[0]} of {total} runs; nothing was written"
    try:
        study = fragility_study(spec.scene, suite, levels, args.states, im=args.im, duration=duration,
                                device=args.device, threads=args.threads, progress=on_member, **settings)
    except (TypeError, ValueError) as exc:
        print(f"error: {exc}", file=sys.stderr)
        return 2
    finally:
        bar.close()
    failed = study.runs[study.runs["status"] != "ok"]
    print(f"{total} runs in {study.wall_time_s:.1f} s on {study.device}"
          + (f"; {len(failed)} did not finish and count in no stripe" if len(failed) else ""))
    for _, row in failed.head(5).iterrows():
        print(f"  {row['record']} at {label} {row['level']:.4g} {unit}: {row['status']}: "
              f"{str(row['error']).splitlines()[0]}")
    table = study.table()
    for _, row in table.iterrows():
        what = state_label(row["state"])
        if np.isfinite(row["median"]):
            print(f"  {what}: median {row['median']:.3g} {unit} (90% {row['median_low']:.3g} to "
                  f"{row['median_high']:.3g}), beta {row['beta']:.2f} ({row['beta_low']:.2f} to {row['beta_high']:.2f})"
                  f", {row['exceeded']} of {row['runs']} runs" + (f"; {row['note']}" if row["note"] else ""))
        else:
            print(f"  {what}: no fit: {row['note']}")
    written = _write_fragility(out, study, path, settings, duration)
    print(f"wrote {', '.join(written)} in {out}")
    return 0


def _record_suite(args):
    """{name: GroundMotion} of the fragility command's records (the bundled four by default), or None after
    printing which record could not be read."""
    from .inputs.excitation import record

    if args.records_dir:
        folder = Path(args.records_dir)
        if not folder.is_dir():
            print(f"error: --records-dir {folder}: not a folder", file=sys.stderr)
            return None
        sources = sorted(str(p) for p in folder.iterdir() if p.suffix.lower() in (".at2", ".txt", ".dat", ".csv"))
        if not sources:
            print(f"error: --records-dir {folder}: no .at2, .txt, .dat or .csv file in it", file=sys.stderr)
            return None
    else:
        sources = args.records or list(records.BUNDLED)
    suite = {}
    for source in sources:
        name = source if source in records.BUNDLED else Path(source).stem
        if name in suite:
            print(f"error: two records are named {name!r}: rename one", file=sys.stderr)
            return None
        try:
            suite[name] = record(source, units=args.units)
        except (OSError, ValueError) as exc:
            print(f"error: record {source}: {exc}", file=sys.stderr)
            return None
    return suite


def _write_fragility(out: Path, study, path: Path, settings: dict, duration) -> list:
    """Write the study's files into ``out``; returns their names."""
    from .analyses.fragility_study import write_study

    return write_study(study, out, f"Fragility of {path.stem}", {"scene": str(path), "duration_s": duration,
                                                                 "simulation": settings})


if __name__ == "__main__":
    sys.exit(main())
