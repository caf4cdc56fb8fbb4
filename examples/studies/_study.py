"""What the study scripts share: where they write, how they run sweeps, how they describe what they found.

Each study writes into ``reports/studies/<name>/``: its figures (PNG), ``results.parquet`` (one row per
run) and ``README.md`` (the trend found, computed from the results, and the command that made it).
Sweeps run in ``.study_cache/<name>/`` (not committed), so an interrupted study resumes.
"""

import functools
import hashlib
import json
import sys
import time
from pathlib import Path

import matplotlib
from _checkout import ROOT

matplotlib.use("Agg")
import matplotlib.pyplot as plt  # noqa: E402
import numpy as np  # noqa: E402
import pandas as pd  # noqa: E402
from matplotlib import ticker, transforms  # noqa: E402

from dem_core.analyses.sweep import Sweep, SweepError, run_sweep  # noqa: E402
from dem_core.analyses.thresholds import Threshold  # noqa: E402

REPORTS = ROOT / "reports" / "studies"
#: what the studies run unless they say otherwise: the default integrator on the default contact law's points
DEFAULT_MODEL = "the default model (Moreau-Jean on the corner law's points: rigid contacts, plastic impacts)"
CACHE = ROOT / ".study_cache"
_SWEPT = []  # tables of the sweeps run by this process, for the compute time in the README
_SEARCHED = []  # seconds each threshold search of this process took when it first ran (NaN: not recorded)


def out_dir(name: str) -> Path:
    path = REPORTS / name
    path.mkdir(parents=True, exist_ok=True)
    return path


#: sweeps run on one worker: the machine is shared, and a study's run time is then comparable between runs
WORKERS = 1


def sweep(name: str, build, parameters: dict, *, workers=WORKERS, mode="grid"):
    """Run (or resume) a sweep of the study and return its table; failures are kept as rows."""
    spec = Sweep(build, parameters, mode=mode)
    try:
        table = run_sweep(spec, CACHE / name, workers=workers)
    except SweepError as refusal:  # the cache holds an older sweep (other code or values): it is only a cache
        print(f"running the sweep again: {refusal}", file=sys.stderr)
        table = run_sweep(spec, CACHE / name, workers=workers, overwrite=True)
    _SWEPT.append(table)
    table.to_parquet(out_dir(name.split("/")[0]) / f"{name.replace('/', '_')}.parquet", index=False)
    bad = table[table.status != "ok"]
    if len(bad):
        print(f"{len(bad)} of {len(table)} runs did not finish:", bad.status.value_counts().to_dict(), file=sys.stderr)
    return table


@functools.cache
def core_fingerprint() -> str:
    """A digest of what decides a threshold (the engine and the run around it, the inputs: scenes, record
    readers and the bundled records, motions, and the search itself), so that a search cached under another
    core, default or record file is never reused."""
    core = ROOT / "dem_core"
    digest = hashlib.sha256()
    for path in sorted([*(core / "engine").rglob("*.py"), *(core / "inputs").rglob("*.py"),
                        *(p for p in (core / "data").rglob("*") if p.is_file()),
                        core / "simulation.py", core / "analyses" / "thresholds.py"]):
        digest.update(path.relative_to(ROOT).as_posix().encode())
        digest.update(path.read_bytes())
    return digest.hexdigest()[:12]


def cached_threshold(name: str, key: str, search) -> Threshold:
    """The threshold search ``search()`` of study ``name``, kept under
    ``.study_cache/<name>/<key>-<core fingerprint>.json`` so that a study started again with the same core
    does not repeat it."""
    path = CACHE / name / f"{key}-{core_fingerprint()}.json"
    if path.exists():
        data = json.loads(path.read_text())
        _SEARCHED.append(data.get("wall_time_s", float("nan")))
        return Threshold(data["criterion"], tuple(map(tuple, data["runs"])), tuple(map(tuple, data["failures"])),
                         data["tolerance"])
    started = time.perf_counter()
    found = search()
    _SEARCHED.append(time.perf_counter() - started)
    path.parent.mkdir(parents=True, exist_ok=True)
    path.write_text(json.dumps({"criterion": found.criterion, "runs": found.runs, "failures": found.failures,
                                "tolerance": found.tolerance, "wall_time_s": _SEARCHED[-1]}))
    return found


def threshold_columns(found: Threshold, prefix: str = "") -> dict:
    """Table columns of a threshold search: the smallest scale with the event, its windows, whether a larger
    scale survived a smaller one's collapse, failed and finished runs."""
    return {f"{prefix}smallest": found.smallest,
            f"{prefix}standing_below": found.below if found.below is not None else np.nan,
            f"{prefix}windows": "; ".join(f"{w.first:.3g}-{w.last:.3g}" for w in found.windows),
            f"{prefix}non_monotonic": found.survives_above_collapse, f"{prefix}failed_runs": len(found.failures),
            f"{prefix}runs": len(found.runs)}


def markdown_table(header: list, rows: list) -> list:
    """Lines of a markdown table."""
    return ["| " + " | ".join(header) + " |", "|" + "---|" * len(header),
            *["| " + " | ".join(str(c) for c in row) + " |" for row in rows], ""]


def curve(ax, x, y, overturned, label, row=0, failed=None, **style):
    """A line through the runs that finished standing; runs that overturned as crosses along the top edge and runs
    that failed (unstable) as open diamonds along the bottom edge, one row of markers per series (neither kind's
    measures are comparable with the standing runs')."""
    x, y, overturned = map(np.asarray, (x, y, overturned))
    failed = np.zeros(len(x), bool) if failed is None else np.asarray(failed, bool)
    overturned = overturned & ~failed
    standing = ~overturned & ~failed
    line = ax.plot(x[standing], y[standing], "o-", ms=3, label=label, **style)[0]
    edge = transforms.blended_transform_factory(ax.transData, ax.transAxes)
    if overturned.any():
        ax.plot(x[overturned], np.full(overturned.sum(), 0.97 - 0.05 * row), "x", color=line.get_color(), ms=7, mew=1.5,
                transform=edge, clip_on=False)
    if failed.any():
        ax.plot(x[failed], np.full(failed.sum(), 0.03 + 0.05 * row), "D", mfc="none", color=line.get_color(), ms=6,
                transform=edge, clip_on=False)
    return line


def plain_log_ticks(axis) -> None:
    """Label a logarithmic axis (``ax.xaxis`` or ``ax.yaxis``) with plain numbers (1, 2, 5, 10, 20), not
    powers of ten."""
    axis.set_major_locator(ticker.LogLocator(subs=(1.0, 2.0, 5.0)))
    axis.set_major_formatter(ticker.FuncFormatter(lambda value, _: f"{value:g}"))
    axis.set_minor_formatter(ticker.NullFormatter())


def save_figure(fig, name: str, file: str, caption: str, *, legend: float | None = None, grid: dict | None = None,
                rect=None) -> tuple[str, str]:
    """Finish ``fig`` and write it as ``file`` of study ``name``: with ``legend`` (a font size), each of its axes
    first gets a light grid (``grid``: further keywords of ``Axes.grid``) and a legend; then it is laid out within
    ``rect`` (default the whole figure), saved and closed.  Returns ``(file, caption)``, a figure as
    :func:`write_readme` takes it."""
    if legend is not None:
        for ax in fig.axes:
            ax.grid(alpha=0.3, **(grid or {}))
            ax.legend(fontsize=legend)
    fig.tight_layout(rect=rect)
    fig.savefig(out_dir(name) / file, dpi=120)
    plt.close(fig)
    return file, caption


def results_table(name: str, rows: list, file: str = "results.parquet") -> pd.DataFrame:
    """``rows`` (dicts) as a table, also written as ``file`` of study ``name``."""
    table = pd.DataFrame(rows)
    table.to_parquet(out_dir(name) / file, index=False)
    return table


def fmt(value, non_monotonic=False, failed=0, digits=3) -> str:
    """A threshold (m/s^2) as the tables show it: ``digits`` significant digits, ``*`` where a larger scale
    survived a smaller one's collapse and the number of failed runs if any; ``none in range`` where the search
    found none (NaN), ``-`` where there is no such value (None: no thesis number, no rigid reference)."""
    if value is None:
        return "-"
    text = f"{value:.{digits}g}" if np.isfinite(value) else "none in range"
    return text + ("*" if non_monotonic else "") + (f" ({failed} failed)" if failed else "")


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
        cost = (f"{runs} runs, {compute:.0f} s of computing in all on {WORKERS} worker(s); an interrupted or "
                "repeated run resumes from `.study_cache/`")
    elif _SEARCHED:
        cost = (f"{len(_SEARCHED)} threshold searches, {np.nansum(_SEARCHED):.0f} s of computing in all on one worker "
                f"when each first ran; they are cached in `.study_cache/`, and this run took "
                f"{time.perf_counter() - started:.0f} s")
    else:
        cost = f"{time.perf_counter() - started:.0f} s on the machine that wrote this"
    lines += ["", f"Regenerate: `python examples/studies/{script}` ({cost})."]
    (out_dir(name) / "README.md").write_text("\n".join(lines) + "\n")
    print("\n".join(lines))
