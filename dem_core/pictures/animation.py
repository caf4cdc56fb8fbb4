"""Drawing runs to scale: animations (GIF, MP4) and snapshot strips.

The blocks are drawn from the scene's polygons moved by the result's
centroid positions and rotations; the base is drawn where the ground is,
and a strip below shows the ground acceleration with a cursor.  GIFs need
only Pillow (a matplotlib dependency); MP4 needs an ffmpeg program: on the
PATH, or the one the ``imageio-ffmpeg`` package ships (``pip install
dem-colonnade[video]``).
"""

import shutil
from pathlib import Path

import matplotlib

matplotlib.use("Agg")
import matplotlib.pyplot as plt
import numpy as np
from matplotlib import animation as mpl_animation
from matplotlib.collections import PolyCollection

from ..engine.geometry import transform

STONE = "#d9cbb0"
EDGE = "#5b4a36"
EPISTYLE = "#c9a77c"


def _local_shapes(scene, result):
    """Vertices of every block in its own frame (about the result's first centroid and angle)."""
    return [transform(block.vertices - (result.x[0, k], result.y[0, k]), -result.theta[0, k])
            for k, block in enumerate(scene.blocks)]


def block_outlines(scene, result, k: int) -> list:
    """World vertices of every block at output ``k`` of ``result`` (list of (n_i, 2) arrays)."""
    return [transform(local, result.theta[k, b], (result.x[k, b], result.y[k, b]))
            for b, local in enumerate(_local_shapes(scene, result))]


def _view(scene, result):
    v = np.concatenate([b.vertices for b in scene.blocks])
    width, height = np.ptp(v[:, 0]), np.ptp(v[:, 1])
    reach = max(width, height)
    x0, x1 = v[:, 0].min() - 0.6 * reach, v[:, 0].max() + 0.6 * reach
    drift = np.nanmax(np.abs(result.base_x)) if len(result.base_x) else 0.0
    return (x0 - drift, x1 + drift), (-0.08 * reach, v[:, 1].max() + 0.15 * reach)


def _colours(scene):
    return [EPISTYLE if "epistyle" in b.name else STONE for b in scene.blocks]


class _Drawing:
    """One axes with the scene drawn at an output index; ``update(k)`` moves it."""

    def __init__(self, ax, scene, result, *, clock=True):
        self.scene, self.result = scene, result
        self.shapes = _local_shapes(scene, result)
        (x0, x1), (y0, y1) = _view(scene, result)
        self.base_half = 0.5 * (x1 - x0) + np.nanmax(np.abs(result.base_x))
        ax.set_xlim(x0, x1)
        ax.set_ylim(y0, y1)
        ax.set_aspect("equal")
        ax.set_xlabel("x (m)")
        ax.set_facecolor("#f7f7f4")
        self.base = plt.Rectangle((x0, y0), x1 - x0, -y0, color="#8c8c8c", zorder=1)
        ax.add_patch(self.base)
        self.blocks = PolyCollection([], facecolors=_colours(scene), edgecolors=EDGE, linewidths=0.6, zorder=2)
        ax.add_collection(self.blocks)
        self.marks = ax.plot([], [], "|", color="k", ms=8, zorder=3)[0]
        self.clock = ax.text(0.02, 0.96, "", transform=ax.transAxes, va="top", fontsize=9,
                             family="monospace") if clock else None
        self.x0 = x0

    def update(self, k):
        self.blocks.set_verts(block_outlines(self.scene, self.result, k))
        ground = self.result.base_x[k]
        self.base.set_x(self.x0 - self.base_half + ground)
        self.base.set_width(4 * self.base_half)
        ticks = ground + np.arange(-20, 21) * 1.0
        self.marks.set_data(ticks, np.zeros_like(ticks))
        if self.clock is not None:
            self.clock.set_text(f"t = {self.result.t[k]:6.2f} s   ground {ground * 100:+6.1f} cm")
        return [self.blocks, self.base, self.marks] + ([self.clock] if self.clock is not None else [])


def _frame_indices(result, fps, speed):
    times = np.arange(result.t[0], result.t[-1] + 1e-12, speed / fps)
    return np.unique(np.clip(np.searchsorted(result.t, times), 0, len(result.t) - 1))


def _ffmpeg():
    path = shutil.which("ffmpeg")
    if path:
        return path
    try:
        import imageio_ffmpeg
    except ImportError:
        return None
    return imageio_ffmpeg.get_ffmpeg_exe()


def animate(scene, result, path, *, excitation=None, fps: int = 25, speed: float = 1.0, title: str = "",
            dpi: int = 90) -> Path:
    """Write an animation of ``result`` (a run of ``scene``) to ``path`` (.gif or .mp4).

    fps : frames per second of the file; speed : simulated seconds per second of playback.
    excitation : the ground motion, to draw its acceleration under the scene (else the base displacement).
    Returns the path written.
    """
    path = Path(path)
    suffix = path.suffix.lower()
    if suffix not in (".gif", ".mp4"):
        raise ValueError(f"animation file must end in .gif or .mp4, got {path.name!r}")
    if suffix == ".mp4":
        ffmpeg = _ffmpeg()
        if ffmpeg is None:
            raise RuntimeError("writing MP4 needs ffmpeg: install it, or pip install imageio-ffmpeg, or write a .gif")
        matplotlib.rcParams["animation.ffmpeg_path"] = ffmpeg
    fig, (ax, ax_g) = plt.subplots(2, 1, figsize=(7, 6.2), gridspec_kw={"height_ratios": [5, 1]})
    drawing = _Drawing(ax, scene, result)
    ax.set_title(title or "", fontsize=10)
    if excitation is not None:
        ground, label = excitation.acceleration(result.t)[0], "ground acc. (m/s$^2$)"
    else:
        ground, label = result.base_x, "ground disp. (m)"
    ax_g.plot(result.t, ground, color="0.35", lw=0.8)
    cursor = ax_g.axvline(result.t[0], color="crimson", lw=1)
    ax_g.set(xlabel="time (s)", ylabel=label, xlim=(result.t[0], result.t[-1]))
    ax_g.yaxis.label.set_size(8)
    ax_g.grid(alpha=0.3)
    if result.overturned:
        ax_g.axvline(result.time_of_overturn, color="k", ls="--", lw=0.8)
    fig.tight_layout()
    frames = _frame_indices(result, fps, speed)

    def draw(k):
        cursor.set_xdata([result.t[k], result.t[k]])
        return [*drawing.update(k), cursor]

    movie = mpl_animation.FuncAnimation(fig, draw, frames=frames, blit=False)
    writer = (mpl_animation.PillowWriter(fps=fps) if suffix == ".gif"
              else mpl_animation.FFMpegWriter(fps=fps, bitrate=1800))
    path.parent.mkdir(parents=True, exist_ok=True)
    movie.save(path, writer=writer, dpi=dpi)
    plt.close(fig)
    return path


def snapshot_strip(scene, result, times, *, title: str = ""):
    """Figure: the scene drawn at each of ``times`` (s; the nearest outputs) side by side."""
    times = list(times)
    (x0, x1), (y0, y1) = _view(scene, result)
    panel = 2.6
    fig, axes = plt.subplots(1, len(times), figsize=(panel * len(times) + 0.6, panel * (y1 - y0) / (x1 - x0) + 1.2),
                             sharey=True, squeeze=False)
    for ax, when in zip(axes[0], times):
        k = int(np.clip(np.searchsorted(result.t, when), 0, len(result.t) - 1))
        _Drawing(ax, scene, result, clock=False).update(k)
        ax.set_title(f"t = {result.t[k]:.2f} s", fontsize=9)
    if title:
        fig.suptitle(title, fontsize=10)
    fig.tight_layout()
    return fig


def default_snapshot_times(result, count: int = 6) -> np.ndarray:
    """Evenly spaced times over the run, ending at the overturn if there was one."""
    end = result.time_of_overturn if result.overturned else result.t[-1]
    return np.linspace(result.t[0], end, count)
