"""Figures of a run: block rotations, displacements and epistyle motion over time, with the ground motion."""

from pathlib import Path

import matplotlib

matplotlib.use("Agg")  # files only: the command line and CI have no screen
import matplotlib.pyplot as plt
import numpy as np


def _ground_panel(ax, result, excitation):
    if excitation is not None:
        a_x, _ = excitation.acceleration(result.t)
        ax.plot(result.t, a_x, color="0.3", lw=0.8)
        ax.set_ylabel("ground acc.\n(m/s$^2$)")
    else:
        ax.plot(result.t, result.base_x, color="0.3", lw=0.8)
        ax.set_ylabel("ground disp.\n(m)")
    ax.grid(alpha=0.3)


def _finish(fig, axes, result, title):
    axes[-1].set_xlabel("time (s)")
    if result.overturned:
        for ax in axes:
            ax.axvline(result.time_of_overturn, color="crimson", ls="--", lw=1)
        axes[0].annotate(f"overturn at {result.time_of_overturn:.2f} s", (result.time_of_overturn, 1.0),
                         xycoords=("data", "axes fraction"), color="crimson", ha="right", va="top", fontsize=8)
    fig.suptitle(title, fontsize=10)
    fig.tight_layout()
    return fig


def _history_figure(result, values, ylabel, colour_map, excitation, title):
    """Figure: one line per block of ``values`` (n, n_blocks) over time, the ground motion below."""
    fig, axes = plt.subplots(2, 1, sharex=True, figsize=(9, 6), gridspec_kw={"height_ratios": [3, 1]})
    colours = colour_map(np.linspace(0, 0.9, result.n_blocks))
    for k, name in enumerate(result.names):
        axes[0].plot(result.t, values[:, k], lw=0.9, color=colours[k], label=name)
    axes[0].set_ylabel(ylabel)
    axes[0].grid(alpha=0.3)
    if result.n_blocks <= 12:
        axes[0].legend(fontsize=7, ncol=min(4, result.n_blocks), loc="upper left")
    _ground_panel(axes[1], result, excitation)
    return _finish(fig, axes, result, title)


def rotations(result, excitation=None, title="Block rotations"):
    """Figure: rotation theta(t) of every block (rad), and the ground motion below."""
    return _history_figure(result, result.theta, "rotation (rad)", plt.cm.viridis, excitation, title)


def displacements(result, excitation=None, title="Block displacements relative to the base"):
    """Figure: horizontal displacement of every block relative to the base (m), and the ground motion."""
    return _history_figure(result, result.relative_x - result.relative_x[0], "displacement (m)", plt.cm.plasma,
                           excitation, title)


def epistyle_names(result) -> list:
    return [n for n in result.names if "epistyle" in n]


def epistyles(result, excitation=None, title="Epistyles"):
    """Figure: horizontal displacement relative to the base (m) and rotation (rad) of every
    epistyle, and the ground motion below."""
    names = epistyle_names(result)
    if not names:
        raise ValueError("the run has no block named like an epistyle")
    index = [result.names.index(n) for n in names]
    fig, axes = plt.subplots(3, 1, sharex=True, figsize=(9, 7), gridspec_kw={"height_ratios": [2, 2, 1]})
    rel = result.relative_x - result.relative_x[0]
    for k, name in zip(index, names):
        axes[0].plot(result.t, rel[:, k], lw=0.9, label=name)
        axes[1].plot(result.t, result.theta[:, k], lw=0.9, label=name)
    axes[0].set_ylabel("displacement (m)")
    axes[1].set_ylabel("rotation (rad)")
    for ax in axes[:2]:
        ax.grid(alpha=0.3)
    axes[0].legend(fontsize=7)
    _ground_panel(axes[2], result, excitation)
    return _finish(fig, axes, result, title)


def save_run_figures(result, out_dir, excitation=None, title=""):
    """Write rotations.png, displacements.png (and epistyles.png if the scene has epistyles)
    into ``out_dir``; returns their paths."""
    out_dir = Path(out_dir)
    paths = []
    figures = [("rotations.png", rotations, "block rotations"),
               ("displacements.png", displacements, "displacements relative to the base")]
    if epistyle_names(result):
        figures.append(("epistyles.png", epistyles, "epistyles"))
    for name, make, what in figures:
        fig = make(result, excitation, title=f"{title}: {what}" if title else what.capitalize())
        path = out_dir / name
        fig.savefig(path, dpi=130)
        plt.close(fig)
        paths.append(path)
    return paths
