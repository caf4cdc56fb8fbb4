"""Compiled polygon kernels: clipping, overlap area, centroid and contact frame.

Private module: every function takes plain arrays and scalars so that the
time-stepping kernel (``_kernels``) can call them without Python objects.
Polygons are convex, counter-clockwise, given as separate x and y arrays of
length ``n`` (only the first ``n`` entries are read).

The contact frame follows FORMULATION section 1: the tangent ``t`` is the
major principal axis of the overlap polygon (the direction of its largest
second moment of area).  For a thin sliver this is its long side; unlike
"longest side of a triangle / longest diagonal of a quadrilateral" it is a
continuous function of the vertices, so it does not jump when the overlap
gains or loses a vertex.
"""

import math

import numba as nb
import numpy as np

# Sutherland-Hodgman can produce at most n_subject + n_clip vertices.
MAX_OVERLAP_VERTICES = 64


@nb.njit(cache=True)
def clip_convex(px, py, n_p, qx, qy, n_q, outx, outy, bufx, bufy):
    """Clip convex polygon P by convex polygon Q (both counter-clockwise).

    Writes the intersection polygon into ``outx``, ``outy`` and returns its
    vertex count (0 when they do not overlap).  ``bufx``, ``bufy`` are scratch
    arrays of the same capacity, at least ``n_p + n_q``.
    """
    n_out = n_p
    for k in range(n_p):
        outx[k] = px[k]
        outy[k] = py[k]
    for e in range(n_q):
        if n_out == 0:
            return 0
        ax = qx[e]
        ay = qy[e]
        bx = qx[(e + 1) % n_q]
        by = qy[(e + 1) % n_q]
        ex = bx - ax
        ey = by - ay
        n_in = n_out
        for k in range(n_in):
            bufx[k] = outx[k]
            bufy[k] = outy[k]
        n_out = 0
        sx = bufx[n_in - 1]
        sy = bufy[n_in - 1]
        s_side = ex * (sy - ay) - ey * (sx - ax)
        for k in range(n_in):
            cx = bufx[k]
            cy = bufy[k]
            c_side = ex * (cy - ay) - ey * (cx - ax)
            if c_side >= 0.0:
                if s_side < 0.0:
                    f = s_side / (s_side - c_side)
                    outx[n_out] = sx + f * (cx - sx)
                    outy[n_out] = sy + f * (cy - sy)
                    n_out += 1
                outx[n_out] = cx
                outy[n_out] = cy
                n_out += 1
            elif s_side >= 0.0:
                f = s_side / (s_side - c_side)
                outx[n_out] = sx + f * (cx - sx)
                outy[n_out] = sy + f * (cy - sy)
                n_out += 1
            sx = cx
            sy = cy
            s_side = c_side
    return n_out


@nb.njit(cache=True)
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
        xi = x[k] - x0
        yi = y[k] - y0
        xj = x[(k + 1) % n] - x0
        yj = y[(k + 1) % n] - y0
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


@nb.njit(cache=True)
def contact_frame(sxx, syy, sxy, cx, cy, ax_c, ay_c):
    """Tangent and normal of a contact from the overlap's second moments.

    ``t`` is the major principal axis of the overlap; ``n = perp(t)`` is
    oriented away from body A, i.e. ``n . (C - c_A) >= 0`` where ``C`` is the
    overlap centroid and ``c_A`` body A's centre of mass.  Returns
    ``(tx, ty, nx, ny)``.
    """
    phi = 0.5 * math.atan2(2.0 * sxy, sxx - syy)
    tx = math.cos(phi)
    ty = math.sin(phi)
    nx = -ty
    ny = tx
    if nx * (cx - ax_c) + ny * (cy - ay_c) < 0.0:
        nx = -nx
        ny = -ny
    return ny, -nx, nx, ny


@nb.njit(cache=True)
def overlap(px, py, n_p, qx, qy, n_q):
    """Overlap of two convex CCW polygons, allocating its own scratch space.

    Returns ``(A, cx, cy, sxx, syy, sxy)`` of the intersection (all zero when
    they do not overlap).  Convenience wrapper for tests and set-up code; the
    time-stepping kernel calls :func:`clip_convex` with preallocated buffers.
    """
    cap = n_p + n_q + 2
    outx = np.empty(cap)
    outy = np.empty(cap)
    bufx = np.empty(cap)
    bufy = np.empty(cap)
    m = clip_convex(px, py, n_p, qx, qy, n_q, outx, outy, bufx, bufy)
    if m < 3:
        return 0.0, 0.0, 0.0, 0.0, 0.0, 0.0
    return polygon_moments(outx, outy, m)
