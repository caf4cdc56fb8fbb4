"""Builders for the scenes of docs/method.md section 3.

Every builder returns an immutable :class:`~dem_core.inputs.scene.Scene` whose base
top is the line y = 0 (turned by ``foundation_tilt``) and whose blocks rest on it touching (zero overlap).
Every builder also takes the keywords of :class:`SceneOptions`: ``density``
(kg/m^3), ``friction``, ``depth`` (m), ``contact``
(:class:`~dem_core.engine.contact.ContactParameters`), ``interface_friction``
({(name_a, name_b): mu}), ``base_width`` (m; by default the blocks' span plus
4 times their height, so that whatever topples lands on the base), the imperfections
of a monument as it stands: ``foundation_tilt`` (rad), ``offsets`` ({name: m}) and
``outlines`` ({name: [[x, y], ...]}), and the ``connectors`` across its joints.

Block names: ``block``; ``block1`` (bottom) .. in stacks; ``drum1`` (bottom) .. ``drumN``, ``capital``;
in colonnades ``c1_drum1`` .. (column ``c1`` is the leftmost), ``epistyle``
or ``epistyle1``/``epistyle2``; in two-tier colonnades ``lower_``/``upper_``
prefixes.  The base is ``base``.
"""

import dataclasses
import functools
import inspect
from collections.abc import Mapping
from dataclasses import dataclass, fields

import numpy as np

from ..engine.contact import ContactParameters
from ..engine.geometry import rectangle, transform
from .connectors import Placement
from .number_types import is_whole
from .scene import TOUCHING_GAP, Block, Scene, SceneError, real_number
from .text_files import did_you_mean

BASE_HEIGHT = 1.0  # m; the base is kinematic, its thickness only places its centroid
#: most blocks a builder makes: past this, a count is surely a typo (a real colonnade has hundreds)
MAX_BLOCKS = 10_000


@dataclass(frozen=True)
class SceneOptions:
    """The keywords every builder takes besides its own: the stone, the contact model and the base.

    density : kg/m^3 of every block (a colonnade's epistyles take ``epistyle_density``).
    friction : Coulomb coefficient of every block and of the base.
    depth : m, out-of-plane thickness of every block and of the base.
    contact : the contact law and its parameters (default ``ContactParameters()``).
    interface_friction : {(name_a, name_b): mu}, friction of named interfaces instead of ``friction``.
    base_width : m; by default the blocks' span plus 4 times their height.
    foundation_tilt : rad, counter-clockwise positive: the whole monument tilted by foundation settlement,
        the scene, base included, turned about the centre of the base top (the origin) and each block's
        ``angle`` increased by it, so that its rotations start from it.
    offsets : {block name: m}, dislocations along the joints: the block shifted along the joint it stands on
        (horizontal before the foundation tilt) relative to the block below, carrying the blocks above it in
        its column, so that the offsets of a column add up; a block that rests on several (an epistyle) is
        carried only where they all moved alike.  Every joint keeps at least half its width in contact.
    outlines : {block name: [[x, y], ...] m}, the block's convex outline instead of its rectangle or
        trapezoid (a chipped or worn drum), in its own frame with the origin at the centre of its bottom
        face as built.  Its lowest point is on the joint below (y = 0) and, under a block resting on it, its
        highest at the built height; the blocks keep their places.
    connectors : [:class:`~dem_core.inputs.connectors.Placement`, ...] or ``(kind, at, position)`` tuples:
        connectors of a kind at the joints ``at`` names (``"all"``, ``"capital"`` or block pairs).
    """

    density: float = 2700.0
    friction: float = 0.7
    depth: float = 1.0
    contact: ContactParameters | None = None
    interface_friction: dict | None = None
    base_width: float | None = None
    foundation_tilt: float = 0.0
    offsets: dict | None = None
    outlines: dict | None = None
    connectors: list | None = None

    def block(self, name: str, vertices, density: float | None = None) -> Block:
        """A block of this stone (of ``density`` instead, if given), upright as built."""
        return Block(name, vertices, density=self.density if density is None else density, depth=self.depth,
                     friction=self.friction)


#: the keywords of :class:`SceneOptions` as keyword-only parameters of every builder's signature
_OPTION_PARAMETERS = tuple(inspect.Parameter(f.name, inspect.Parameter.KEYWORD_ONLY, default=f.default,
                                             annotation=f.type) for f in fields(SceneOptions))
_OPTION_NAMES = frozenset(p.name for p in _OPTION_PARAMETERS)


def _takes_scene_options(build):
    """The public builder of ``build(..., options)``: it takes ``build``'s own arguments and the keywords of
    :class:`SceneOptions` (in its signature too, which scene files read), and passes those on as ``options``."""
    own = inspect.signature(build)
    signature = own.replace(parameters=[p for p in own.parameters.values() if p.name != "options"]
                            + list(_OPTION_PARAMETERS))

    @functools.wraps(build)
    def builder(*args, **kwargs):
        if "options" in kwargs:  # not a keyword of the public builder
            raise TypeError(f"{build.__name__}() got an unexpected keyword argument 'options'")
        options = SceneOptions(**{name: kwargs.pop(name) for name in _OPTION_NAMES & kwargs.keys()})
        return build(*args, **kwargs, options=options)

    builder.__signature__ = signature
    return builder


def _scene(blocks, options: SceneOptions, slenderness, tilt: float = 0.0) -> Scene:
    """The scene of ``blocks`` as built (upright, resting on the base top y = 0 and on one another) with the
    outlines and offsets of ``options``, turned by ``tilt`` (rad) as one body about the bottom corner of
    ``blocks[0]`` that it rests on (:func:`_tilted`), on a base, everything then turned by the foundation
    tilt about the origin."""
    base_width = options.base_width
    if base_width is not None:
        _positive(base_width=base_width)
    foundation_tilt = _number("foundation_tilt", options.foundation_tilt)
    if not abs(foundation_tilt) < np.pi / 2.0:
        raise SceneError(f"foundation_tilt must be an angle in (-pi/2, pi/2) rad, got {foundation_tilt}")
    blocks = _tilted(_imperfect(blocks, options), tilt)
    span = max(b.vertices[:, 0].max() for b in blocks) - min(b.vertices[:, 0].min() for b in blocks)
    tall = max(b.vertices[:, 1].max() for b in blocks)
    # wide enough that the tallest block toppling outwards still lands on it
    base_width = span + 4.0 * tall if base_width is None else base_width
    base = Block("base", rectangle(base_width, BASE_HEIGHT, -base_width / 2.0, -BASE_HEIGHT),
                 density=1.0, depth=options.depth, friction=options.friction)
    if foundation_tilt:
        blocks = [_turned(b, foundation_tilt) for b in blocks]
        base = _turned(base, foundation_tilt)
    scene = Scene(tuple(blocks), base, contact=options.contact or ContactParameters(),
                  interface_friction=options.interface_friction or {}, slenderness=slenderness)
    placements = options.connectors or ()
    if isinstance(placements, (Placement, str)) or not isinstance(placements, (list, tuple)):
        raise SceneError(f"connectors must be a list of Placement(kind, at, position), got {placements!r}")
    if not placements:
        return scene
    return scene.replace(connectors=tuple(c for p in placements for c in _placement(p).connectors(scene)))


def _placement(placement) -> Placement:
    """A :class:`~dem_core.inputs.connectors.Placement` as given, or from a ``(kind, at[, position])`` tuple."""
    if isinstance(placement, Placement):
        return placement
    if isinstance(placement, tuple) and 1 <= len(placement) <= 3:
        return Placement(*placement)
    raise SceneError(f"a connectors entry is a Placement(kind, at, position) or a (kind, at, position) tuple, got "
                     f"{placement!r}")


def _turned(block: Block, angle: float, pivot=(0.0, 0.0)) -> Block:
    """``block`` turned by ``angle`` (rad, counter-clockwise) about ``pivot`` (2,) m, its ``angle`` increased by it."""
    pivot = np.asarray(pivot, float)
    return dataclasses.replace(block, vertices=transform(block.vertices - pivot, angle, pivot),
                               angle=block.angle + angle)


def _tilted(blocks, tilt: float) -> list:
    """``blocks`` (resting on the base top y = 0 and on one another) turned by ``tilt`` (rad) as one body about the
    bottom corner of ``blocks[0]`` that it then rests on: its left corner for a positive (counter-clockwise) tilt,
    its right corner for a negative one."""
    tilt = _number("tilt", tilt)
    if not tilt:
        return list(blocks)
    left, right = _face(blocks[0].vertices, lowest=True)
    pivot = np.array([left if tilt > 0 else right, blocks[0].vertices[:, 1].min()])
    turned = []
    for upright in blocks:
        turned.append(_turned(upright, tilt, pivot))
        below = -turned[-1].vertices[:, 1].min()
        if below > 1e-4 * min(upright.width, upright.height):  # the default overlap tolerance of Scene
            raise SceneError(f"tilted by {tilt:g} rad about a bottom corner of {blocks[0].name}, {upright.name} "
                             f"({upright.width:g} m wide) reaches {below:.3g} m below the base top: a block wider "
                             f"than those below it cannot tilt with them")
    return turned


def _face(vertices, lowest: bool) -> tuple:
    """``(left, right)`` x (m) of the ends of the bottom face (``lowest``) or the top face of an upright outline
    ``vertices`` (n, 2): its vertices within 1e-9 of its size of its lowest (highest) point."""
    heights = vertices[:, 1] if lowest else -vertices[:, 1]
    on_face = vertices[heights <= heights.min() + 1e-9 * np.ptp(vertices, axis=0).max(), 0]
    return float(on_face.min()), float(on_face.max())


def _imperfect(blocks, options: SceneOptions) -> list:
    """``blocks`` as built with the ``outlines`` and ``offsets`` of ``options`` (:class:`SceneOptions`): outlines
    first, then the offsets, each joint's limit judged on the outlined blocks."""
    offsets, outlines = _offsets(options.offsets), _outlines(options.outlines)
    if not offsets and not outlines:
        return list(blocks)
    names = [b.name for b in blocks]
    for what, given in (("offsets", offsets), ("outlines", outlines)):
        unknown = [name for name in given if name not in names]
        if unknown:
            shown = ", ".join(names[:12]) + (f" and {len(names) - 12} more" if len(names) > 12 else "")
            raise SceneError(f"{what}: no block named {unknown[0]!r}{did_you_mean(unknown[0], names)}; "
                             f"the blocks: {shown}")
    joints = _joints(blocks)
    carrying = {lower for _, lower in joints}
    blocks = [_outlined(b, outlines[b.name], k in carrying) if b.name in outlines else b for k, b in enumerate(blocks)]
    shifts = _shifts(blocks, joints, offsets)
    _check_joints(blocks, joints, shifts, options.base_width)
    return [dataclasses.replace(b, vertices=b.vertices + [s, 0.0]) if s else b for b, s in zip(blocks, shifts)]


def _offsets(given) -> dict:
    """The ``offsets`` keyword checked: {block name: m}."""
    if given is None:
        return {}
    if not isinstance(given, Mapping):
        raise SceneError(f"offsets must be a mapping {{block name: m}}, got {given!r}")
    return {name: _number(f"offset of {name!r}", value) for name, value in given.items()}


def _outlines(given) -> dict:
    """The ``outlines`` keyword checked: {block name: (n, 2) array, m}."""
    if given is None:
        return {}
    if not isinstance(given, Mapping):
        raise SceneError(f"outlines must be a mapping {{block name: [[x, y], ...]}}, got {given!r}")
    checked = {}
    for name, points in given.items():
        try:
            outline = np.array(points, dtype=float) if not isinstance(points, (str, bytes)) else None
        except (TypeError, ValueError):
            outline = None
        if outline is None or outline.ndim != 2 or outline.shape[1] != 2 or len(outline) < 3:
            raise SceneError(f"outline of {name!r} must be at least 3 [x, y] points in m, got {points!r}")
        checked[name] = outline
    return checked


def _joints(blocks) -> list:
    """``(upper, lower)`` indices into ``blocks`` (upright as built) of every joint: ``upper``'s bottom face flush on
    ``lower``'s top face and overlapping it (``lower`` -1: the base top, y = 0), within ``TOUCHING_GAP`` of the
    smaller block's smaller extent."""
    bottom = np.array([b.vertices[:, 1].min() for b in blocks])
    top = np.array([b.vertices[:, 1].max() for b in blocks])
    size = np.array([min(b.width, b.height) for b in blocks])
    bottom_faces = np.array([_face(b.vertices, lowest=True) for b in blocks])
    top_faces = np.array([_face(b.vertices, lowest=False) for b in blocks])
    by_top = np.argsort(top, kind="stable")
    joints = []
    for upper in range(len(blocks)):
        reach = TOUCHING_GAP * size[upper]
        if abs(bottom[upper]) <= reach:
            joints.append((upper, -1))
            continue
        first = np.searchsorted(top[by_top], bottom[upper] - reach, side="left")
        last = np.searchsorted(top[by_top], bottom[upper] + reach, side="right")
        for lower in by_top[first:last]:
            gap = TOUCHING_GAP * min(size[upper], size[lower])
            overlap = (min(bottom_faces[upper, 1], top_faces[lower, 1])
                       - max(bottom_faces[upper, 0], top_faces[lower, 0]))
            if abs(bottom[upper] - top[lower]) <= gap and overlap > gap:
                joints.append((upper, int(lower)))
    return joints


def _outlined(block: Block, outline: np.ndarray, carries: bool) -> Block:
    """``block`` (upright as built) with ``outline`` (n, 2) m, given about the centre of its bottom face, in its
    place; ``carries``: a block rests on its top face, which the outline must keep at the built height."""
    left, right = _face(block.vertices, lowest=True)
    bottom, height = block.vertices[:, 1].min(), np.ptp(block.vertices[:, 1])
    try:
        outlined = dataclasses.replace(block, vertices=outline + [0.5 * (left + right), bottom])
    except SceneError as exc:
        raise SceneError(f"outlines: {exc}") from None
    gap = TOUCHING_GAP * min(block.width, block.height)
    frame = "its frame's origin is the centre of its bottom face as built"
    if abs(outline[:, 1].min()) > gap:
        raise SceneError(f"outlines: '{block.name}' must rest on the joint below, its lowest point at y = 0 "
                         f"({frame}), not at y = {outline[:, 1].min():.6g} m")
    if carries and abs(outline[:, 1].max() - height) > gap:
        raise SceneError(f"outlines: '{block.name}' carries the block above on its top face, which must stay at "
                         f"y = {height:.6g} m ({frame}), not at y = {outline[:, 1].max():.6g} m")
    return outlined


def _shifts(blocks, joints, offsets: dict) -> np.ndarray:
    """(n,) m, how far ``offsets`` move each of ``blocks`` (upright) along its joints: its own offset plus the shift
    of the blocks it rests on where they all moved alike (the base does not move)."""
    below = {k: set() for k in range(len(blocks))}
    for upper, lower in joints:
        below[upper].add(lower)
    shifts = np.zeros(len(blocks))
    for k in sorted(range(len(blocks)), key=lambda k: blocks[k].vertices[:, 1].min()):  # supports first
        moved = {shifts[lower] if lower >= 0 else 0.0 for lower in below[k]}
        shifts[k] = offsets.get(blocks[k].name, 0.0) + (moved.pop() if len(moved) == 1 else 0.0)
    return shifts


def _check_joints(blocks, joints, shifts, base_width) -> None:
    """Refuse ``shifts`` (n,) m of ``blocks`` (upright, outlined) that leave a joint with less than half its width
    in contact, naming the block above, its offset and the limits; ``base_width`` m (None: the base is made wide
    enough for the blocks)."""
    half_base = np.inf if base_width is None else 0.5 * base_width
    for upper, lower in joints:
        up = np.array(_face(blocks[upper].vertices, lowest=True))
        down = (np.array(_face(blocks[lower].vertices, lowest=False)) if lower >= 0
                else np.array([-half_base, half_base]))
        below = blocks[lower].name if lower >= 0 else "base"
        width = min(up[1], down[1]) - max(up[0], down[0])
        if not width > 0:
            raise SceneError(f"outlines: '{blocks[upper].name}' no longer rests on '{below}': their faces do not meet")
        offset = shifts[upper] - (shifts[lower] if lower >= 0 else 0.0)
        low, high = down[0] + 0.5 * width - up[1], down[1] - 0.5 * width - up[0]
        slack = 1e-12 * width
        if not low - slack <= offset <= high + slack:
            kept = min(up[1] + offset, down[1]) - max(up[0] + offset, down[0])
            raise SceneError(f"offsets: '{blocks[upper].name}' would stand {offset:+.6g} m off '{below}', keeping "
                             f"{max(kept, 0.0):.6g} m of their {width:.6g} m joint in contact, less than half; its "
                             f"offset relative to '{below}' may be {low:.6g} to {high:.6g} m")


def _number(name: str, value) -> float:
    """``value`` as a float if it is a finite number (:func:`~dem_core.inputs.scene.real_number`)."""
    number = real_number(name, value)
    if not np.isfinite(number):
        raise SceneError(f"{name} must be finite, got {value}")
    return number


def _positive(**values):
    for k, v in values.items():
        if not _number(k, v) > 0:
            raise SceneError(f"{k} must be positive, got {v}")


def _count(name: str, value, minimum: int) -> int:
    """``value`` as an int if it is a whole number (a float without fraction too, not a boolean) >= ``minimum``."""
    if not is_whole(value) or value < minimum:
        raise SceneError(f"{name} must be {'a positive integer' if minimum == 1 else f'an integer >= {minimum}'}, "
                         f"got {value!r}")
    return int(value)


def _not_too_many(count: int, what: str) -> None:
    if count > MAX_BLOCKS:
        raise SceneError(f"{what} would make {count} blocks; more than {MAX_BLOCKS} is surely a typo")


def _materials(options: SceneOptions):
    """Type checks of the material keywords every builder takes (their ranges are the blocks' to check)."""
    for name in ("density", "friction", "depth"):
        _number(name, getattr(options, name))


@_takes_scene_options
def block(width: float, height: float, tilt: float = 0.0, *, name: str = "block", options: SceneOptions) -> Scene:
    """A single rectangular block (2b x 2h = width x height, m) on the base.

    tilt : rad, initial rotation about the bottom corner it rests on:
        positive (counter-clockwise) rests on the left corner (-b, 0),
        negative on the right corner.
    """
    _positive(width=width, height=height)
    _materials(options)
    return _scene([options.block(name, rectangle(width, height, -width / 2.0, 0.0))], options,
                  np.arctan2(width, height), tilt)


@_takes_scene_options
def stack(sizes, tilt: float = 0.0, *, options: SceneOptions) -> Scene:
    """Rectangular blocks stacked on their common centre line, bottom first.

    sizes : ((width, height), ...) in m; blocks are named ``block1`` (bottom) .. ``blockN``.
    tilt : rad, the whole stack rotated as one body about the bottom corner of
        ``block1`` it rests on (sign as in :func:`block`); each block's initial
        angle is ``tilt``.
    """
    if isinstance(sizes, (str, bytes)) or not len(sizes):
        raise SceneError("a stack needs at least one block: sizes = ((width, height), ...)")
    _not_too_many(len(sizes), "sizes")
    for k, size in enumerate(sizes):
        if isinstance(size, (str, bytes)) or np.shape(size) != (2,):
            raise SceneError(f"size of block{k + 1} must be a (width, height) pair, got {size!r}")
        _positive(**{f"width of block{k + 1}": size[0], f"height of block{k + 1}": size[1]})
    _materials(options)
    blocks, y = [], 0.0
    for k, (w, h) in enumerate(sizes):
        blocks.append(options.block(f"block{k + 1}", rectangle(w, h, -w / 2.0, y)))
        y += h
    return _scene(blocks, options, np.arctan2(sizes[0][0], sizes[0][1]), tilt)


def _check_column(n_drums, width, height, taper=0.0, capital=None, tier=""):
    """Type and range checks of a column's shape; ``tier`` ("lower_", "upper_") names the keywords."""
    n_drums = _count(f"{tier}drums" if tier else "n_drums", n_drums, 1)
    _positive(**{f"{tier}width": width, f"{tier}height": height})
    if not 0.0 <= _number("taper", taper) < 2.0:
        raise SceneError(f"taper must be in [0, 2), got {taper}")
    if capital is not None:
        if isinstance(capital, (str, bytes)) or np.shape(capital) != (2,):
            raise SceneError(f"capital must be a (width, height) pair in m, got {capital!r}")
        _positive(capital_width=capital[0], capital_height=capital[1])
    return n_drums


def _column_blocks(n_drums, width, height, taper, capital, x_centre, y0, options: SceneOptions, prefix):
    """Drums (trapezoids if tapered) and an optional capital, bottom to top (arguments checked by
    :func:`_check_column`)."""
    # mean width equals `width`, so the tapered column has the prismatic column's mass
    w_bottom = width / (1.0 - taper / 2.0) if taper else width
    w_top = w_bottom * (1.0 - taper)
    drum_h = height / n_drums
    blocks = []
    for k in range(n_drums):
        f0, f1 = k / n_drums, (k + 1) / n_drums
        wb = w_bottom + (w_top - w_bottom) * f0
        wt = w_bottom + (w_top - w_bottom) * f1
        yb, yt = y0 + k * drum_h, y0 + (k + 1) * drum_h
        v = np.array([[x_centre - wb / 2, yb], [x_centre + wb / 2, yb], [x_centre + wt / 2, yt],
                      [x_centre - wt / 2, yt]])
        blocks.append(options.block(f"{prefix}drum{k + 1}", v))
    top = y0 + height
    if capital is not None:
        cw, ch = capital
        blocks.append(options.block(f"{prefix}capital", rectangle(cw, ch, x_centre - cw / 2.0, top)))
        top += ch
    return blocks, top


@_takes_scene_options
def column(n_drums: int = 8, width: float = 1.0, height: float = 6.0, *, taper: float = 0.0,
           capital: tuple | None = None, tilt: float = 0.0, options: SceneOptions) -> Scene:
    """A standalone column of ``n_drums`` equal-height drums, total ``height`` (m).

    width : m, mean width of the shaft.
    taper : (W_bottom - W_top) / W_bottom, with the mean width kept at
        ``width`` so a tapered column has the prismatic column's mass.
    capital : (width, height) in m of a block on top, or None.
    tilt : rad, the whole column turned as one body about the bottom corner of
        ``drum1`` it rests on (as :func:`stack`); each block's initial angle is ``tilt``.
    """
    return _column_scene(n_drums, width, height, taper, capital, None, tilt, options)


@_takes_scene_options
def loaded_column(load: tuple, n_drums: int = 8, width: float = 1.0, height: float = 6.0, *, taper: float = 0.0,
                  capital: tuple | None = None, tilt: float = 0.0, options: SceneOptions) -> Scene:
    """A standalone :func:`column` carrying a block named ``load`` on its top (on the capital, if any).

    load : (width m, height m, density kg/m^3) of that block: the share of an epistyle that a column of a
        colonnade carries (L. Papaloizou 2009, section 7.1).  It is a mass, free to slide and rock on the
        column like an epistyle: it lowers the column's uplift acceleration to ``g b / h_G``, ``b`` the half
        width of the base and ``h_G`` the height of the combined centre of mass, and the scene's rocking
        slenderness is ``atan(b / h_G)``.  Other arguments as :func:`column`.
    """
    if isinstance(load, (str, bytes)) or np.shape(load) != (3,):
        raise SceneError(f"load must be a (width m, height m, density kg/m^3) triple, got {load!r}")
    _positive(load_width=load[0], load_height=load[1], load_density=load[2])
    return _column_scene(n_drums, width, height, taper, capital, load, tilt, options)


def _column_scene(n_drums, width, height, taper, capital, load, tilt, options: SceneOptions) -> Scene:
    """The scene of :func:`column` and :func:`loaded_column` (``load`` checked, or None)."""
    n_drums = _check_column(n_drums, width, height, taper, capital)
    _not_too_many(n_drums, f"n_drums = {n_drums}")
    _materials(options)
    blocks, top = _column_blocks(n_drums, width, height, taper, capital, 0.0, 0.0, options, "")
    slenderness = np.arctan2(width, top)
    if load is not None:
        blocks.append(options.block("load", rectangle(load[0], load[1], -load[0] / 2.0, top), density=load[2]))
        mass = np.array([b.mass for b in blocks])
        centre_height = np.array([b.centroid[1] for b in blocks]) @ mass / mass.sum()
        slenderness = np.arctan2(0.5 * np.ptp(blocks[0].vertices[:, 0]), centre_height)
    return _scene(blocks, options, slenderness, tilt)


def _epistyles(kind, centres, col_top_width, y, thickness, density, options: SceneOptions, prefix):
    """Epistyle blocks of type a-d (docs/method.md section 3) over column centres ``centres``, of ``density``."""
    n = len(centres)
    left_edge = centres[0] - col_top_width / 2.0
    right_edge = centres[-1] + col_top_width / 2.0
    if kind in ("a", "b"):
        x0, x1 = left_edge, right_edge
    elif kind in ("c", "d"):
        x0, x1 = centres[0], centres[-1]
    else:
        raise SceneError(f"epistyle type must be 'a', 'b', 'c' or 'd', got {kind!r}")
    if kind in ("a", "c"):
        spans = [(x0, x1)]
    else:
        if n % 2 == 0:
            raise SceneError(f"epistyle type {kind!r} meets over a middle column: needs an odd number of columns, "
                             f"got {n}")
        mid = centres[n // 2]
        spans = [(x0, mid), (mid, x1)]
    names = [f"{prefix}epistyle"] if len(spans) == 1 else [f"{prefix}epistyle{k + 1}" for k in range(len(spans))]
    return [options.block(nm, rectangle(b - a, thickness, a, y), density=density) for nm, (a, b) in zip(names, spans)]


@_takes_scene_options
def colonnade(n_columns: int = 3, n_drums: int = 3, spacing: float = 2.5, *, epistyle: str = "a",
              epistyle_density: float = 2700.0, epistyle_height: float = 0.8, width: float = 1.0,
              height: float = 6.0, taper: float = 0.0, capital: tuple | None = None, options: SceneOptions) -> Scene:
    """``n_columns`` equal columns at centre spacing ``spacing`` (m) carrying epistyles.

    epistyle : "a" one block over the full width of the outer columns;
        "b" two blocks meeting over the middle column, full width;
        "c" one block from the centre line of the first column to that of the last;
        "d" two such blocks meeting over the middle column.
    epistyle_density : kg/m^3 (5000 to 10000 models the lost frieze load).
    epistyle_height : m.  Other arguments as :func:`column`.
    """
    n_columns = _count("n_columns", n_columns, 2)
    n_drums = _check_column(n_drums, width, height, taper, capital)
    _not_too_many(n_columns * n_drums, f"n_columns = {n_columns} columns of n_drums = {n_drums}")
    _materials(options)
    _positive(spacing=spacing, epistyle_height=epistyle_height, epistyle_density=epistyle_density)
    top_width = capital[0] if capital is not None else width * (1.0 - taper) / (1.0 - taper / 2.0)
    if spacing < top_width:
        raise SceneError(f"spacing {spacing} m is smaller than the column top width {top_width} m: columns would "
                         "overlap")
    centres = (np.arange(n_columns) - (n_columns - 1) / 2.0) * spacing
    blocks = []
    top = 0.0
    for c, xc in enumerate(centres):
        col, top = _column_blocks(n_drums, width, height, taper, capital, xc, 0.0, options, f"c{c + 1}_")
        blocks += col
    blocks += _epistyles(epistyle, centres, top_width, top, epistyle_height, epistyle_density, options, "")
    return _scene(blocks, options, np.arctan2(width, top))


@_takes_scene_options
def two_tier_colonnade(n_columns: int = 3, spacing: float = 2.5, *, lower_drums: int = 3,
                       lower_height: float = 4.5, lower_width: float = 0.9, upper_drums: int = 2,
                       upper_height: float = 2.5, upper_width: float = 0.6, epistyle: str = "a",
                       epistyle_height: float = 0.6, epistyle_density: float = 2700.0,
                       options: SceneOptions) -> Scene:
    """A lower row of columns, an epistyle, an upper row of smaller columns, another epistyle.

    Both rows stand on the same centre lines, ``spacing`` apart; each row
    carries epistyles of type ``epistyle`` (see :func:`colonnade`).
    """
    n_columns = _count("n_columns", n_columns, 2)
    lower_drums = _check_column(lower_drums, lower_width, lower_height, tier="lower_")
    upper_drums = _check_column(upper_drums, upper_width, upper_height, tier="upper_")
    _not_too_many(n_columns * (lower_drums + upper_drums), f"n_columns = {n_columns} columns of "
                  f"lower_drums = {lower_drums} and upper_drums = {upper_drums}")
    _materials(options)
    _positive(spacing=spacing, epistyle_height=epistyle_height, epistyle_density=epistyle_density)
    if spacing < max(lower_width, upper_width):
        raise SceneError(f"spacing {spacing} m is smaller than a column width: columns would overlap")
    centres = (np.arange(n_columns) - (n_columns - 1) / 2.0) * spacing
    blocks = []
    for c, xc in enumerate(centres):
        blocks += _column_blocks(lower_drums, lower_width, lower_height, 0.0, None, xc, 0.0, options,
                                 f"lower_c{c + 1}_")[0]
    blocks += _epistyles(epistyle, centres, lower_width, lower_height, epistyle_height, epistyle_density,
                         options, "lower_")
    y_upper = lower_height + epistyle_height
    for c, xc in enumerate(centres):
        blocks += _column_blocks(upper_drums, upper_width, upper_height, 0.0, None, xc, y_upper, options,
                                 f"upper_c{c + 1}_")[0]
    blocks += _epistyles(epistyle, centres, upper_width, y_upper + upper_height, epistyle_height,
                         epistyle_density, options, "upper_")
    return _scene(blocks, options, np.arctan2(lower_width, lower_height))
