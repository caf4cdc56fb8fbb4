"""Figures of a run over time, with the ground motion below: block rotations, displacements,
epistyle motion and the sliding accumulated at each interface.

A column's drums are drawn as one line where they move together: consecutive drums whose
values stay within :data:`DRUM_AGREEMENT` of the column's peak of each other at every output
share one line (their mean) and a shaded band (from the lowest to the highest of them), its
legend entry saying how far apart they get ("drum1\u2013drum8, within 0.0027 rad of each
other"); a drum that moves differently gets its own line, drawn over the groups' lines and
bands.

The rotation axis fits the response: the critical angle is drawn when it is within
:data:`CRITICAL_IN_VIEW` times the peak rotation, and otherwise named in the legend, off the axis.
"""

from pathlib import Path

import matplotlib

matplotlib.use("Agg")  # files only: the command line and CI have no screen
import matplotlib.pyplot as plt
import numpy as np

from ..analyses.damage import critical_angles
from ..analyses.thresholds import SLIP_THRESHOLD
from ..inputs.excitation import GroundMotion, peak_acceleration
from ..inputs.records import G_STANDARD
from ..output_files import replacing
from . import slip_scale

#: drums within this fraction of their column's peak |value| of each other at all times share a line
DRUM_AGREEMENT = 0.10
#: the critical angle is drawn (and the axis widened to it) when it is at most this many times the peak rotation;
#: otherwise the axis fits the response and the legend names the critical angle, off the axis
CRITICAL_IN_VIEW = 2.0
#: interfaces whose accumulated slip stays below this (m) are drawn together as one grey line
SLID = SLIP_THRESHOLD
#: the most interfaces drawn each in its own colour (the qualitative map's colours, none repeated); the others
#: that slid join the grey line
MOST_SLIP_LINES = 10
OVERTURN = "crimson"
#: the dashed lines at the critical angle, and their legend's sample where they are off the axis
CRITICAL_LINE = {"color": "0.2", "ls": "--", "lw": 0.9}


def _ground_panel(ax, result, excitation):
    """The ground's horizontal acceleration under a figure's panels, named with its peak (m/s^2 and g; a ramp's at
    the run's end) above it; the base's displacement where no motion is given."""
    if excitation is not None:
        a_x, _ = excitation.acceleration(result.t)
        ax.plot(result.t, a_x, color="0.3", lw=0.8)
        peak = peak_acceleration(GroundMotion(excitation.horizontal), float(result.t[-1]))
        ax.set_title(f"{excitation.name}: peak ground acceleration {peak:.3g} m/s$^2$ ({peak / G_STANDARD:.3g} g)",
                     loc="left", fontsize=8)
        ax.set_ylabel("ground acc.\n(m/s$^2$)")
        in_g = ax.secondary_yaxis("right", functions=(lambda a: a / G_STANDARD, lambda g: g * G_STANDARD))
        in_g.set_ylabel("(g)")
    else:
        ax.plot(result.t, result.base_x, color="0.3", lw=0.8)
        ax.set_ylabel("ground disp.\n(m)")
    ax.grid(alpha=0.3)


def _first_to_overturn(result) -> str:
    first = [n for n, t in zip(result.names, result.overturn_time) if t == result.time_of_overturn]
    for column in result.columns:
        if set(column.blocks) == set(first):
            return f"column {column.blocks[0]}\u2013{column.blocks[-1]}"
    return ", ".join(first) if len(first) <= 3 else f"{first[0]} and {len(first) - 1} more"


def _finish(fig, axes, result, title):
    """Overturn marker on every panel and its label inside the top one, the title, a tight layout."""
    axes[-1].set_xlabel("time (s)")
    if result.overturned:
        when = result.time_of_overturn
        for ax in axes:
            ax.axvline(when, color=OVERTURN, ls="--", lw=1)
        x0, x1 = axes[0].get_xlim()
        right_half = when > 0.5 * (x0 + x1)
        axes[0].annotate(f"{_first_to_overturn(result)} overturns at {when:.2f} s", (when, 0.99),
                         xycoords=("data", "axes fraction"), xytext=(-4 if right_half else 4, 0),
                         textcoords="offset points", ha="right" if right_half else "left", va="top",
                         color=OVERTURN, fontsize=8, bbox={"fc": "white", "ec": "none", "alpha": 0.8, "pad": 1})
    fig.suptitle(title, fontsize=10)
    fig.tight_layout()
    return fig


def _legend(ax, **options):
    """The legend to the right of the axes, where it hides no line."""
    ax.legend(fontsize=7, loc="upper left", bbox_to_anchor=(1.01, 1.0), borderaxespad=0.0, alignment="left",
              **options)


def block_groups(result, values, tolerance: float = DRUM_AGREEMENT) -> list:
    """Blocks drawn as one line, as tuples of indices in scene order: runs of consecutive drums of a
    column (``result.columns``) whose ``values`` (n, n_blocks) stay within ``tolerance`` times the
    column's peak |value| of each other at every output; every other block alone."""
    groups, done = [], set()
    members = {name: column for column in result.columns for name in column.blocks}
    for k, name in enumerate(result.names):
        if k in done:
            continue
        if name not in members:
            groups.append((k,))
            continue
        drums = [result.index(n) for n in members[name].blocks]
        allowed = tolerance * np.nanmax(np.abs(values[:, drums]))
        run = [drums[0]]
        for drum in drums[1:]:
            joined = values[:, run + [drum]]
            if np.nanmax(joined.max(axis=1) - joined.min(axis=1)) <= allowed:
                run.append(drum)
            else:
                groups.append(tuple(run))
                run = [drum]
        groups.append(tuple(run))
        done.update(drums)
    return groups


def _group_label(result, group, values=None, unit: str = "") -> str:
    """A group's legend entry: its block, or its first and last drums and (given ``values``) the most they are
    apart at any output, "drum1\u2013drum8,\\nwithin 0.0027 rad of each other"."""
    if len(group) == 1:
        return result.names[group[0]]
    label = f"{result.names[group[0]]}\u2013{result.names[group[-1]]}"
    if values is None:
        return label
    part = values[:, list(group)]
    spread = float(np.nanmax(part.max(axis=1) - part.min(axis=1))) if len(part) else 0.0
    return f"{label},\nwithin {spread:.2g}{' ' + unit if unit else ''} of each other"


def _draw_groups(ax, result, values, groups, colour_map, unit: str = ""):
    """One line per group (the mean of its blocks) and, for groups of several drums, their spread: the bands
    under every line, and the lines of single blocks over those of groups, so that none hides another."""
    colours = colour_map(np.linspace(0, 0.9, len(groups)))
    for group, colour in zip(groups, colours):
        part = values[:, list(group)]
        ax.plot(result.t, part.mean(axis=1), lw=0.9, color=colour, zorder=3 if len(group) == 1 else 2,
                label=_group_label(result, group, values, unit))
        if len(group) > 1:
            ax.fill_between(result.t, part.min(axis=1), part.max(axis=1), color=colour, alpha=0.3, lw=0, zorder=1)


def _spread_note(groups) -> str:
    if all(len(g) == 1 for g in groups):
        return ""
    return (f"drums within {DRUM_AGREEMENT:.0%} of their column's\npeak of each other: one line (their mean),"
            "\nshaded from the lowest to the highest")


def _history_figure(result, values, ylabel, colour_map, excitation, title, unit: str = ""):
    """Figure: ``values`` (n, n_blocks) over time, a line per group of :func:`block_groups`, the
    ground motion below; returns the figure, its axes and the groups."""
    fig, axes = plt.subplots(2, 1, sharex=True, figsize=(10, 6), gridspec_kw={"height_ratios": [3, 1]})
    groups = block_groups(result, values)
    _draw_groups(axes[0], result, values, groups, colour_map, unit)
    axes[0].set_ylabel(ylabel)
    axes[0].grid(alpha=0.3)
    _ground_panel(axes[1], result, excitation)
    return fig, axes, groups


def _holders(result, groups, alpha, value) -> str:
    """Who has critical angle ``value``: the columns, or the blocks by name."""
    labels = [_group_label(result, g) for g in groups if np.isclose(alpha[g[0]], value)]
    column_drums = {n for c in result.columns for n in c.blocks}
    if all(result.names[g[0]] in column_drums for g in groups if np.isclose(alpha[g[0]], value)):
        return "columns" if len(result.columns) > 1 else "column"
    return ", ".join(labels) if len(labels) <= 3 else f"{len(labels)} blocks"


def rotations(result, excitation=None, title="Block rotations", *, relative: bool = False):
    """Figure: rotation of every block over time, and the ground motion below.

    relative : plot theta / alpha (alpha the critical angle: a column's for its drums, a block's own
        otherwise), with dashed lines at +-1; else theta in rad with dashed lines at +-alpha (an
        alpha far beyond the motion is named in the legend instead).
    Drums that move together share a line (:func:`block_groups`).
    """
    has_alpha = result.critical_angle is not None
    if relative and not has_alpha:
        raise ValueError("cannot plot theta / alpha: the result carries no critical angles")
    alpha = critical_angles(result) if has_alpha else None
    values = result.theta / alpha if relative else result.theta
    ylabel = "rotation / critical angle, $\\theta/\\alpha$" if relative else "rotation $\\theta$ (rad)"
    fig, axes, groups = _history_figure(result, values, ylabel, plt.cm.viridis, excitation, title,
                                        "" if relative else "rad")
    ax = axes[0]
    peak = float(np.nanmax(np.abs(values))) if values.size else 0.0
    reach = peak
    if relative:
        levels = {1.0: "critical angle, $\\theta/\\alpha = \\pm 1$"}
    elif has_alpha:
        levels = {value: f"critical angle $\\pm\\alpha$ = {value:.3g} rad ({_holders(result, groups, alpha, value)})"
                  for value in sorted({float(alpha[g[0]]) for g in groups})}
    else:
        levels = {}
    for value, label in levels.items():
        if value <= CRITICAL_IN_VIEW * peak:
            reach = max(reach, value)
            ax.axhline(value, **CRITICAL_LINE, label=label)
            ax.axhline(-value, **CRITICAL_LINE)
        else:
            times = f" ({value / peak:.2g} \u00d7 the peak)" if peak > 0 else ""
            ax.plot([], [], **CRITICAL_LINE, label=f"{label}:\noff the axis{times}")
    if not reach > 0:
        reach = min(levels) if levels else 1.0
    ax.set_ylim(-1.1 * reach, 1.1 * reach)
    _legend(ax, title=_spread_note(groups) or None, title_fontsize=7)
    return _finish(fig, axes, result, title)


def displacements(result, excitation=None, title="Horizontal displacements of the blocks relative to the base"):
    """Figure: horizontal displacement of every block relative to the base since the start (m),
    and the ground motion below; drums that move together share a line."""
    values = result.relative_x - result.relative_x[0]
    fig, axes, groups = _history_figure(result, values, "horizontal displacement (m)", plt.cm.plasma, excitation, title,
                                        "m")
    _legend(axes[0], title=_spread_note(groups) or None, title_fontsize=7)
    return _finish(fig, axes, result, title)


def epistyle_names(result) -> list:
    return [n for n in result.names if "epistyle" in n]


def epistyles(result, excitation=None, title="Epistyles"):
    """Figure: horizontal displacement relative to the base (m) and rotation (rad) of every
    epistyle, and the ground motion below."""
    names = epistyle_names(result)
    if not names:
        raise ValueError("the run has no block named like an epistyle")
    index = [result.names.index(n) for n in names]
    fig, axes = plt.subplots(3, 1, sharex=True, figsize=(10, 7), gridspec_kw={"height_ratios": [2, 2, 1]})
    rel = result.relative_x - result.relative_x[0]
    for k, name in zip(index, names):
        axes[0].plot(result.t, rel[:, k], lw=0.9, label=name)
        axes[1].plot(result.t, result.theta[:, k], lw=0.9, label=name)
    axes[0].set_ylabel("horizontal displacement (m)")
    axes[1].set_ylabel("rotation $\\theta$ (rad)")
    for ax in axes[:2]:
        ax.grid(alpha=0.3)
    _legend(axes[0])
    _ground_panel(axes[2], result, excitation)
    return _finish(fig, axes, result, title)


def sliding(result, excitation=None, title="Sliding at the interfaces", *, threshold: float = SLID):
    """Figure: slip accumulated at each interface over time (:func:`~dem_core.pictures.slip_scale` of the largest),
    from ``result.slip_history``: a line per interface (named lower/upper, as interfaces.csv names it) whose slip passed
    ``threshold`` m, the largest :data:`MOST_SLIP_LINES` of them each in a colour of its own, the others as one grey
    line (the largest of them at each output); the ground motion below."""
    if result.slip_history is None:
        raise ValueError("the result carries no slip history (an engine that does not measure it)")
    slip = np.asarray(result.slip_history, dtype=float)
    total = np.nanmax(slip, axis=0, initial=0.0) if len(slip) else np.zeros(len(result.interfaces))
    order = [int(k) for k in np.argsort(-total, kind="stable")]
    drawn = [k for k in order if total[k] > threshold][:MOST_SLIP_LINES]
    rest = [k for k in order if k not in drawn]
    scale, unit = slip_scale(float(np.max(total, initial=0.0)))
    fig, axes = plt.subplots(2, 1, sharex=True, figsize=(10, 6), gridspec_kw={"height_ratios": [3, 1]})
    ax = axes[0]
    t = result.t[:len(slip)]
    for k, colour in zip(drawn, plt.cm.tab10(np.arange(len(drawn)))):
        ax.plot(t, scale * slip[:, k], lw=1.0, color=colour, label="/".join(result.interfaces[k]))
    if rest:
        largest = scale * total[rest[0]]
        others = "other " if drawn else ""
        label = ("/".join(result.interfaces[rest[0]]) if len(rest) == 1 else
                 f"largest slip of {len(rest)} {others}interfaces")
        ax.plot(t, scale * np.nanmax(slip[:, rest], axis=1), lw=1.0, color="0.6",
                label=f"{label} (at most {largest:.2g} {unit})")
    ax.set_ylabel(f"accumulated sliding ({unit})")
    top = max(ax.get_ylim()[1], 1.05 * scale * threshold)  # slips under the threshold lie flat, above the axis
    ax.set_ylim(-0.02 * top, top)
    ax.grid(alpha=0.3)
    if len(result.interfaces):
        _legend(ax, title=None if drawn else f"no interface slid more than {scale * threshold:g} {unit}",
                title_fontsize=7)
    _ground_panel(axes[1], result, excitation)
    return _finish(fig, axes, result, title)


def save_run_figures(result, out_dir, excitation=None, title="", *, relative_rotations: bool = False):
    """Write rotations.png, displacements.png, sliding.png (when the result has a slip history) and
    epistyles.png (when the scene has epistyles) into ``out_dir`` (created if need be); returns their
    paths.  Each file is written whole or not at all (:func:`dem_core.output_files.replacing`).
    relative_rotations : rotations as theta / alpha (see :func:`rotations`)."""
    out_dir = Path(out_dir)
    out_dir.mkdir(parents=True, exist_ok=True)
    paths = []

    def rotation_figure(result, excitation, title):
        return rotations(result, excitation, title, relative=relative_rotations)

    figures = [("rotations.png", rotation_figure, "block rotations"),
               ("displacements.png", displacements, "horizontal displacements relative to the base")]
    if result.slip_history is not None and len(result.interfaces):
        figures.append(("sliding.png", sliding, "sliding at the interfaces"))
    if epistyle_names(result):
        figures.append(("epistyles.png", epistyles, "epistyles"))
    for name, make, what in figures:
        fig = make(result, excitation, title=f"{title}: {what}" if title else what.capitalize())
        path = out_dir / name
        try:
            with replacing(path) as tmp:
                fig.savefig(tmp, dpi=130, format="png")
        finally:
            plt.close(fig)
        paths.append(path)
    return paths
