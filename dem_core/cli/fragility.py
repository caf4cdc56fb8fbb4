"""``dem-core fragility [SCENE] --out DIR``: fragility curves of the scene under a suite of records scaled to stripes
of PGA, PGV or Sa(T), every run one batch (:mod:`dem_core.analyses.fragility_study`)."""

import sys
from pathlib import Path

import numpy as np

from ..analyses.cluster import ClusterError
from ..analyses.fragility_study import (DEFAULT_STATES, DEFAULT_TOP, INTENSITY_MEASURES, RESIDUAL_REST,
                                        check_period, fragility_study, state_label, stripes, write_study)
from ..analyses.study_members import LOG
from ..batch import DEVICES, check_device
from ..inputs import records
from ..inputs.records import G_STANDARD
from ..inputs.excitation import record, strong_motion_cuts
from ..inputs.suites import BUNDLED_SUITES, DEFAULT_SUITE, METADATA, SuiteError, load_suite
from ..output_files import output_folder
from ..simulation import integrator_for
from .arguments import (DEFAULT_SCENE, LEVELS, POSITIVE, REST, SECONDS, STATE, WORKERS, add_integrator,
                        add_no_progress, scene_and_settings)
from .progress import compile_first, progress_bar


def add(sub):
    fragility = sub.add_parser(
        "fragility", help="fragility curves: the scene under a suite of records scaled to stripes of PGA, PGV or Sa(T)",
        description="Run the scene under each record of the suite scaled to each of --levels intensities evenly "
        "spaced up to --max (multiple-stripe analysis), as batches on every core (or on the workers of a Dask "
        "cluster), and fit lognormal fragilities to the damage states together by maximum likelihood, one "
        "dispersion and ordered medians so that no curves cross, with 90% bands drawn by record "
        "(dem_core.analyses.nested_fragility).  A "
        "damage state is a peak |theta|/alpha (alpha the column's critical angle for a drum, else the block's "
        "own); 1 is overturning.  Writes fragility.csv (median and dispersion per state with their "
        "bands), counts.csv (runs and exceedances per level and state), runs.csv (every run's measures), "
        "fragility.png and study.json (the settings, the machine and the wall time).  Every finished run is saved "
        "in OUT/members.jsonl as "
        "it ends: after Ctrl-C or a crash the same command resumes, running only what is missing.")
    fragility.add_argument("scene", nargs="?", help=f"scene file (its [excitation] is ignored); default the bundled "
                           f"{DEFAULT_SCENE}")
    suite = fragility.add_mutually_exclusive_group()
    suite.add_argument("--suite", default=DEFAULT_SUITE, help=f"a record suite: a folder of record files with an "
                       f"optional {METADATA} (see dem-core records), or a bundled suite's name (default: "
                       f"{DEFAULT_SUITE}, {BUNDLED_SUITES[DEFAULT_SUITE]})")
    suite.add_argument("--records", nargs="+", metavar="RECORD", help="bundled record names or record files (AT2 "
                       "or text) as the suite instead (default: none, --suite)")
    fragility.add_argument("--units", choices=("m/s^2", "g", "cm/s^2"), default="m/s^2", help=f"units of text "
                           f"records {METADATA} gives none for (AT2 files state theirs)")
    fragility.add_argument("--im", choices=tuple(INTENSITY_MEASURES), default="pga", help="intensity measure of the "
                           "horizontal component: peak ground acceleration (m/s^2) or velocity (m/s), or the "
                           "5%%-damped spectral acceleration at --period (m/s^2)")
    fragility.add_argument("--period", type=POSITIVE,
                           help="s, the period of --im sa (default: none; required with --im sa)")
    fragility.add_argument("--levels", type=LEVELS, default=32, help="intensity levels (stripes) per record, 2 to "
                           "100000")
    fragility.add_argument("--max", type=POSITIVE, help="highest level, in the measure's unit; the levels are evenly "
                           "spaced from max/levels to max (default: 1 g of PGA or Sa, 1 m/s of PGV)")
    fragility.add_argument("--states", type=STATE, nargs="+", default=list(DEFAULT_STATES),
                           help="damage states as peak |theta|/alpha, each above 0 and at most 1; 1 is overturning")
    fragility.add_argument("--dislocation", type=POSITIVE, nargs="+", metavar="MM", help="damage states as the "
                           "largest residual dislocation of a block over the one below it, in mm, measured after "
                           "--rest (default: none)")
    fragility.add_argument("--tilt", type=POSITIVE, nargs="+", metavar="RAD", help="damage states as the residual "
                           "tilt, rad: the lean the run added to the line through a column's bottom and top blocks, or "
                           "a lone block's rotation, measured after --rest (default: none)")
    fragility.add_argument("--rest", type=REST, help=f"s of ground at rest after each record, so that the runs end "
                           f"at rest (default: {RESIDUAL_REST:g} with --dislocation or --tilt, else 0)")
    fragility.add_argument("--out", required=True, help="output folder, created if need be")
    fragility.add_argument("--duration", type=SECONDS, help="simulated time of each run in s (default: from the "
                           "file, else each record's length)")
    add_integrator(fragility)
    fragility.add_argument("--device", choices=DEVICES, default="auto", help="where the batch runs")
    fragility.add_argument("--threads", type=WORKERS, help="runs at once on this machine (default: one per core)")
    fragility.add_argument("--scheduler", help="address of a running Dask scheduler, e.g. tcp://10.0.0.5:8786, whose "
                           "workers each run one record's stripes as a batch on their cores or GPU (default: none, "
                           "this machine)")
    add_no_progress(fragility)


def run(args) -> int:
    try:
        check_device(args.device)
    except ValueError as exc:
        print(f"error: --device: {exc}", file=sys.stderr)
        return 2
    loaded = scene_and_settings(args)
    if loaded is None:
        return 2
    path, spec, settings = loaded
    suite = _record_suite(args)
    if suite is None:
        return 2
    duration = settings.pop("duration", None)
    settings.pop("output_dt", None)
    refused = _refusal(args, suite, duration)
    if refused:
        print(f"error: {refused}", file=sys.stderr)
        return 2
    label, unit = INTENSITY_MEASURES[args.im]
    if args.im == "sa":
        label = f"Sa({args.period:g} s)"
    out = output_folder(args.out, "--out")
    levels = stripes(args.levels, args.max or DEFAULT_TOP[args.im])
    total = len(levels) * len(suite)
    integrator = integrator_for(spec.scene, settings.get("integrator"))
    where = f" on the Dask scheduler {args.scheduler}" if args.scheduler else ""
    print(f"fragility of {path.name}: {len(suite)} record(s) x {len(levels)} {label} levels from {levels[0]:.4g} to "
          f"{levels[-1]:.4g} {unit} ({total} runs), integrator {integrator}{where}", flush=True)
    if args.scheduler is None:
        compile_first(spec.scene, next(iter(suite.values())), settings)
    bar = progress_bar(total=total, desc="runs", unit="run", disable=args.no_progress)
    log = out / LOG
    done = [0]

    def on_member(finished, _total):
        done[0] = finished
        bar.update(finished - bar.n)

    args.on_interrupt = lambda: (f"stopped after {done[0]} of {total} runs, saved in {log}: run the same command "
                                 f"again to resume")
    try:
        residual = {name: values for name, values in (("dislocation", args.dislocation), ("tilt", args.tilt))
                    if values}
        study = fragility_study(spec.scene, suite, levels, args.states, im=args.im, period=args.period,
                                duration=duration, device=args.device, threads=args.threads, progress=on_member,
                                log=log, scheduler=args.scheduler, residual=residual, rest=args.rest, **settings)
    except (TypeError, ValueError) as exc:
        print(f"error: {f'--scheduler: {exc}' if isinstance(exc, ClusterError) else exc}", file=sys.stderr)
        return 2
    finally:
        bar.close()
    failed = study.runs[study.runs["status"] != "ok"]
    resumed = f" ({study.resumed} read from {log}, saved by an earlier run)" if study.resumed else ""
    print(f"{total} runs{resumed} in {study.wall_time_s:.1f} s on {study.device}"
          + (f"; {len(failed)} did not finish and count in no stripe" if len(failed) else ""))
    for _, row in failed.head(5).iterrows():
        print(f"  {row['record']} at {label} {row['level']:.4g} {unit}: {row['status']}: "
              f"{str(row['error']).splitlines()[0]}")
    written = _write_fragility(out, study, path, settings, duration)
    _print_fits(study, unit)
    print(f"wrote {', '.join(written)} in {out}")
    return 0


def _print_fits(study, unit: str) -> None:
    """Each damage state's fit, the runs left moving at the end of their rest, and the intensity measures'
    dispersions, as the command prints them."""
    table = study.table()
    print(f"  each measure's states fitted together (one beta, ordered medians); 90% bands drawn by record from "
          f"{study.runs['record'].nunique()} records")
    moving = study.still_moving()
    if moving:
        print(f"  {moving} standing run(s) still moved at the end of their {study.settings['rest']:g} s rest (the "
              f"residual measures leave a column's rocking as one body out; a longer --rest lets it die out)")
    for _, row in table.iterrows():
        what = state_label(row["state"] if row["measure"] == "peak" else (row["measure"], row["state"]))
        if np.isfinite(row["median"]):
            in_g = f" = {row['median'] / G_STANDARD:.3g} g" if unit == "m/s^2" else ""
            ida = (f"; IDA-style {row['ida_median']:.3g} {unit} ({row['ida_records']} of {row['records']} records)"
                   if np.isfinite(row["ida_median"]) else "")
            print(f"  {what}: median {row['median']:.3g} {unit}{in_g} (90% {row['median_low']:.3g} to "
                  f"{row['median_high']:.3g}), beta {row['beta']:.2f} ({row['beta_low']:.2f} to {row['beta_high']:.2f})"
                  f", {row['exceeded']} of {row['runs']} runs{ida}" + (f"; {row['note']}" if row["note"] else ""))
        else:
            print(f"  {what}: no fit: {row['note']}")
    measures = study.intensity_measures()
    if len(measures):
        print("  dispersion by intensity measure (the smaller, the better it predicts the damage): " + ", ".join(
            f"{row['measure'].split(' (')[0]} {row['beta']:.2f}" for _, row in measures.iterrows()))


def _refusal(args, suite: dict, duration) -> str:
    """Why the fragility command cannot run the suite, or '': a duration that cuts a record's strong motion, or a
    period missing, unusable for a record, or given without --im sa."""
    if (args.dislocation or args.tilt) and duration is not None and args.rest != 0:
        given = "--duration" if args.duration is not None else "the scene file's [simulation] duration"
        return (f"{given}: residual states are read after each whole record and --rest s at rest; leave out the "
                f"duration, or give --rest 0 to read them at its end")
    cuts = strong_motion_cuts((motion, duration) for motion in suite.values())
    if cuts:
        return (f"{'--duration' if args.duration is not None else 'the scene file duration'}: {cuts[0]}; a "
                f"fragility of cut records would understate the damage")
    if args.im != "sa":
        return f"--period is the period of --im sa, not of --im {args.im}" if args.period is not None else ""
    if args.period is None:
        return "--im sa: give the period with --period"
    for motion in suite.values():
        try:
            check_period(motion, args.period)
        except ValueError as exc:
            return f"--period: {exc}"
    return ""


def _record_suite(args):
    """{name: GroundMotion} of the fragility command's records (--records, else the --suite), or None after printing
    which record could not be read."""
    if not args.records:
        try:
            return load_suite(args.suite, args.units).motions()
        except SuiteError as exc:
            print(f"error: --suite: {exc}", file=sys.stderr)
            return None
    suite = {}
    for source in args.records:
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
    return write_study(study, out, f"Fragility of {path.stem}", {"scene": str(path), "duration_s": duration,
                                                                 "simulation": settings})
