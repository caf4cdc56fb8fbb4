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
* ``rotations.png``, ``displacements.png`` (and ``epistyles.png`` for colonnades).
"""

import argparse
import json
import sys
import time
from importlib import resources
from pathlib import Path

import numpy as np

from .inputs import records
from .inputs.scene_file import SceneFileError, load, read_toml
from .engine.simulation import SimulationUnstable, simulate

DEFAULT_SCENE = "column_el_centro.toml"


def default_scene_path() -> Path:
    return Path(str(resources.files("dem_core") / "data" / "scenes" / DEFAULT_SCENE))


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
    ramp = sub.add_parser("ramp", help="rocking, sliding and overturning accelerations under a monotonic ramp")
    ramp.add_argument("scene", help="scene file (its [excitation] is ignored)")
    ramp.add_argument("--rate", type=float, default=0.5, help="m/s^2 per s (default 0.5)")
    ramp.add_argument("--duration", type=float, help="s (default: until the ramp reaches 1 g)")
    anim = sub.add_parser("animate", help="run a scene file and write an animation and snapshots")
    anim.add_argument("scene", nargs="?", help=f"scene file; default the bundled {DEFAULT_SCENE}")
    anim.add_argument("--out", default="animation.gif", help="file to write (.gif or .mp4)")
    anim.add_argument("--duration", type=float)
    anim.add_argument("--fps", type=int, default=25)
    anim.add_argument("--speed", type=float, default=1.0, help="simulated seconds per second of playback")
    spectrum = sub.add_parser("spectrum", help="elastic response spectra of records")
    spectrum.add_argument("records", nargs="+", help="bundled record names or record files")
    spectrum.add_argument("--damping", type=float, default=0.05)
    spectrum.add_argument("--out", default="spectra.png", help="figure to write; a .csv beside it holds the values")
    stiffness = sub.add_parser("stiffness", help="rerun a scene file at stiffer contacts and compare the measures")
    stiffness.add_argument("scene", nargs="?", help=f"scene file; default the bundled {DEFAULT_SCENE}")
    stiffness.add_argument("--factors", type=float, nargs="+", default=[1.0, 10.0, 100.0],
                           help="multiples of the scene's K_n (default 1 10 100)")
    stiffness.add_argument("--duration", type=float)
    sub.add_parser("records", help="list the bundled accelerograms")
    args = parser.parse_args(argv)
    if args.command == "records":
        for name, entry in records.BUNDLED.items():
            print(f"{name:18s} {entry.description}")
        return 0
    commands = {"run": _run, "sweep": _sweep, "threshold": _threshold, "ramp": _ramp, "animate": _animate,
                "spectrum": _spectrum, "stiffness": _stiffness}
    return commands[args.command](args)


def _run(args) -> int:
    path = Path(args.scene) if args.scene else default_scene_path()
    try:
        spec = load(path)
    except SceneFileError as exc:
        print(f"error: {exc}", file=sys.stderr)
        return 2
    out = Path(args.out) if args.out else Path("results") / path.stem
    out.mkdir(parents=True, exist_ok=True)
    settings = dict(spec.simulation)
    if args.duration is not None:
        settings["duration"] = args.duration
    fmt = args.format or spec.output.get("format", "csv")
    print(f"scene {path} ({len(spec.scene.blocks)} blocks), ground motion: {spec.excitation.name}")
    started = time.perf_counter()
    status = 0
    try:
        result = simulate(spec.scene, spec.excitation, **settings)
    except SimulationUnstable as exc:
        print(f"error: {exc}", file=sys.stderr)
        result, status = exc.partial, 3
    except ValueError as exc:
        print(f"error: {path}: {exc}", file=sys.stderr)
        return 2
    wall = time.perf_counter() - started
    _write(result, out, fmt)
    if not args.no_plots and spec.output.get("plots", True) and len(result.t) > 1:
        from .pictures.plots import save_run_figures  # matplotlib loads only when figures are written

        save_run_figures(result, out, spec.excitation, title=path.stem)
    if args.animate:
        _write_animation(spec, result, out / args.animate, out / "snapshots.png", path.stem)
    info = result.info
    print(f"dt = {result.dt:.3g} s (stability limit {info.get('stability_limit_s', float('nan')):.3g} s), "
          f"{info.get('steps')} steps, run {info.get('run_time_s', 0):.2f} s, total {wall:.2f} s")
    print(f"peak |theta| {np.max(result.peak_theta):.4g} rad, total sliding {result.total_sliding:.4g} m, "
          f"overturned: {f'yes at t = {result.time_of_overturn:.3f} s' if result.overturned else 'no'}")
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


def _write_animation(spec, result, movie, strip, title, fps=25, speed=1.0):
    from .pictures.animation import animate, default_snapshot_times, snapshot_strip

    animate(spec.scene, result, movie, excitation=spec.excitation, fps=fps, speed=speed, title=title)
    figure = snapshot_strip(spec.scene, result, default_snapshot_times(result), title=title)
    figure.savefig(strip, dpi=110)
    print(f"animation written to {movie}, snapshots to {strip}")


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
                          progress=not args.no_progress, retry_failed=args.retry_failed, overwrite=args.overwrite)
    except SweepError as exc:
        print(f"error: {exc}", file=sys.stderr)
        return 2
    counts = table.status.value_counts().to_dict()
    print(f"{len(table)} runs in {args.out}/results.parquet: {counts}")
    for _, row in table[table.status != "ok"].head(5).iterrows():
        print(f"  {row.run_id} {row.status}: {row.error.splitlines()[0] if row.error else ''}")
    return 0 if counts.get("failed", 0) == 0 else 1


def _threshold(args) -> int:
    from .analyses.sweep import SceneFileBuild
    from .analyses.thresholds import onset_threshold, overturning_threshold

    try:
        build = SceneFileBuild(read_toml(args.scene), str(args.scene))
        spec = build({})
    except SceneFileError as exc:
        print(f"error: {exc}", file=sys.stderr)
        return 2
    key = f"excitation.{args.parameter}"

    def motion_at(value):
        return build({key: value}).excitation

    try:
        motion_at(args.low)
        if args.criterion == "overturning":
            found = overturning_threshold(spec.scene, motion_at, args.low, args.high, tolerance=args.tolerance,
                                          scan=args.scan, **spec.simulation)
        else:
            found = onset_threshold(spec.scene, motion_at, args.low, args.high, criterion=args.criterion,
                                    tolerance=args.tolerance, scan=args.scan, **spec.simulation)
    except (SceneFileError, ValueError) as exc:
        print(f"error: {exc}", file=sys.stderr)
        return 2
    for value, happened in found.runs:
        print(f"  {args.parameter} = {value:.5g}: {args.criterion if happened else 'no ' + args.criterion}")
    if np.isfinite(found.value):
        print(f"{args.criterion} threshold: {args.parameter} = {found.value:.4g} (between {found.below:.4g} and "
              f"{found.above:.4g}){'' if found.monotonic else '; not monotonic: see the runs above'}")
    elif found.above is None:
        print(f"no {args.criterion} up to {args.parameter} = {args.high:g}")
    else:
        print(f"{args.criterion} already at {args.parameter} = {args.low:g}: lower --low")
    return 0


def _ramp(args) -> int:
    from .analyses.thresholds import onset_under_ramp

    spec = _load_or_fail(args.scene)
    if spec is None:
        return 2
    settings = {k: v for k, v in spec.simulation.items() if k not in ("duration", "output_dt")}
    found = onset_under_ramp(spec.scene, args.rate, args.duration, **settings)
    for what, value in (("rocking starts", found.rocking), ("sliding starts", found.sliding),
                        ("overturns", found.overturning)):
        text = f"{value:.4g} m/s^2 ({value / spec.scene.gravity:.4g} g)" if np.isfinite(value) else "not reached"
        print(f"{what:15s} {text}")
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
    settings["output_dt"] = min(settings.get("output_dt", 0.01), args.speed / args.fps)
    try:
        result = simulate(spec.scene, spec.excitation, **settings)
    except SimulationUnstable as exc:
        print(f"error: {exc}; animating up to there", file=sys.stderr)
        result = exc.partial
    movie = Path(args.out)
    _write_animation(spec, result, movie, movie.with_name(movie.stem + "_snapshots.png"), path.stem, args.fps,
                     args.speed)
    return 0


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
        print(f"{s.name}: PGA {s.pga:.3g} m/s^2, peak PSA {s.psa[k]:.3g} m/s^2 at T = {s.periods[k]:.3g} s")
    print(f"written {out} and {out.with_suffix('.csv')}")
    return 0


def _stiffness(args) -> int:
    from .analyses.convergence import MEASURES, stiffness_convergence

    loaded = _scene_and_settings(args)
    if loaded is None:
        return 2
    _, spec, settings = loaded
    settings.pop("dt", None)  # each stiffness takes its own automatic step
    try:
        table = stiffness_convergence(spec.scene, spec.excitation, factors=args.factors, **settings)
    except (ValueError, SimulationUnstable) as exc:
        print(f"error: {exc}", file=sys.stderr)
        return 2
    print(table[["factor", "kn", "dt_s", "run_time_s", *MEASURES]].to_string(index=False, float_format="%.4g"))
    worst = table.iloc[0][[f"change:{m}" for m in MEASURES[:3]]].abs().max()
    print(f"largest relative change of the first three measures from K_n x {table.factor.iloc[0]:g} to "
          f"x {table.factor.iloc[-1]:g}: {worst:.1%}")
    return 0


if __name__ == "__main__":
    sys.exit(main())
