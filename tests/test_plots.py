"""Figures of a run: drums that move together share a line, the critical angle is drawn, sliding per
interface, and no label falls outside its figure."""

import numpy as np
import pytest
from matplotlib.axes import Axes
from matplotlib.collections import PolyCollection
from matplotlib.text import Text

from dem_core.analyses.spectra import response_spectrum, spectrum_figure
from dem_core.engine.result import Result
from dem_core.engine.stacks import Column
from dem_core.inputs import excitation, scenes
from dem_core.pictures import plots
from dem_core.pictures.animation import snapshot_strip

T = np.linspace(0.0, 10.0, 501)
COLUMN_ALPHA = 0.2
DRUM_ALPHA = 0.5
EPISTYLE_ALPHA = 1.3


def hand_result(theta, names=("drum1", "drum2", "drum3"), *, columns=None, slip=None, interfaces=(),
                overturn_at=np.nan, critical=None):
    """A Result of len(names) blocks with rotations ``theta`` (n, n_blocks), drums 0.5 m apart up a column."""
    n, nb = theta.shape
    x = 3.0 * theta * np.arange(1, nb + 1)
    y = np.tile(0.25 + 0.5 * np.arange(nb), (n, 1))
    columns = (Column(tuple(names[:3]), COLUMN_ALPHA),) if columns is None else columns
    critical = np.full(nb, DRUM_ALPHA) if critical is None else critical
    return Result(T[:n], x, y, theta, np.zeros(n), np.zeros(n), tuple(names), np.max(np.abs(theta), axis=0),
                  np.full(nb, overturn_at), {}, 1e-4, interfaces=interfaces, slip_history=slip,
                  critical_angle=np.asarray(critical, float), columns=columns)


def data_lines(ax):
    return [line.get_label() for line in ax.get_lines() if len(line.get_xdata()) == len(T)]


def rocking(*amplitudes):
    return np.column_stack([a * 0.05 * np.sin(2 * np.pi * 0.5 * T) for a in amplitudes])


def test_drums_that_agree_are_one_line_with_their_spread():
    result = hand_result(rocking(1.0, 1.01, 1.02))  # within 2% of the column's peak of each other
    fig = plots.rotations(result)
    ax = fig.axes[0]
    assert data_lines(ax) == ["drum1\u2013drum3,\nwithin 0.001 rad of each other"]
    assert sum(isinstance(c, PolyCollection) for c in ax.collections) == 1  # the band
    np.testing.assert_allclose(ax.get_lines()[0].get_ydata(), result.theta.mean(axis=1))


def test_drums_that_differ_get_a_line_each():
    result = hand_result(rocking(1.0, 1.3, 1.6))
    fig = plots.rotations(result)
    assert data_lines(fig.axes[0]) == ["drum1", "drum2", "drum3"]
    assert not any(isinstance(c, PolyCollection) for c in fig.axes[0].collections)


def test_only_the_drum_that_differs_is_drawn_apart():
    result = hand_result(rocking(0.5, 1.0, 1.02))
    assert plots.block_groups(result, result.theta) == [(0,), (1, 2)]
    ax = plots.rotations(result).axes[0]
    assert data_lines(ax) == ["drum1", "drum2\u2013drum3,\nwithin 0.001 rad of each other"]
    single, group = (line for line in ax.get_lines() if len(line.get_xdata()) == len(T))
    assert single.get_zorder() > group.get_zorder()  # the lone drum is drawn over the group, never hidden


def test_a_drum_that_stays_near_the_others_joins_them_and_the_axis_fits_the_response():
    """The default run's rotations.png: drum 1 within 0.0027 rad of drums 2 to 8 (7.8% of their 0.035 rad peak)
    was a line of its own hidden under theirs, on an axis of +-0.17 rad (the critical angle) where the response
    filled a fifth of the height.  Now one line says how close they are, and the axis fits the response, the
    critical angle named in the legend, off the axis."""
    theta = rocking(1.0, 1.078, 1.078)
    result = hand_result(theta)
    ax = plots.rotations(result).axes[0]
    spread = np.max(theta.max(axis=1) - theta.min(axis=1))
    assert data_lines(ax) == [f"drum1\u2013drum3,\nwithin {spread:.2g} rad of each other"]
    peak = np.max(np.abs(theta))
    assert ax.get_ylim() == pytest.approx((-1.1 * peak, 1.1 * peak))
    assert not [line for line in ax.get_lines() if len(line.get_xdata()) == 2]  # no critical-angle line
    legend = [text.get_text() for text in ax.get_legend().get_texts()]
    assert any(t.startswith(f"critical angle $\\pm\\alpha$ = {COLUMN_ALPHA:g} rad (column):\noff the axis (3.7")
               for t in legend), legend


def test_a_critical_angle_within_twice_the_peak_is_drawn_and_in_view():
    result = hand_result(rocking(3.0, 3.0, 3.0))  # peak 0.15 rad, critical angle 0.2 rad
    ax = plots.rotations(result).axes[0]
    levels = {round(float(line.get_ydata()[0]), 6) for line in ax.get_lines() if len(line.get_xdata()) == 2}
    assert levels == {COLUMN_ALPHA, -COLUMN_ALPHA}
    assert ax.get_ylim() == pytest.approx((-1.1 * COLUMN_ALPHA, 1.1 * COLUMN_ALPHA))


def test_critical_angles_are_the_columns_for_drums_and_their_own_for_other_blocks():
    names = ("drum1", "drum2", "drum3", "epistyle1")
    result = hand_result(rocking(3.0, 3.0, 3.0, 0.2), names,
                         critical=[DRUM_ALPHA, DRUM_ALPHA, DRUM_ALPHA, EPISTYLE_ALPHA])
    np.testing.assert_allclose(plots.critical_angles(result), [COLUMN_ALPHA] * 3 + [EPISTYLE_ALPHA])
    ax = plots.rotations(result).axes[0]
    levels = {round(float(line.get_ydata()[0]), 6) for line in ax.get_lines() if len(line.get_xdata()) == 2}
    assert levels == {COLUMN_ALPHA, -COLUMN_ALPHA}  # the epistyle's 1.3 rad is named, not drawn
    assert any("off the axis" in text.get_text() for text in ax.get_legend().get_texts())


def test_relative_rotations_are_theta_over_alpha_with_lines_at_one():
    result = hand_result(rocking(3.0, 3.0, 3.0))
    ax = plots.rotations(result, relative=True).axes[0]
    np.testing.assert_allclose(ax.get_lines()[0].get_ydata(), result.theta[:, 0] / COLUMN_ALPHA)
    levels = {float(line.get_ydata()[0]) for line in ax.get_lines() if len(line.get_xdata()) == 2}
    assert levels == {1.0, -1.0}
    small = plots.rotations(hand_result(rocking(1.0, 1.0, 1.0)), relative=True).axes[0]  # a quarter of alpha
    assert not [line for line in small.get_lines() if len(line.get_xdata()) == 2]
    assert small.get_ylim() == pytest.approx((-1.1 * 0.25, 1.1 * 0.25))


def test_sliding_has_a_line_per_interface_that_slid_and_one_grey_line_for_the_rest():
    interfaces = (("base", "drum1"), ("drum1", "drum2"), ("drum2", "drum3"))
    slip = np.column_stack([0.002 * T / T[-1], 1e-6 * T / T[-1], 0.01 * T / T[-1]])
    result = hand_result(rocking(1.0, 1.0, 1.0), slip=slip, interfaces=interfaces)
    ax = plots.sliding(result).axes[0]
    assert data_lines(ax)[:2] == ["drum2/drum3", "base/drum1"]  # largest first
    assert data_lines(ax)[2] == "drum1/drum2 (at most 0.001 mm)"
    assert len(data_lines(ax)) == 3
    assert ax.get_ylabel() == "accumulated sliding (mm)"  # the largest, 10 mm, is under SLIP_IN_MM_BELOW
    np.testing.assert_allclose(ax.get_lines()[0].get_ydata(), 1e3 * slip[:, 2])


def test_a_colonnades_interfaces_that_slid_get_colours_none_repeated_and_the_rest_one_grey_line():
    names = tuple(f"b{k}" for k in range(16))
    interfaces = tuple(zip(names[:-1], names[1:]))
    slip = np.outer(T / T[-1], 0.01 + 0.001 * np.arange(len(interfaces)))  # 15 interfaces, each past 0.1 mm
    theta = np.zeros((len(T), len(names)))
    result = hand_result(theta, names, slip=slip, interfaces=interfaces, critical=np.full(len(names), DRUM_ALPHA))
    ax = plots.sliding(result).axes[0]
    lines = [line for line in ax.get_lines() if len(line.get_xdata()) == len(T)]
    assert len(lines) == plots.MOST_SLIP_LINES + 1
    colours = [tuple(np.round(np.atleast_1d(line.get_color()), 6)) for line in lines[:-1]]
    assert len(set(colours)) == plots.MOST_SLIP_LINES
    assert lines[-1].get_label() == "largest slip of 5 other interfaces (at most 14 mm)"


def test_sliding_under_the_threshold_is_drawn_flat_in_mm_with_the_threshold_in_view():
    interfaces = (("base", "drum1"), ("drum1", "drum2"))
    slip = np.column_stack([2e-11 * T / T[-1], 1e-11 * T / T[-1]])
    ax = plots.sliding(hand_result(rocking(1.0, 1.0, 1.0), slip=slip, interfaces=interfaces)).axes[0]
    assert ax.get_legend().get_title().get_text() == "no interface slid more than 0.1 mm"
    assert data_lines(ax) == ["largest slip of 2 interfaces (at most 2e-08 mm)"]
    assert ax.get_ylim()[1] >= 0.1


def test_sliding_figure_is_skipped_without_a_slip_history(tmp_path):
    result = hand_result(rocking(1.0, 1.0, 1.0))
    with pytest.raises(ValueError, match="slip history"):
        plots.sliding(result)
    written = plots.save_run_figures(result, tmp_path)
    assert [p.name for p in written] == ["rotations.png", "displacements.png"]


def undrawn_tick_labels(fig) -> set:
    """Tick labels matplotlib keeps but does not draw: those of ticks outside the axis' view."""
    hidden = set()
    for ax in fig.findobj(Axes):
        for axis in (ax.xaxis, ax.yaxis):
            low, high = sorted(axis.get_view_interval())
            slack = 1e-9 * (high - low)
            for tick in axis.get_major_ticks() + axis.get_minor_ticks():
                if not low - slack <= tick.get_loc() <= high + slack:
                    hidden.update({id(tick.label1), id(tick.label2)})
    return hidden


def assert_text_inside(fig, dpi=130):
    """Every text drawn in ``fig`` at ``dpi`` lies inside the figure (1 pixel of slack)."""
    fig.set_dpi(dpi)
    fig.canvas.draw()
    renderer = fig.canvas.get_renderer()
    box = fig.bbox
    hidden = undrawn_tick_labels(fig)
    for text in fig.findobj(Text):
        if not text.get_visible() or not text.get_text() or id(text) in hidden:
            continue
        extent = text.get_window_extent(renderer)
        assert (extent.x0 >= box.x0 - 1 and extent.x1 <= box.x1 + 1 and extent.y0 >= box.y0 - 1
                and extent.y1 <= box.y1 + 1), f"{text.get_text()!r} at {extent} outside the figure {box}"


def overturning_colonnade_result():
    names = ("drum1", "drum2", "drum3", "epistyle1")
    theta = rocking(1.0, 1.0, 1.0, 0.3)
    interfaces = (("base", "drum1"), ("drum3", "epistyle1"))
    slip = np.column_stack([0.003 * T / T[-1], 0.02 * T / T[-1]])
    overturn = np.array([9.9, 9.9, 9.9, np.nan])
    result = hand_result(theta, names, slip=slip, interfaces=interfaces,
                         critical=[DRUM_ALPHA] * 3 + [EPISTYLE_ALPHA])
    return Result(**{**result.__dict__, "overturn_time": overturn})


@pytest.mark.parametrize("figure", [plots.rotations, plots.displacements, plots.sliding, plots.epistyles])
def test_labels_of_run_figures_lie_inside_the_figure(figure):
    result = overturning_colonnade_result()
    motion = excitation.harmonic(pga=2.0, frequency=0.5)
    fig = figure(result, motion, title="a long title: " + "x" * 40)
    assert_text_inside(fig)
    ax = fig.axes[0]
    label = next(t for t in ax.texts if "overturns" in t.get_text())
    assert label.get_text() == "column drum1\u2013drum3 overturns at 9.90 s"
    extent = label.get_window_extent()
    marker = ax.transData.transform((9.9, 0.0))[0]
    assert ax.bbox.x0 < extent.x0 and extent.x1 < marker - 2 and extent.y1 <= ax.bbox.y1  # clear of the line
    # the ground's panel names the motion and its peak, so that a figure read alone says what shook the scene
    assert f"{motion.name}: peak ground acceleration 2 m/s$^2$ (0.204 g)" in [a.get_title(loc="left") for a in fig.axes]


def test_labels_of_the_spectrum_and_the_snapshots_lie_inside_their_figures():
    spectra = [response_spectrum(excitation.sine_pulse(3.0, 0.5), duration=3.0)]
    assert_text_inside(spectrum_figure(spectra))
    scene = scenes.column(3)
    result = hand_result(rocking(1.0, 1.0, 1.0))
    assert_text_inside(snapshot_strip(scene, result, [0.0, 5.0], title="column", exaggerate=10), dpi=110)


def test_cli_md_says_how_drums_share_a_line_and_how_the_default_run_draws_them():
    """docs/cli.md's words on rotations.png: the tolerance the grouping uses, and the default run's drums drawn as
    it says (all eight agree)."""
    from pathlib import Path

    from dem_core import simulate
    from dem_core.cli import default_scene_path
    from dem_core.inputs.scene_file import load

    text = " ".join((Path(__file__).resolve().parents[1] / "docs" / "cli.md").read_text().split())
    assert f"within {plots.DRUM_AGREEMENT:.0%} of the column's peak of each other" in text
    spec = load(default_scene_path())
    done = simulate(spec.scene, spec.excitation, **spec.simulation)
    assert plots.block_groups(done, done.theta) == [tuple(range(8))]
    assert "the default run: all eight drums on one line" in text
