"""Colonnades under harmonic motion at 0.5 to 2 Hz: number of columns, spacing, epistyle type a to d, epistyle
density 5000 to 10000 kg/m^3, tapered columns, and a two-tier colonnade."""

import time

import matplotlib.pyplot as plt
import numpy as np
from _study import DEFAULT_MODEL, curve, save_figure, sweep, write_readme

from dem_core import excitation, scenes
from dem_core.analyses.sweep import RunSpec

NAME = "colonnades"
FREQUENCIES = [0.5, 0.75, 1.0, 1.5, 2.0]
PGA = 3.0  # m/s^2
DURATION = 10.0  # s
FRICTION = 0.7  # the builders' default, stated here


def _run(scene, p):
    motion = excitation.harmonic(pga=p.get("pga", PGA), frequency=p["frequency"])
    return RunSpec(scene, motion, {"duration": DURATION, "output_dt": 0.01})


def epistyles(p):
    return _run(scenes.colonnade(3, 3, spacing=2.5, epistyle=p["epistyle"], epistyle_density=p["density"],
                                 friction=FRICTION), p)


def layout(p):
    return _run(scenes.colonnade(p["n_columns"], 3, spacing=p["spacing"], epistyle="a", friction=FRICTION), p)


def taper(p):
    return _run(scenes.colonnade(3, 3, spacing=2.5, epistyle="a", taper=p["taper"], friction=FRICTION), p)


def two_tier(p):
    return _run(scenes.two_tier_colonnade(3, 2.5, epistyle="a", friction=FRICTION), p)


def epistyle_displacement(table, prefix=""):
    """Largest peak displacement (m) of the epistyles named ``<prefix>epistyle...``."""
    cols = [c for c in table.columns if c.startswith(f"peak_abs_displacement_m[{prefix}epistyle")]
    return table[cols].max(axis=1)


def peak(table):
    return table.max_peak_abs_theta_rad * 1e3  # mrad


def epi(table):
    return epistyle_displacement(table) * 1e3  # mm


def upper_epi(table):
    return epistyle_displacement(table, "upper_") * 1e3  # mm


def failed(table):
    return (table.status != "ok").to_numpy()


def panel(ax, table, group, label, measure, ylabel):
    for k, value in enumerate(sorted(table[group].unique())):
        runs = table[table[group] == value].sort_values("frequency")
        curve(ax, runs.frequency, measure(runs), runs.overturned.fillna(False).astype(bool), f"{label} {value:g}",
              row=k, failed=failed(runs))
    ax.set(xlabel="frequency (Hz)", ylabel=ylabel)
    ax.grid(alpha=0.3)
    ax.legend(fontsize=7)


def outcome_counts(runs) -> str:
    ok = runs[runs.status == "ok"]
    text = f"{int(ok.overturned.sum())} overturned, {int((~ok.overturned).sum())} standing"
    bad = runs[runs.status != "ok"]
    return text + (f", {len(bad)} failed ({', '.join(f'{s}' for s in bad.status)})" if len(bad) else "")


def common_medians(runs, group, measure):
    """Median of ``measure`` per value of ``group`` over the frequencies at which every value of ``group``
    finished standing (the same set of runs for each), and those frequencies."""
    standing = runs[(runs.status == "ok") & ~runs.overturned.fillna(False).astype(bool)]
    groups = sorted(runs[group].unique())
    frequencies = sorted(set.intersection(*(set(standing[standing[group] == g].frequency) for g in groups)))
    common = standing[standing.frequency.isin(frequencies)]
    return common.groupby(group).apply(lambda t: float(np.median(measure(t)))), frequencies


def main():
    started = time.perf_counter()
    kinds = sweep(f"{NAME}/epistyles", epistyles, {"epistyle": ["a", "b", "c", "d"], "density": [2700.0, 5000.0,
                                                                                              7500.0, 10000.0],
                                                   "frequency": FREQUENCIES})
    spans = sweep(f"{NAME}/layout", layout, {"n_columns": [2, 3, 4, 5], "spacing": [1.5, 2.5, 4.0],
                                             "frequency": FREQUENCIES})
    tapers = sweep(f"{NAME}/taper", taper, {"taper": [0.0, 0.1, 0.2, 0.3], "frequency": FREQUENCIES})
    tiers = sweep(f"{NAME}/two_tier", two_tier, {"pga": [1.5, 3.0, 4.5], "frequency": FREQUENCIES})
    shown = figures(kinds, spans, tapers, tiers)
    write_readme(NAME, "Colonnades under harmonic motion", findings(kinds, spans, tapers, tiers), shown, started,
                 "colonnades.py")


def two_row_figure(panels, group, label, setup, figsize):
    """Peak rotation (top row) and epistyle displacement (bottom row) against frequency: a column of panels per
    ``(title, runs)`` of ``panels``, a line per value of ``group``; ``setup`` begins the figure's title."""
    fig, axes = plt.subplots(2, len(panels), figsize=figsize, sharex=True)
    for k, (title, runs) in enumerate(panels):
        panel(axes[0, k], runs, group, label, peak, "peak rotation (mrad)")
        panel(axes[1, k], runs, group, label, epi, "epistyle displacement (mm)")
        axes[0, k].set_title(title)
    fig.suptitle(f"{setup}, harmonic PGA {PGA:g} m/s^2 (x on top: overturned; open diamond at the bottom: run "
                 "failed)", fontsize=10)
    return fig


def figures(kinds, spans, tapers, tiers):
    """The study's three figures, as :func:`write_readme` takes them."""
    fig = two_row_figure([(f"epistyle type {kind}", kinds[kinds.epistyle == kind]) for kind in "abcd"], "density",
                         "kg/m^3", "3 columns x 3 drums, spacing 2.5 m", (16, 7))
    found = [save_figure(fig, NAME, "epistyle_type_density.png",
                         "Peak rotation (top) and epistyle displacement (bottom) against frequency, one panel per "
                         "epistyle type, one line per epistyle density; crosses along the top are runs that "
                         "overturned, open diamonds along the bottom runs that failed.")]
    fig = two_row_figure([(f"spacing {spacing:g} m", spans[spans.spacing == spacing])
                          for spacing in sorted(spans.spacing.unique())], "n_columns", "columns:",
                         "Colonnades of 3-drum columns, one epistyle (a)", (13, 7))
    found.append(save_figure(fig, NAME, "columns_spacing.png",
                             "The same measures for 2 to 5 columns (lines) at each spacing (panels); failed runs are "
                             "the open diamonds, not standing runs."))
    fig, axes = plt.subplots(1, 4, figsize=(17, 4))
    panel(axes[0], tapers, "taper", "taper", peak, "peak rotation (mrad)")
    panel(axes[1], tapers, "taper", "taper", epi, "epistyle displacement (mm)")
    panel(axes[2], tiers, "pga", "PGA", lambda t: epistyle_displacement(t, "lower_") * 1e3,
          "lower epistyle displacement (mm)")
    panel(axes[3], tiers, "pga", "PGA", upper_epi, "upper epistyle displacement (mm)")
    axes[0].set_title("tapered columns (same mass)")
    axes[2].set_title("two-tier colonnade: lower epistyle")
    axes[3].set_title("two-tier colonnade: upper epistyle")
    found.append(save_figure(fig, NAME, "taper_two_tier.png",
                             "Tapered colonnades (left two panels) and the two-tier colonnade's lower and upper "
                             "epistyles at three PGAs (right two panels)."))
    return found


def rotation_finding(heading, runs, group, by, item):
    """A finding: the outcomes of ``runs`` and their median peak rotation by ``group`` (called ``by``), each
    value and median written as ``item(value, median)``."""
    medians, common = common_medians(runs, group, peak)
    return (f"{heading}: {outcome_counts(runs)} of {len(runs)} runs; median peak rotation at "
            f"{', '.join(f'{f:g}' for f in common) or 'no'} Hz by {by}: "
            + (", ".join(item(value, median) for value, median in medians.items()) or "none") + ".")


def findings(kinds, spans, tapers, tiers):
    """The study's findings, computed from its sweeps."""
    found = [f"Set-up: friction {FRICTION:g} at every interface, {DEFAULT_MODEL}, "
             f"harmonic ground motion for {DURATION:g} s at PGA {PGA:g} "
             "m/s^2 unless stated; columns 6 m x 1 m of 3 drums, epistyles 0.8 m high. Medians are over the "
             "frequencies at which every compared case stood, named in each line; failed runs (the run stopped "
             "on an energy-balance or stability error) are counted apart, never as standing."]
    found += [rotation_finding(f"Epistyle {kind}", kinds[kinds.epistyle == kind], "density", "epistyle density",
                               lambda d, v: f"{d:g} kg/m^3 {v:.3g} mrad") for kind in "abcd"]
    found += [rotation_finding(f"Spacing {spacing:g} m", spans[spans.spacing == spacing], "n_columns",
                               "number of columns", lambda n, v: f"{n}: {v:.3g} mrad")
              for spacing in sorted(spans.spacing.unique())]
    found.append(rotation_finding("Taper", tapers, "taper", "taper", lambda t, v: f"{t:g}: {v:.3g} mrad"))
    for pga in sorted(tiers.pga.unique()):
        runs = tiers[tiers.pga == pga]
        standing = runs[(runs.status == "ok") & ~runs.overturned.fillna(False).astype(bool)]
        lower = epistyle_displacement(standing, "lower_") * 1e3
        upper = upper_epi(standing)
        found.append(f"Two-tier colonnade at PGA {pga:g} m/s^2: {outcome_counts(runs)} of {len(runs)} runs; "
                     "largest peak displacement of the standing runs: lower epistyle "
                     + (f"{lower.max():.3g} mm, upper epistyle {upper.max():.3g} mm" if len(standing) else "none")
                     + ".")
    return found


if __name__ == "__main__":
    main()
