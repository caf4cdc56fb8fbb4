"""Polygon geometry in plain numpy: mass properties, validation and overlaps.

Vertices are ``(n, 2)`` arrays in metres.  Mass properties are exact for a
uniform polygon (shoelace formulas); the overlap functions call the same
compiled kernels as the time-stepping loop.
"""

from typing import NamedTuple

import numpy as np

from . import _broadphase, _polygon


class GeometryError(ValueError):
    """A polygon that cannot be a block (degenerate, non-convex, bad size)."""


class PolygonProperties(NamedTuple):
    area: float  # m^2
    centroid: np.ndarray  # (2,) m
    polar_moment: float  # integral of |r - centroid|^2 dA, m^4


class ContactGeometry(NamedTuple):
    area: float  # overlap area, m^2
    centroid: np.ndarray  # (2,) point of action C, m
    tangent: np.ndarray  # (2,) unit tangent t
    normal: np.ndarray  # (2,) unit normal n, from P into Q's side
    length: float  # extent of the overlap along t, m (area / length = mean penetration)


def polygon_properties(vertices) -> PolygonProperties:
    """Area, centroid and polar second moment of a counter-clockwise polygon.

    ``vertices``: ``(n, 2)``.  The rotational inertia of a block of density
    ``rho`` and depth ``d`` about its centroid is ``rho * d * polar_moment``.
    """
    v = np.asarray(vertices, dtype=float)
    a, cx, cy, sxx, syy, _ = _polygon.polygon_moments(v[:, 0].copy(), v[:, 1].copy(), len(v))
    return PolygonProperties(a, np.array([cx, cy]), sxx + syy)


def as_convex_ccw(vertices, name: str = "polygon") -> np.ndarray:
    """Validate a convex polygon and return it as a counter-clockwise ``(n, 2)`` array.

    Raises :class:`GeometryError` naming ``name`` for fewer than 3 vertices,
    non-finite coordinates, repeated vertices, zero area or a non-convex
    outline.  Clockwise input is reversed.
    """
    v = np.array(vertices, dtype=float)
    if v.ndim != 2 or v.shape[1] != 2 or len(v) < 3:
        raise GeometryError(f"{name}: needs at least 3 vertices as (x, y) pairs, got shape {v.shape}")
    if not np.all(np.isfinite(v)):
        raise GeometryError(f"{name}: vertices are not all finite")
    size = np.ptp(v, axis=0).max()
    edges = np.roll(v, -1, axis=0) - v
    if np.any(np.hypot(edges[:, 0], edges[:, 1]) <= 1e-12 * max(size, 1e-300)):
        raise GeometryError(f"{name}: repeated vertices (zero-length edge)")
    area = polygon_properties(v).area
    if abs(area) <= 1e-12 * size * size:
        raise GeometryError(f"{name}: degenerate polygon (zero area)")
    if area < 0:
        v = v[::-1].copy()
        edges = np.roll(v, -1, axis=0) - v
    turns = edges[:, 0] * np.roll(edges[:, 1], -1) - edges[:, 1] * np.roll(edges[:, 0], -1)
    if np.any(turns < -1e-12 * size * size):
        bad = int(np.argmin(turns) + 1) % len(v)
        raise GeometryError(f"{name}: polygon is not convex (reflex angle at vertex {bad})")
    return v


def rectangle(width: float, height: float, x0: float = 0.0, y0: float = 0.0) -> np.ndarray:
    """Counter-clockwise rectangle with lower-left corner ``(x0, y0)``."""
    return np.array([[x0, y0], [x0 + width, y0], [x0 + width, y0 + height], [x0, y0 + height]], float)


def transform(vertices, angle: float = 0.0, offset=(0.0, 0.0)) -> np.ndarray:
    """Rotate ``vertices`` by ``angle`` (rad, counter-clockwise) about the origin, then shift."""
    c, s = np.cos(angle), np.sin(angle)
    v = np.asarray(vertices, dtype=float)
    return np.column_stack([c * v[:, 0] - s * v[:, 1], s * v[:, 0] + c * v[:, 1]]) + np.asarray(offset)


def overlapping_boxes(low, high, margin: float) -> np.ndarray:
    """Sorted int64 keys ``i * n + j`` (i < j) of the pairs among ``n`` axis-aligned boxes, ``low`` and
    ``high`` (n, 2) m, that overlap once each is grown by ``margin`` (m): the engine's broad phase
    (sort-and-sweep, :mod:`dem_core.engine._broadphase`)."""
    boxes = np.ascontiguousarray(np.array([low[:, 0], high[:, 0], low[:, 1], high[:, 1]], float))
    n = boxes.shape[1]
    keys = np.empty(4 * n + 4, np.int64)
    while (count := _broadphase.candidate_keys(boxes, float(margin), np.arange(n, dtype=np.int64), keys)) < 0:
        keys = np.empty(2 * len(keys), np.int64)
    return keys[:count].copy()


def _split(p):
    p = np.ascontiguousarray(p, dtype=float)
    return p[:, 0].copy(), p[:, 1].copy(), len(p)


def overlap_area(p, q) -> float:
    """Area of the intersection of two convex counter-clockwise polygons (m^2)."""
    return _polygon.overlap(*_split(p), *_split(q))[0]


def contact_geometry(p, q) -> ContactGeometry | None:
    """Overlap area, point of action and contact frame of convex polygons ``p`` and ``q``.

    ``None`` when they do not overlap.  The normal points from ``p`` towards
    ``q`` (away from ``p``'s centroid), docs/method.md 1.4.
    """
    px, py, n_p = _split(p)
    qx, qy, n_q = _split(q)
    cap = n_p + n_q + 2
    out = [np.empty(cap), np.empty(cap)]
    m = _polygon.clip_convex(px, py, 0, n_p, qx, qy, 0, n_q, out[0], out[1], np.empty((2, 2, cap)))
    a, cx, cy, sxx, syy, sxy = _polygon.polygon_moments(out[0], out[1], m)
    if a <= 0.0:
        return None
    c_p = polygon_properties(p).centroid
    tx, ty, nx, ny = _polygon.contact_frame(sxx, syy, sxy, cx, cy, c_p[0], c_p[1])
    along = out[0][:m] * tx + out[1][:m] * ty
    return ContactGeometry(a, np.array([cx, cy]), np.array([tx, ty]), np.array([nx, ny]), float(np.ptp(along)))
