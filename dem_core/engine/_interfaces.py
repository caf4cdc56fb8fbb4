"""Compiled: the interfaces' slip, the tangential travel of one block over the other, measured on their motion.

Private module: :func:`follow_interfaces`, the driver's stage after the base is placed, which also measures any
other engine's states (:class:`adapters._driver._Joints`) and any history (:func:`~.model.interface_history`).
An interface is a pair of bodies touching at the start, ``a`` (the first of the pair) and ``b``; its row of
:data:`~.model_arrays.ModelArrays` ``interface_geometry`` holds the point where they touch in each body's own
frame, the interface's tangent in ``a``'s frame (``t = (n_y, -n_x)``, ``n`` from ``a`` into ``b``), half the
interface's width ``w`` and the bodies' starting relative turn.

The offset of the interface is where ``b``'s point is along ``t`` in ``a``'s frame, less the part that rocking
without slip gives it: turned by ``phi`` relative to ``a`` about an end of the interface, ``b``'s point moves
``-sign(phi) w (1 - cos phi)`` along ``t``.  So

    s = (R(-theta_a) (x_b + R(theta_b) A_b - x_a) - A_a) . t + sign(phi) w (1 - cos phi),

0 at the start, constant while the blocks rock on each other or fly without sliding, and the slip is the total
variation of ``s``: its travel, back and forth, airborne phases included.
"""

import numba as nb

from ._angles import cosine, sine

#: columns of an interface's geometry row: the touching point in the first body's frame and in the second's (m),
#: the tangent in the first body's frame, half the interface's width (m) and the second body's turn relative to the
#: first at the start (rad)
A_X, A_Y, B_X, B_Y, T_X, T_Y, HALF_WIDTH, TURN0 = range(8)
N_GEOMETRY = 8


@nb.njit(cache=True, inline="always")
def interface_offset(pos_a, pos_b, row):
    """The offset ``s`` (m) of the module docstring of an interface with geometry ``row``, its first body at
    ``pos_a`` and its second at ``pos_b`` (x, y, theta: m, m, rad)."""
    ca = cosine(pos_a[2])
    sa = sine(pos_a[2])
    cb = cosine(pos_b[2])
    sb = sine(pos_b[2])
    wx = pos_b[0] + cb * row[B_X] - sb * row[B_Y] - pos_a[0]
    wy = pos_b[1] + sb * row[B_X] + cb * row[B_Y] - pos_a[1]
    along = (ca * wx + sa * wy - row[A_X]) * row[T_X] + (-sa * wx + ca * wy - row[A_Y]) * row[T_Y]
    phi = pos_b[2] - pos_a[2] - row[TURN0]
    rocking = 2.0 * row[HALF_WIDTH] * sine(0.5 * phi) ** 2  # w (1 - cos phi), without cancellation
    return along + (rocking if phi > 0.0 else -rocking)


@nb.njit(cache=True, inline="always")
def follow_interfaces(pos, keys, geometry, offset, travel):
    """The driver's stage: each interface's offset at the bodies' present positions ``pos`` (nb, 3), its change
    since the last into ``travel`` (n_if,) m and the offset kept in ``offset`` (n_if,) m.  keys (n_if,) int64
    ``a * nb + b`` of the interfaces, geometry (n_if, N_GEOMETRY)."""
    nb_ = pos.shape[0]
    for k in range(keys.shape[0]):
        s = interface_offset(pos[keys[k] // nb_], pos[keys[k] % nb_], geometry[k])
        travel[k] += abs(s - offset[k])
        offset[k] = s
