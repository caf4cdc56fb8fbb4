"""Command line: ``dem-core run [SCENE.toml]`` (also ``python -m dem_core run``).

Runs a scene file (or the bundled default: an 8-drum column under the 1940
El Centro record) and writes into the output folder:

* ``time_history.csv`` (or ``.parquet``): one row per output time and block
  (t, block, x, y, theta, x_rel, base_x, base_y);
* ``metrics.csv``: per block peak |theta|, residual displacement, sliding,
  mean |theta|, overturn;
* ``summary.json``: scene-level measures and run facts (time step and
  stability limit, steps, compile and run wall times);
* ``rotations.png`` and ``displacements.png``.
"""

import argparse
import json
import sys
import time
from importlib import resources
from pathlib import Path

import numpy as np

from . import records
from .scene_file import SceneFileError, load
from .simulation import SimulationUnstable, simulate

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
    sub.add_parser("records", help="list the bundled accelerograms")
    args = parser.parse_args(argv)
    if args.command == "records":
        for name, entry in records.BUNDLED.items():
            print(f"{name:18s} {entry.description}")
        return 0
    return _run(args)


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
        from .plots import save_run_figures  # matplotlib loads only when figures are written

        save_run_figures(result, out, spec.excitation, title=path.stem)
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


if __name__ == "__main__":
    sys.exit(main())
