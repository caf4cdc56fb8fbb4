"""Compiled checks on a state: overturning of blocks and columns, and mechanical energy.

Private module, shared by the stepping kernel (every step) and the other engines' driver (every
output, :mod:`adapters._driver`), so that every engine counts an overturn by the same rule
(docs/method.md section 3): a block overturns when it passes its critical angle or its centre of
mass falls half its smaller extent; a column (a stack, :mod:`dem_core.engine.stacks`) when the
centre of mass of its blocks passes an end of its bottom block's base.
"""

import math

import numba as nb
import numpy as np


@nb.njit(cache=True, inline="always")
def block_overturned(pos, b, critical_angle, y_start, drop_limit):
    """Whether body ``b`` at ``pos`` (nb, 3) is past its critical angle or its centre of mass has fallen more than
    ``drop_limit[b]`` below ``y_start[b]``."""
    return abs(pos[b, 2]) > critical_angle[b] or y_start[b] - pos[b, 1] > drop_limit[b]


@nb.njit(cache=True, inline="always")
def any_block_overturned(pos, critical_angle, y_start, drop_limit):
    """Whether some free body at ``pos`` (nb, 3; row 0 the base) is overturned by :func:`block_overturned` now."""
    for b in range(1, pos.shape[0]):
        if block_overturned(pos, b, critical_angle, y_start, drop_limit):
            return True
    return False


@nb.njit(cache=True, inline="always")
def mark_overturns(pos, critical_angle, y_start, drop_limit, mass, stack_id, bottom, stack_mass, foot,
                   overturn_step, stack_step, moment, step):
    """Record in ``overturn_step`` (nb,) and ``stack_step`` (ns,) the bodies and stacks that have
    overturned by ``pos`` (nb, 3; row 0 the base) and were not marked yet, with ``step``.

    critical_angle, y_start, drop_limit, mass : the model's :class:`~dem_core.engine.model.Bodies`
    fields; stack_id, bottom, stack_mass, foot : its :class:`~dem_core.engine.model.Stacks`;
    moment : (ns,) scratch.  Returns the first body found overturning now (a stack reports its bottom
    body), or -1.  One pass over the bodies and one over the stacks.
    """
    first = -1
    moment[:] = 0.0
    for b in range(1, pos.shape[0]):
        k = stack_id[b]
        if k >= 0:
            moment[k] += pos[b, 0] * mass[b]
        if overturn_step[b] >= 0:
            continue
        if block_overturned(pos, b, critical_angle, y_start, drop_limit):
            overturn_step[b] = step
            if first < 0:
                first = b
    tipped = False
    for k in range(bottom.shape[0]):
        if stack_step[k] >= 0:
            continue
        com = moment[k] / stack_mass[k]
        f = bottom[k]
        c = math.cos(pos[f, 2])
        s = math.sin(pos[f, 2])
        xa = pos[f, 0] + c * foot[k, 0, 0] - s * foot[k, 0, 1]
        xb = pos[f, 0] + c * foot[k, 1, 0] - s * foot[k, 1, 1]
        if com < min(xa, xb) or com > max(xa, xb):
            stack_step[k] = step
            tipped = True
            if first < 0:
                first = f
    if tipped:  # rare: mark the bodies of the stacks that tipped now
        for b in range(1, pos.shape[0]):
            k = stack_id[b]
            if k >= 0 and stack_step[k] == step and overturn_step[b] < 0:
                overturn_step[b] = step
    return first


@nb.njit(cache=True, inline="always")
def mechanical_energy(pos, vel, mass, inv_inertia, gravity):
    """Kinetic plus gravitational energy of the free bodies (J), with velocities ``vel`` (nb, 3)."""
    e = 0.0
    for b in range(1, pos.shape[0]):
        m = mass[b]
        e += 0.5 * m * (vel[b, 0] ** 2 + vel[b, 1] ** 2) + 0.5 * vel[b, 2] ** 2 / inv_inertia[b] + m * gravity * pos[b, 1]
    return e


@nb.njit(cache=True)
def first_overturns(states, bodies, stacks):
    """First index into ``states`` (n, nb, 3; row 0 of each state the base) at which each body
    overturned and each stack tipped: ``(overturn (nb,), stack (ns,))`` int64, -1 if never."""
    overturn = np.full(states.shape[1], -1, np.int64)
    stack = np.full(stacks.bottom.shape[0], -1, np.int64)
    moment = np.empty(stacks.bottom.shape[0])
    for k in range(states.shape[0]):
        mark_overturns(states[k], bodies.critical_angle, bodies.y_start, bodies.drop_limit, bodies.mass,
                       stacks.stack_id, stacks.bottom, stacks.mass, stacks.foot, overturn, stack, moment, k)
    return overturn, stack
