"""The comparison report: tables, Pareto and convergence figures, stability map, verdicts, as HTML.

``python -m comparisons report [--quick] [--out reports]`` runs the harness
(:mod:`comparisons.harness`) and the stability stress tests
(:mod:`comparisons.stress`), then writes into the output folder
``results.csv`` (the tidy table), ``stability.csv``, one PNG per figure and
``index.html`` that shows them.
"""

import html
import time
from pathlib import Path

import matplotlib

matplotlib.use("Agg")
import matplotlib.pyplot as plt
import numpy as np
import pandas as pd

from comparisons.cases import all_cases
from comparisons.stress import WRONG

COLOURS = {"dem": "#1b9e77", "pymunk": "#d95f02", "pybullet": "#7570b3", "mujoco": "#e7298a"}
ACCURACY_LEVELS = (0.10, 0.03, 0.01)


def primary_metric(case, table) -> str:
    metrics = table.loc[(table.case == case.name) & (table.metric != "none"), "metric"].unique()
    return case.primary or (metrics[0] if len(metrics) else "none")


def observed_order(dts, errors) -> float:
    """Slope of log|error| against log dt (NaN with fewer than two usable points)."""
    dts, errors = np.asarray(dts, float), np.abs(np.asarray(errors, float))
    keep = np.isfinite(errors) & (errors > 0)
    if keep.sum() < 2 or np.ptp(np.log(dts[keep])) == 0:
        return float("nan")
    return float(np.polyfit(np.log(dts[keep]), np.log(errors[keep]), 1)[0])


def case_summary(table, case) -> pd.DataFrame:
    """Per engine, for the case's primary metric: best error, its wall time, the fastest run within each
    accuracy level, and the observed order of convergence in dt."""
    metric = primary_metric(case, table)
    rows = table[(table.case == case.name) & (table.metric == metric) & (table.status == "ok")]
    out = []
    for engine, runs in rows.groupby("engine", sort=False):
        plain = runs[runs.settings == "{}"]
        best = runs.loc[runs.error.abs().idxmin()]
        entry = {"engine": engine, "metric": metric, "best_error": abs(best.error), "best_dt": best["dt"],
                 "best_wall_s": best.wall_time_s, "order": observed_order(plain["dt"], plain.error)}
        for level in ACCURACY_LEVELS:
            within = runs[runs.error.abs() <= level]
            entry[f"fastest_within_{level:g}_s"] = within.wall_time_s.min() if len(within) else np.nan
        out.append(entry)
    return pd.DataFrame(out)


def verdict(case, summary: pd.DataFrame) -> str:
    """One paragraph: which engine wins on this case and by how much."""
    if summary.empty:
        return "No engine completed this case."
    metric = summary.metric.iloc[0]
    best = summary.loc[summary.best_error.idxmin()]
    others = summary[summary.engine != best.engine]
    text = (f"Most accurate: {best.engine}, |{metric}| = {best.best_error:.3g} (dt = {best.best_dt:.3g} s, "
            f"{best.best_wall_s:.3g} s of wall time)")
    if len(others):
        runner = others.loc[others.best_error.idxmin()]
        ratio = runner.best_error / best.best_error if best.best_error > 0 else np.inf
        text += f", {ratio:.3g} times smaller than the next, {runner.engine} ({runner.best_error:.3g})"
    if metric.endswith(("_m", "_rad")):  # an absolute measure (drift): no relative accuracy levels
        fastest = summary.loc[summary.best_wall_s.idxmin()]
        return text + f". Fastest run: {fastest.engine} ({fastest.best_wall_s:.3g} s)."
    for level in (0.03, 0.10):
        column = f"fastest_within_{level:g}_s"
        reached = summary.dropna(subset=[column])
        if len(reached):
            fastest = reached.loc[reached[column].idxmin()]
            text += f". Fastest within {level:.0%}: {fastest.engine} ({fastest[column]:.3g} s"
            rest = reached[reached.engine != fastest.engine]
            if len(rest):
                second = rest.loc[rest[column].idxmin()]
                text += f", {second[column] / fastest[column]:.3g} times faster than {second.engine}"
            text += ")"
            break
    else:
        text += ". No engine came within 10%"
    return text + "."


def _figure_rows(table, case, plain_only=False):
    metric = primary_metric(case, table)
    rows = table[(table.case == case.name) & (table.metric == metric) & (table.status == "ok")]
    return metric, rows[rows.settings == "{}"] if plain_only else rows


def _finish_log_figure(fig, ax, xlabel, ylabel, title, path):
    ax.set_xscale("log")
    ax.set_yscale("log")
    ax.set_xlabel(xlabel)
    ax.set_ylabel(ylabel)
    ax.set_title(title, fontsize=10)
    ax.grid(alpha=0.3, which="both")
    ax.legend(fontsize=8)
    fig.tight_layout()
    fig.savefig(path, dpi=110)
    plt.close(fig)


def pareto_figure(table, case, path):
    """|error| of the primary metric against wall time, one point per run, labelled by its step."""
    metric, rows = _figure_rows(table, case)
    fig, ax = plt.subplots(figsize=(6.4, 4.2))
    for engine, runs in rows.groupby("engine", sort=False):
        ax.scatter(runs.wall_time_s, np.maximum(runs.error.abs(), 1e-16), color=COLOURS.get(engine), label=engine)
        for _, r in runs.iterrows():
            ax.annotate(r.step, (r.wall_time_s, max(abs(r.error), 1e-16)), fontsize=6, alpha=0.7,
                        xytext=(3, 2), textcoords="offset points")
    _finish_log_figure(fig, ax, "wall time of the run (s)", f"|{metric}|", f"{case.name}: error against run time",
                       path)


def convergence_figure(table, case, path):
    """|error| of the primary metric against dt per engine, with the observed order in the legend."""
    metric, rows = _figure_rows(table, case, plain_only=True)
    fig, ax = plt.subplots(figsize=(6.4, 4.2))
    for engine, runs in rows.groupby("engine", sort=False):
        runs = runs.sort_values("dt")
        order = observed_order(runs["dt"], runs.error)
        ax.plot(runs["dt"], np.maximum(runs.error.abs(), 1e-16), "o-", color=COLOURS.get(engine),
                label=f"{engine} (order {order:.2g})")
    _finish_log_figure(fig, ax, "time step dt (s)", f"|{metric}|", f"{case.name}: convergence in dt", path)


STATUS_COLOURS = {"ok": "#1b9e77", "silently wrong": "#e6ab02", "stopped": "#d95f02"}


def _outcome(status: str) -> str:
    return "stopped" if status.startswith("stopped") else status


def stability_map_figure(rows: pd.DataFrame, title: str, path) -> None:
    """One stress test as tiles: a row per engine, a tile per setting, coloured by outcome,
    labelled with the setting and the measured value."""
    engines = list(dict.fromkeys(rows.engine))
    width = max(rows.groupby("engine").setting.nunique())
    fig, ax = plt.subplots(figsize=(max(4.0, 1.9 * width + 1.5), 0.9 + 0.6 * len(engines)))
    for row, engine in enumerate(engines):
        runs = rows[rows.engine == engine]
        for col, setting in enumerate(dict.fromkeys(runs.setting)):
            here = runs[runs.setting == setting]
            outcome = _outcome(here.status.iloc[0])
            values = "\n".join(f"{m} {v:.3g}" for m, v in zip(here.metric, here.value) if np.isfinite(v))
            ax.add_patch(plt.Rectangle((col, row), 0.95, 0.9, color=STATUS_COLOURS.get(outcome, "0.6")))
            ax.text(col + 0.47, row + 0.45, f"{setting}: {outcome}\n{values}", ha="center", va="center", fontsize=6)
    ax.set_xlim(0, width)
    ax.set_ylim(0, len(engines))
    ax.set_yticks(np.arange(len(engines)) + 0.45, engines, fontsize=8)
    ax.set_xticks([])
    ax.set_title(f"{title}: ok, silently wrong (error of {WRONG:.0%} or more) or stopped by the engine", fontsize=8)
    fig.tight_layout()
    fig.savefig(path, dpi=110)
    plt.close(fig)


def stiffness_figure(rows: pd.DataFrame, path) -> None:
    """Free-rocking errors and the automatic time step of the native core against K_n."""
    kn = rows.setting.str.removeprefix("kn = ").astype(float)
    fig, (ax, ax_dt) = plt.subplots(1, 2, figsize=(9, 3.5))
    for metric in ("quarter_period", "peak_decay"):
        pick = rows.metric == metric
        ax.loglog(kn[pick], np.abs(rows.value[pick]), "o-", label=metric)
    pick = rows.metric == "dt_s"
    ax_dt.loglog(kn[pick], rows.value[pick], "s-", color="0.3")
    ax.set(xlabel="K_n (N/m^2)", ylabel="|relative error|", title="Free rocking, native core")
    ax_dt.set(xlabel="K_n (N/m^2)", ylabel="automatic dt (s)", title="Time step")
    ax.legend(fontsize=8)
    for a in (ax, ax_dt):
        a.grid(True, which="both", alpha=0.3)
    fig.tight_layout()
    fig.savefig(path, dpi=110)
    plt.close(fig)


def _stability_sections(stability: pd.DataFrame, out: Path) -> str:
    parts = []
    for k, test in enumerate(dict.fromkeys(stability.test)):
        rows = stability[stability.test == test]
        image = f"stability_{k + 1}.png"
        stability_map_figure(rows, test, out / image)
        extra = ""
        if "contact stiffness" in test:
            stiffness_figure(rows, out / "stability_stiffness.png")
            extra = '<img src="stability_stiffness.png" alt="errors and time step against contact stiffness">'
        parts.append(f"<h3>{html.escape(test)}</h3><img src=\"{image}\" alt=\"stability map: {html.escape(test)}\" "
                     f"style=\"max-width:100%\">{extra}")
    return "".join(parts)


def _table_html(frame: pd.DataFrame) -> str:
    return frame.to_html(index=False, float_format=lambda v: f"{v:.3g}", na_rep="-", border=0, classes="t")


def write_report(table: pd.DataFrame, stability: pd.DataFrame, out: Path, *, quick: bool, run_time_s: float) -> Path:
    """Write figures, CSV tables and index.html into ``out``; returns the path of index.html."""
    out.mkdir(parents=True, exist_ok=True)
    table.to_csv(out / "results.csv", index=False)
    stability.to_csv(out / "stability.csv", index=False)
    sections = []
    for case in all_cases():
        if case.name not in set(table.case):
            continue
        pareto, convergence = f"pareto_{case.name}.png", f"convergence_{case.name}.png"
        pareto_figure(table, case, out / pareto)
        convergence_figure(table, case, out / convergence)
        summary = case_summary(table, case)
        failed = table[(table.case == case.name) & (table.status != "ok")][["engine", "step", "status"]]
        failed = failed.drop_duplicates()
        sections.append(
            f'<section id="{case.name}"><h2>{html.escape(case.title)}</h2>'
            f'<p class="verdict">{html.escape(verdict(case, summary))}</p>'
            f'<img src="{pareto}" alt="error against run time for {case.name}">'
            f'<img src="{convergence}" alt="convergence in dt for {case.name}">'
            f'{_table_html(summary)}'
            + (f"<h3>Runs that stopped</h3>{_table_html(failed)}" if len(failed) else "") + "</section>")
    stability_images = _stability_sections(stability, out) if len(stability) else ""
    page = f"""<!DOCTYPE html>
<html lang="en"><head><meta charset="utf-8"><title>Engine comparison: rocking and sliding of stone blocks</title>
<style>body{{font-family:sans-serif;max-width:1100px;margin:2em auto;color:#222}}img{{max-width:49%}}
table.t{{border-collapse:collapse;font-size:12px;margin:0.5em 0}}table.t td,table.t th{{border:1px solid #ccc;
padding:2px 6px}}.verdict{{background:#f4f4f4;padding:0.5em}}</style></head><body>
<h1>Engine comparison: rocking and sliding of stone blocks</h1>
<p>{"Quick" if quick else "Full"} run of {len(table.drop_duplicates(["case", "engine", "step", "settings"]))}
simulations over {table.case.nunique()} cases in {run_time_s:.0f} s of wall time
({time.strftime("%Y-%m-%d %H:%M")}). Errors are relative to the analytical reference of each case
(FORMULATION section 4) or to the native core converged in dt; wall times exclude compilation and model
building. Tables: <a href="results.csv">results.csv</a>, <a href="stability.csv">stability.csv</a>.</p>
{"".join(sections)}
<section id="stability"><h2>Stability map</h2>{stability_images}{_table_html(stability)}</section>
</body></html>"""
    index = out / "index.html"
    index.write_text(page, encoding="utf-8")
    return index
