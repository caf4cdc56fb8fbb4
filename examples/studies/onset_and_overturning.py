"""Rocking-onset and overturning acceleration of a 6 m x 1 m column under a 0.5 m/s^2/s ramp, against the
number of drums (1 to 8) and against taper."""

import time

import matplotlib.pyplot as plt
from _study import DEFAULT_MODEL, results_table, save_figure, write_readme

from comparisons.cases.measures import first_exceedance
from comparisons.references import analytical
from dem_core import scenes
from dem_core.analyses.thresholds import ROCKING_FRACTION, onset_under_ramp

NAME = "onset_and_overturning"
RATE = 0.5  # m/s^2 per s
DRUMS = range(1, 9)
TAPERS = (0.0, 0.1, 0.2, 0.3)
G_TAN_ALPHA = 9.81 * 1.0 / 6.0  # rigid monolith: g b / h
FRICTION = 0.7


def measure(n_drums, taper):
    scene = scenes.column(n_drums, taper=taper, friction=FRICTION)
    found = onset_under_ramp(scene, RATE, duration=12.0)
    return {"n_drums": n_drums, "taper": taper, "rocking_onset": found.rocking, "sliding_onset": found.sliding,
            "overturning": found.overturning}


def main():
    started = time.perf_counter()
    rows = [measure(n, 0.0) for n in DRUMS] + [measure(n, t) for n in (1, 4, 8) for t in TAPERS if t > 0]
    table = results_table(NAME, rows)
    prismatic = table[table.taper == 0.0]
    fig, (ax_n, ax_t) = plt.subplots(1, 2, figsize=(10, 4))
    ax_n.plot(prismatic.n_drums, prismatic.rocking_onset, "o-", label="rocking starts (theta_cr/30)")
    ax_n.plot(prismatic.n_drums, prismatic.overturning, "s-", label="overturns")
    ax_n.axhline(G_TAN_ALPHA, color="0.5", ls=":", label="g b/h (rigid monolith)")
    ax_n.set(xlabel="number of drums", ylabel="ground acceleration (m/s$^2$)",
             title=f"Prismatic 6 m x 1 m column, ramp {RATE:g} m/s$^2$/s")
    for n in (1, 4, 8):
        runs = table[table.n_drums == n].sort_values("taper")
        ax_t.plot(runs.taper, runs.rocking_onset, "o-", label=f"{n} drums: rocking starts")
        ax_t.plot(runs.taper, runs.overturning, "s--", label=f"{n} drums: overturns")
    ax_t.set(xlabel="taper (W_bottom - W_top) / W_bottom", ylabel="ground acceleration (m/s$^2$)",
             title="Tapered columns (same mass)")
    figures = [save_figure(fig, NAME, "onset_overturning.png",
                           "Left: the ramp accelerations at which rocking starts and the column overturns against the "
                           "number of drums, with the rigid uplift g b/h; right: the same against taper for 1, 4 and 8 "
                           "drums.", legend=7)]
    one, eight = prismatic.iloc[0], prismatic.iloc[-1]
    block = analytical.RockingBlock.from_size(1.0, 6.0)
    rigid = analytical.rocking_response(block, lambda t: RATE * t, 12.0, max_step=1e-3)
    rigid_onset = RATE * first_exceedance(rigid.t, rigid.theta, ROCKING_FRACTION * block.alpha)
    rigid_overturn = RATE * rigid.overturn_time
    findings = [
        (f"Set-up: columns 6 m x 1 m, friction {FRICTION:g} (the builders' default), {DEFAULT_MODEL}, "
         f"ground acceleration rising at {RATE:g} m/s^2 per s; tapered "
         "columns keep the prismatic column's mass."),
        (f"Monolith: rocking starts at {one.rocking_onset:.3g} m/s^2 and it overturns at {one.overturning:.3g} m/s^2. "
         f"The rigid rocking equation under the same ramp passes theta_cr/30 at {rigid_onset:.3g} m/s^2 and "
         f"overturns at {rigid_overturn:.3g} m/s^2 (uplift itself starts at g b/h = {G_TAN_ALPHA:.3g} m/s^2): "
         f"differences {one.rocking_onset / rigid_onset - 1:+.1%} and {one.overturning / rigid_overturn - 1:+.1%}."),
        (f"8 drums: rocking starts at {eight.rocking_onset:.3g} m/s^2 and the column overturns at "
        f"{eight.overturning:.3g} m/s^2; over 1 to 8 drums the onset spans {prismatic.rocking_onset.min():.3g} to "
        f"{prismatic.rocking_onset.max():.3g} m/s^2 and the overturning {prismatic.overturning.min():.3g} to "
        f"{prismatic.overturning.max():.3g} m/s^2."),
    ]
    by_taper = table[table.n_drums.isin((1, 4, 8))].pivot_table(index="taper", columns="n_drums",
                                                                  values=["rocking_onset", "overturning"])
    spread = float((by_taper.T.groupby(level=0).max() - by_taper.T.groupby(level=0).min()).max().max())
    findings.append(f"Tapered columns of 1, 4 and 8 drums differ by at most {spread:.2g} m/s^2 at the same taper "
                    "(their lines in the right panel lie on one another).")
    for n in (1, 4, 8):
        runs = table[table.n_drums == n].sort_values("taper")
        findings.append(f"{n} drum(s): taper 0 to {runs.taper.max():g} moves the rocking onset from "
                        f"{runs.rocking_onset.iloc[0]:.3g} to {runs.rocking_onset.iloc[-1]:.3g} m/s^2 and the "
                        f"overturning from {runs.overturning.iloc[0]:.3g} to {runs.overturning.iloc[-1]:.3g} m/s^2.")
    write_readme(NAME, "Rocking onset and overturning under a ramp: number of drums and taper", findings, figures,
                 started, "onset_and_overturning.py", resumes=False)


if __name__ == "__main__":
    main()
