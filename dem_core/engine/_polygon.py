"""Compiled polygon kernels: clipping, overlap area, centroid and contact frame.

Private module: every function takes plain arrays and scalars so that the
time-stepping kernel (``_kernels``) can call them without Python objects.
Polygons are convex, counter-clockwise, given as separate x and y arrays of
length ``n`` (only the first ``n`` entries are read).

The contact frame follows docs/method.md 1.4: the tangent ``t`` is the
major principal axis of the overlap polygon (the direction of its largest
second moment of area).  For a thin sliver this is its long side; unlike
"longest side of a triangle / longest diagonal of a quadrilateral" it is a
continuous function of the vertices, so it does not jump when the overlap
gains or loses a vertex.
"""

import math

import numpy as np

from ._build import kernel

# Sutherland-Hodgman can produce at most n_subject + n_clip vertices.
MAX_OVERLAP_VERTICES = 64


@kernel()
def clip_convex(px, py, p0, n_p, qx, qy, q0, n_q, outx, outy, scratch):
    """Clip convex polygon P by convex polygon Q (both counter-clockwise).

    P is ``px[p0:p0 + n_p]``, ``py[...]``; Q likewise from ``q0``.  Writes the
    intersection polygon into ``outx``, ``outy`` and returns its vertex count
    (0 when they do not overlap).  ``scratch`` is a ``(2, 2, cap)`` work array;
    ``cap`` and the length of ``outx``, ``outy`` must be at least ``n_p + n_q``.
    Passes alternate between ``scratch[0]`` and ``scratch[1]`` by index (no
    array variables are reassigned, which would cost reference counting), and
    an edge of Q that leaves every vertex inside is skipped.
    """
    for k in range(n_p):
        scratch[0, 0, k] = px[p0 + k]
        scratch[0, 1, k] = py[p0 + k]
    cur = 0
    n_in = n_p
    for e in range(n_q):
        ax = qx[q0 + e]
        ay = qy[q0 + e]
        e1 = q0 + e + 1 if e + 1 < n_q else q0  # no modulo: integer division is slow
        ex = qx[e1] - ax
        ey = qy[e1] - ay
        all_inside = True
        for k in range(n_in):
            if ex * (scratch[cur, 1, k] - ay) - ey * (scratch[cur, 0, k] - ax) < 0.0:
                all_inside = False
                break
        if all_inside:
            continue
        nxt = 1 - cur
        n_out = 0
        sx = scratch[cur, 0, n_in - 1]
        sy = scratch[cur, 1, n_in - 1]
        s_side = ex * (sy - ay) - ey * (sx - ax)
        for k in range(n_in):
            cx = scratch[cur, 0, k]
            cy = scratch[cur, 1, k]
            c_side = ex * (cy - ay) - ey * (cx - ax)
            if c_side >= 0.0:
                if s_side < 0.0:
                    f = s_side / (s_side - c_side)
                    scratch[nxt, 0, n_out] = sx + f * (cx - sx)
                    scratch[nxt, 1, n_out] = sy + f * (cy - sy)
                    n_out += 1
                scratch[nxt, 0, n_out] = cx
                scratch[nxt, 1, n_out] = cy
                n_out += 1
            elif s_side >= 0.0:
                f = s_side / (s_side - c_side)
                scratch[nxt, 0, n_out] = sx + f * (cx - sx)
                scratch[nxt, 1, n_out] = sy + f * (cy - sy)
                n_out += 1
            sx = cx
            sy = cy
            s_side = c_side
        if n_out == 0:
            return 0
        cur = nxt
        n_in = n_out
    for k in range(n_in):
        outx[k] = scratch[cur, 0, k]
        outy[k] = scratch[cur, 1, k]
    return n_in


@kernel()
def polygon_moments(x, y, n):
    """Area, centroid and central second moments of a polygon.

    Returns ``(A, cx, cy, sxx, syy, sxy)`` with ``A`` the signed area (positive
    for counter-clockwise), ``(cx, cy)`` the centroid and
    ``sxx = integral (x - cx)^2 dA`` etc.  Coordinates are taken relative to
    the first vertex so that slivers far from the origin keep their digits.
    """
    if n < 3:
        return 0.0, 0.0, 0.0, 0.0, 0.0, 0.0
    x0 = x[0]
    y0 = y[0]
    a2 = 0.0
    mx = 0.0
    my = 0.0
    ixx = 0.0
    iyy = 0.0
    ixy = 0.0
    for k in range(n):
        k1 = k + 1 if k + 1 < n else 0
        xi = x[k] - x0
        yi = y[k] - y0
        xj = x[k1] - x0
        yj = y[k1] - y0
        cr = xi * yj - xj * yi
        a2 += cr
        mx += (xi + xj) * cr
        my += (yi + yj) * cr
        ixx += (xi * xi + xi * xj + xj * xj) * cr
        iyy += (yi * yi + yi * yj + yj * yj) * cr
        ixy += (xi * yj + 2.0 * xi * yi + 2.0 * xj * yj + xj * yi) * cr
    area = 0.5 * a2
    if area == 0.0:
        return 0.0, x0, y0, 0.0, 0.0, 0.0
    cxl = mx / (3.0 * a2)
    cyl = my / (3.0 * a2)
    sxx = ixx / 12.0 - area * cxl * cxl
    syy = iyy / 12.0 - area * cyl * cyl
    sxy = ixy / 24.0 - area * cxl * cyl
    return area, cxl + x0, cyl + y0, sxx, syy, sxy


@kernel()
def contact_frame(sxx, syy, sxy, cx, cy, ax_c, ay_c):
    """Tangent and normal of a contact from the overlap's second moments.

    ``t`` is the major principal axis of the overlap; ``n = perp(t)`` is
    oriented away from body A, i.e. ``n . (C - c_A) >= 0`` where ``C`` is the
    overlap centroid and ``c_A`` body A's centre of mass.  Returns
    ``(tx, ty, nx, ny)``.
    """
    # major eigenvector of [[sxx, sxy], [sxy, syy]] from the half-angle formulas
    d = sxx - syy
    r = math.sqrt(d * d + 4.0 * sxy * sxy)
    if r == 0.0:
        tx, ty = 1.0, 0.0
    else:
        c2 = d / r
        tx = math.sqrt(max(0.5 * (1.0 + c2), 0.0))
        ty = math.copysign(math.sqrt(max(0.5 * (1.0 - c2), 0.0)), sxy)
    nx = -ty
    ny = tx
    if nx * (cx - ax_c) + ny * (cy - ay_c) < 0.0:
        nx = -nx
        ny = -ny
    return ny, -nx, nx, ny


@kernel()
def overlap(px, py, n_p, qx, qy, n_q):
    """Overlap of two convex CCW polygons, allocating its own scratch space.

    Returns ``(A, cx, cy, sxx, syy, sxy)`` of the intersection (all zero when
    they do not overlap).  Convenience wrapper for tests and set-up code; the
    time-stepping kernel calls :func:`clip_convex` with preallocated buffers.
    """
    cap = n_p + n_q + 2
    outx = np.empty(cap)
    outy = np.empty(cap)
    m = clip_convex(px, py, 0, n_p, qx, qy, 0, n_q, outx, outy, np.empty((2, 2, cap)))
    if m < 3:
        return 0.0, 0.0, 0.0, 0.0, 0.0, 0.0
    a, cx, cy, sxx, syy, sxy = polygon_moments(outx, outy, m)
    if a <= 0.0:  # edges that only touch leave a round-off sliver of either sign
        return 0.0, 0.0, 0.0, 0.0, 0.0, 0.0
    return a, cx, cy, sxx, syy, sxy
