"""What a scene is: immutable blocks, the base, contact parameters, friction overrides.

A :class:`Scene` describes the model only; where the blocks are during a run
lives in the simulation state (see :mod:`dem_core.simulation`).  Every engine
(native core and adapters) builds from this one description.
"""

import dataclasses
from dataclasses import dataclass, field
from functools import cached_property

import numpy as np

from ..engine import geometry
from ..engine.contact import ContactParameters
from .connectors import Connector
from .errors import SceneError
from .number_types import is_real
from .text_files import did_you_mean, shown

#: relative gap within which two blocks count as touching at the start (of the smaller block's size)
TOUCHING_GAP = 1e-6
STANDARD_GRAVITY = 9.81  # m/s^2, the value docs/method.md 4.6 uses (g b/h = 1.635 for 1 x 6 m)
#: an overlap of two blocks smaller than this times the product of their sizes is round-off, not
#: penetration: coordinates carry a relative error of about 1e-16, so faces that meet (a tilted stack's
#: joints) can cross by slivers of order 1e-16 L^2, whose area over their tiny length is no depth at all
OVERLAP_ROUNDOFF = 1e-12
#: a block rests on another when the gap between them is at most this fraction of the smaller extent
#: of the two: what a block is dropped from within it is a settling, not a fall
SUPPORT_GAP = 0.01


@dataclass(frozen=True, eq=False)
class Block:
    """One rigid convex block (a drum, capital, epistyle, or the base).

    vertices : (n, 2) array, m
        Outline at the start of the run, world coordinates, convex.  Stored
        counter-clockwise (clockwise input is reversed).
    density : kg/m^3
    depth : m, out-of-plane thickness; mass = density * area * depth.
    friction : Coulomb coefficient of the block's surface; an interface uses
        the smaller of its two blocks' values unless the scene overrides it.
    angle : rad, rotation of ``vertices`` from the block's reference
        orientation; reported rotations start from it.
    """

    name: str
    vertices: np.ndarray
    density: float = 2700.0
    depth: float = 1.0
    friction: float = 0.7
    angle: float = 0.0

    def __post_init__(self):
        if not isinstance(self.name, str) or not self.name:
            raise SceneError(f"block name must be a non-empty string, got {self.name!r}")
        try:
            v = geometry.as_convex_ccw(self.vertices, name=f"block '{self.name}'")
        except geometry.GeometryError as exc:
            raise SceneError(str(exc)) from None
        v.flags.writeable = False
        object.__setattr__(self, "vertices", v)
        for attr in ("density", "depth"):
            value = float(getattr(self, attr))
            if not np.isfinite(value) or value <= 0:
                raise SceneError(f"block '{self.name}': {attr} must be positive, got {value}")
            object.__setattr__(self, attr, value)
        mu = float(self.friction)
        if not np.isfinite(mu) or mu < 0:
            raise SceneError(f"block '{self.name}': friction must be >= 0, got {mu}")
        object.__setattr__(self, "friction", mu)
        object.__setattr__(self, "angle", float(self.angle))

    @cached_property
    def _properties(self) -> geometry.PolygonProperties:
        return geometry.polygon_properties(self.vertices)

    @property
    def area(self) -> float:
        """Polygon area, m^2."""
        return self._properties.area

    @property
    def centroid(self) -> np.ndarray:
        """Centre of mass at the start, (2,) m."""
        return self._properties.centroid

    @property
    def mass(self) -> float:
        """kg."""
        return self.density * self.area * self.depth

    @property
    def inertia(self) -> float:
        """Rotational inertia about the centre of mass, kg m^2 (exact for the polygon)."""
        return self.density * self.depth * self._properties.polar_moment

    @property
    def width(self) -> float:
        """Horizontal extent at the start, m."""
        return float(np.ptp(self.vertices[:, 0]))

    @property
    def height(self) -> float:
        """Vertical extent at the start, m."""
        return float(np.ptp(self.vertices[:, 1]))

    @property
    def circumradius(self) -> float:
        """Largest distance from the centre of mass to a vertex, m."""
        return float(np.max(np.hypot(*(self.vertices - self.centroid).T)))

    @property
    def critical_angle(self) -> float:
        """Rotation past which gravity alone tips the block over a bottom corner, rad.

        ``atan(b / h)`` in the reference orientation (``angle`` undone): the
        angle between the vertical and the line from the centre of mass to the
        nearer of the lowest corners.
        """
        v = geometry.transform(self.vertices - self.centroid, -self.angle)
        size = np.ptp(v, axis=0).max()
        low = v[:, 1] <= v[:, 1].min() + 1e-9 * size
        return float(np.arctan2(np.abs(v[low, 0]).min(), -v[:, 1].min()))


def _friction_key(a: str, b: str) -> tuple[str, str]:
    return (a, b) if a <= b else (b, a)


def real_number(name: str, value) -> float:
    """``value`` as a float; :class:`SceneError` naming ``name`` and the value (its type too) for anything not a
    real number (:func:`~dem_core.inputs.number_types.is_real`)."""
    if not is_real(value):
        raise SceneError(f"{name} must be a number, got {type(value).__name__} {shown(value)}")
    return float(value)


@dataclass(frozen=True, eq=False)
class Scene:
    """A complete model: blocks resting on a base, contact law, friction overrides.

    blocks : the free bodies, in the order results report them.
    base : the stylobate; it moves with the ground and has no dynamics.
    contact : :class:`~dem_core.engine.contact.ContactParameters`.
    interface_friction : mapping ``{(name_a, name_b): mu}`` that overrides the
        default (smaller of the two blocks' values) at chosen interfaces.
    gravity : m/s^2.
    overlap_tolerance : allowed mean penetration between blocks at the start,
        as a fraction of the smaller block's smaller extent.
    slenderness : rad, atan(b/h) of the body that rocks as a unit (a whole
        column, not one drum); sets the default contact damping
        (:func:`dem_core.engine.contact.housner_damping_ratio`).  The builders set
        it; None takes atan(width/height) of the blocks' bounding box.
    allow_free_blocks : accept blocks that start out of contact with the base and
        with every block resting on it (they fall from t = 0).  By default such a
        scene is refused, naming the blocks: a free fall is rarely meant and ends
        in results that read as an overturn.
    connectors : (:class:`~dem_core.inputs.connectors.Connector`, ...) bars or pins across joints, each between
        two blocks that touch at the start and within their joint.
    """

    blocks: tuple
    base: Block
    contact: ContactParameters = field(default_factory=ContactParameters)
    interface_friction: dict = field(default_factory=dict)
    gravity: float = STANDARD_GRAVITY
    overlap_tolerance: float = 1e-4
    slenderness: float | None = None
    allow_free_blocks: bool = False
    connectors: tuple = ()

    def __post_init__(self):
        blocks = tuple(self.blocks)
        if not blocks:
            raise SceneError("a scene needs at least one block")
        for b in (*blocks, self.base):
            if not isinstance(b, Block):
                raise SceneError(f"scene members must be Block objects, got {type(b).__name__}")
        object.__setattr__(self, "blocks", blocks)
        names = [b.name for b in (self.base, *blocks)]
        seen = set()
        for n in names:
            if n in seen:
                raise SceneError(f"block name '{n}' is used twice; names identify blocks in results and friction "
                                 "overrides")
            seen.add(n)
        overrides = {}
        for key, mu in dict(self.interface_friction).items():
            a, b = key
            for n in (a, b):
                if n not in seen:
                    raise SceneError(f"interface friction ({a!r}, {b!r}): no block named '{n}'")
            if a == b:
                raise SceneError(f"interface friction ({a!r}, {b!r}): a block has no interface with itself")
            mu = real_number(f"interface friction ({a!r}, {b!r}): mu", mu)
            if not np.isfinite(mu) or mu < 0:
                raise SceneError(f"interface friction ({a!r}, {b!r}): mu must be >= 0, got {mu}")
            overrides[_friction_key(a, b)] = mu
        object.__setattr__(self, "interface_friction", overrides)
        for name in ("gravity", "overlap_tolerance") + (("slenderness",) if self.slenderness is not None else ()):
            real_number(name, getattr(self, name))
        if not np.isfinite(self.gravity) or self.gravity < 0:
            raise SceneError(f"gravity must be >= 0, got {self.gravity}")
        if not (np.isfinite(self.overlap_tolerance) and self.overlap_tolerance >= 0):
            raise SceneError(f"overlap_tolerance must be a finite fraction >= 0, got {self.overlap_tolerance}")
        if self.slenderness is not None and not 0 < self.slenderness < np.pi / 2:
            raise SceneError(f"slenderness must be an angle in (0, pi/2) rad, got {self.slenderness}")
        self._check_start()
        self._check_connectors()

    @property
    def free_bodies(self) -> tuple:
        """Indices into :attr:`bodies` (0 is the base) of the blocks that start out of contact with the
        base and with everything resting on it (only with ``allow_free_blocks``).  Their fall is not an
        overturn: the falling-block rule of the overturn check does not apply to them."""
        return self._free_bodies

    @property
    def rocking_slenderness(self) -> float:
        """Slenderness angle (rad) used for the default contact damping."""
        if self.slenderness is not None:
            return float(self.slenderness)
        v = np.concatenate([b.vertices for b in self.blocks])
        width, height = np.ptp(v, axis=0)
        return float(np.arctan2(width, height))

    @cached_property
    def bodies(self) -> tuple:
        """Base first, then the blocks: the index order of the compiled kernels."""
        return (self.base, *self.blocks)

    @property
    def block_names(self) -> list:
        return [b.name for b in self.blocks]

    def friction(self, a: str, b: str) -> float:
        """Coulomb coefficient of the interface between blocks named ``a`` and ``b``."""
        key = _friction_key(a, b)
        if key in self.interface_friction:
            return self.interface_friction[key]
        return min(self._by_name[a].friction, self._by_name[b].friction)

    @cached_property
    def _by_name(self) -> dict:
        return {blk.name: blk for blk in self.bodies}

    def replace(self, **changes) -> "Scene":
        """A copy with fields changed (the scene itself is immutable)."""
        return dataclasses.replace(self, **changes)

    def with_interface_friction(self, a: str, b: str, mu: float) -> "Scene":
        """A copy whose interface between ``a`` and ``b`` has friction ``mu``."""
        return self.replace(interface_friction={**self.interface_friction, (a, b): mu})

    def touching_pairs(self) -> tuple:
        """``(i, j, contact)`` for every pair of bodies (0 = base, i < j) touching at the start.

        Two blocks touch when moving one towards the other by ``TOUCHING_GAP`` times the smaller block
        size makes them overlap; ``contact`` is the :class:`~dem_core.engine.geometry.ContactGeometry`
        of that thin overlap.  The pairs are found by the engine's broad phase (sort-and-sweep) and
        computed once per scene.
        """
        return self._touching

    @cached_property
    def _touching(self) -> tuple:
        bodies = self.bodies
        low = np.array([b.vertices.min(axis=0) for b in bodies])
        high = np.array([b.vertices.max(axis=0) for b in bodies])
        margin = TOUCHING_GAP * float(np.min(high - low))
        n = len(bodies)
        pairs = []
        for key in geometry.overlapping_boxes(low, high, margin):
            i, j = divmod(int(key), n)
            p, q = bodies[i], bodies[j]
            offset = q.centroid - p.centroid
            nudge = TOUCHING_GAP * min(p.width, p.height, q.width, q.height)
            touch = geometry.contact_geometry(p.vertices, q.vertices - nudge * offset / np.hypot(*offset))
            if touch is not None:
                pairs.append((i, j, touch))
        return tuple(pairs)

    def _pairs_near(self, slack: float):
        """``(i, j)`` of the pairs whose bounding boxes are at most ``slack`` times the smaller extent
        of the two apart."""
        low = np.array([b.vertices.min(axis=0) for b in self.bodies])
        high = np.array([b.vertices.max(axis=0) for b in self.bodies])
        extents = np.min(high - low, axis=1)
        for i in range(len(low) - 1):
            apart = np.max(np.maximum(low[i + 1:] - high[i], low[i] - high[i + 1:]), axis=1)
            for j in np.flatnonzero(apart <= slack * np.minimum(extents[i], extents[i + 1:])):
                yield i, i + 1 + int(j)

    def _check_start(self):
        """Refuse blocks that start overlapping (beyond round-off) or, unless allowed, out of contact."""
        bodies = self.bodies
        neighbours = {k: set() for k in range(len(bodies))}
        for i, j in self._pairs_near(SUPPORT_GAP):
            p, q = bodies[i], bodies[j]
            contact = geometry.contact_geometry(p.vertices, q.vertices)
            if contact is not None and contact.area > OVERLAP_ROUNDOFF * _size(p) * _size(q):
                depth = contact.area / max(contact.length, 1e-300)
                allowed = self.overlap_tolerance * _smaller_extent(p, q)
                if depth > allowed:
                    raise SceneError(
                        f"blocks '{p.name}' and '{q.name}' overlap at the start "
                        f"(area {contact.area:.3e} m^2, mean penetration {depth:.3e} m > tolerance {allowed:.3e} m)"
                    )
            if contact is not None or _distance(p.vertices, q.vertices) <= SUPPORT_GAP * _smaller_extent(p, q):
                neighbours[i].add(j)
                neighbours[j].add(i)
        self._check_supported(neighbours)

    def _check_connectors(self):
        """Refuse a connector between blocks that do not exist, that do not touch at the start, or off its joint."""
        connectors = tuple(self.connectors)
        object.__setattr__(self, "connectors", connectors)
        if not connectors:
            return
        index = {b.name: k for k, b in enumerate(self.bodies)}
        joints = {}
        for i, j, touch in self.touching_pairs():
            joints[(i, j)] = touch
        for c in connectors:
            if not isinstance(c, Connector):
                raise SceneError(f"scene connectors must be Connector objects, got {type(c).__name__}")
            for n in c.between:
                if n not in index:
                    raise SceneError(f"connector {c.name}: no block named '{n}'{did_you_mean(n, list(index))}")
            i, j = sorted(index[n] for n in c.between)
            touch = joints.get((i, j))
            if touch is None:
                near = [f"{self.bodies[a].name}/{self.bodies[b].name}" for a, b in joints if i in (a, b) or j in (a, b)]
                raise SceneError(f"connector {c.name}: '{c.between[0]}' and '{c.between[1]}' do not touch at the "
                                 "start, so there is no joint between them "
                                 f"(their joints: {', '.join(near) or 'none'})")
            if abs(c.position) >= 0.5 * touch.length:
                raise SceneError(f"connector {c.name}: position {c.position:g} m is off its joint, "
                                 f"{touch.length:.4g} m long (|position| < {0.5 * touch.length:.4g} m)")

    def _check_supported(self, neighbours):
        supported, frontier = {0}, [0]
        while frontier:
            for k in neighbours[frontier.pop()] - supported:
                supported.add(k)
                frontier.append(k)
        free = [k for k in range(1, len(self.bodies)) if k not in supported]
        object.__setattr__(self, "_free_bodies", tuple(free))
        if not free or self.allow_free_blocks:
            return
        bodies = self.bodies
        gaps = []
        for k in free[:3]:
            gap, nearest = min((_distance(bodies[k].vertices, bodies[s].vertices), s) for s in supported)
            gaps.append(f"'{bodies[k].name}' is {gap:.4g} m from '{bodies[nearest].name}'")
        names = ", ".join(f"'{bodies[k].name}'" for k in free[:3]) + (f" and {len(free) - 3} more" if len(free) > 3
                                                                        else "")
        one = len(free) == 1
        raise SceneError(
            f"block{'' if one else 's'} {names} start{'s' if one else ''} out of contact with the base and with every "
            f"block resting on it ({'; '.join(gaps)}): {'it' if one else 'they'} would fall freely from t = 0. "
            f"Move {'it' if one else 'them'} onto {'its' if one else 'their'} support, or allow free blocks: "
            f"Scene(..., allow_free_blocks=True), or allow_free_blocks = true in a scene file's [scene] table"
        )


def _size(block: Block) -> float:
    """Larger extent of a block at the start, m."""
    return max(block.width, block.height)


def _smaller_extent(p: Block, q: Block) -> float:
    """Smallest of the widths and heights of two blocks at the start, m."""
    return min(p.width, p.height, q.width, q.height)


def _distance(p, q) -> float:
    """Distance between convex polygons ``p`` and ``q`` (vertices (n, 2), m) that do not overlap: the
    shortest from a vertex of one to an edge of the other."""
    return min(_vertices_to_edges(p, q), _vertices_to_edges(q, p))


def _vertices_to_edges(points, polygon) -> float:
    """Shortest distance from any of ``points`` (n, 2) to the outline of ``polygon`` (m, 2), m."""
    start = polygon
    edge = np.roll(polygon, -1, axis=0) - start
    offset = points[:, None, :] - start[None, :, :]
    along = np.clip(np.sum(offset * edge, axis=2) / np.sum(edge * edge, axis=1), 0.0, 1.0)
    return float(np.sqrt(np.min(np.sum((offset - along[:, :, None] * edge) ** 2, axis=2))))
