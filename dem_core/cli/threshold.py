"""``dem-core threshold SCENE``: the smallest value of an [excitation] key at which the scene overturns, or starts
rocking or sliding, by the scan and bisection of :mod:`dem_core.analyses.thresholds`."""

import json
import math
import sys

import numpy as np
import pandas as pd

from ..analyses.cluster import ClusterError
from ..analyses.study_members import LOG
from ..analyses.sweep import SceneFileBuild
from ..analyses.thresholds import SCAN_STEP, TOLERANCE, onset_threshold, overturning_threshold, scan_grid
from ..inputs.scene_file import SceneFileError, read_toml
from ..output_files import output_folder, replacing
from .arguments import (DEFAULT_SCENE, FRACTION, POSITIVE, SCALES, SECONDS, add_integrator, add_no_progress,
                        default_scene_path, with_integrator)
from .console import acceleration_text, percent
from .progress import compile_first, progress_bar, simulate_options


def add(sub):
    threshold = sub.add_parser(
        "threshold", help="smallest excitation value that overturns the scene (or starts it rocking or sliding), "
        "by a fine scan and bisection",
        description="The smallest value of an [excitation] key (the PGA by default) at which the scene overturns, "
        "or starts rocking or sliding: the search of dem_core.analyses.thresholds with its defaults.  Every "
        "value of a scan from --low to --high is run (each the last plus --step of it, the increase capped at "
        "--absolute-step; or --scan evenly spaced values), then every change between neighbouring values "
        "(standing to overturned, and back: the response is not monotonic) is bisected until its bracket is "
        "narrower than --tolerance of its upper end.")
    threshold.add_argument("scene", nargs="?", help=f"scene file whose [excitation] is scaled; default the bundled "
                           f"{DEFAULT_SCENE}")
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
    add_integrator(threshold)
    threshold.add_argument("--out", help="output folder, created if need be: runs.csv (every run's value and "
                           "outcome) and threshold.json (the answer and the settings), and members.jsonl, every "
                           "finished run as it ends, from which the same command resumes after Ctrl-C or a crash "
                           "(default: none, nothing written)")
    threshold.add_argument("--scheduler", help="address of a running Dask scheduler, e.g. tcp://10.0.0.5:8786, whose "
                           "workers run the scan's runs, one a task (default: none, this machine's cores)")
    add_no_progress(threshold)


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


def parameter_text(value, unit, digits=4) -> str:
    if unit == "m/s^2":
        return acceleration_text(value, digits)
    return f"{value:.{digits}g} {unit}".rstrip()


def _bisections(width, above, tolerance) -> int:
    """Halvings that bring a bracket of ``width`` below ``tolerance`` times ``above`` (an estimate of
    the runs a search has left, for its progress bar)."""
    if not (tolerance > 0 and above > 0) or width <= tolerance * above:
        return 0
    return math.ceil(math.log2(width / (tolerance * above)))


def run(args) -> int:
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
    settings = with_integrator(spec.simulation, args)
    if args.duration is not None:
        settings["duration"] = args.duration
    step = SCAN_STEP if args.step is None else args.step
    search = {"step": step, "absolute_step": args.absolute_step, "scan": args.scan, "tolerance": args.tolerance}
    grid = scan_grid(args.low, args.high, step=step, absolute_step=args.absolute_step, scan=args.scan)
    print(f"searching for {args.criterion}: {args.parameter} from {parameter_text(args.low, unit)} to "
          f"{parameter_text(args.high, unit)}: {_scan_text(args, step, unit, len(grid))}, then each change "
          f"refined to {percent(args.tolerance)} of its value")
    out = output_folder(args.out, "--out") if args.out else None
    if args.scheduler is None:
        compile_first(spec.scene, spec.excitation, settings)

    def gap(value):
        """The scan's step near ``value``: the bracket each change starts from."""
        if args.scan is not None:
            return (args.high - args.low) / (args.scan - 1)
        return min(step * value, args.absolute_step or math.inf)

    bar = progress_bar(total=len(grid) + _bisections(gap(args.high), args.high, args.tolerance), desc="runs",
                       unit="run", disable=args.no_progress)

    def on_run(value, happened):
        if happened and not any(h for _, h in runs_so_far):
            bar.total = len(grid) + _bisections(gap(value), value, args.tolerance)
        runs_so_far.append((value, happened))
        bar.set_postfix_str(f"{args.parameter} = {value:.4g} {unit}".rstrip())
        bar.update()

    runs_so_far = []
    log = None if out is None else out / LOG
    args.on_interrupt = lambda: (f"the search was stopped after {len(runs_so_far)} run(s); " + (
        "nothing was written" if log is None else f"the finished ones are saved in {log}: run the same command "
                                                  f"again to resume"))
    options = {**search, "on_run": on_run, "log": log, "scheduler": args.scheduler,
               **simulate_options(settings, progress=False)}
    try:
        if args.criterion == "overturning":
            found = overturning_threshold(spec.scene, motion_at, args.low, args.high, **options)
        else:
            found = onset_threshold(spec.scene, motion_at, args.low, args.high, criterion=args.criterion, **options)
    except (SceneFileError, TypeError, ValueError) as exc:
        print(f"error: {f'--scheduler: {exc}' if isinstance(exc, ClusterError) else exc}", file=sys.stderr)
        return 2
    finally:
        bar.total = bar.n
        bar.close()
    for first, last, count, happened in _outcome_ranges(found.runs):
        values = parameter_text(first, unit) if count == 1 else \
            f"{parameter_text(first, unit)} to {parameter_text(last, unit)} ({count} runs)"
        print(f"  {args.parameter} = {values}: {args.criterion if happened else 'no ' + args.criterion}")
    for value, message in found.failures:
        print(f"  {args.parameter} = {parameter_text(value, unit)}: failed ({message.splitlines()[0]})")
    if np.isfinite(found.value):
        bracket = f"{found.below:.4g} and {found.above:.4g} {unit}".rstrip()
        print(f"{args.criterion} threshold: {args.parameter} = {parameter_text(found.value, unit)}, between "
              f"{bracket}{'' if found.monotonic else '; not monotonic: see the runs above'}")
    elif found.above is None:
        print(f"no {args.criterion} up to {args.parameter} = {parameter_text(args.high, unit)}")
    else:
        print(f"{args.criterion} already at {args.parameter} = {parameter_text(args.low, unit)}: lower --low")
    if out is not None:
        _write_threshold(out, found, args, unit, settings)
        print(f"wrote runs.csv and threshold.json in {out}")
    return 0


def _write_threshold(out, found, args, unit: str, settings: dict) -> None:
    """``runs.csv`` (value, outcome: the criterion happened, not, or failed with its message) and ``threshold.json``
    (the answer, its bracket and the search's settings) of a search, each whole or not at all."""
    runs = pd.DataFrame([(value, "yes" if happened else "no", "") for value, happened in found.runs]
                        + [(value, "failed", message.splitlines()[0]) for value, message in found.failures],
                        columns=[args.parameter, args.criterion, "error"]).sort_values(args.parameter)
    answer = {"criterion": args.criterion, "parameter": args.parameter, "unit": unit,
              "threshold": found.value if np.isfinite(found.value) else None, "below": found.below,
              "above": found.above, "monotonic": found.monotonic, "runs": len(found.runs),
              "failures": len(found.failures), "scene": str(args.scene), "low": args.low, "high": args.high,
              "step": args.step, "absolute_step": args.absolute_step, "scan": args.scan,
              "tolerance": args.tolerance, "simulation": settings}
    with replacing(out / "runs.csv") as tmp:
        runs.to_csv(tmp, index=False)
    with replacing(out / "threshold.json") as tmp:
        tmp.write_text(json.dumps(answer, indent=2, default=str))


def _scan_text(args, step, unit, runs) -> str:
    """How the threshold command scans, in words: "a scan of 91 runs, each 2% above the last"."""
    if args.scan is not None:
        return f"a scan of {runs} evenly spaced runs"
    cap = f", at most {parameter_text(args.absolute_step, unit, 3)}" if args.absolute_step is not None else ""
    return f"a scan of {runs} runs, each {percent(step)} above the last{cap}"


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
    args.scene = args.scene or default_scene_path()
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
