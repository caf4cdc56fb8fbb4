"""Builders for the scenes of docs/method.md section 3.

Every builder returns an immutable :class:`~dem_core.inputs.scene.Scene` whose base
top is the line y = 0 and whose blocks rest on it touching (zero overlap).
Every builder also takes the keywords of :class:`SceneOptions`: ``density``
(kg/m^3), ``friction``, ``depth`` (m), ``contact``
(:class:`~dem_core.engine.contact.ContactParameters`), ``interface_friction``
({(name_a, name_b): mu}) and ``base_width`` (m; by default the blocks' span plus
4 times their height, so that whatever topples lands on the base).

Block names: ``block``; ``block1`` (bottom) .. in stacks; ``drum1`` (bottom) .. ``drumN``, ``capital``;
in colonnades ``c1_drum1`` .. (column ``c1`` is the leftmost), ``epistyle``
or ``epistyle1``/``epistyle2``; in two-tier colonnades ``lower_``/``upper_``
prefixes.  The base is ``base``.
"""

import functools
import inspect
import numbers
from dataclasses import dataclass, fields

import numpy as np

from ..engine.contact import ContactParameters
from ..engine.geometry import rectangle, transform
from .scene import Block, Scene, SceneError

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
    """

    density: float = 2700.0
    friction: float = 0.7
    depth: float = 1.0
    contact: ContactParameters | None = None
    interface_friction: dict | None = None
    base_width: float | None = None

    def block(self, name: str, vertices, density: float | None = None, angle: float = 0.0) -> Block:
        """A block of this stone (of ``density`` instead, if given)."""
        return Block(name, vertices, density=self.density if density is None else density, depth=self.depth,
                     friction=self.friction, angle=angle)


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


def _scene(blocks, options: SceneOptions, slenderness) -> Scene:
    base_width = options.base_width
    if base_width is not None:
        _positive(base_width=base_width)
    span = max(b.vertices[:, 0].max() for b in blocks) - min(b.vertices[:, 0].min() for b in blocks)
    tall = max(b.vertices[:, 1].max() for b in blocks)
    # wide enough that the tallest block toppling outwards still lands on it
    base_width = span + 4.0 * tall if base_width is None else base_width
    base = Block("base", rectangle(base_width, BASE_HEIGHT, -base_width / 2.0, -BASE_HEIGHT),
                 density=1.0, depth=options.depth, friction=options.friction)
    return Scene(tuple(blocks), base, contact=options.contact or ContactParameters(),
                 interface_friction=options.interface_friction or {}, slenderness=slenderness)


def _number(name: str, value) -> float:
    """``value`` as a float if it is a finite number (not a boolean, not a string)."""
    if isinstance(value, bool) or not isinstance(value, numbers.Real):
        raise SceneError(f"{name} must be a number, got {value!r}")
    if not np.isfinite(value):
        raise SceneError(f"{name} must be finite, got {value}")
    return float(value)


def _positive(**values):
    for k, v in values.items():
        if not _number(k, v) > 0:
            raise SceneError(f"{k} must be positive, got {v}")


def _count(name: str, value, minimum: int) -> int:
    """``value`` as an int if it is a whole number (a float without fraction too, not a boolean) >= ``minimum``."""
    whole = isinstance(value, numbers.Integral) or (isinstance(value, numbers.Real) and float(value).is_integer())
    if isinstance(value, bool) or not whole or value < minimum:
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
    tilt = _number("tilt", tilt)
    v = rectangle(width, height, -width / 2.0, 0.0)
    if tilt:
        pivot = np.array([-width / 2.0 if tilt > 0 else width / 2.0, 0.0])
        v = transform(v - pivot, tilt, pivot)
    return _scene([options.block(name, v, angle=tilt)], options, np.arctan2(width, height))


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
    tilt = _number("tilt", tilt)
    blocks, y = [], 0.0
    pivot = np.array([-sizes[0][0] / 2.0 if tilt > 0 else sizes[0][0] / 2.0, 0.0])
    for k, (w, h) in enumerate(sizes):
        v = rectangle(w, h, -w / 2.0, y)
        if tilt:
            v = transform(v - pivot, tilt, pivot)
            below = -v[:, 1].min()
            if below > 1e-4 * min(w, h):  # the default overlap tolerance of Scene
                raise SceneError(f"tilted by {tilt:g} rad about a bottom corner of block1, block{k + 1} ({w:g} m wide) "
                                 f"reaches {below:.3g} m below the base top: a block wider than those below it "
                                 f"cannot tilt with them")
        blocks.append(options.block(f"block{k + 1}", v, angle=tilt))
        y += h
    return _scene(blocks, options, np.arctan2(sizes[0][0], sizes[0][1]))


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
        v = np.array([[x_centre - wb / 2, yb], [x_centre + wb / 2, yb], [x_centre + wt / 2, yt], [x_centre - wt / 2, yt]])
        blocks.append(options.block(f"{prefix}drum{k + 1}", v))
    top = y0 + height
    if capital is not None:
        cw, ch = capital
        blocks.append(options.block(f"{prefix}capital", rectangle(cw, ch, x_centre - cw / 2.0, top)))
        top += ch
    return blocks, top


@_takes_scene_options
def column(n_drums: int = 8, width: float = 1.0, height: float = 6.0, *, taper: float = 0.0,
           capital: tuple | None = None, options: SceneOptions) -> Scene:
    """A standalone column of ``n_drums`` equal-height drums, total ``height`` (m).

    width : m, mean width of the shaft.
    taper : (W_bottom - W_top) / W_bottom, with the mean width kept at
        ``width`` so a tapered column has the prismatic column's mass.
    capital : (width, height) in m of a block on top, or None.
    """
    return _column_scene(n_drums, width, height, taper, capital, None, options)


@_takes_scene_options
def loaded_column(load: tuple, n_drums: int = 8, width: float = 1.0, height: float = 6.0, *, taper: float = 0.0,
                  capital: tuple | None = None, options: SceneOptions) -> Scene:
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
    return _column_scene(n_drums, width, height, taper, capital, load, options)


def _column_scene(n_drums, width, height, taper, capital, load, options: SceneOptions) -> Scene:
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
    return _scene(blocks, options, slenderness)


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
            raise SceneError(f"epistyle type {kind!r} meets over a middle column: needs an odd number of columns, got {n}")
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
        raise SceneError(f"spacing {spacing} m is smaller than the column top width {top_width} m: columns would overlap")
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
