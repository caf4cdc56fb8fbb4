"""Command line: ``dem-core COMMAND`` (also ``python -m dem_core COMMAND``).

* ``run [SCENE.toml]``: run a scene file (default: the bundled 8-drum column
  under the 1940 El Centro record), write results and plots (below);
  ``--animate run.gif`` adds an animation and a snapshot strip;
* ``sweep SPEC.toml --out DIR``: a parametric sweep (:mod:`dem_core.analyses.sweep`) on
  this machine's cores or, with ``--scheduler ADDRESS``, on a Dask cluster;
* ``threshold SCENE.toml``: the smallest PGA (or other excitation parameter)
  that overturns the scene, or starts it rocking or sliding;
* ``ramp SCENE.toml --rate 0.5``: rocking, sliding and overturning
  accelerations under a monotonic ramp;
* ``animate SCENE.toml --out run.gif``: run and animate (GIF or MP4);
* ``spectrum RECORD ... --out spectra.png``: elastic response spectra;
* ``stiffness SCENE.toml``: the run again at 10 and 100 times the contact stiffness, to see
  whether the answer depends on it;
* ``records``: the bundled accelerograms.

``run`` writes into the output folder:

* ``time_history.csv`` (or ``.parquet``): one row per output time and block
  (t, block, x, y, theta, x_rel, base_x, base_y);
* ``metrics.csv``: per block peak |theta|, residual displacement, sliding,
  mean |theta|, overturn;
* ``summary.json``: scene-level measures and run facts (time step and
  stability limit, steps, compile and run wall times);
* ``rotations.png``, ``displacements.png``, ``sliding.png`` (and ``epistyles.png`` for colonnades).

Accelerations are printed in m/s^2 with g in brackets, ``PGA 2.75 m/s^2 (0.281 g)``; every other
quantity in SI units.  Long work (frames, the runs of a search) shows a progress bar with an
estimate of the time left when stderr is a terminal, and nothing otherwise (CI, logs).
"""

import argparse
import json
import math
import re
import sys
import time
import warnings
from importlib import resources
from pathlib import Path

import numpy as np

from .inputs import records
from .inputs.records import G_STANDARD
from .inputs.scene_file import SceneFileError, load, read_toml
from .simulation import SimulationUnstable, simulate

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
    own bar over the runs and pass False)."""
    options = dict(settings)
    if progress and sys.stderr.isatty():
        options["progress"] = _StepProgress()
    return options


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


def main(argv=None) -> int:
    parser = argparse.ArgumentParser(prog="dem-core", description="Seismic response of stone columns and colonnades "
                                     "(native soft-contact DEM).")
    sub = parser.add_subparsers(dest="command", required=True)
    run = sub.add_parser("run", help="run a scene file and write results and plots")
    run.add_argument("scene", nargs="?", help=f"scene file (TOML); default: the bundled {DEFAULT_SCENE}")
    run.add_argument("--out", help="output folder (default: results/<scene name>)")
    run.add_argument("--format", choices=("csv", "parquet"), help="time-history format (default from the file, csv)")
    run.add_argument("--duration", type=float, help="simulated time in s (default from the file or the record)")
    run.add_argument("--no-plots", action="store_true", help="skip the figures")
    run.add_argument("--animate", metavar="FILE", help="also write an animation (.gif or .mp4, relative to --out) "
                     "and snapshots.png")
    run.add_argument("--exaggerate", type=float, default=1.0, metavar="K",
                     help="draw rotations and displacements K times larger in the animation (default 1)")
    run.add_argument("--relative-rotations", action="store_true",
                     help="plot rotations as theta / alpha, alpha the critical angle (column's for drums)")
    sweep = sub.add_parser("sweep", help="run a parametric sweep file; resumes where a previous run stopped")
    sweep.add_argument("spec", help="sweep file: a scene file with a [sweep] table")
    sweep.add_argument("--out", required=True, help="output folder (results.parquet, runs/, histories/)")
    sweep.add_argument("--workers", type=int, help="processes on this machine (default: one per core)")
    sweep.add_argument("--scheduler", help="address of a running Dask scheduler, e.g. tcp://10.0.0.5:8786")
    sweep.add_argument("--retry-failed", action="store_true", help="run again the points that failed before")
    sweep.add_argument("--overwrite", action="store_true", help="delete the results already in --out and run every "
                       "point (without it, another sweep's results there are refused)")
    sweep.add_argument("--no-progress", action="store_true")
    threshold = sub.add_parser("threshold", help="smallest excitation scale that overturns the scene (or starts "
                               "rocking or sliding), by a scan and bisection")
    threshold.add_argument("scene", help="scene file whose [excitation] is scaled")
    threshold.add_argument("--parameter", default="pga", help="the [excitation] key that is varied (default pga)")
    threshold.add_argument("--low", type=float, required=True)
    threshold.add_argument("--high", type=float, required=True)
    threshold.add_argument("--criterion", choices=("overturning", "rocking", "sliding"), default="overturning")
    threshold.add_argument("--tolerance", type=float, default=0.02, help="relative width of the final bracket")
    threshold.add_argument("--scan", type=int, default=6, help="scales tried before bisecting")
    threshold.add_argument("--duration", type=float, help="simulated time of each run in s (default from the file "
                           "or the record)")
    ramp = sub.add_parser("ramp", help="rocking, sliding and overturning accelerations under a monotonic ramp")
    ramp.add_argument("scene", help="scene file (its [excitation] is ignored)")
    ramp.add_argument("--rate", type=float, default=0.5, help="m/s^2 per s (default 0.5)")
    ramp.add_argument("--duration", type=float, help="s (default: until the ramp reaches 1 g)")
    anim = sub.add_parser("animate", help="run a scene file and write an animation and snapshots")
    anim.add_argument("scene", nargs="?", help=f"scene file; default the bundled {DEFAULT_SCENE}")
    anim.add_argument("--out", default="animation.gif", help="file to write (.gif or .mp4)")
    anim.add_argument("--duration", type=float, help="simulated time in s (default from the file or the record)")
    anim.add_argument("--fps", type=int, default=25)
    anim.add_argument("--speed", type=float, default=1.0, help="simulated seconds per second of playback")
    anim.add_argument("--exaggerate", type=float, default=1.0, metavar="K",
                      help="draw rotations and displacements relative to the start K times larger (default 1)")
    spectrum = sub.add_parser("spectrum", help="elastic response spectra of records")
    spectrum.add_argument("records", nargs="+", help="bundled record names or record files")
    spectrum.add_argument("--damping", type=float, default=0.05)
    spectrum.add_argument("--out", default="spectra.png", help="figure to write; a .csv beside it holds the values")
    stiffness = sub.add_parser("stiffness", help="rerun a scene file at stiffer contacts and compare the measures")
    stiffness.add_argument("scene", nargs="?", help=f"scene file; default the bundled {DEFAULT_SCENE}")
    stiffness.add_argument("--factors", type=float, nargs="+", default=[1.0, 10.0, 100.0],
                           help="multiples of the scene's K_n (default 1 10 100)")
    stiffness.add_argument("--duration", type=float, help="simulated time in s (default from the file or the record)")
    sub.add_parser("records", help="list the bundled accelerograms")
    args = parser.parse_args(argv)
    if args.command == "records":
        return _records()
    commands = {"run": _run, "sweep": _sweep, "threshold": _threshold, "ramp": _ramp, "animate": _animate,
                "spectrum": _spectrum, "stiffness": _stiffness}
    with warnings.catch_warnings():
        warnings.showwarning = _show_warning
        return commands[args.command](args)


def _show_warning(message, category, filename, lineno, file=None, line=None):
    """Warnings as a line a user reads ("warning: a long run: ..."), not Python's file, line and source."""
    print(f"warning: {message}", file=sys.stderr if file is None else file, flush=True)


def _records() -> int:
    from .inputs.excitation import record

    for name, entry in records.BUNDLED.items():
        horizontal = record(name).horizontal
        what = re.sub(r"\s*\(PGA [^)]*\)", "", entry.description)
        print(f"{name:18s} PGA {acceleration_text(horizontal.peak_acceleration)}, {horizontal.end_time:.4g} s "
              f"every {horizontal.dt:.3g} s: {what}")
    return 0


def _motion_text(motion) -> str:
    """The ground motion's name and, when it has one, its peak horizontal acceleration."""
    peak = motion.horizontal.peak_acceleration
    return f"{motion.name}, PGA {acceleration_text(peak)}" if np.isfinite(peak) and peak > 0 else motion.name


def _run(args) -> int:
    path = Path(args.scene) if args.scene else default_scene_path()
    try:
        spec = load(path)
    except SceneFileError as exc:
        print(f"error: {exc}", file=sys.stderr)
        return 2
    if not args.exaggerate > 0:
        print(f"error: --exaggerate must be positive, got {args.exaggerate:g}", file=sys.stderr)
        return 2
    if args.exaggerate != 1 and not args.animate:
        print("note: --exaggerate applies to the animation: add --animate run.gif", file=sys.stderr)
    if args.animate and not _movie_name_ok(args.animate, "--animate"):
        return 2
    out = Path(args.out) if args.out else Path("results") / path.stem
    out.mkdir(parents=True, exist_ok=True)
    settings = dict(spec.simulation)
    if args.duration is not None:
        settings["duration"] = args.duration
    fmt = args.format or spec.output.get("format", "csv")
    print(f"scene {path} ({len(spec.scene.blocks)} blocks), ground motion: {_motion_text(spec.excitation)}")
    started = time.perf_counter()
    status = 0
    try:
        result = simulate(spec.scene, spec.excitation, **_simulate_options(settings))
    except SimulationUnstable as exc:
        print(f"error: {exc}", file=sys.stderr)
        result, status = exc.partial, 3
    except ValueError as exc:
        print(f"error: {path}: {exc}", file=sys.stderr)
        return 2
    wall = time.perf_counter() - started
    info = result.info
    print(f"{info.get('contact_law', '?')} contact law, K_n = {info.get('kn', float('nan')):.3g} N/m^2; dt = "
          f"{result.dt:.3g} s (stability limit {info.get('stability_limit_s', float('nan')):.3g} s), "
          f"{info.get('steps')} steps, run {info.get('run_time_s', 0):.2f} s, total {wall:.2f} s")
    print(f"peak |theta| {np.max(result.peak_theta):.4g} rad, total sliding {result.total_sliding:.4g} m, "
          f"overturned: {f'yes at t = {result.time_of_overturn:.3f} s' if result.overturned else 'no'}")
    _write(result, out, fmt)
    if not args.no_plots and spec.output.get("plots", True) and len(result.t) > 1:
        from .pictures.plots import save_run_figures  # matplotlib loads only when figures are written

        written = save_run_figures(result, out, spec.excitation, title=path.stem,
                                   relative_rotations=args.relative_rotations)
        print(f"figures: {', '.join(p.name for p in written)}")
    if args.animate:
        _write_animation(spec, result, out / args.animate, out / "snapshots.png", path.stem,
                         exaggerate=args.exaggerate)
    print(f"results written to {out}/")
    return status


def _write(result, out: Path, fmt: str):
    frame = result.to_frame()
    if fmt == "parquet":
        frame.to_parquet(out / "time_history.parquet", index=False)
    else:
        frame.to_csv(out / "time_history.csv", index=False)
    result.metrics().to_csv(out / "metrics.csv", index=False)
    summary = {k: (v.item() if isinstance(v, np.generic) else v) for k, v in result.summary().items()}
    summary["blocks"] = list(result.names)
    summary = {k: (None if isinstance(v, float) and not np.isfinite(v) else v) for k, v in summary.items()}
    (out / "summary.json").write_text(json.dumps(summary, indent=2))


def _write_animation(spec, result, movie, strip, title, fps=25, speed=1.0, exaggerate=1.0):
    from .pictures.animation import animate, default_snapshot_times, frame_indices, snapshot_strip

    animate(spec.scene, result, movie, excitation=spec.excitation, fps=fps, speed=speed, title=title,
            exaggerate=exaggerate, progress=_interactive())
    figure = snapshot_strip(spec.scene, result, default_snapshot_times(result), title=title, exaggerate=exaggerate)
    figure.savefig(strip, dpi=110)
    frames = len(frame_indices(result, fps, speed))
    shown = f", rotations and displacements x {exaggerate:g}" if exaggerate != 1 else ""
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
    from .analyses.sweep import SweepError, load_sweep, run_sweep

    try:
        sweep = load_sweep(args.spec)
    except SweepError as exc:
        print(f"error: {exc}", file=sys.stderr)
        return 2
    points = len(sweep.points())
    where = f"Dask scheduler {args.scheduler}" if args.scheduler else f"{args.workers or 'all'} local worker(s)"
    print(f"sweep {args.spec}: {points} runs over {', '.join(sweep.parameters)} on {where}")
    try:
        table = run_sweep(sweep, args.out, workers=args.workers, scheduler=args.scheduler,
                          progress=False if args.no_progress else None, retry_failed=args.retry_failed,
                          overwrite=args.overwrite)
    except SweepError as exc:
        print(f"error: {exc}", file=sys.stderr)
        return 2
    counts = table.status.value_counts().to_dict()
    print(f"{len(table)} runs in {args.out}/results.parquet: {counts}")
    for _, row in table[table.status != "ok"].head(5).iterrows():
        print(f"  {row.run_id} {row.status}: {row.error.splitlines()[0] if row.error else ''}")
    return 0 if counts.get("failed", 0) == 0 else 1


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
    from .analyses.sweep import SceneFileBuild
    from .analyses.thresholds import onset_threshold, overturning_threshold

    try:
        data = read_toml(args.scene)
        build = SceneFileBuild(data, str(args.scene))
        spec = build({})
    except SceneFileError as exc:
        print(f"error: {exc}", file=sys.stderr)
        return 2
    key = f"excitation.{args.parameter}"
    unit = _parameter_unit(data.get("excitation", {}).get("kind"), args.parameter)
    settings = dict(spec.simulation)
    if args.duration is not None:
        settings["duration"] = args.duration

    def motion_at(value):
        return build({key: value}).excitation

    scan_step = (args.high - args.low) / max(args.scan - 1, 1)
    bar = _progress(total=args.scan + _bisections(scan_step, args.high, args.tolerance), desc="runs", unit="run")

    def on_run(value, happened):
        if happened and not any(h for _, h in runs_so_far):
            bar.total = len(runs_so_far) + 1 + _bisections(scan_step, value, args.tolerance)
        runs_so_far.append((value, happened))
        bar.set_postfix_str(f"{args.parameter} = {value:.4g} {unit}".rstrip())
        bar.update()

    runs_so_far = []
    options = {"tolerance": args.tolerance, "scan": args.scan, "on_run": on_run,
               **_simulate_options(settings, progress=False)}
    try:
        motion_at(args.low)
        if args.criterion == "overturning":
            found = overturning_threshold(spec.scene, motion_at, args.low, args.high, **options)
        else:
            found = onset_threshold(spec.scene, motion_at, args.low, args.high, criterion=args.criterion, **options)
    except (SceneFileError, ValueError) as exc:
        print(f"error: {exc}", file=sys.stderr)
        return 2
    finally:
        bar.total = bar.n
        bar.close()
    for value, happened in found.runs:
        print(f"  {args.parameter} = {_parameter_text(value, unit)}: "
              f"{args.criterion if happened else 'no ' + args.criterion}")
    if np.isfinite(found.value):
        bracket = f"{found.below:.4g} and {found.above:.4g} {unit}".rstrip()
        print(f"{args.criterion} threshold: {args.parameter} = {_parameter_text(found.value, unit)}, between "
              f"{bracket}{'' if found.monotonic else '; not monotonic: see the runs above'}")
    elif found.above is None:
        print(f"no {args.criterion} up to {args.parameter} = {_parameter_text(args.high, unit)}")
    else:
        print(f"{args.criterion} already at {args.parameter} = {_parameter_text(args.low, unit)}: lower --low")
    return 0


def _ramp(args) -> int:
    from .analyses.thresholds import onset_under_ramp

    spec = _load_or_fail(args.scene)
    if spec is None:
        return 2
    settings = {k: v for k, v in spec.simulation.items() if k not in ("duration", "output_dt")}
    found = onset_under_ramp(spec.scene, args.rate, args.duration, **_simulate_options(settings))
    print(f"ramp of {args.rate:g} m/s^2 per s, run for {found.result.t[-1]:.4g} s; the ground acceleration when "
          "the scene")
    for what, value in (("starts rocking", found.rocking), ("starts sliding", found.sliding),
                        ("overturns", found.overturning)):
        print(f"  {what:15s} {acceleration_text(value, 4) if np.isfinite(value) else 'not reached'}")
    return 0


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
    if not args.exaggerate > 0:
        print(f"error: --exaggerate must be positive, got {args.exaggerate:g}", file=sys.stderr)
        return 2
    if not _movie_name_ok(args.out, "--out"):
        return 2
    if not (args.fps > 0 and args.speed > 0):
        print(f"error: --fps and --speed must be positive, got {args.fps} and {args.speed:g}", file=sys.stderr)
        return 2
    settings["output_dt"] = min(settings.get("output_dt", 0.01), args.speed / args.fps)
    print(f"scene {path} ({len(spec.scene.blocks)} blocks), ground motion: {_motion_text(spec.excitation)}")
    try:
        result = simulate(spec.scene, spec.excitation, **_simulate_options(settings))
    except SimulationUnstable as exc:
        print(f"error: {exc}; animating up to there", file=sys.stderr)
        result = exc.partial
    except ValueError as exc:
        print(f"error: {path}: {exc}", file=sys.stderr)
        return 2
    movie = Path(args.out)
    _write_animation(spec, result, movie, movie.with_name(movie.stem + "_snapshots.png"), path.stem, args.fps,
                     args.speed, args.exaggerate)
    return 0


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

    from .inputs.excitation import record
    from .analyses.spectra import response_spectrum, spectrum_figure

    try:
        spectra = [response_spectrum(record(name), damping=args.damping) for name in args.records]
    except (OSError, ValueError) as exc:
        print(f"error: {exc}", file=sys.stderr)
        return 2
    out = Path(args.out)
    out.parent.mkdir(parents=True, exist_ok=True)
    figure = spectrum_figure(spectra)
    figure.savefig(out, dpi=130)
    plt.close(figure)
    table = pd.concat([pd.DataFrame({"record": s.name, "period_s": s.periods, "sd_m": s.sd, "psv_m_s": s.psv,
                                     "psa_m_s2": s.psa, "damping": s.damping}) for s in spectra])
    table.to_csv(out.with_suffix(".csv"), index=False)
    for s in spectra:
        k = int(np.argmax(s.psa))
        print(f"{s.name}: PGA {acceleration_text(s.pga)}, peak PSA {acceleration_text(s.psa[k])} at "
              f"T = {s.periods[k]:.3g} s, peak SD {np.max(s.sd):.3g} m")
    print(f"written {out} and {out.with_suffix('.csv')}")
    return 0


def _stiffness(args) -> int:
    from .analyses.convergence import MEASURES, stiffness_convergence

    loaded = _scene_and_settings(args)
    if loaded is None:
        return 2
    _, spec, settings = loaded
    settings.pop("dt", None)  # each stiffness takes its own automatic step
    # a run's length grows as the square root of the stiffness (the step shrinks so): the bar counts that
    bar = _progress(total=sum(math.sqrt(max(f, 0.0)) for f in args.factors), desc="runs",
                    bar_format="{desc}: {percentage:3.0f}%|{bar}| [{elapsed}<{remaining}{postfix}]")

    def on_run(factor, result):
        bar.set_postfix_str(f"K_n x {factor:g} done")
        bar.update(math.sqrt(max(factor, 0.0)))

    try:
        table = stiffness_convergence(spec.scene, spec.excitation, factors=args.factors, on_run=on_run,
                                      **_simulate_options(settings))
    except (ValueError, SimulationUnstable) as exc:
        print(f"error: {exc}", file=sys.stderr)
        return 2
    finally:
        bar.close()
    shown = table[["factor", "kn", "dt_s", "run_time_s", *MEASURES]].rename(columns={"kn": "kn_N/m^2"})
    print(shown.to_string(index=False, float_format="%.4g"))
    worst = table.iloc[0][[f"change:{m}" for m in MEASURES[:3]]].abs().max()
    print(f"largest relative change of the first three measures from K_n x {table.factor.iloc[0]:g} to "
          f"x {table.factor.iloc[-1]:g}: {worst:.1%}")
    return 0


if __name__ == "__main__":
    sys.exit(main())
