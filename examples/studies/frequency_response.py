"""Total sliding and mean rocking against the frequency of harmonic ground motion, for several friction
coefficients and PGAs: a small-scale column of 7 blocks (48 x 48 x 29 mm) and a 6 m x 1 m 8-drum column."""

import time

import matplotlib.pyplot as plt
import numpy as np
from _study import DEFAULT_MODEL, curve, plain_log_ticks, save_figure, sweep, write_readme

from dem_core import excitation, scenes
from dem_core.analyses.sweep import RunSpec

NAME = "frequency_response"
SMALL = {"frequency": list(np.round(np.geomspace(1.0, 20.0, 12), 3)), "pga": [3.0, 5.0, 7.0],
         "mu": [0.3, 0.5, 0.68]}
LARGE = {"frequency": [0.5, 0.75, 1.0, 1.25, 1.5, 2.0, 2.5, 3.0, 4.0, 5.0], "pga": [2.0, 3.0, 4.0],
         "mu": [0.3, 0.5, 0.7]}


def small_column(p):
    scene = scenes.column(7, width=0.048, height=7 * 0.029, depth=0.048, friction=p["mu"])
    return RunSpec(scene, excitation.harmonic(pga=p["pga"], frequency=p["frequency"]),
                   {"duration": 5.0, "output_dt": 0.005})


def large_column(p):
    scene = scenes.column(8, friction=p["mu"])
    return RunSpec(scene, excitation.harmonic(pga=p["pga"], frequency=p["frequency"]),
                   {"duration": 10.0, "output_dt": 0.01})


def figure(table, title, mu_ref):
    pgas = sorted(table.pga.unique())
    fig, axes = plt.subplots(len(pgas), 2, figsize=(10, 2.8 * len(pgas)), sharex=True, squeeze=False)
    for row, pga in enumerate(pgas):
        for k, mu in enumerate(sorted(table.mu.unique())):
            runs = table[(table.pga == pga) & (table.mu == mu)].sort_values("frequency")
            for col, measure, scale in ((0, "total_sliding_m", 1e3), (1, "mean_rocking_rad", 1e3)):
                curve(axes[row, col], runs.frequency, runs[measure] * scale, runs.overturned.fillna(False).astype(bool),
                      f"mu = {mu:g}", row=k, failed=(runs.status != "ok").to_numpy(), lw=2 if mu == mu_ref else 1)
        axes[row, 0].set_ylabel(f"PGA {pga:g} m/s$^2$\ntotal sliding (mm)")
        axes[row, 1].set_ylabel("mean |rotation| (mrad)")
    for ax in axes.ravel():
        ax.set_xscale("log")
        plain_log_ticks(ax.xaxis)
        ax.grid(True, which="both", alpha=0.3)
    for ax in axes[-1]:
        ax.set_xlabel("frequency (Hz)")
    axes[0, 0].legend(fontsize=8)
    fig.suptitle(f"{title} (x on top: overturned)", fontsize=10)
    return fig


def findings(table, label, mu_ref):
    out = []
    ok = table[table.status == "ok"]
    for pga in sorted(ok.pga.unique()):
        runs = ok[(ok.pga == pga) & (ok.mu == mu_ref)].sort_values("frequency")
        standing = runs[~runs.overturned]
        fallen = runs[runs.overturned]
        if len(standing):
            top = standing.loc[standing.mean_rocking_rad.idxmax()]
            high = standing[standing.frequency == standing.frequency.max()].iloc[0]
            out.append(f"{label}, PGA {pga:g} m/s^2, mu {mu_ref:g}: of the runs left standing, the largest mean "
                       f"rocking is at {top.frequency:g} Hz ({top.mean_rocking_rad * 1e3:.3g} mrad), the one at the "
                       f"highest frequency ({high.frequency:g} Hz) {high.mean_rocking_rad * 1e3:.3g} mrad; "
                       "overturned at "
                       + (", ".join(f"{f:g}" for f in fallen.frequency) + " Hz" if len(fallen) else "no frequency")
                       + ".")
    by_mu = ok[~ok.overturned].groupby("mu").total_sliding_m.median()
    out.append(f"{label}: median total sliding over all frequencies and PGAs of the runs left standing "
               + ", ".join(f"{v * 1e3:.3g} mm at mu {m:g}" for m, v in by_mu.items()) + " (each mu over its own "
               "standing runs).")
    fallen = ok[ok.overturned]
    if len(fallen):
        out.append(f"{label}: {len(fallen)} of {len(ok)} finished runs overturned, at frequencies "
                   f"{fallen.frequency.min():g} to {fallen.frequency.max():g} Hz "
                   f"(PGAs {', '.join(f'{p:g}' for p in sorted(fallen.pga.unique()))} m/s^2).")
    else:
        out.append(f"{label}: none of the {len(ok)} finished runs overturned.")
    failed = table[table.status != "ok"]
    out.append(f"{label}: {len(failed)} runs stopped without a result"
               + (f": {failed.status.value_counts().to_dict()}" if len(failed) else "") + ".")
    return out


def main():
    started = time.perf_counter()
    small = sweep(f"{NAME}/small_column", small_column, SMALL)
    large = sweep(f"{NAME}/column_8_drums", large_column, LARGE)
    figures = [save_figure(figure(small, "7-block column 48 x 48 x 29 mm under harmonic motion", 0.68), NAME,
                           "small_column.png", "Small-scale column: total sliding (left) and mean rocking (right) "
                           "against frequency, one row per PGA, one line per friction coefficient."),
               save_figure(figure(large, "8-drum column 6 m x 1 m under harmonic motion", 0.7), NAME,
                           "column_8_drums.png", "The same for the 8-drum column.")]
    text = [f"Set-up: {DEFAULT_MODEL}, harmonic ground "
            f"motion scaled to its PGA; small-scale column 5 s, mu {', '.join(f'{m:g}' for m in SMALL['mu'])}; "
            f"8-drum column 10 s, mu {', '.join(f'{m:g}' for m in LARGE['mu'])}. Overturned runs are crosses at "
            "the top of the figures, failed runs open diamonds at the bottom."]
    text += findings(small, "Small-scale column", 0.68) + findings(large, "8-drum column", 0.7)
    write_readme(NAME, "Sliding and rocking against excitation frequency", text, figures, started,
                 "frequency_response.py")


if __name__ == "__main__":
    main()
