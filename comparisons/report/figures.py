"""The report's figures, each saved only once every text in it is seen whole.

:func:`save` draws a figure and refuses it (:class:`FigureTextCut`) if any drawn artist reaches past
the figure's edge (a title cut mid-word) or a text placed in a tile runs out of it; titles are
wrapped to the figure's width first.  Errors below the exact floor are drawn on the floor line.  Relative
errors are drawn in percent (the tables' unit), axes say what they plot, legends use plain words, and point
labels that would overlap another label, a point or the legend are left out (:func:`label_points`).
"""

import json
import textwrap

import matplotlib

matplotlib.use("Agg")
import matplotlib.pyplot as plt
import numpy as np

from comparisons.cases.case import exact_floor, metric_kind
from comparisons.harness.engines import USUAL_STEP, step_label
from comparisons.report.glossary import AXIS_NAMES
from comparisons.report.verdicts import observed_order

COLOURS = {"dem": "#1b9e77", "dem-overlap": "#66a61e", "dem-moreau": "#1f78b4", "pymunk": "#d95f02", "pybullet": "#7570b3",
           "mujoco": "#e7298a"}
STATUS_COLOURS = {"ok": "#1b9e77", "silently wrong": "#e6ab02", "stopped": "#d95f02"}
DPI = 110
#: characters of a title line per inch of figure width at the title font size
TITLE_CHARACTERS_PER_INCH = 13


class FigureTextCut(RuntimeError):
    """A figure would be saved with a text cut at its edge or outside its tile."""


def title(ax, text: str, fontsize: float = 10) -> None:
    """Set ``text`` as the axes' title, wrapped to the figure's width."""
    width = ax.figure.get_figwidth() * ax.get_position().width
    ax.set_title("\n".join(textwrap.wrap(text, max(20, int(width * TITLE_CHARACTERS_PER_INCH * 10 / fontsize)))),
                 fontsize=fontsize)


def save(fig, path, tiles=(), layout: bool = True) -> None:
    """Lay out, check and write ``fig`` to ``path`` (PNG), then close it.

    tiles : ``(text, patch)`` pairs: each text must lie inside its patch.
    layout : apply ``tight_layout`` (False when the caller laid the figure out itself).
    Raises :class:`FigureTextCut` naming the first text that does not fit.
    """
    if layout:
        fig.tight_layout()
    fig.canvas.draw()
    renderer = fig.canvas.get_renderer()
    drawn = fig.get_tightbbox(renderer)
    edge = fig.bbox_inches
    slack = 0.5 / DPI
    if (drawn.x0 < edge.x0 - slack or drawn.y0 < edge.y0 - slack or drawn.x1 > edge.x1 + slack
            or drawn.y1 > edge.y1 + slack):
        plt.close(fig)
        raise FigureTextCut(f"{path}: something is drawn past the figure's edge ({_outside_text(fig, renderer)})")
    for text, patch in tiles:
        inner, outer = text.get_window_extent(renderer), patch.get_window_extent(renderer)
        if inner.x0 < outer.x0 or inner.x1 > outer.x1 or inner.y0 < outer.y0 or inner.y1 > outer.y1:
            plt.close(fig)
            raise FigureTextCut(f"{path}: the text {text.get_text()!r} runs out of its tile")
    fig.savefig(path, dpi=DPI)
    plt.close(fig)


def _outside_text(fig, renderer) -> str:
    frame = fig.bbox
    for text in fig.findobj(matplotlib.text.Text):
        if text.get_visible() and text.get_text().strip() and text.get_figure() is fig:
            box = text.get_window_extent(renderer)
            if box.x0 < frame.x0 or box.x1 > frame.x1 or box.y0 < frame.y0 or box.y1 > frame.y1:
                return f"text {text.get_text()!r}"
    return "a drawn artist"


def is_relative_error(metric: str) -> bool:
    """Whether ``metric`` is a relative error (drawn and printed in percent); ``*_s`` stress-test values and
    ``*_m``, ``*_rad``, ``*_J`` errors are not."""
    return metric_kind(metric) == "relative" and not metric.endswith("_s")


def error_label(metric: str) -> str:
    """The axis label of the |error| of ``metric``: ``peak rotation |error| (%)``, ``horizontal drift |error| (m)``."""
    name = AXIS_NAMES.get(metric, metric.replace("_", " "))
    if is_relative_error(metric):
        return f"{name} |error| (%)"
    unit = metric.rsplit("_", 1)[-1]
    return f"{name.removesuffix(f' ({unit})')} |error| ({unit})"


def spectrum_label(spec) -> str:
    """A spectrum in a few plain words: ``sine pulse, 1.5 x 6 m block``."""
    width, height = spec.block
    return f"{spec.pulse} pulse, {width:g} x {height:g} m block"


def run_label(step: str, settings: str = "{}") -> str:
    """A run as its point's label: its step, and the solver iterations where it was run with more."""
    iterations = json.loads(settings or "{}").get("iterations")
    return step if iterations is None else f"{step}, {iterations} iterations"


#: offsets (points) tried in turn for a point's label: right above, right below, left above, left below
LABEL_OFFSETS = ((4, 2), (4, -8), (-4, 2), (-4, -8))


def label_points(ax, xs, ys, labels, fontsize: float = 6) -> int:
    """Write each label beside its point where it overlaps no label already placed, no point and not the legend,
    and stays inside the axes; try :data:`LABEL_OFFSETS` in turn and leave the label out where none fits. Call
    it once the figure is laid out (after ``tight_layout``; save with ``layout=False``). Returns how many were
    placed."""
    fig = ax.figure
    fig.canvas.draw()
    renderer = fig.canvas.get_renderer()
    frame = ax.get_window_extent(renderer)
    points = [(x, y) for x, y in zip(xs, ys, strict=True) if np.isfinite(x) and np.isfinite(y) and x > 0 and y > 0]
    centres = ax.transData.transform(np.array(points, float)) if points else np.empty((0, 2))
    half = 2.5  # pixels around a marker kept free of labels
    taken = [matplotlib.transforms.Bbox([[cx - half, cy - half], [cx + half, cy + half]]) for cx, cy in centres]
    legend = ax.get_legend()
    if legend is not None:
        taken.append(legend.get_window_extent(renderer))
    placed = 0
    for x, y, label in zip(xs, ys, labels, strict=True):
        if not (np.isfinite(x) and np.isfinite(y) and x > 0 and y > 0):
            continue
        for dx, dy in LABEL_OFFSETS:
            text = ax.annotate(label, (x, y), xytext=(dx, dy), textcoords="offset points", fontsize=fontsize,
                               alpha=0.8, ha="left" if dx > 0 else "right")
            box = text.get_window_extent(renderer).padded(1.5)  # a gap between neighbouring labels
            inside = frame.x0 <= box.x0 and box.x1 <= frame.x1 and frame.y0 <= box.y0 and box.y1 <= frame.y1
            if inside and not any(box.overlaps(other) for other in taken):
                taken.append(box)
                placed += 1
                break
            text.remove()
    return placed


def plain_log(ax, axes="xy") -> None:
    """Log scale on ``axes`` with major ticks as plain numbers and no minor tick labels (which overlap); an
    axis whose data all lie on one value spans a decade either side of it."""
    for name in axes:
        axis = ax.xaxis if name == "x" else ax.yaxis
        low, high = ax.dataLim.intervalx if name == "x" else ax.dataLim.intervaly
        if low == high > 0:
            (ax.set_xlim if name == "x" else ax.set_ylim)(low / 10, high * 10)
        (ax.set_xscale if name == "x" else ax.set_yscale)("log")
        axis.set_major_formatter(matplotlib.ticker.FuncFormatter(lambda v, _: f"{v:g}"))
        axis.set_minor_formatter(matplotlib.ticker.NullFormatter())


def _log_axes(ax, xlabel, ylabel, metric=None):
    """Log axes, except a linear y for a yes-or-no measure (0 agrees, 1 disagrees)."""
    if metric is not None and metric_kind(metric) == "mismatch":
        plain_log(ax, "x")
        ax.set_ylim(-0.1, 1.1)
        ax.set_yticks([0, 1], ["agrees (0)", "disagrees (1)"])
        ylabel = ""
    else:
        plain_log(ax)
    ax.set_xlabel(xlabel)
    ax.set_ylabel(ylabel)
    ax.grid(alpha=0.3, which="both")
    if ax.get_legend_handles_labels()[0]:
        ax.legend(fontsize=7)


def _scale(metric) -> float:
    """What an error of ``metric`` is multiplied by to be drawn: 100 (percent) for a relative error, else 1."""
    return 100.0 if is_relative_error(metric) else 1.0


def _on_floor(errors, metric):
    """|errors| raised to the exact floor (a mismatch as it is: 0 or 1), in the drawn unit (percent for a
    relative error), and the floor in that unit."""
    if metric_kind(metric) == "mismatch":
        return np.abs(np.asarray(errors, float)), 0.0
    floor = exact_floor(metric)
    scale = _scale(metric)
    return scale * np.maximum(np.abs(np.asarray(errors, float)), floor), scale * floor


def _floor_line(ax, errors, metric) -> None:
    """The exact floor as a dashed line, where some error comes within a factor 100 of it."""
    floor = exact_floor(metric)
    if floor and len(errors) and np.nanmin(np.abs(np.asarray(errors, float))) < 100 * floor:
        ax.axhline(_scale(metric) * floor, color="0.5", ls="--", lw=0.8, label="exact below this")


def pareto_figure(runs, case_name, metric, path, case_title: str | None = None) -> None:
    """|error| of ``metric`` against wall time, a point per run labelled by its step where the label fits
    (``runs``: the case's rows of that metric that finished); errors below the exact floor sit on the dashed
    floor line."""
    fig, ax = plt.subplots(figsize=(6.4, 4.2))
    xs, ys, labels = [], [], []
    for engine, mine in runs.groupby("engine", sort=False):
        y, _ = _on_floor(mine.error, metric)
        ax.scatter(mine.wall_time_s, y, color=COLOURS.get(engine), label=engine, s=18)
        xs += list(mine.wall_time_s)
        ys += list(y)
        labels += [run_label(step, settings) for step, settings in zip(mine.step, mine.settings, strict=True)]
    _floor_line(ax, runs.error, metric)
    title(ax, f"{case_title or case_name}: |error| against run time")
    _log_axes(ax, "wall time of the run (s)", error_label(metric), metric)
    fig.tight_layout()
    label_points(ax, xs, ys, labels)
    save(fig, path, layout=False)


def convergence_figure(runs, case_name, metric, path, case_title: str | None = None) -> None:
    """|error| of ``metric`` against dt per engine (default settings), the observed order in the legend."""
    fig, ax = plt.subplots(figsize=(6.4, 4.2))
    plain = runs[runs.settings == "{}"]
    for engine, mine in plain.groupby("engine", sort=False):
        mine = mine.sort_values("dt")
        y, _ = _on_floor(mine.error, metric)
        order = observed_order(mine["dt"], np.where(np.abs(mine.error) < exact_floor(metric), np.nan, mine.error))
        ax.plot(mine["dt"], y, "o-", color=COLOURS.get(engine), label=f"{engine} (order {order:.2g})", ms=4)
    _floor_line(ax, plain.error, metric)
    title(ax, f"{case_title or case_name}: convergence in dt")
    _log_axes(ax, "time step dt (s)", error_label(metric), metric)
    save(fig, path)


def ensemble_pareto_figure(summary, name, path, overturning: bool = True, ensemble_title: str | None = None) -> None:
    """Median |peak error| (point) to its 90th percentile (bar) against the median run time, and (with
    ``overturning``) the agreement on overturning against the median run time; a point per engine and step,
    labelled by its step where the label fits."""
    if overturning:
        fig, (ax, ax_agree) = plt.subplots(1, 2, figsize=(11, 4.2))
    else:
        fig, ax = plt.subplots(figsize=(6.4, 4.2))
        ax_agree = None
    floor = 1e-4  # percent: a median of 0 is drawn here
    for engine, mine in summary.groupby("engine", sort=False):
        colour = COLOURS.get(engine)
        median = np.maximum(100 * mine.median_error, floor)
        ax.errorbar(mine.median_wall_time_s, median,
                    yerr=[np.zeros(len(mine)), np.maximum(100 * mine.p90_error - median, 0.0)],
                    fmt="o", color=colour, label=engine, capsize=2, ms=5)
        if ax_agree is not None:
            ax_agree.plot(mine.median_wall_time_s, 100 * mine.overturn_agreement, "o", color=colour, label=engine)
    name = ensemble_title or name
    title(ax, f"{name}: median |peak error| (point) and 90th percentile (bar top) against run time")
    _log_axes(ax, "median wall time of a run (s)", "median |peak error| (%)")
    if ax_agree is not None:
        plain_log(ax_agree, "x")
        ax_agree.set(xlabel="median wall time of a run (s)", ylabel="runs agreeing on overturning (%)")
        ax_agree.set_ylim(min(80.0, 100 * summary.overturn_agreement.min() - 2), 101)
        ax_agree.grid(alpha=0.3, which="both")
        title(ax_agree, "Agreement on overturning against run time")
    fig.tight_layout()
    label_points(ax, list(summary.median_wall_time_s), list(np.maximum(100 * summary.median_error, floor)),
                 list(summary.step))
    if ax_agree is not None:
        label_points(ax_agree, list(summary.median_wall_time_s), list(100 * summary.overturn_agreement),
                     list(summary.step))
    save(fig, path, layout=False)


def ensemble_members_figure(table, name, unit, path) -> None:
    """Each engine's peak against the reference's, run by run, at its usual step: rotation over alpha for
    rocking, slip in mm for sliding; overturned runs at 1 (rocking)."""
    at_usual = np.array([step == step_label(e, USUAL_STEP[e]) for e, step in zip(table.engine, table.step,
                                                                                 strict=True)], dtype=bool)
    usual = table[at_usual & (table.settings == "{}").to_numpy()]
    engines = list(dict.fromkeys(usual.engine))
    fig, axes = plt.subplots(1, max(1, len(engines)), figsize=(2.6 * max(1, len(engines)) + 0.6, 3.2),
                             sharex=True, sharey=True, squeeze=False)
    for ax, engine in zip(axes[0], engines, strict=False):
        mine = usual[usual.engine == engine]
        ref, got = _scaled(mine, unit)
        ax.plot(ref, got, ".", color=COLOURS.get(engine), ms=4)
        if unit == "alpha":
            low, high = 0.0, 1.0
            ax.set(xlim=(0, 1.05), ylim=(0, 1.05))
        else:
            low, high = np.nanmin(ref[ref > 0]), max(np.nanmax(ref), np.nanmax(got))
            plain_log(ax)
        ax.plot([low, high], [low, high], color="0.5", lw=0.8)
        ax.set_xlabel(f"reference peak ({unit})", fontsize=8)
        title(ax, engine, fontsize=9)
        ax.tick_params(labelsize=7)
        ax.grid(alpha=0.3, which="both")
    axes[0][0].set_ylabel(f"engine's peak ({unit})", fontsize=8)
    save(fig, path)


def _scaled(rows, unit):
    if unit == "mm":
        return 1e3 * rows.reference_peak.to_numpy(float), 1e3 * rows.peak.to_numpy(float)
    alpha = np.arctan2(*np.array([_block_size(b) for b in rows.block]).T)
    ref = np.where(rows.reference_overturned, 1.0, rows.reference_peak / alpha)
    return ref, np.where(rows.overturned, 1.0, rows.peak / alpha)


def _block_size(label):
    width, height = label.removesuffix(" m").split(" x ")
    return float(width), float(height)


def spectrum_figure(table, spec, closed_form, path) -> None:
    """A panel per engine: the reference's boundaries (lines: the first one; ticks: every change of
    outcome), each point filled where the engine overturns, red where it disagrees with the reference;
    ``closed_form`` (x -> amplitude, or None) is drawn dashed."""
    engines = list(dict.fromkeys(table.engine))
    columns = sorted(table.column.unique())
    transitions = table.drop_duplicates("column").set_index("column").transitions
    first = [transitions[c][0] if len(transitions[c]) else np.nan for c in columns]
    fig, axes = plt.subplots(1, max(1, len(engines)), figsize=(2.6 * max(1, len(engines)) + 0.6, 3.4),
                             sharex=True, sharey=True, squeeze=False)
    for ax, engine in zip(axes[0], engines, strict=False):
        ax.plot(columns, first, "-", color="0.3", lw=1, label="reference")
        for c in columns:
            for a in transitions[c]:
                ax.plot([c], [a], "_", color="0.2", ms=8)
        if closed_form is not None:
            x = np.geomspace(min(columns), max(columns), 100)
            ax.plot(x, closed_form(x), "--", color="0.5", lw=0.8, label="linearised")
        mine = table[table.engine == engine]
        agree = mine.overturned == mine.reference_overturned
        for wrong, colour in ((False, COLOURS.get(engine)), (True, "red")):
            pick = mine[agree != wrong]
            ax.scatter(pick.column, pick.amplitude, s=14, edgecolors=colour,
                       facecolors=[colour if o else "none" for o in pick.overturned], linewidths=0.8)
        plain_log(ax)
        ax.set_xlabel(spec.x_label, fontsize=8)
        ax.tick_params(labelsize=7)
        ax.grid(alpha=0.3, which="both")
        title(ax, f"{engine}: {agree.mean():.0%} agree", fontsize=9)
    axes[0][0].set_ylabel("a_p / (g tan alpha)", fontsize=8)
    axes[0][0].legend(fontsize=6)
    fig.text(0.5, 0.01, "filled: the engine overturns; hollow: it survives; red: it disagrees with the reference",
             ha="center", fontsize=8)
    fig.tight_layout(rect=(0, 0.05, 1, 1))
    save(fig, path, layout=False)


def spectra_overview_figure(summary, path, labels: dict | None = None) -> None:
    """Agreement with the reference's overturning spectra against the median run time, a point per engine
    (colour), spectrum (marker) and step; two short legends, one per engine and one per spectrum.

    labels : ``{spectrum name: plain words}`` (default: the name)."""
    labels = labels or {}
    fig, ax = plt.subplots(figsize=(7.4, 4.2))
    markers = dict(zip(dict.fromkeys(summary.spectrum), "osD^v<>p*", strict=False))
    for (engine, spectrum), mine in summary.groupby(["engine", "spectrum"], sort=False):
        ax.plot(mine.median_wall_time_s, 100 * mine.agreement, markers[spectrum], color=COLOURS.get(engine),
                ms=5, alpha=0.85)
    plain_log(ax, "x")
    ax.set(xlabel="median wall time of a run (s)", ylabel="points agreeing with the reference (%)")
    ax.grid(alpha=0.3, which="both")
    line = matplotlib.lines.Line2D
    engines = [line([], [], ls="", marker="o", color=COLOURS.get(e), label=e) for e in dict.fromkeys(summary.engine)]
    spectra = [line([], [], ls="", marker=m, color="0.35", label=labels.get(s, s)) for s, m in markers.items()]
    first = ax.legend(handles=engines, title="engine", fontsize=7, title_fontsize=7, loc="upper left",
                      bbox_to_anchor=(1.02, 1.0), frameon=False)
    ax.add_artist(first)
    ax.legend(handles=spectra, title="spectrum", fontsize=7, title_fontsize=7, loc="lower left",
              bbox_to_anchor=(1.02, 0.0), frameon=False)
    title(ax, "Overturning spectra: agreement against run time")
    save(fig, path)


def stress_value(metric: str, value: float) -> str:
    """A stress-test value as a tile shows it: a relative error in percent, anything else in its unit."""
    name = AXIS_NAMES.get(metric, metric.replace("_", " "))
    if is_relative_error(metric):
        return f"{name} error {100 * abs(value):.3g}%"
    return f"{name} {value:.3g}"


def _outcome(status: str) -> str:
    return "stopped" if status.startswith("stopped") else status


def stability_map_figure(rows, test_name, wrong, path) -> None:
    """One stress test as tiles: a row per engine, a tile per setting, coloured by outcome, with the
    setting, the outcome and the measured values written whole inside the tile."""
    engines = list(dict.fromkeys(rows.engine))
    width = max(rows.groupby("engine").setting.nunique())
    fig, ax = plt.subplots(figsize=(max(5.0, 2.4 * width + 1.5), 1.2 + 0.8 * len(engines)))
    tiles = []
    for row, engine in enumerate(engines):
        mine = rows[rows.engine == engine]
        for col, setting in enumerate(dict.fromkeys(mine.setting)):
            here = mine[mine.setting == setting]
            outcome = _outcome(here.status.iloc[0])
            values = [stress_value(m, v) for m, v in zip(here.metric, here.value, strict=True) if np.isfinite(v)]
            patch = plt.Rectangle((col, row), 0.95, 0.9, color=STATUS_COLOURS.get(outcome, "0.6"))
            ax.add_patch(patch)
            text = ax.text(col + 0.47, row + 0.45, "\n".join([f"{setting}: {outcome}", *values]), ha="center",
                           va="center", fontsize=7)
            tiles.append((text, patch))
    ax.set_xlim(0, width)
    ax.set_ylim(0, len(engines))
    ax.set_yticks(np.arange(len(engines)) + 0.45, engines, fontsize=8)
    ax.set_xticks([])
    title(ax, f"{test_name}: ok, silently wrong (an error of {wrong:.0%} or more) or stopped by the engine",
          fontsize=9)
    save(fig, path, tiles)


def stiffness_figure(rows, path) -> None:
    """Free-rocking errors and the automatic time step of the explicit core against K_n; a dotted line marks each
    K_n whose run stopped with an error (it has no error to plot)."""
    kn = rows.setting.str.removeprefix("kn = ").astype(float)
    fig, (ax, ax_dt) = plt.subplots(1, 2, figsize=(9, 3.5))
    for metric in ("quarter_period", "peak_decay"):
        pick = rows.metric == metric
        ax.loglog(kn[pick], 100 * np.abs(rows.value[pick]), "o-", label=AXIS_NAMES.get(metric, metric))
    for stopped in sorted(set(kn[(rows.status == "stopped") & (rows.metric != "dt_s")])):
        ax.axvline(stopped, color="C3", linestyle=":")
        ax.text(stopped, 0.5, " stopped", transform=ax.get_xaxis_transform(), color="C3", fontsize=8,
                rotation=90, va="center")
    pick = rows.metric == "dt_s"
    ax_dt.loglog(kn[pick], rows.value[pick], "s-", color="0.3")
    plain_log(ax)
    plain_log(ax_dt)
    limits = np.concatenate((ax.get_xlim(), ax_dt.get_xlim()))
    for a in (ax, ax_dt):
        a.set_xlim(limits.min(), limits.max())
    ax.set(xlabel="K_n (N/m^2)", ylabel="|error| (%)")
    title(ax, "Free rocking, explicit core: errors against contact stiffness")
    ax_dt.set(xlabel="K_n (N/m^2)", ylabel="automatic dt (s)")
    title(ax_dt, "Its automatic time step")
    ax.legend(fontsize=8)
    for a in (ax, ax_dt):
        a.grid(True, which="both", alpha=0.3)
    save(fig, path)
