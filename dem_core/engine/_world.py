"""Compiled: every body's vertices, edge normals and bounding box in the world at its present pose.

Private module, the driver's geometry stage (:mod:`._driver`): the narrow phase reads the world vertices and
normals, the broad phase the boxes.
"""

import math

import numba as nb

from ._angles import cosine, sine


@nb.njit(cache=True, inline="always")
def world_geometry(pos, local_x, local_y, normal_x, normal_y, vstart, wx, wy, wnx, wny):
    """World vertices (m) and edge normals of every body at ``pos`` (nb, 3), from its own frame's (nv,)."""
    for b in range(pos.shape[0]):
        c = cosine(pos[b, 2])
        s = sine(pos[b, 2])
        for k in range(vstart[b], vstart[b + 1]):
            wx[k] = pos[b, 0] + c * local_x[k] - s * local_y[k]
            wy[k] = pos[b, 1] + s * local_x[k] + c * local_y[k]
            wnx[k] = c * normal_x[k] - s * normal_y[k]
            wny[k] = s * normal_x[k] + c * normal_y[k]


@nb.njit(cache=True, inline="always")
def bounding_boxes(wx, wy, vstart, boxes):
    """Axis-aligned boxes (m) of every body from its world vertices into ``boxes`` (4, nb), rows lowest x, highest
    x, lowest y, highest y."""
    for b in range(vstart.shape[0] - 1):
        x0 = math.inf
        x1 = -math.inf
        y0 = math.inf
        y1 = -math.inf
        for k in range(vstart[b], vstart[b + 1]):
            x0 = min(x0, wx[k])
            x1 = max(x1, wx[k])
            y0 = min(y0, wy[k])
            y1 = max(y1, wy[k])
        boxes[0, b] = x0
        boxes[1, b] = x1
        boxes[2, b] = y0
        boxes[3, b] = y1


@nb.njit(cache=True, inline="always")
def boxes_apart(boxes, i, j, reach):
    """Whether the boxes of bodies ``i`` and ``j`` (:func:`bounding_boxes`) are more than ``reach`` (m) apart along
    x or along y: the one test of every stage that asks whether two bodies can touch."""
    return (boxes[0, j] > boxes[1, i] + reach or boxes[0, i] > boxes[1, j] + reach
            or boxes[2, j] > boxes[3, i] + reach or boxes[2, i] > boxes[3, j] + reach)
