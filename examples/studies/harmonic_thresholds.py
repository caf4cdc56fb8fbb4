"""Rocking-onset and overturning acceleration of the 8-drum column against the frequency of harmonic motion
(the thesis' chapter 6 study of the standalone column), with the rigid monolith's as reference.

For each frequency, the peak ground acceleration of a harmonic motion of fixed duration is searched
(:func:`dem_core.analyses.thresholds.onset_threshold`, :func:`overturning_threshold`): the smallest PGA
that starts rocking (a drum rotating past theta_cr/30) and the smallest that overturns, every overturning
window kept.  The rocking equation of the 1 x 6 m monolith under the same motions is the rigid reference.
"""

import sys
import time

import matplotlib.pyplot as plt
import numpy as np
from _rigid import overturning as rigid_overturning
from _study import (
    DEFAULT_MODEL,
    cached_threshold,
    fmt,
    markdown_table,
    plain_log_ticks,
    results_table,
    save_figure,
    threshold_columns,
    write_readme,
)

from comparisons.references.analytical import RockingBlock
from dem_core import excitation, scenes
from dem_core.analyses.thresholds import onset_threshold, overturning_threshold

NAME = "harmonic_thresholds"
FREQUENCIES = (0.5, 1.0, 2.0, 4.0)  # Hz
DURATION = 8.0  # s of harmonic motion (sine in displacement, from rest)
FRICTION = 0.485
N_DRUMS = 8
G = 9.80665
UPLIFT = G * 1.0 / 6.0  # m/s^2, g b / h
LOW, HIGH = 0.8 * UPLIFT, 30.0  # m/s^2, the overturning scan
ONSET_SCAN = 12  # evenly spaced PGAs from LOW to ONSET_HIGH, then every change refined
ONSET_HIGH = 3.0 * UPLIFT
STEP, TOLERANCE = 0.02, 0.005


def motion(frequency):
    return lambda pga: excitation.harmonic(pga=pga, frequency=frequency)


def main():
    started = time.perf_counter()
    scene = scenes.column(N_DRUMS, friction=FRICTION)
    block = RockingBlock.from_size(1.0, 6.0)
    rows = []
    for f in FREQUENCIES:
        onset = cached_threshold(NAME, f"onset_{f:g}", lambda: onset_threshold(
            scene, motion(f), LOW, ONSET_HIGH, criterion="rocking", scan=ONSET_SCAN, tolerance=TOLERANCE,
            duration=DURATION))
        over = cached_threshold(NAME, f"overturning_{f:g}", lambda: overturning_threshold(
            scene, motion(f), LOW, HIGH, step=STEP, tolerance=TOLERANCE, duration=DURATION, output_dt=0.05))
        rigid = cached_threshold(NAME, f"rigid_{f:g}", lambda: rigid_overturning(
            block, block.restitution, motion(f), LOW, HIGH, DURATION, step=STEP, tolerance=TOLERANCE))
        rows.append({"frequency": f, "onset": onset.value, "onset_failed": len(onset.failures),
                     **threshold_columns(over), **threshold_columns(rigid, "rigid_")})
        print(f"{f:g} Hz: onset {onset.value:.3g}, overturning {over.smallest:.3g}, rigid {rigid.smallest:.3g}",
              file=sys.stderr, flush=True)
    report(results_table(NAME, rows), started)


def report(table, started):
    setup = [f"Set-up: 8-drum column 6 m x 1 m, friction {FRICTION:g}, {DEFAULT_MODEL}; "
             f"harmonic ground motion u_g = A sin(2 pi f t) for {DURATION:g} s, "
             f"scaled by its PGA A (2 pi f)^2. Onset: theta_cr/30, {ONSET_SCAN} PGAs from {LOW:.3g} to "
             f"{ONSET_HIGH:.3g} m/s^2, each change refined to {TOLERANCE:.1%}. Overturning: {STEP:.0%} steps from "
             f"{LOW:.3g} to {HIGH:g} m/s^2, refined to {TOLERANCE:.1%}; the rigid reference is the rocking equation of "
             f"the monolith under the same motion. Uplift of a rigid column: g b/h = {UPLIFT:.3g} m/s^2.", ""]
    rows = [[f"{r.frequency:g}", fmt(r.onset, failed=r.onset_failed), fmt(r.smallest, r.non_monotonic, r.failed_runs),
             r.windows or "-", fmt(r.rigid_smallest, r.rigid_non_monotonic), r.rigid_windows or "-"]
            for r in table.itertuples(index=False)]
    setup += markdown_table(["f (Hz)", "rocking onset PGA", "overturning PGA (8 drums)", "overturning windows",
                             "overturning PGA (rigid monolith)", "rigid windows"], rows)
    findings = []
    onset = table.onset.to_numpy()
    findings.append(f"Rocking onset from {np.nanmin(onset):.3g} to {np.nanmax(onset):.3g} m/s^2 over "
                    f"{table.frequency.min():g} to {table.frequency.max():g} Hz ({np.nanmin(onset) / UPLIFT:.2f} to "
                    f"{np.nanmax(onset) / UPLIFT:.2f} times g b/h).")
    over = table.smallest.to_numpy()
    rising = np.all(np.diff(np.nan_to_num(over, nan=np.inf)) > 0)
    findings.append("Overturning PGA of the 8-drum column: " + ", ".join(
        f"{fmt(v)} at {f:g} Hz" for f, v in zip(table.frequency, over)) + "; it "
        + ("rises with the frequency at every step." if rising else "does not rise at every step."))
    ratio = table.smallest / table.rigid_smallest
    findings.append("8 drums over the rigid monolith: " + ", ".join(
        f"{r:.2f} at {f:g} Hz" for f, r in zip(table.frequency, ratio) if np.isfinite(r)) + ".")
    odd = table[table.non_monotonic]
    findings.append(f"Searches with a PGA left standing above one that toppled (*): {len(odd)} of {len(table)}"
                    + (f" ({', '.join(f'{f:g} Hz' for f in odd.frequency)})" if len(odd) else "") + ".")
    write_readme(NAME, "Onset and overturning of the 8-drum column against harmonic frequency", findings,
                 [figure(table)], started, "harmonic_thresholds.py", resumes=False, tables=setup)


def figure(table):
    fig, ax = plt.subplots(figsize=(7, 4.5))
    ax.plot(table.frequency, table.onset, "o-", label="8 drums: rocking starts (theta_cr/30)")
    ax.plot(table.frequency, table.smallest, "s-", label="8 drums: smallest overturning PGA")
    ax.plot(table.frequency, table.rigid_smallest, "kx--", label="rigid monolith: smallest overturning PGA")
    ax.axhline(UPLIFT, color="0.5", ls=":", label="g b/h")
    ax.set(xscale="log", yscale="log", xlabel="frequency (Hz)", ylabel="PGA (m/s$^2$)",
           title=f"Harmonic motion, {DURATION:g} s, friction {FRICTION:g}, default contact law")
    plain_log_ticks(ax.xaxis)
    plain_log_ticks(ax.yaxis)
    ax.set_xticks(sorted(table.frequency.unique()))  # the frequencies run
    return save_figure(fig, NAME, "harmonic_thresholds.png",
                       "The table's thresholds against frequency: rocking onset and smallest overturning PGA of the "
                       "8-drum column, and the rigid monolith's smallest overturning PGA; the dotted line is the rigid "
                       "uplift g b/h.", legend=8, grid={"which": "both"})


if __name__ == "__main__":
    main()
