"""``dem-core run [SCENE]``: run a scene file and write its results and figures into a folder
(:mod:`dem_core.run_folder`)."""

import json
import sys
from pathlib import Path

import numpy as np

from ..engine.result import EVENT_MEASURES
from ..engine.settings import MOREAU_RESCUE_SWEEPS, MOREAU_SOLVER_FAILURE
from ..output_files import output_file, output_folder
from ..pictures import slip_scale
from ..run_folder import RUN_FILES, run_summary, write_run, write_summary
from ..scene_json import write_scene_json
from ..simulation import SimulationUnstable
from .arguments import (
    DEFAULT_SCENE,
    POSITIVE,
    SECONDS,
    add_integrator,
    default_scene_path,
    load_or_fail,
    with_integrator,
)
from .console import Refused, motion_text, stopped_text
from .interrupts import INTERRUPTS
from .single_run import movie_name_ok, simulated, write_animation


def add(sub):
    command = sub.add_parser("run", help="run a scene file and write results and plots",
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
                             "interface (sliding_m, adding up to the total sliding); under a sequence of records "
                             "(source = [...]) events.csv, one row per event with the residual dislocation of each "
                             "joint and the residual tilt of each column it left; summary.json; the figures.")
    command.add_argument("scene", nargs="?", help=f"scene file (TOML); default: the bundled {DEFAULT_SCENE}")
    command.add_argument("--out", help="output folder (default: results/<scene name>), created if need be")
    command.add_argument("--overwrite", action="store_true", help="replace the results of another scene's run in "
                         "--out (its files are deleted before this run's are written); without it such a folder is "
                         "refused")
    command.add_argument("--format", choices=("csv", "parquet"), help="time-history format (default: the file's "
                         "[output] format, else csv)")
    command.add_argument("--duration", type=SECONDS, help="simulated time in s (default: from the file or the record)")
    add_integrator(command)
    command.add_argument("--no-plots", action="store_true", help="skip the figures")
    command.add_argument("--animate", metavar="FILE", help="also write an animation (.gif or .mp4, relative to --out) "
                         "and snapshots.png (default: none)")
    command.add_argument("--exaggerate", type=POSITIVE, default=1.0, metavar="K",
                         help="draw each block's rotation and displacement on what it rests on K times larger in the "
                         "animation, K > 0 (default: 1); a block rocking on a corner still stands on it")
    command.add_argument("--vtu", action="store_true", help="also write the blocks as a VTU time series for "
                         "ParaView: vtu/blocks.pvd (open it) and a VTU file per frame, at most 25 frames per "
                         "simulated second")
    command.add_argument("--relative-rotations", action="store_true",
                         help="plot rotations as theta / alpha, alpha the critical angle (column's for drums)")


def run(args) -> int:
    path = Path(args.scene) if args.scene else default_scene_path()
    spec = load_or_fail(path)
    if spec is None:
        return 2
    if args.exaggerate != 1 and not args.animate:
        print("note: --exaggerate applies to the animation: add --animate run.gif", file=sys.stderr)
    if args.animate and not movie_name_ok(args.animate, "--animate"):
        return 2
    out = output_folder(Path(args.out) if args.out else Path("results") / path.stem, "--out")
    movie = output_file(out / args.animate, "--animate") if args.animate else None
    previous = _previous_run(out, path, args.overwrite)
    settings = with_integrator(spec.simulation, args)
    if args.duration is not None:
        settings["duration"] = args.duration
    fmt = args.format or spec.output.get("format", "csv")
    print(f"scene {path} ({len(spec.scene.blocks)} blocks), ground motion: {motion_text(spec.excitation)}")
    args.on_interrupt = lambda: f"the run was stopped before its results were written: {out}/ is as it was"
    stopped = ""
    try:
        result, setup = simulated(spec, settings)
    except SimulationUnstable as exc:
        INTERRUPTS.check()
        result, stopped, setup = exc.partial, stopped_text(exc), getattr(exc, "setup_s", None)
        if result is None or len(result.t) == 0:
            print(f"error: {stopped}; nothing was written", file=sys.stderr)
            return 3
    except (TypeError, ValueError) as exc:
        print(f"error: {path}: {exc}", file=sys.stderr)
        return 2
    INTERRUPTS.check()
    ratio = result.damage_ratio
    scale, unit = slip_scale(result.total_sliding)
    print(f"peak |theta| {np.max(result.peak_theta):.4g} rad"
          + (f" (peak |theta|/alpha {ratio:.3g}, alpha the critical angle that governs each block, its "
             "column's for a drum)"
             if np.isfinite(ratio) else "")
          + f", total sliding {scale * result.total_sliding:.4g} {unit}, "
          f"overturned: {f'yes at t = {result.time_of_overturn:.3f} s' if result.overturned else 'no'}")
    for line in _solver_lines(result) + _connector_lines(result):
        print(line)
    for line in _event_lines(result):
        print(line)
    args.on_interrupt = lambda: (f"writing the results into {out}/ was stopped: they are incomplete (summary.json "
                                 "says so); run the same command again")
    args.after_write_error = lambda: f"the results in {out}/ are incomplete"
    for old in previous:
        old.unlink(missing_ok=True)
    summary = run_summary(result, path, stopped, setup)
    written = write_run(result, out, fmt, summary)
    write_scene_json(spec.scene, out / "scene.json")
    written.append("scene.json")
    if not args.no_plots and spec.output.get("plots", True) and len(result.t) > 1:
        from ..pictures.plots import save_run_figures  # matplotlib loads only when figures are written

        figures = save_run_figures(result, out, spec.excitation, title=path.stem,
                                   relative_rotations=args.relative_rotations)
        written += [p.name for p in figures]
        print(f"figures: {', '.join(p.name for p in figures)}")
    if movie is not None:
        write_animation(spec, result, movie, out / "snapshots.png", path.stem, exaggerate=args.exaggerate)
        written += [movie.resolve().relative_to(out.resolve()).as_posix() if _inside(movie, out) else str(movie),
                    "snapshots.png"]
    if args.vtu:
        from ..vtu_series import write_vtu_series  # meshio loads only when a series is written

        collection = write_vtu_series(spec.scene, result, out / "vtu")
        written += [collection.relative_to(out).as_posix(), "vtu/blocks_*.vtu"]
        print(f"VTU time series: {collection.relative_to(out).as_posix()} (open it in ParaView)")
    write_summary(out, {**summary, "status": "stopped" if stopped else "complete", "files": written})
    if not stopped:
        print(f"results written to {out}/")
        return 0
    print(f"results up to t = {result.t[-1]:.4g} s written to {out}/")
    print(f"error: {stopped}; the results up to t = {result.t[-1]:.6g} s are written to {out}/, marked \"stopped\" "
          "in summary.json", file=sys.stderr)
    return 3


def _solver_lines(result) -> list:
    """A line on Moreau-Jean's contact solves that ended short of their tolerance (none if none did, or under central
    differences): how many, in how many steps (a step split at an impact solves each part), which of them a part
    keeps (those whose last sweep, after up to ``MOREAU_RESCUE_SWEEPS`` more, changed no velocity by more than
    ``MOREAU_SOLVER_FAILURE`` g times the part's length; the others' parts are taken again at half their length, and
    a part whose retries fail too stops the run with an error), what a finished run's kept solves met and how to
    check its measures (the run again at half its step), and where summary.json and the method say more."""
    unconverged = result.info.get("unconverged_steps", 0)
    if not unconverged:
        return []
    return [f"contact solve: {unconverged:,} solves in {result.info['steps']:,} steps ended short of their tolerance "
            f"after the sweeps a part allows; such a solve is kept where its last sweep (after up to "
            f"{MOREAU_RESCUE_SWEEPS:,} more) changed no velocity by more than {MOREAU_SOLVER_FAILURE:g} g times the "
            "part's length, else the part is taken again at half its length, and a run whose retries fail too stops "
            "with an error. The run finished, so each solve it kept met that bound, not the tolerance; the same run at "
            f"half the step ([simulation] dt = {result.dt / 2:g}) shows how far its measures are from converged, "
            "these solves included (unconverged_steps in summary.json; docs/method.md 1.8)"]


def _connector_lines(result) -> list:
    """A line on the scene's connectors (none without): how many yielded and ruptured, and the largest shear."""
    table = result.connectors
    if table is None:
        return []
    worst = table.loc[table.peak_shear_N.idxmax()]
    return [f"connectors: {len(table)}, {int(table.yielded.sum())} yielded, {int(table.ruptured.sum())} ruptured; "
            f"largest shear {worst.peak_shear_N / 1e3:.3g} kN ({worst['name']}, {worst.kind}); connectors.csv"]


def _event_lines(result) -> list:
    """A line per event of a sequence of ground motions (:attr:`~dem_core.Result.events`; none under one motion): its
    motion, when it ran and what it left against the run's start, the largest residual tilt and dislocation."""
    if result.events is None:
        return []
    lines = []
    for row in result.events.to_dict("records"):
        dislocations, tilts = ({key[len(measure) + 1:-1]: abs(value) for key, value in row.items()
                                if key.startswith(measure + "[")} for measure in EVENT_MEASURES)
        joint = max(dislocations, key=dislocations.get, default=None)
        lines.append(f"event {row['event']}, {row['motion']} ({row['start_s']:.4g} to {row['end_s']:.4g} s): residual "
                     f"tilt {max(tilts.values(), default=0.0):.3g} rad, largest dislocation "
                     + (f"{1e3 * dislocations[joint]:.3g} mm ({joint})" if joint else "none (no joints)"))
    return lines


def _previous_run(out: Path, scene: Path, overwrite: bool) -> list:
    """The files of an earlier run in ``out``, to be deleted before this run's are written ([] if none): an
    earlier run of the same scene file is replaced whole (said on stderr); another scene's run, or one whose
    scene is not recorded, raises :class:`Refused` naming it, unless ``overwrite``."""
    try:
        previous = json.loads((out / "summary.json").read_text())
    except (OSError, ValueError):
        previous = {}
    previous = previous if isinstance(previous, dict) else {}
    listed = previous.get("files") if isinstance(previous.get("files"), list) else []
    names = {*RUN_FILES, *(name for name in listed if isinstance(name, str))}
    found = (p for name in names for p in (out.glob(name) if "*" in name else [out / name]))  # a pattern: a series
    files = sorted(p for p in found if _inside(p, out) and p.is_file())
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
    raise Refused(f"--out {out} holds {what}; the results of two runs are not mixed: give another --out, or "
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
