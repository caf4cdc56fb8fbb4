"""Different friction at different interfaces of 4- and 8-block columns: mu = 0.05 to 0.35 at one interface,
0.48 at the others, under harmonic motion at 0.5 Hz with 0.3 m amplitude."""

import time

import matplotlib.pyplot as plt
import numpy as np
from _study import DEFAULT_MODEL, save_figure, sweep, write_readme

from dem_core import excitation, scenes
from dem_core.analyses.sweep import RunSpec

NAME = "interface_friction"
MU_ELSEWHERE = 0.48
MUS = [0.05, 0.1, 0.15, 0.2, 0.25, 0.3, 0.35]
FREQUENCY, AMPLITUDE = 0.5, 0.3  # Hz, m: PGA = A (2 pi f)^2 = 2.96 m/s^2
DURATION = 20.0  # s


def interface_names(n_blocks, k):
    """Interface k (0 = base) of an n-block column as a pair of block names."""
    return ("base" if k == 0 else f"drum{k}", f"drum{k + 1}")


def column(p):
    n = p["blocks"]
    weak = interface_names(n, p["interface"])
    scene = scenes.column(n, friction=MU_ELSEWHERE, interface_friction={weak: p["mu"]})
    return RunSpec(scene, excitation.harmonic(AMPLITUDE, FREQUENCY), {"duration": DURATION, "output_dt": 0.01})


def main():
    started = time.perf_counter()
    tables = {n: sweep(f"{NAME}/column_{n}", column, {"blocks": [n], "interface": list(range(n)), "mu": MUS})
              for n in (4, 8)}
    fig, axes = plt.subplots(2, 2, figsize=(12, 7.5))
    findings = [f"Set-up: columns 6 m x 1 m of 4 and 8 blocks, friction {MU_ELSEWHERE:g} except at one interface, "
                f"{DEFAULT_MODEL}, harmonic ground motion "
                f"{AMPLITUDE:g} m at {FREQUENCY:g} Hz for {DURATION:g} s."]
    for row, (n, table) in enumerate(tables.items()):
        for k in range(n):
            runs = table[table.interface == k].sort_values("mu")
            label = "base" if k == 0 else f"{k}-{k + 1}"
            standing = np.where(runs.overturned, runs.overturn_time_s, DURATION)
            axes[row, 0].plot(runs.mu, runs.total_sliding_m * 1e3 / standing, "o-", ms=3, label=f"weak: {label}")
            axes[row, 1].plot(runs.mu, standing, "o-", ms=3, label=f"weak: {label}")
        axes[row, 0].set(ylabel=f"{n} blocks: total sliding per second\nstanding (mm/s)", yscale="log")
        axes[row, 1].set(ylabel=f"time standing (s; {DURATION:g} = survived)")
        for ax in axes[row]:
            ax.set_xlabel(f"mu at the weak interface (elsewhere {MU_ELSEWHERE:g})")
            ax.grid(alpha=0.3)
        axes[row, 0].legend(fontsize=7, ncol=2)
        finished = table[table.status == "ok"]
        survived = finished[~finished.overturned].sort_values(["interface", "mu"])
        findings.append(f"{n} blocks: {len(survived)} of {len(table)} runs stay up: "
                        + ("; ".join(f"weak interface {int(r.interface)} (0 = base) at mu {r.mu:g}, total sliding "
                                     f"{r.total_sliding_m * 1e3:.3g} mm, mean rocking "
                                     f"{r.mean_rocking_rad * 1e3:.3g} mrad"
                                     for r in survived.itertuples()) or "none") + ".")
        fallen = finished[finished.overturned]
        findings.append(f"{n} blocks: the others overturn after {fallen.overturn_time_s.min():.3g} to "
                        f"{fallen.overturn_time_s.max():.3g} s (median {fallen.overturn_time_s.median():.3g} s); "
                        "by weak interface, median time standing: " + ", ".join(
                            f"{k}: {v:.3g} s" for k, v in fallen.groupby("interface").overturn_time_s.median().items())
                        + ".")
        bad = table[table.status != "ok"]
        findings.append(f"{n} blocks: {len(bad)} runs failed (counted neither as standing nor as overturned)"
                        + (f": {bad.status.value_counts().to_dict()}" if len(bad) else "") + ".")
        low = finished[finished.mu == min(MUS)]
        findings.append(f"{n} blocks, mu {min(MUS):g}: total sliding up to the end or the overturn, by weak interface "
                        "(0 = base): " + ", ".join(f"{int(r.interface)}: {r.total_sliding_m * 1e3:.3g} mm"
                                                   for r in low.sort_values("interface").itertuples()) + ".")
    fig.suptitle(f"One weak interface, harmonic {AMPLITUDE:g} m at {FREQUENCY:g} Hz "
                 f"(PGA {AMPLITUDE * (2 * np.pi * FREQUENCY) ** 2:.2f} m/s^2; sliding up to the end of the run or the "
                 "overturn)", fontsize=10)
    figures = [save_figure(fig, NAME, "weak_interface.png",
                           "Left: total sliding per second standing against the weak interface's friction, one line "
                           "per weak interface; right: time standing (the run's length for a column that survived).")]
    write_readme(NAME, "Different friction at different interfaces", findings, figures, started,
                 "interface_friction.py")


if __name__ == "__main__":
    main()
