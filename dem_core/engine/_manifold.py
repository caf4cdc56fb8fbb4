"""Compiled contact manifold of two convex polygons for the corner law (docs/method.md 1.3).

Private module.  Polygons are counter-clockwise, given as slices of world vertex arrays
``wx[start:start + n]``, ``wy[...]`` with the outward unit normal of each edge (edge ``k`` runs from
vertex ``k`` to ``k + 1``) in ``wnx``, ``wny``.

The manifold follows the separating-axis and face-clipping construction of rigid-body engines
(Box2D's ``b2CollidePolygons``): the reference face is the face of least penetration over both
polygons, the incident face the other polygon's face most opposed to it; the incident face is
clipped to the reference face's side lines, and the clipped points below the reference face are the
contact points (at most two).  Each point carries its depth, and a feature key naming the reference
face and the incident vertex (or the incident face and the side line that clipped it), under which
its tangential history is kept from step to step.
"""

import math

import numba as nb

from ._build import kernel

#: bits of a reference code and of a point code within a feature key
FACE_BITS = 20
POINT_BITS = 23
#: the other polygon's face must be better than last step's reference by this fraction of the
#: penetration before the reference changes sides (flush faces tie to round-off and must not flip)
REFERENCE_HYSTERESIS = 0.1


@nb.njit(cache=True, inline="always")
def face_separation(ax, ay, anx, any_, a0, na, bx, by, b0, nb_, bcx, bcy, first):
    """Largest, over the faces of A, of the smallest signed distance of B's vertices from the face's
    line (m; negative: B's deepest vertex is inside by that much), and that face (index within A).

    (bcx, bcy) : a point inside B (its centre of mass).  Since B's deepest vertex along a face normal
    is no shallower than any point inside B, ``n . (c_B - a)`` bounds a face's separation from above,
    and a face whose bound is below the best so far is skipped without visiting B's vertices.
    first : the face to try first (last step's reference, if on A), so that the others prune early.
    """
    best = -math.inf
    face = -1
    for step in range(na):
        k = first + step
        if k >= na:
            k -= na
        nx = anx[a0 + k]
        ny = any_[a0 + k]
        px = ax[a0 + k]
        py = ay[a0 + k]
        if nx * (bcx - px) + ny * (bcy - py) <= best:
            continue
        lowest = math.inf
        for m in range(nb_):
            lowest = min(lowest, nx * (bx[b0 + m] - px) + ny * (by[b0 + m] - py))
        if lowest > best:
            best = lowest
            face = k
    return best, face


@kernel()
def reference_code(side, face):
    """Code of a reference face: ``side`` 0 for polygon A's face, 1 for B's."""
    return (side << FACE_BITS) | face


@nb.njit(cache=True, inline="always")
def edge(wx, wy, start, count, k):
    """Edge ``k`` of the polygon of ``count`` world vertices from ``start``: ``(k's successor, x1, y1, x2, y2)``
    of its first and second vertex (counter-clockwise)."""
    following = k + 1 if k + 1 < count else 0
    return following, wx[start + k], wy[start + k], wx[start + following], wy[start + following]


@nb.njit(cache=True, inline="always")
def corner_manifold(wx, wy, wnx, wny, a0, na, acx, acy, b0, nb_, bcx, bcy, previous, points, keys, row, margin):
    """Contact points of convex polygons A (``a0``, ``na``, centre of mass ``acx``, ``acy``) and B.

    previous : last step's reference code of this pair (-1 if none): its side is kept unless the
        other polygon's best face penetrates less by ``REFERENCE_HYSTERESIS`` of the penetration.
    points : (n, 2, 3) output, in ``points[row]`` per point x, y (m) where the force acts (midway
        between the incident point and the reference face) and depth (m, >= -margin).
    keys : (n, 2) int64 output, in ``keys[row]`` the points' feature keys.
    (Whole arrays and a row, not the row's view: a view taken in a parallel loop updates its parent's
    reference count atomically from every thread, which serialises them.)

    margin : m, how far apart polygons and points may be and still be returned (0: only overlapping ones;
        the Moreau-Jean integrator looks ahead by this much).
    Returns ``(count, nx, ny, code)``: the number of points (0 when the polygons are more than ``margin`` apart),
    the reference face's outward normal (pointing from the reference polygon into the incident one)
    and the reference code (side 0: A is the reference).
    """
    side_before = previous >> FACE_BITS if previous >= 0 else -1
    face_before = previous & ((1 << FACE_BITS) - 1) if previous >= 0 else 0
    sep_a, face_a = face_separation(wx, wy, wnx, wny, a0, na, wx, wy, b0, nb_, bcx, bcy,
                                    face_before if side_before == 0 else 0)
    if sep_a > margin:
        return 0, 0.0, 0.0, -1
    sep_b, face_b = face_separation(wx, wy, wnx, wny, b0, nb_, wx, wy, a0, na, acx, acy,
                                    face_before if side_before == 1 else 0)
    if sep_b > margin:
        return 0, 0.0, 0.0, -1
    hysteresis = REFERENCE_HYSTERESIS * abs(max(sep_a, sep_b))
    if side_before == 1:
        use_b = not sep_a > sep_b + hysteresis
    else:
        use_b = sep_b > sep_a + hysteresis
    if use_b:
        r0, nr, i0, ni, face, side = b0, nb_, a0, na, face_b, 1
    else:
        r0, nr, i0, ni, face, side = a0, na, b0, nb_, face_a, 0
    code = reference_code(side, face)
    nx = wnx[r0 + face]
    ny = wny[r0 + face]
    tx = -ny  # the face runs along t from its first vertex to its second (counter-clockwise)
    ty = nx
    _, v1x, v1y, v2x, v2y = edge(wx, wy, r0, nr, face)

    incident = 0
    most_opposed = math.inf
    for k in range(ni):
        d = wnx[i0 + k] * nx + wny[i0 + k] * ny
        if d < most_opposed:
            most_opposed = d
            incident = k
    next_incident, p0x, p0y, p1x, p1y = edge(wx, wy, i0, ni, incident)
    f0 = incident << 1  # point codes: vertex v -> 2 v; clipped by side line s of incident face e -> 2 (2 e + s) + 1
    f1 = next_incident << 1

    # side line 0 through v1 keeps t . (p - v1) >= 0; side line 1 through v2 keeps t . (v2 - p) >= 0
    for s in range(2):
        if s == 0:
            d0 = tx * (p0x - v1x) + ty * (p0y - v1y)
            d1 = tx * (p1x - v1x) + ty * (p1y - v1y)
        else:
            d0 = tx * (v2x - p0x) + ty * (v2y - p0y)
            d1 = tx * (v2x - p1x) + ty * (v2y - p1y)
        if d0 < 0.0 and d1 < 0.0:
            return 0, 0.0, 0.0, -1
        clipped = (((incident << 1) | s) << 1) | 1
        if d0 < 0.0:
            f = d0 / (d0 - d1)
            p0x += f * (p1x - p0x)
            p0y += f * (p1y - p0y)
            f0 = clipped
        elif d1 < 0.0:
            f = d1 / (d1 - d0)
            p1x += f * (p0x - p1x)
            p1y += f * (p0y - p1y)
            f1 = clipped

    count = 0
    for q in range(2):
        px = p0x if q == 0 else p1x
        py = p0y if q == 0 else p1y
        depth = -(nx * (px - v1x) + ny * (py - v1y))
        if depth >= -margin:
            points[row, count, 0] = px + 0.5 * depth * nx
            points[row, count, 1] = py + 0.5 * depth * ny
            points[row, count, 2] = depth
            keys[row, count] = (code << POINT_BITS) | (f0 if q == 0 else f1)
            count += 1
    return count, nx, ny, code
