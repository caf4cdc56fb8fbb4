"""What the study scripts share: where they write, how they run sweeps, how they describe what they found.

Each study writes into ``reports/studies/<name>/``: its figures (PNG), ``results.parquet`` (one row per
run) and ``README.md`` (the trend found, computed from the results, and the command that made it).
Sweeps run in ``.study_cache/<name>/`` (not committed), so an interrupted study resumes.
"""

import sys
import time
from pathlib import Path

import matplotlib

matplotlib.use("Agg")
import matplotlib.pyplot as plt
import numpy as np
from matplotlib import transforms

from dem_core.analyses.sweep import Sweep, run_sweep

ROOT = Path(__file__).resolve().parents[2]
REPORTS = ROOT / "reports" / "studies"
CACHE = ROOT / ".study_cache"
_SWEPT = []  # tables of the sweeps run by this process, for the compute time in the README


def out_dir(name: str) -> Path:
    path = REPORTS / name
    path.mkdir(parents=True, exist_ok=True)
    return path


def sweep(name: str, build, parameters: dict, *, workers=None, mode="grid"):
    """Run (or resume) a sweep of the study and return its table; failures are kept as rows."""
    table = run_sweep(Sweep(build, parameters, mode=mode), CACHE / name, workers=workers)
    _SWEPT.append(table)
    table.to_parquet(out_dir(name.split("/")[0]) / f"{name.replace('/', '_')}.parquet", index=False)
    bad = table[table.status != "ok"]
    if len(bad):
        print(f"{len(bad)} of {len(table)} runs did not finish:", bad.status.value_counts().to_dict(), file=sys.stderr)
    return table


def curve(ax, x, y, overturned, label, row=0, **style):
    """A line through the runs that stayed up; runs that overturned as crosses along the top edge,
    one row of crosses per series (their measures stop at the overturn and are not comparable)."""
    x, y, overturned = map(np.asarray, (x, y, overturned))
    line = ax.plot(x[~overturned], y[~overturned], "o-", ms=3, label=label, **style)[0]
    if overturned.any():
        top = transforms.blended_transform_factory(ax.transData, ax.transAxes)
        ax.plot(x[overturned], np.full(overturned.sum(), 0.97 - 0.05 * row), "x", color=line.get_color(), ms=7, mew=1.5,
                transform=top, clip_on=False)
    return line


def save(fig, name: str, file: str) -> str:
    fig.savefig(out_dir(name) / file, dpi=120)
    plt.close(fig)
    return file


def write_readme(name: str, title: str, findings: list, figures: list, started: float, script: str, *,
                 resumes: bool = True, tables: list = ()) -> None:
    """README.md of a study: ``tables`` (markdown lines) first, then the findings as bullets, the figures
    (file names, or (file name, what it shows) pairs) and the command that regenerates it."""
    lines = [f"# {title}", "", *tables, *[f"- {f}" for f in findings], ""]
    for figure in figures:
        file, caption = figure if isinstance(figure, tuple) else (figure, "")
        lines += [f"![{file}]({file})", "", *([caption, ""] if caption else [])]
    if resumes:
        runs = sum(len(t) for t in _SWEPT)
        compute = sum(t.wall_time_s.sum() for t in _SWEPT)
        cost = (f"{runs} runs, {compute:.0f} s of computing in all, spread over the cores; an interrupted or "
                "repeated run resumes from `.study_cache/`")
    else:
        cost = f"{time.perf_counter() - started:.0f} s on the machine that wrote this"
    lines += ["", f"Regenerate: `python examples/studies/{script}` ({cost})."]
    (out_dir(name) / "README.md").write_text("\n".join(lines) + "\n")
    print("\n".join(lines))
