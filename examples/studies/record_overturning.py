"""The smallest PGA that overturns columns and colonnades under each bundled record, and the check of the
search against the rigid rocking equation.

1. Check: the 6 m x 1 m monolith on a rigid base (friction 2: no sliding) under each bundled record, as
   bundled, in the native core's two integrators (Moreau-Jean, the default, and the explicit core at the default
   stiffness), against the rocking equation (comparisons/references/rocking_equation.py); both by the same search,
   and again by a fine scan upward in 0.02 m/s^2 steps to the first overturn; the smaller of the two searches'
   answers is compared too.
2. Study, in the thesis' set-up (friction 0.485; Mexico City SCT north-south): standalone columns of 1 to 3
   drums and colonnades of three columns of 1, 2, 3 and 5 drums under one epistyle (type a, 2.5 m spacing), by
   the default integrator on the corner law's points.

Every search (:func:`dem_core.analyses.thresholds.overturning_threshold`): 2% steps from 0.8 of the rigid
uplift acceleration g b / h up to a cap per record, each change refined to 0.5%; every overturning window
is kept, and runs that lost stability are counted apart.
"""

import sys
import time

import matplotlib.pyplot as plt
import numpy as np
import pandas as pd
from _rigid import overturning as rigid_overturning
from _study import cached_threshold, fmt, markdown_table, out_dir, save_figure, threshold_columns, write_readme

from comparisons.references.analytical import RockingBlock
from dem_core import excitation, records, scenes
from dem_core.analyses.thresholds import overturning_threshold
from dem_core.engine.contact import DEFAULT_STIFFNESS

NAME = "record_overturning"
STEP, TOLERANCE = 0.02, 0.005
G = 9.80665
UPLIFT = G * 1.0 / 6.0  # m/s^2, g b / h of every column here
LOW = 0.8 * UPLIFT
CAP = {"el_centro_1940": 12.0, "mexico_city_1985": 6.0, "northridge_1994": 12.0, "kalamata_1986": 30.0}  # m/s^2
#: the check passes when the native core's smallest overturning PGA is within this of the rocking equation's
RIGID_AGREEMENT = 0.05
#: m/s^2: the check's fine scan, upward from LOW to the first overturn (rigid overturning boundaries under a
#: record are speckled with windows a few hundredths of a m/s^2 wide, which a 2% scan hits or misses by chance)
FINE_STEP = 0.02
#: the fine scan as search options: every FINE_STEP (a 100% relative step is always above it), up to the first overturn
FINE = {"step": 1.0, "absolute_step": FINE_STEP, "first_only": True}
#: the check's native models: column prefix -> (label, simulate options)
CHECK_MODELS = {"moreau": ("Moreau-Jean", {"integrator": "moreau"}),
                "explicit": (f"explicit, K_n {DEFAULT_STIFFNESS['corner']:.0e}", {"integrator": "explicit"})}
CHECK_FRICTION = 2.0
FRICTION = 0.485
COMPONENT = {"mexico_city_1985": 1}  # the study uses Mexico City's north-south component, as the thesis
COLUMN_DRUMS = (1, 2, 3)
COLONNADE_DRUMS = (1, 2, 3, 5)


def motion(record, component=None):
    return lambda pga: excitation.record(record, component=component, pga=pga)


def check_rows():
    """The monolith against the rocking equation under each bundled record (Mexico City as bundled: east-west)."""
    block = RockingBlock.from_size(1.0, 6.0)
    rows = []
    for record in records.BUNDLED:
        started = time.perf_counter()
        rigid = cached_threshold(NAME, f"check_{record}_rigid", lambda: rigid_overturning(
            block, block.restitution, motion(record), LOW, CAP[record], step=STEP, tolerance=TOLERANCE))
        fine = cached_threshold(NAME, f"check_{record}_rigid_fine", lambda: rigid_overturning(
            block, block.restitution, motion(record), LOW, CAP[record], tolerance=TOLERANCE, **FINE))
        row = {"record": record, **threshold_columns(rigid, "rigid_"), "rigid_fine": fine.smallest}
        scene = scenes.column(1, friction=CHECK_FRICTION)
        for key, (_, options) in CHECK_MODELS.items():
            found = cached_threshold(NAME, f"check_{record}_{key}", lambda: overturning_threshold(
                scene, motion(record), LOW, CAP[record], step=STEP, tolerance=TOLERANCE, output_dt=0.05, **options))
            fine = cached_threshold(NAME, f"check_{record}_{key}_fine", lambda: overturning_threshold(
                scene, motion(record), LOW, CAP[record], tolerance=TOLERANCE, output_dt=0.05, **FINE, **options))
            row.update(threshold_columns(found, f"{key}_"))
            row[f"{key}_fine"] = fine.smallest
        row["wall_time_s"] = time.perf_counter() - started
        print(f"check {record}: rigid {row['rigid_smallest']:.3g} (fine {row['rigid_fine']:.3g}), " + ", ".join(
            f"{label} {row[key + '_smallest']:.3g} (fine {row[key + '_fine']:.3g})"
            for key, (label, _) in CHECK_MODELS.items()), file=sys.stderr, flush=True)
        rows.append(row)
    return pd.DataFrame(rows)


def study_scenes():
    for n in COLUMN_DRUMS:
        yield "column", n, scenes.column(n, friction=FRICTION)
    for n in COLONNADE_DRUMS:
        yield "colonnade", n, scenes.colonnade(3, n, spacing=2.5, epistyle="a", friction=FRICTION)


def study_rows():
    rows = []
    for record in records.BUNDLED:
        for kind, n, scene in study_scenes():
            started = time.perf_counter()
            found = cached_threshold(NAME, f"{kind}_{n}_{record}", lambda: overturning_threshold(
                scene, motion(record, COMPONENT.get(record)), LOW, CAP[record], step=STEP, tolerance=TOLERANCE,
                output_dt=0.05))
            peak = float(np.max(np.abs(excitation.record(record, component=COMPONENT.get(record)).horizontal.samples)))
            rows.append({"kind": kind, "n_drums": n, "record": record, "record_pga": peak, **threshold_columns(found),
                         "wall_time_s": time.perf_counter() - started})
            print(f"{kind} {n} {record}: {rows[-1]['smallest']:.3g} ({rows[-1]['windows']})", file=sys.stderr,
                  flush=True)
    table = pd.DataFrame(rows)
    table["scale_factor"] = table.smallest / table.record_pga
    return table


def scanned(row, prefix: str) -> float:
    """The smallest overturning PGA of a check row's model ``prefix`` found by the 2% scan."""
    return row[f"{prefix}_smallest"]


def lowest(row, prefix: str) -> float:
    """The smallest overturning PGA of a check row's model ``prefix`` found by either search."""
    return float(np.fmin(row[f"{prefix}_smallest"], row[f"{prefix}_fine"]))


def main():
    started = time.perf_counter()
    check = check_rows()
    check.to_parquet(out_dir(NAME) / "rigid_check.parquet", index=False)
    table = study_rows()
    table.to_parquet(out_dir(NAME) / "results.parquet", index=False)
    report(check, table, started)


def report(check, table, started):
    labels = [(kind, n) for kind, n, _ in study_scenes()]
    recs = list(records.BUNDLED)
    tables = check_tables(check) + study_tables(table, labels, recs)
    findings = check_findings(check) + study_findings(table, recs)
    write_readme(NAME, "Overturning PGA of columns and colonnades under the bundled records", findings,
                 [figure(table, labels, recs)], started, "record_overturning.py", resumes=False, tables=tables)


def against_rigid(check, threshold, shown) -> list:
    """Rows of a check table: per record the rocking equation's threshold, then each model's with its
    difference from it and whether that is within RIGID_AGREEMENT; ``threshold(row, prefix)`` is a model's
    threshold, ``shown(row, prefix)`` its cell."""
    rows = []
    for _, r in check.iterrows():
        cells = [r.record, shown(r, "rigid")]
        for k in CHECK_MODELS:
            ratio = threshold(r, k) / threshold(r, "rigid")
            cells += [shown(r, k), f"{ratio - 1:+.1%}" if np.isfinite(ratio) else "-",
                      "yes" if abs(ratio - 1) <= RIGID_AGREEMENT else "no" if np.isfinite(ratio) else "-"]
        rows.append(cells)
    return rows


def check_tables(check) -> list:
    """Markdown lines of the check: the 2% scan's thresholds against the rocking equation's, their windows, and the
    smallest thresholds either search found."""
    def scan_cell(r, prefix):  # the rocking equation's searches show no failed runs
        return fmt(r[f"{prefix}_smallest"], r[f"{prefix}_non_monotonic"],
                   0 if prefix == "rigid" else r[f"{prefix}_failed_runs"])

    header = ["record", "rocking equation"] + [c for label, _ in CHECK_MODELS.values() for c in
                                               (label, "difference", f"within {RIGID_AGREEMENT:.0%}")]
    lines = ["Check: smallest overturning PGA (m/s^2) of the 1 x 6 m monolith (friction 2) under each bundled "
             "record as bundled, the native core's two integrators on the corner law's points against the rocking "
             "equation; * a larger PGA survived where a smaller one toppled.", ""]
    lines += markdown_table(header, against_rigid(check, scanned, scan_cell))
    lines += markdown_table(["record", "rocking equation: windows"] + [f"{label}: windows"
                                                                       for label, _ in CHECK_MODELS.values()],
                            [[r.record, r.rigid_windows] + [r[f"{k}_windows"] for k in CHECK_MODELS]
                             for _, r in check.iterrows()])
    lines += ["The smallest overturning PGA found by either search: the scan above with its refinements, or a "
              f"fine scan going up from {LOW:.2f} m/s^2 in {FINE_STEP} m/s^2 steps to the first overturn (a "
              "refined window can fall between two of its steps).", ""]
    return lines + markdown_table(header, against_rigid(check, lowest, lambda r, p: fmt(lowest(r, p), digits=4)))


def study_tables(table, labels, recs) -> list:
    """Markdown lines of the study: each system's smallest overturning PGA under each record, and the windows."""
    lines = [f"Study: smallest overturning PGA (m/s^2), friction {FRICTION:g}, the default integrator "
             "(Moreau-Jean) on the corner law's points; Mexico City north-south; (scale factor "
             "over the record's own PGA).", ""]
    cell = {(r.kind, r.n_drums, r.record): r for r in table.itertuples(index=False)}
    lines += markdown_table(
        ["system"] + [f"{r} (PGA {cell[labels[0] + (r,)].record_pga:.3g})" for r in recs],
        [[f"{kind}, {n} drum{'s' * (n > 1)}"] + [
            f"{fmt(cell[(kind, n, r)].smallest, cell[(kind, n, r)].non_monotonic, cell[(kind, n, r)].failed_runs)}"
            + (f" ({cell[(kind, n, r)].scale_factor:.2f}x)" if np.isfinite(cell[(kind, n, r)].smallest) else "")
            for r in recs] for kind, n in labels])
    return lines + ["Overturning windows (m/s^2):", ""] + markdown_table(
        ["system"] + recs, [[f"{kind}, {n}"] + [cell[(kind, n, r)].windows or "-" for r in recs] for kind, n in labels])


def check_findings(check) -> list:
    """How many records each search of the native core puts within RIGID_AGREEMENT of the rocking equation, and
    where the fine scan found an earlier first overturn than the 2% scan."""
    findings = []
    for k, (label, _) in CHECK_MODELS.items():
        for scan, threshold in ((f"{STEP:.0%} scan", scanned),
                                (f"either search (with the fine {FINE_STEP} m/s^2 scan)", lowest)):
            close = np.array([abs(threshold(r, k) / threshold(r, "rigid") - 1) <= RIGID_AGREEMENT
                              for _, r in check.iterrows()])
            findings.append(f"Check, {label}, {scan}: {int(close.sum())} of {len(check)} records "
                            f"within {RIGID_AGREEMENT:.0%} of the rocking equation"
                            + ("" if close.all() else ": not " + ", ".join(
                                f"{r.record} ({threshold(r, k):.3g} against {threshold(r, 'rigid'):.3g})"
                                for _, r in check[~close].iterrows())) + ".")
    kn = next(iter(CHECK_MODELS))
    lower = [(r.record, r.rigid_smallest, lowest(r, "rigid"), r[f"{kn}_smallest"], lowest(r, kn))
             for _, r in check.iterrows() if lowest(r, "rigid") < (1 - TOLERANCE) * r.rigid_smallest
             or lowest(r, kn) < (1 - TOLERANCE) * r[f"{kn}_smallest"]]
    if lower:
        findings.append("The fine scan found an earlier first overturn than the 2% scan under " + "; ".join(
            f"{record} (rocking equation {coarse:.4g} -> {fine:.4g}, {CHECK_MODELS[kn][0]} "
            f"{native_coarse:.4g} -> {native_fine:.4g})" for record, coarse, fine, native_coarse, native_fine in lower)
            + ": narrow windows below the first one a 2% scan finds. The study below scans in 2% steps, so under "
            "those records its values can lie above the smallest overturning PGA by as much.")
    return findings


def study_findings(table, recs) -> list:
    """The study's trends: lowest and highest system per record, the colonnades against the number of drums,
    colonnades against standalone columns, non-monotonic searches and failed runs."""
    findings = []
    for record in recs:
        runs = table[(table.record == record) & np.isfinite(table.smallest)]
        if len(runs):
            low, high = runs.loc[runs.smallest.idxmin()], runs.loc[runs.smallest.idxmax()]
            findings.append(f"{record}: lowest {low.kind}, {low.n_drums} drum(s) ({low.smallest:.3g} m/s^2), highest "
                            f"{high.kind}, {high.n_drums} drum(s) ({high.smallest:.3g} m/s^2); "
                            f"{int((table.record == record).sum() - len(runs))} systems overturned nowhere in the "
                            "scan.")
        colonnade = table[(table.record == record) & (table.kind == "colonnade")].sort_values("n_drums")
        values = colonnade.smallest.to_numpy()
        trend = ("rises" if np.all(np.diff(values) > 0) else "falls" if np.all(np.diff(values) < 0) else
                 "is not monotonic" if np.all(np.isfinite(values)) else "cannot be ranked (not all overturned)")
        findings.append(f"{record}, colonnades of {', '.join(str(n) for n in colonnade.n_drums)} drums: "
                        f"{', '.join(fmt(v) for v in values)} m/s^2: the threshold {trend} with the number of drums.")
    both = table[table.n_drums.isin(COLUMN_DRUMS)].pivot_table(index=["record", "n_drums"], columns="kind",
                                                                 values="smallest")
    ratio = (both.colonnade / both.column).dropna()
    if len(ratio):
        findings.append(f"Colonnade over standalone column, same record and drums ({len(ratio)} pairs): "
                        f"{ratio.min():.2f} to {ratio.max():.2f}, median {ratio.median():.2f}.")
    odd = table[table.non_monotonic]
    findings.append(f"{len(odd)} of {len(table)} searches found a PGA left standing above one that toppled (*).")
    failed = table[table.failed_runs > 0]
    findings.append(f"Failed (unstable) runs: {int(table.failed_runs.sum())}"
                    + (" in " + ", ".join(f"{r.kind} {r.n_drums} / {r.record}" for r in failed.itertuples())
                       if len(failed) else "") + ".")
    return findings


def figure(table, labels, recs):
    fig, ax = plt.subplots(figsize=(11, 4.8))
    width = 0.8 / len(labels)
    for k, (kind, n) in enumerate(labels):
        rows = table[(table.kind == kind) & (table.n_drums == n)].set_index("record").loc[recs]
        bars = ax.bar(np.arange(len(recs)) + (k - len(labels) / 2 + 0.5) * width, rows.smallest, width,
                      label=f"{kind}, {n} drum{'s' * (n > 1)}", hatch="//" if kind == "colonnade" else None)
        for bar, odd in zip(bars, rows.non_monotonic):
            if odd:
                ax.text(bar.get_x() + bar.get_width() / 2, bar.get_height(), "*", ha="center", va="bottom")
    ax.set_xticks(np.arange(len(recs)), recs)
    ax.set_ylabel("smallest overturning PGA (m/s$^2$)")
    ax.set_title(f"Friction {FRICTION:g}, default contact law; scan in {STEP:.0%} steps from {LOW:.2f} m/s$^2$, "
                 "refined to 0.5%; * a larger PGA survived", fontsize=9)
    ax.grid(axis="y", alpha=0.3)
    ax.legend(fontsize=7, ncol=2)
    return save_figure(fig, NAME, "overturning_pga.png",
                       "The study table as bars: for each record, the smallest overturning PGA of each system "
                       "(hatched: colonnades); a star marks a search where a larger PGA left standing what a smaller "
                       "one toppled; a missing bar, nothing overturned up to the cap.")


if __name__ == "__main__":
    main()
