"""``dem-core sweep SPEC --out DIR``: a parametric sweep (:mod:`dem_core.analyses.sweep`) on this machine's cores or
a Dask cluster, resumed where a previous run of it stopped."""

import sys

from ..analyses.sweep import SweepError, load_sweep, run_sweep, saved_runs, with_simulation
from ..engine.settings import INTEGRATORS
from ..output_files import output_folder
from .arguments import SECONDS, WORKERS, add_no_progress
from .progress import compile_first, progress_bar


def add(sub):
    command = sub.add_parser("sweep", help="run a parametric sweep file; resumes where a previous run stopped",
                           description="Run a parametric sweep.  Each finished run is saved at once in "
                             "OUT/runs/: after Ctrl-C (exit status 130) or a crash, the same command resumes, "
                             "running only what is missing; a saved run that cannot be read is run again.")
    command.add_argument("spec", help="sweep file: a scene file with a [sweep] table")
    command.add_argument("--out", required=True, help="output folder (results.parquet, runs/, histories/)")
    command.add_argument("--workers", type=WORKERS, help="processes on this machine, at least 1 (default: one per "
                         "core)")
    command.add_argument("--scheduler", help="address of a running Dask scheduler, e.g. tcp://10.0.0.5:8786 "
                         "(default: none, the runs go to processes on this machine)")
    command.add_argument("--retry-failed", action="store_true", help="run again the points that failed before")
    command.add_argument("--overwrite", action="store_true", help="delete the results already in --out and run every "
                         "point (without it, another sweep's results there are refused)")
    command.add_argument("--duration", type=SECONDS, help="simulated time of every run in s, replacing the file's "
                         "[simulation] duration; part of what identifies a run, so a folder of runs of another "
                         "duration is refused, not mixed (default: the file's, or each record's length)")
    command.add_argument("--integrator", choices=INTEGRATORS, help="the integrator of every run, replacing the file's "
                         "[simulation] integrator; part of what identifies a run, as --duration is (default: the "
                         "file's, else moreau, or explicit for the overlap-area law)")
    add_no_progress(command)


def run(args) -> int:
    try:
        sweep = load_sweep(args.spec)
        given = {key: value for key, value in (("duration", args.duration), ("integrator", args.integrator))
                 if value is not None}
        if given:
            sweep = with_simulation(sweep, **given)
    except SweepError as exc:
        print(f"error: {args.spec}: {exc}" if str(args.spec) not in str(exc) else f"error: {exc}", file=sys.stderr)
        return 2
    out = output_folder(args.out, "--out")
    points = len(sweep.points())
    where = f"Dask scheduler {args.scheduler}" if args.scheduler else f"{args.workers or 'all'} local worker(s)"
    each = f", each run for {args.duration:g} s (--duration)" if args.duration is not None else ""
    each += f", each by the {args.integrator} integrator (--integrator)" if args.integrator is not None else ""
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
                          progress=not args.no_progress, progress_bar=progress_bar, retry_failed=args.retry_failed,
                          overwrite=args.overwrite, on_start=on_start)
    except SweepError as exc:
        print(f"error: {exc}", file=sys.stderr)
        return 2
    counts = table.status.value_counts().to_dict() if len(table) else {}
    print(f"{run_counts(len(table), counts)}; results in {out}/results.parquet")
    for _, row in (table[table.status != "ok"].head(5).iterrows() if len(table) else ()):
        print(f"  {row.run_id} {row.status}: {row.error.splitlines()[0] if row.error else ''}")
    return 0 if counts.get("failed", 0) == 0 else 1


def run_counts(runs: int, counts: dict) -> str:
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
        compile_first(spec.scene, spec.excitation, spec.simulation)
        return
