"""A block's geometry as the engines take it: its start pose, whether it is a rectangle, its prism.

The scene's blocks are convex counter-clockwise polygons in the x-y plane (m).  The 3D
engines (PyBullet, MuJoCo) build them in their x-z plane (z up) as prisms of the scene's
depth, which runs along their y axis, centred on y = 0: the scene's point ``(x, y)`` is the
engine's ``(x, 0, y)``, and the scene's counter-clockwise rotation is a rotation about -y.
"""

import math
from dataclasses import dataclass

import numpy as np

from dem_core.engine.geometry import transform

#: a quadrilateral is a rectangle when its adjacent edges have ``|e_i . e_j| <= tol max|e|^2``: every vertex
#: within about ``tol`` times the block's size of where a rectangle puts it; an axis-aligned one has
#: ``|sin(2 angle)| <= tol``
RECTANGLE_TOLERANCE = 1e-9


@dataclass(frozen=True)
class StartPose:
    """Where a block's body starts: its centre of mass ``centroid`` (2,) m and its ``angle`` (rad,
    counter-clockwise), the rotation of its outline from its reference orientation."""

    centroid: np.ndarray
    angle: float


def start_pose(block) -> StartPose:
    """The pose a block's body starts in (:class:`dem_core.Block`'s ``centroid`` and ``angle``)."""
    return StartPose(block.centroid, block.angle)


def start_states(blocks) -> np.ndarray:
    """(n_blocks, 3) ``x, y, theta`` (m, m, rad) of each block at the start: what an engine whose joint
    coordinates start at zero adds them to."""
    return np.array([[*pose.centroid, pose.angle] for pose in map(start_pose, blocks)])


def outline_at_start(block) -> np.ndarray:
    """(n, 2) vertices about the centre of mass at the starting angle, m: the shape of a body whose
    joints start at zero (PyBullet, MuJoCo)."""
    return block.vertices - start_pose(block).centroid


def outline_in_reference(block) -> np.ndarray:
    """(n, 2) vertices about the centre of mass with the starting angle undone, m: the shape of a body
    that carries the angle itself (pymunk).  ``transform(outline, angle, centroid)`` is the block."""
    pose = start_pose(block)
    return transform(block.vertices - pose.centroid, -pose.angle)


@dataclass(frozen=True)
class Rectangle:
    """A rectangle: ``centre`` (2,) m, ``half_extents`` (2,) m along its first edge and its second,
    ``angle`` (rad) of its first edge from the x axis."""

    centre: np.ndarray
    half_extents: np.ndarray
    angle: float

    def axis_aligned(self, tolerance: float = RECTANGLE_TOLERANCE) -> bool:
        """Whether its edges run along x and y: ``|sin(2 angle)| <= tolerance``."""
        return abs(math.sin(2.0 * self.angle)) <= tolerance

    def half_extents_on_axes(self) -> np.ndarray:
        """(2,) half extents along x and y, m, of an axis-aligned rectangle."""
        along_x = abs(math.cos(self.angle)) >= abs(math.sin(self.angle))
        return self.half_extents if along_x else self.half_extents[::-1]


def rectangle(outline, tolerance: float = RECTANGLE_TOLERANCE) -> Rectangle | None:
    """The :class:`Rectangle` an (n, 2) convex outline (m) is, or None if it is not one.

    A quadrilateral whose four corners are square to ``tolerance``: ``|e_i . e_{i+1}| <= tolerance
    max|e|^2`` for its edges ``e``, so the tolerance is relative to the block's size.
    """
    v = np.asarray(outline, dtype=float)
    if len(v) != 4:
        return None
    edges = np.roll(v, -1, axis=0) - v
    dots = np.einsum("ij,ij->i", edges, np.roll(edges, -1, axis=0))
    if not np.all(np.abs(dots) <= tolerance * np.sum(edges**2, axis=1).max()):
        return None
    half = np.array([np.hypot(*edges[0]) / 2, np.hypot(*edges[1]) / 2])
    return Rectangle(v.mean(axis=0), half, float(np.arctan2(edges[0][1], edges[0][0])))


def inset(outline, distance: float) -> np.ndarray:
    """(n, 2) the convex counter-clockwise ``outline`` (m) with every edge moved inwards by ``distance`` (m)."""
    v = np.asarray(outline, dtype=float)
    edges = np.roll(v, -1, axis=0) - v
    normals = np.column_stack([edges[:, 1], -edges[:, 0]]) / np.hypot(edges[:, 0], edges[:, 1])[:, None]
    points = v - distance * normals  # a point on each moved edge (the normals point outwards)
    corners = []
    for k in range(len(v)):
        a, da = points[k - 1], edges[k - 1]
        b, db = points[k], edges[k]
        corners.append(a + _cross(b - a, db) / _cross(da, db) * da)
    return np.array(corners)


def _cross(u, v):
    return u[0] * v[1] - u[1] * v[0]


@dataclass(frozen=True)
class Prism:
    """A convex outline extruded along the engine's y axis.

    vertices : (2n, 3) m, in the engine's frame: outline vertex k at ``y = -depth/2`` (row 2k) and at
        ``y = +depth/2`` (row 2k + 1); the engines build the convex hull of these points.
    faces : (4n - 4, 3) vertex indices of triangles, counter-clockwise seen from outside: the two caps
        fanned from vertex 0 and two triangles per side.
    """

    vertices: np.ndarray
    faces: np.ndarray

    @property
    def volume(self) -> float:
        """m^3, by the divergence theorem over the faces."""
        a, b, c = (self.vertices[self.faces[:, k]] for k in range(3))
        return float(np.einsum("ij,ij->i", a, np.cross(b, c)).sum() / 6.0)


def prism(outline, depth: float, inset_by: float = 0.0) -> Prism:
    """The prism of an (n, 2) convex counter-clockwise ``outline`` (m) and ``depth`` (m), centred on the
    engine's y = 0; ``inset_by`` (m) moves every face of it inwards (outline edges and both caps)."""
    flat = inset(outline, inset_by) if inset_by else np.asarray(outline, dtype=float)
    half = depth / 2 - inset_by
    n = len(flat)
    vertices = np.array([[x, s * half, y] for x, y in flat for s in (-1.0, 1.0)])
    # the scene's counter-clockwise turn is about the engine's -y: the outline's order faces y = -half
    front = [(0, 2 * k, 2 * (k + 1)) for k in range(1, n - 1)]
    back = [(1, 2 * (k + 1) + 1, 2 * k + 1) for k in range(1, n - 1)]
    sides = []
    for k in range(n):
        j = (k + 1) % n
        sides += [(2 * k, 2 * j + 1, 2 * j), (2 * k, 2 * k + 1, 2 * j + 1)]
    return Prism(vertices, np.array(front + back + sides))
