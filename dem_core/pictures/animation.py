"""Drawing runs to scale: animations (GIF, MP4) and snapshot strips.

The blocks are drawn from the scene's polygons moved by the result's
centroid positions and rotations; the base is drawn where the ground is,
and a strip below shows the ground acceleration with a cursor.  Small
motions can be exaggerated: with ``exaggerate=K`` each block's motion
relative to the body it rests on (the base, or the block below: its
*support*, :func:`supports`) since the start is drawn K times larger, about
the block's corner lowest on that support: its rotation on the support is
K times the true one, turned about that corner, and that corner's
displacement on the support (sliding, uplift) is K times the true one; each
block is then carried by its support as drawn.  A block rocking on a
corner therefore still stands on it, on the ground or on the drum below, as
it does in the run (scaling each block's motion about its own centre would
push the corner it rocks on below what it rests on, and part the drums of a
column rocking as one).  Every rotation is still K times the true one.  A
block resting on two bodies (an epistyle on two capitals) follows the one
it touches along the longer contact, and may part from or overlap the
other; every frame says that the drawing is exaggerated.

Frames are rendered by blitting: the axes, the ground strip and the labels
are drawn once, and each frame redraws only the blocks, the base and the
cursor on a copy of that background; Pillow writes the clock onto the frame
(matplotlib would lay out and rasterise that text anew every frame, the
slowest part of a frame).  GIFs are written by Pillow with one palette for
all frames; MP4s by piping the frames to an ffmpeg
program: on the PATH, or the one the ``imageio-ffmpeg`` package ships
(``pip install dem-colonnade[video]``).
"""

import shutil
import subprocess
from pathlib import Path

import numpy as np
from matplotlib import font_manager
from matplotlib.backends.backend_agg import FigureCanvasAgg
from matplotlib.collections import PolyCollection
from matplotlib.figure import Figure
from matplotlib.patches import Rectangle
from PIL import Image, ImageDraw, ImageFont
from tqdm import tqdm

from ..engine.geometry import transform
from ..inputs.records import G_STANDARD
from ..output_files import replacing

STONE = "#d9cbb0"
EDGE = "#5b4a36"
EPISTYLE = "#c9a77c"
OVERTURN = "crimson"


def _local_shapes(scene, result):
    """Vertices of every block in its own frame (about the result's first centroid and angle)."""
    return [transform(block.vertices - (result.x[0, k], result.y[0, k]), -result.theta[0, k])
            for k, block in enumerate(scene.blocks)]


def _resting_on(scene) -> dict:
    """``{block: [(body, contact length), ...]}`` (scene body indices): the bodies each block touches at the start
    below its centre of mass, through a contact lower than that centre, the body's own centre lower too."""
    bodies = scene.bodies
    below = {}
    for i, j, contact in scene.touching_pairs():
        for upper, lower in ((i, j), (j, i)):
            height = bodies[upper].centroid[1]
            if upper and contact.centroid[1] < height and (lower == 0 or bodies[lower].centroid[1] < height):
                below.setdefault(upper, []).append((lower, contact.length))
    return below


def supports(scene) -> list:
    """The support of each block, in scene order: the index of the block it rests on, -1 for the base, None for
    a block resting on nothing at the start.  Of the bodies a block rests on (:func:`_resting_on`), the one it
    touches along the longest contact."""
    below = _resting_on(scene)
    return [max(below[b], key=lambda held: held[1])[0] - 1 if b in below else None
            for b in range(1, len(scene.bodies))]


def _two_supported(scene) -> bool:
    """Whether a block of ``scene`` rests at the start on more than one body (an epistyle on two capitals)."""
    return any(len({lower for lower, _ in held}) > 1 for held in _resting_on(scene).values())


def _rotate(angle, vectors):
    """(n, 2) ``vectors`` rotated by (n,) ``angle`` (rad), row by row."""
    c, s = np.cos(angle), np.sin(angle)
    return np.column_stack([c * vectors[:, 0] - s * vectors[:, 1], s * vectors[:, 0] + c * vectors[:, 1]])


def drawn_poses(result, exaggerate: float = 1.0, scene=None):
    """(x, y, theta): each (n, n_blocks), the centroid positions (m) and rotations (rad) at which the blocks
    are drawn, ``exaggerate`` times their motion since the start.

    With ``scene`` (the run's), each block's motion relative to its support (:func:`supports`) is exaggerated
    about its corner lowest on that support, and the block carried by its support as drawn (see the module's
    description): a block rocking on a corner still touches what it rocks on.  Without ``scene`` (or for a
    block resting on nothing), the block's rotation and its displacement relative to the moving base are
    exaggerated about its centre of mass.  Rotations are ``exaggerate`` times the true ones either way, and
    ``exaggerate=1`` draws the run as it is.
    """
    k = float(exaggerate)
    if not k > 0:
        raise ValueError(f"exaggerate must be positive, got {exaggerate}")
    rel_x = result.x - result.base_x[:, None]
    rel_y = result.y - result.base_y[:, None]
    x = result.base_x[:, None] + rel_x[0] + k * (rel_x - rel_x[0])
    y = result.base_y[:, None] + rel_y[0] + k * (rel_y - rel_y[0])
    theta = result.theta[0] + k * (result.theta - result.theta[0])
    if scene is None or k == 1:
        return (result.x.copy(), result.y.copy(), result.theta.copy()) if k == 1 else (x, y, theta)
    held = supports(scene)
    turned = result.theta - result.theta[0]  # each block's rotation since the start
    ground = np.column_stack([result.base_x, result.base_y])
    true_centre = [np.column_stack([result.x[:, b], result.y[:, b]]) for b in range(result.n_blocks)]
    drawn_centre, drawn_turn = {}, {}
    for b in sorted(range(result.n_blocks), key=lambda b: scene.blocks[b].centroid[1]):
        support = held[b]
        if support is None or (support >= 0 and support not in drawn_centre):
            drawn_centre[b] = np.column_stack([x[:, b], y[:, b]])
            drawn_turn[b] = turned[:, b] * k
            continue
        if support < 0:
            origin = drawn_origin = ground
            origin_turn = drawn_origin_turn = np.zeros(len(result.t))
        else:
            origin, origin_turn = true_centre[support], turned[:, support]
            drawn_origin, drawn_origin_turn = drawn_centre[support], drawn_turn[support]
        relative = _rotate(-origin_turn, true_centre[b] - origin)  # the centre in the support's frame
        rocking = turned[:, b] - origin_turn  # the rotation on the support
        corners = scene.blocks[b].vertices - true_centre[b][0]  # about the centre, as at the start
        heights = relative[:, 1][:, None] + np.sin(rocking)[:, None] * corners[:, 0] \
            + np.cos(rocking)[:, None] * corners[:, 1]
        corner = corners[np.argmin(heights, axis=1)]  # (n, 2): the corner lowest on the support
        pivot = relative + _rotate(rocking, corner)
        start = relative[0] + corner
        drawn_relative = start + k * (pivot - start) - _rotate(k * rocking, corner)
        drawn_centre[b] = drawn_origin + _rotate(drawn_origin_turn, drawn_relative)
        drawn_turn[b] = drawn_origin_turn + k * rocking
    for b in range(result.n_blocks):
        x[:, b], y[:, b] = drawn_centre[b][:, 0], drawn_centre[b][:, 1]
        theta[:, b] = result.theta[0, b] + drawn_turn[b]
    return x, y, theta


def block_outlines(scene, result, k: int, exaggerate: float = 1.0) -> list:
    """World vertices of every block at output ``k`` of ``result`` (list of (n_i, 2) arrays, m), each block's
    motion since the start on what it rests on multiplied by ``exaggerate`` (:func:`drawn_poses`); for many outputs,
    :class:`BlockOutlines`."""
    return BlockOutlines(scene, result, exaggerate)(k)


class BlockOutlines:
    """Block outlines at any output index (``outlines(k)``: :func:`block_outlines`), the local shapes and drawn
    poses computed once."""

    def __init__(self, scene, result, exaggerate=1.0):
        self.shapes = _local_shapes(scene, result)
        self.x, self.y, self.theta = drawn_poses(result, exaggerate, scene)

    def __call__(self, k):
        return [transform(local, self.theta[k, b], (self.x[k, b], self.y[k, b]))
                for b, local in enumerate(self.shapes)]


def _view(scene, result, exaggerate=1.0):
    """((x0, x1), (y0, y1)) axis limits, m: the scene with room around it for the ground's travel
    and for the blocks as drawn (exaggerated motions reach further, up to the scene's size again)."""
    v = np.concatenate([b.vertices for b in scene.blocks])
    reach = max(np.ptp(v[:, 0]), np.ptp(v[:, 1]))
    low, high = v.min(axis=0), v.max(axis=0)
    if exaggerate != 1:
        x, y, _ = drawn_poses(result, exaggerate, scene)
        radius = np.array([np.max(np.linalg.norm(s, axis=1)) for s in _local_shapes(scene, result)])
        centres = np.stack([x - result.base_x[:, None], y - result.base_y[:, None]], axis=-1)
        low = np.maximum(np.minimum(low, np.min(centres - radius[:, None], axis=(0, 1))), low - reach)
        high = np.minimum(np.maximum(high, np.max(centres + radius[:, None], axis=(0, 1))), high + reach)
    x0, x1 = low[0] - 0.6 * reach, high[0] + 0.6 * reach
    drift = np.nanmax(np.abs(result.base_x)) if len(result.base_x) else 0.0
    return (x0 - drift, x1 + drift), (-0.08 * reach, high[1] + 0.15 * reach)


def _colours(scene):
    return [EPISTYLE if "epistyle" in b.name else STONE for b in scene.blocks]


def exaggeration_note(exaggerate: float, scene=None) -> str:
    """What a drawing exaggerated ``exaggerate`` times says about it ("" when drawn true to scale): that each
    block's motion on what it rests on is drawn that many times larger, and (for a ``scene`` with a block on
    two supports) that such a block follows one of them."""
    if exaggerate == 1:
        return ""
    note = f"rotations and displacements \u00d7 {exaggerate:g}\n(each block's on what it rests on)"
    if scene is not None and _two_supported(scene):
        note += ";\na block on two supports follows one:\nit may part from or overlap the other"
    return note


class _Drawing:
    """One axes with the scene drawn at an output index; ``update(k)`` moves it and returns the
    artists that move, ``animated``: left out of ``canvas.draw()`` to be blitted frame by frame."""

    def __init__(self, ax, scene, result, *, exaggerate=1.0, animated=False):
        self.result = result
        self.outlines = BlockOutlines(scene, result, exaggerate)
        (x0, x1), (y0, y1) = _view(scene, result, exaggerate)
        self.base_half = 0.5 * (x1 - x0) + np.nanmax(np.abs(result.base_x))
        ax.set_xlim(x0, x1)
        ax.set_ylim(y0, y1)
        ax.set_aspect("equal")
        ax.set_xlabel("x (m)")
        ax.set_facecolor("#f7f7f4")
        self.base = Rectangle((x0, y0), x1 - x0, -y0, color="#8c8c8c", zorder=1)
        ax.add_patch(self.base)
        self.blocks = PolyCollection([], facecolors=_colours(scene), edgecolors=EDGE, linewidths=0.6, zorder=2)
        ax.add_collection(self.blocks)
        self.marks = ax.plot([], [], "|", color="k", ms=8, zorder=3)[0]
        self.x0 = x0
        self.moving = [self.base, self.blocks, self.marks]
        for artist in self.moving:
            artist.set_animated(animated)

    def update(self, k):
        self.blocks.set_verts(self.outlines(k))
        ground = self.result.base_x[k]
        self.base.set_x(self.x0 - self.base_half + ground)
        self.base.set_width(4 * self.base_half)
        ticks = ground + np.arange(-20, 21) * 1.0
        self.marks.set_data(ticks, np.zeros_like(ticks))
        return self.moving


def clock_text(result, k: int) -> str:
    """What the clock of frame ``k`` says: the time, the ground displacement and, once it has
    happened, the overturn."""
    t = result.t[k]
    text = f"t = {t:6.2f} s   ground {result.base_x[k]:+.3f} m"
    if result.overturned and t >= result.time_of_overturn:
        text += f"\noverturned at {result.time_of_overturn:.2f} s"
    return text


class _Clock:
    """Writes the clock text onto rendered frames with Pillow, in matplotlib's monospace font at
    ``fontsize`` points, its top left corner at ``(0.02, 0.96)`` of the axes."""

    def __init__(self, ax, fontsize=9):
        fig = ax.figure
        path = font_manager.findfont(font_manager.FontProperties(family="monospace"))
        self.font = ImageFont.truetype(path, round(fontsize * fig.dpi / 72))
        x, y = ax.transAxes.transform((0.02, 0.96))
        self.corner = (round(x), round(fig.bbox.height - y))

    def write(self, image, text):
        ImageDraw.Draw(image).multiline_text(self.corner, text, font=self.font, fill=(0, 0, 0), spacing=3)
        return image


def frame_indices(result, fps: int, speed: float = 1.0) -> np.ndarray:
    """Output indices of ``result`` shown by the frames of an animation at ``fps`` frames per second
    and ``speed`` simulated seconds per second of playback (one frame per tick from the first output
    to the last, which ends the animation in any case)."""
    times = np.arange(result.t[0], result.t[-1] + 1e-12, speed / fps)
    ticks = np.clip(np.searchsorted(result.t, times), 0, len(result.t) - 1)
    return np.unique(np.append(ticks, len(result.t) - 1))


def _ffmpeg():
    path = shutil.which("ffmpeg")
    if path:
        return path
    try:
        import imageio_ffmpeg
    except ImportError:
        return None
    return imageio_ffmpeg.get_ffmpeg_exe()


def can_write_mp4() -> bool:
    """Whether an ffmpeg (on the PATH, or from imageio-ffmpeg) is there to write MP4."""
    return _ffmpeg() is not None


def _ground_strip(ax, result, excitation):
    """The ground motion over the run (acceleration in m/s^2 and g, else displacement in m), an
    overturn marker, and the cursor (returned) that follows the clock."""
    if excitation is not None:
        ax.plot(result.t, excitation.acceleration(result.t)[0], color="0.35", lw=0.8)
        ax.set_ylabel("ground acc.\n(m/s$^2$)", fontsize=8)
        in_g = ax.secondary_yaxis("right", functions=(lambda a: a / G_STANDARD, lambda g: g * G_STANDARD))
        in_g.set_ylabel("(g)", fontsize=8)
        in_g.tick_params(labelsize=8)
    else:
        ax.plot(result.t, result.base_x, color="0.35", lw=0.8)
        ax.set_ylabel("ground disp.\n(m)", fontsize=8)
    ax.set(xlabel="time (s)", xlim=(result.t[0], result.t[-1]))
    ax.tick_params(labelsize=8)
    ax.grid(alpha=0.3)
    if result.overturned:
        ax.axvline(result.time_of_overturn, color=OVERTURN, ls="--", lw=0.8)
    return ax.axvline(result.t[0], color="crimson", lw=1, animated=True)


class _GifFrames:
    """Frames collected as palette images of one shared palette, written by Pillow at the end."""

    def __init__(self, path, fps, palette_from):
        self.path, self.fps = path, fps
        sample = Image.fromarray(np.concatenate([np.asarray(image) for image in palette_from], axis=0))
        self.palette = sample.quantize(colors=256, method=Image.Quantize.MEDIANCUT)
        self.frames = []

    def add(self, image):
        self.frames.append(image.quantize(palette=self.palette, dither=Image.Dither.NONE))

    def close(self):
        first, *rest = self.frames
        first.save(self.path, format="GIF", save_all=True, append_images=rest, duration=1000.0 / self.fps, loop=0)

    def abort(self):
        self.frames = []


class _Mp4Frames:
    """Frames piped as raw RGB to an ffmpeg process encoding H.264."""

    def __init__(self, path, fps, size, ffmpeg):
        width, height = size
        command = [ffmpeg, "-y", "-loglevel", "error", "-f", "rawvideo", "-pix_fmt", "rgb24",
                   "-s", f"{width}x{height}", "-r", str(fps), "-i", "-",
                   "-vf", "pad=ceil(iw/2)*2:ceil(ih/2)*2",  # H.264 in yuv420p needs even sides
                   "-c:v", "libx264", "-pix_fmt", "yuv420p", "-movflags", "+faststart", "-f", "mp4", str(path)]
        self.process = subprocess.Popen(command, stdin=subprocess.PIPE, stderr=subprocess.PIPE)

    def add(self, image):
        self.process.stdin.write(image.tobytes())

    def close(self):
        _, errors = self.process.communicate()
        if self.process.returncode != 0:
            raise RuntimeError(f"ffmpeg failed ({self.process.returncode}): {errors.decode(errors='replace')}")

    def abort(self):
        self.process.kill()
        self.process.communicate()


def animate(scene, result, path, *, excitation=None, fps: int = 25, speed: float = 1.0, title: str = "",
            dpi: int = 90, exaggerate: float = 1.0, progress: bool = False) -> Path:
    """Write an animation of ``result`` (a run of ``scene``) to ``path`` (.gif or .mp4).

    fps : frames per second of the file; speed : simulated seconds per second of playback.
    excitation : the ground motion, to draw its acceleration under the scene (else the base displacement).
    exaggerate : each block's rotation and displacement since the start on what it rests on are drawn this
        many times larger (:func:`drawn_poses`; each frame says so when it is not 1).
    progress : show a progress bar of the frames rendered (on stderr).
    Returns the path written.  The file is written under a temporary name and renamed when complete: an
    error or Ctrl-C leaves no partial animation.
    """
    path = Path(path)
    suffix = path.suffix.lower()
    if suffix not in (".gif", ".mp4"):
        raise ValueError(f"animation file must end in .gif or .mp4, got {path.name!r}")
    ffmpeg = _ffmpeg() if suffix == ".mp4" else None
    if suffix == ".mp4" and ffmpeg is None:
        raise RuntimeError("writing MP4 needs ffmpeg: install it, or pip install imageio-ffmpeg, or write a .gif")
    (x0, x1), (y0, y1) = _view(scene, result, exaggerate)
    scene_height = float(np.clip(6.0 * (y1 - y0) / (x1 - x0), 2.0, 4.4))  # inches, for 6 in of width
    fig = Figure(figsize=(7, scene_height + 1.9), dpi=dpi)
    canvas = FigureCanvasAgg(fig)
    ax, ax_g = fig.subplots(2, 1, gridspec_kw={"height_ratios": [scene_height, 1.1]})
    drawing = _Drawing(ax, scene, result, exaggerate=exaggerate, animated=True)
    ax.set_title(title or "", fontsize=10)
    note = exaggeration_note(exaggerate, scene)
    if note:
        ax.text(0.98, 0.96, note, transform=ax.transAxes, ha="right", va="top", fontsize=9, color=OVERTURN)
    cursor = _ground_strip(ax_g, result, excitation)
    fig.tight_layout()
    canvas.draw()
    background = canvas.copy_from_bbox(fig.bbox)
    clock = _Clock(ax)

    def render(k):
        canvas.restore_region(background)
        for artist in drawing.update(k):
            ax.draw_artist(artist)
        for spine in ax.spines.values():  # the moving base is drawn over the bottom of the frame
            ax.draw_artist(spine)
        cursor.set_xdata([result.t[k], result.t[k]])
        ax_g.draw_artist(cursor)
        frame = Image.frombuffer("RGBA", canvas.get_width_height(), canvas.buffer_rgba(), "raw", "RGBA", 0, 1)
        return clock.write(frame.convert("RGB"), clock_text(result, k))

    frames = frame_indices(result, fps, speed)
    path.parent.mkdir(parents=True, exist_ok=True)
    with replacing(path) as tmp:  # the file appears whole or not at all
        if suffix == ".gif":
            writer = _GifFrames(tmp, fps, [render(frames[0]), render(frames[-1])])
        else:
            writer = _Mp4Frames(tmp, fps, canvas.get_width_height(), ffmpeg)
        try:
            for k in tqdm(frames, desc="frames", unit="frame", disable=not progress):
                writer.add(render(k))
        except BaseException:
            writer.abort()
            raise
        writer.close()
    return path


def snapshot_strip(scene, result, times, *, title: str = "", exaggerate: float = 1.0):
    """Figure: the scene drawn at each of ``times`` (s; the nearest outputs) side by side, each block's motion
    since the start on what it rests on multiplied by ``exaggerate`` (:func:`drawn_poses`; said in the title)."""
    times = list(times)
    (x0, x1), (y0, y1) = _view(scene, result, exaggerate)
    note = exaggeration_note(exaggerate, scene).replace("\n(", " (").replace(":\n", ": ")  # the strip is wide
    heading = ", ".join(part for part in (title, note) if part)
    panel = 2.6
    fig = Figure(figsize=(panel * len(times) + 0.6,
                          panel * (y1 - y0) / (x1 - x0) + 1.2 + 0.2 * max(heading.count("\n"), 0)))
    FigureCanvasAgg(fig)
    axes = fig.subplots(1, len(times), sharey=True, squeeze=False)
    for ax, when in zip(axes[0], times):
        k = int(np.clip(np.searchsorted(result.t, when), 0, len(result.t) - 1))
        _Drawing(ax, scene, result, exaggerate=exaggerate).update(k)
        ax.set_title(f"t = {result.t[k]:.2f} s", fontsize=9)
    if heading:
        fig.suptitle(heading, fontsize=10)
    fig.tight_layout()
    return fig


def default_snapshot_times(result, count: int = 6) -> np.ndarray:
    """Evenly spaced times over the run, ending at the overturn if there was one."""
    end = result.time_of_overturn if result.overturned else result.t[-1]
    return np.linspace(result.t[0], end, count)
