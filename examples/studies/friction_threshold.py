"""The smallest overturning PGA of 1- and 3-drum columns against the friction coefficient, under El Centro 1940
and Kalamata 1986 (the thesis' study of the threshold against friction).

Every interface has the same friction mu.  Below mu = tan(alpha) = 1/6 a rigid column slides before it
rocks; above it rocking comes first, and sliding only at mu g.  Each search
(:func:`dem_core.analyses.thresholds.overturning_threshold`): 2% steps from 0.8 g b/h up to a cap,
each change refined to 0.5%.
"""

import sys
import time

import matplotlib.pyplot as plt
import numpy as np
from _study import (
    DEFAULT_MODEL,
    cached_threshold,
    fmt,
    markdown_table,
    results_table,
    save_figure,
    threshold_columns,
    write_readme,
)

from dem_core import excitation, scenes
from dem_core.analyses.thresholds import overturning_threshold

NAME = "friction_threshold"
FRICTIONS = (0.2, 0.3, 0.4, 0.485, 0.6, 0.8, 1.0)
DRUMS = (1, 3)
RECORDS = {"el_centro_1940": 12.0, "kalamata_1986": 30.0}  # record: top of the scan, m/s^2
G = 9.80665
LOW = 0.8 * G / 6.0
STEP, TOLERANCE = 0.02, 0.005


def main():
    started = time.perf_counter()
    rows = []
    for record, high in RECORDS.items():
        for n in DRUMS:
            for mu in FRICTIONS:
                scene = scenes.column(n, friction=mu)
                found = cached_threshold(NAME, f"{record}_{n}_{mu:g}", lambda: overturning_threshold(
                    scene, lambda pga: excitation.record(record, pga=pga), LOW, high, step=STEP, tolerance=TOLERANCE,
                    output_dt=0.05))
                rows.append({"record": record, "n_drums": n, "mu": mu, **threshold_columns(found)})
                print(f"{record} {n} drums mu {mu:g}: {found.smallest:.3g} ({rows[-1]['windows']})", file=sys.stderr,
                      flush=True)
    report(results_table(NAME, rows), started)


def report(table, started):
    setup = [f"Set-up: columns 6 m x 1 m of 1 and 3 drums, the same friction at every interface, "
             f"{DEFAULT_MODEL}; records El Centro 1940 and Kalamata 1986 (read at "
             f"0.01 s) scaled to the PGA searched; {STEP:.0%} steps from {LOW:.3g} m/s^2 to "
             + ", ".join(f"{h:g} m/s^2 ({r})" for r, h in RECORDS.items()) + f", refined to {TOLERANCE:.1%}. "
             "Smallest overturning PGA (m/s^2); * a larger PGA left standing what a smaller one toppled.", ""]
    columns = [(r, n) for r in RECORDS for n in DRUMS]
    cell = {(r.record, r.n_drums, r.mu): r for r in table.itertuples(index=False)}
    rows = [[f"{mu:g}"] + [fmt(cell[(r, n, mu)].smallest, cell[(r, n, mu)].non_monotonic,
                                cell[(r, n, mu)].failed_runs) for r, n in columns] for mu in FRICTIONS]
    setup += markdown_table(["mu"] + [f"{r}, {n} drum{'s' * (n > 1)}" for r, n in columns], rows)
    findings = []
    for r, n in columns:
        runs = table[(table.record == r) & (table.n_drums == n)].sort_values("mu")
        v = runs.smallest.to_numpy()
        finite = np.isfinite(v)
        if finite.sum() >= 2:
            known = runs[finite]
            at_low = known[np.isclose(known.smallest, known.smallest.min(), rtol=TOLERANCE)].mu
            at_high = known[np.isclose(known.smallest, known.smallest.max(), rtol=TOLERANCE)].mu
            findings.append(f"{r}, {n} drum(s): lowest {known.smallest.min():.3g} m/s^2 at mu "
                            f"{', '.join(f'{m:g}' for m in at_low)}, highest {known.smallest.max():.3g} m/s^2 at mu "
                            f"{', '.join(f'{m:g}' for m in at_high)}; from mu 0.485 to 1.0 the threshold changes by "
                            f"{v[-1] / v[list(runs.mu).index(0.485)] - 1:+.0%}.")
        else:
            findings.append(f"{r}, {n} drum(s): overturned at {int(finite.sum())} of {len(v)} frictions.")
    findings.append(f"Searches with a PGA left standing above one that toppled: {int(table.non_monotonic.sum())} of "
                    f"{len(table)}; failed runs: {int(table.failed_runs.sum())}.")
    write_readme(NAME, "Overturning PGA against friction", findings, [figure(table, columns)], started,
                 "friction_threshold.py", resumes=False, tables=setup)


def figure(table, columns):
    fig, ax = plt.subplots(figsize=(7, 4.5))
    for r, n in columns:
        runs = table[(table.record == r) & (table.n_drums == n)].sort_values("mu")
        ax.plot(runs.mu, runs.smallest, "o-" if n == 1 else "s--", label=f"{r}, {n} drum{'s' * (n > 1)}")
    ax.axvline(1.0 / 6.0, color="0.5", ls=":", label="tan(alpha) = 1/6")
    ax.set(xlabel="friction coefficient", ylabel="smallest overturning PGA (m/s$^2$)",
           title="Columns 6 m x 1 m, default contact law")
    return save_figure(fig, NAME, "friction_threshold.png",
                       "The table's smallest overturning PGA against the friction coefficient, one line per record "
                       "and drum count; a gap is a friction at which nothing overturned within the scan.", legend=8)


if __name__ == "__main__":
    main()
