"""Colonnades under harmonic motion at 0.5 to 2 Hz: number of columns, spacing, epistyle type a to d, epistyle
density 5000 to 10000 kg/m^3, tapered columns, and a two-tier colonnade."""

import time

import matplotlib.pyplot as plt
from _study import curve, save, sweep, write_readme

from dem_core import excitation, scenes
from dem_core.analyses.sweep import RunSpec

NAME = "colonnades"
FREQUENCIES = [0.5, 0.75, 1.0, 1.5, 2.0]
PGA = 3.0  # m/s^2
DURATION = 10.0  # s


def _run(scene, p):
    motion = excitation.harmonic(pga=p.get("pga", PGA), frequency=p["frequency"])
    return RunSpec(scene, motion, {"duration": DURATION, "output_dt": 0.01})


def epistyles(p):
    return _run(scenes.colonnade(3, 3, spacing=2.5, epistyle=p["epistyle"], epistyle_density=p["density"]), p)


def layout(p):
    return _run(scenes.colonnade(p["n_columns"], 3, spacing=p["spacing"], epistyle="a"), p)


def taper(p):
    return _run(scenes.colonnade(3, 3, spacing=2.5, epistyle="a", taper=p["taper"]), p)


def two_tier(p):
    return _run(scenes.two_tier_colonnade(3, 2.5, epistyle="a"), p)


def epistyle_displacement(table):
    cols = [c for c in table.columns if c.startswith("peak_displacement:") and "epistyle" in c]
    return table[cols].max(axis=1)


def peak(table):
    return table.max_peak_abs_theta_rad * 1e3  # mrad


def epi(table):
    return epistyle_displacement(table) * 1e3  # mm


def panel(ax, table, group, label, measure, ylabel):
    for k, value in enumerate(sorted(table[group].unique())):
        runs = table[table[group] == value].sort_values("frequency")
        curve(ax, runs.frequency, measure(runs), runs.overturned, f"{label} {value:g}", row=k)
    ax.set(xlabel="frequency (Hz)", ylabel=ylabel)
    ax.grid(alpha=0.3)
    ax.legend(fontsize=7)


def main():
    started = time.perf_counter()
    kinds = sweep(f"{NAME}/epistyles", epistyles, {"epistyle": ["a", "b", "c", "d"], "density": [2700.0, 5000.0,
                                                                                              7500.0, 10000.0],
                                                   "frequency": FREQUENCIES})
    spans = sweep(f"{NAME}/layout", layout, {"n_columns": [2, 3, 4, 5], "spacing": [1.5, 2.5, 4.0],
                                             "frequency": FREQUENCIES})
    tapers = sweep(f"{NAME}/taper", taper, {"taper": [0.0, 0.1, 0.2, 0.3], "frequency": FREQUENCIES})
    tiers = sweep(f"{NAME}/two_tier", two_tier, {"pga": [1.5, 3.0, 4.5], "frequency": FREQUENCIES})

    fig, axes = plt.subplots(2, 4, figsize=(16, 7), sharex=True)
    for k, kind in enumerate("abcd"):
        panel(axes[0, k], kinds[kinds.epistyle == kind], "density", "kg/m^3", peak, "peak rotation (mrad)")
        panel(axes[1, k], kinds[kinds.epistyle == kind], "density", "kg/m^3", epi, "epistyle displacement (mm)")
        axes[0, k].set_title(f"epistyle type {kind}")
    fig.suptitle(f"3 columns x 3 drums, spacing 2.5 m, harmonic PGA {PGA:g} m/s^2 (x on top: overturned)", fontsize=10)
    fig.tight_layout()
    figures = [save(fig, NAME, "epistyle_type_density.png")]

    fig, axes = plt.subplots(2, 3, figsize=(13, 7), sharex=True)
    for k, spacing in enumerate(sorted(spans.spacing.unique())):
        panel(axes[0, k], spans[spans.spacing == spacing], "n_columns", "columns:", peak, "peak rotation (mrad)")
        panel(axes[1, k], spans[spans.spacing == spacing], "n_columns", "columns:", epi, "epistyle displacement (mm)")
        axes[0, k].set_title(f"spacing {spacing:g} m")
    fig.suptitle(f"Colonnades of 3-drum columns, one epistyle (a), harmonic PGA {PGA:g} m/s^2", fontsize=10)
    fig.tight_layout()
    figures.append(save(fig, NAME, "columns_spacing.png"))

    fig, axes = plt.subplots(1, 3, figsize=(14, 4))
    panel(axes[0], tapers, "taper", "taper", peak, "peak rotation (mrad)")
    panel(axes[1], tapers, "taper", "taper", epi, "epistyle displacement (mm)")
    panel(axes[2], tiers, "pga", "two-tier, PGA", epi, "top epistyle displacement (mm)")
    axes[0].set_title("tapered columns (same mass)")
    axes[2].set_title("two-tier colonnade")
    fig.tight_layout()
    figures.append(save(fig, NAME, "taper_two_tier.png"))

    ok = kinds[kinds.status == "ok"]
    findings = []
    for kind in "abcd":
        runs = ok[ok.epistyle == kind]
        fallen = runs[runs.overturned]
        standing = runs[~runs.overturned]
        by_density = standing.groupby("density").max_peak_abs_theta_rad.median() * 1e3
        findings.append(f"Epistyle {kind}: overturned in {len(fallen)} of {len(runs)} runs (at "
                        f"{', '.join(f'{f:g}' for f in sorted(fallen.frequency.unique())) or 'no'} Hz); median peak "
                        "rotation of the standing runs by epistyle density: "
                        + ", ".join(f"{d:g} kg/m^3 {v:.3g} mrad" for d, v in by_density.items()) + ".")
    fallen = spans[spans.overturned]
    standing = spans[~spans.overturned & (spans.frequency >= 1.0)]
    findings.append(f"Number of columns and spacing: {len(fallen)} of {len(spans)} runs overturned, at "
                    f"{', '.join(f'{f:g}' for f in sorted(fallen.frequency.unique()))} Hz; by number of columns "
                    f"{fallen.groupby('n_columns').size().to_dict()}, by spacing "
                    f"{fallen.groupby('spacing').size().to_dict()}. Median peak rotation at 1 to 2 Hz by number of "
                    "columns: " + ", ".join(f"{n}: {v * 1e3:.3g} mrad" for n, v in
                                           standing.groupby("n_columns").max_peak_abs_theta_rad.median().items()) + ".")
    standing = tapers[~tapers.overturned & (tapers.frequency >= 1.0)]
    findings.append("Taper, median peak rotation at 1 to 2 Hz: " + ", ".join(
        f"{t:g}: {v * 1e3:.3g} mrad" for t, v in standing.groupby("taper").max_peak_abs_theta_rad.median().items())
        + f"; overturned runs by taper: {tapers.groupby('taper').overturned.sum().astype(int).to_dict()}.")
    standing = tiers[~tiers.overturned]
    findings.append("Two-tier colonnade, overturned runs by PGA: "
                    f"{tiers.groupby('pga').overturned.sum().astype(int).to_dict()}; top epistyle peak displacement "
                    "of the standing runs by PGA: " + ", ".join(
                        f"{p:g} m/s^2 {v * 1e3:.3g} mm" for p, v in
                        epistyle_displacement(standing).groupby(standing.pga).max().items()) + ".")
    write_readme(NAME, "Colonnades under harmonic motion", findings, figures, started, "colonnades.py")


if __name__ == "__main__":
    main()
