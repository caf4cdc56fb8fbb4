"""Compiled: the explicit integrator's stage, contact forces and central differences (docs/method.md 1.6).

Private module.  Central differences in velocity form: ``v(t + dt/2) = v(t - dt/2) + dt M^-1 F(t)``,
``x(t + dt) = x(t) + dt v(t + dt/2)``, with the dashpots acting on the lagging half-step velocities.  One part of
a step (:func:`explicit_part`, the driver's integrator stage under ``EXPLICIT``), in order:

1. per listed pair whose boxes touch (:func:`pair_forces`): the corner manifold (:mod:`._manifold`) or the overlap
   polygon (:mod:`._polygon`), then the contact law (:mod:`._contact_law`) (:func:`corner_pair`,
   :func:`overlap_pair`); then, touching or not, its connectors' forces (:func:`~._connectors.connector_forces`);
   each pair writes only its own rows, so the pairs may run in parallel;
2. per body the sum of its pairs' forces, in one order (:func:`gather_forces`); a contact past the penetration
   limit stops the run (:func:`deepest_pair`);
3. the ground's work (:func:`~._checks.ground_work`), then velocities and positions advance (:func:`move`).

While a block is overturned and the run goes on past overturns, a step is taken in ``substeps`` parts
(:func:`explicit_parts`); the driver places the base between its places at the step's ends before each part.  The
loops over pairs and bodies run over ``prange``, ``range`` here and numba's ``prange`` in the driver's threaded
build (:mod:`._driver`); their bodies read arrays, not the named tuples, which numba cannot lower in a parallel
loop.
"""

import math

import numba as nb

from ._broadphase import forget_pair
from ._checks import any_block_overturned, ground_work
from ._connectors import connector_forces
from ._contact_law import CORNER, dashpot, effective_mass, normal_force, tangential_force
from ._manifold import FACE_BITS, corner_manifold
from ._polygon import clip_convex, contact_frame, polygon_moments
from ._tally import tally_slip
from ._world import boxes_apart
from .model_arrays import (CONTACT_LIMIT, CRITICAL_ANGLE, DROP_LIMIT, INV_INERTIA, INV_MASS, LAW_ZETA_N, LAW_ZETA_T,
                           MASS, Y_START)
from .settings import CONTACT_LAW, DT, GRAVITY, STATUS_DEEP_OVERLAP, STATUS_OK, SUBSTEPS
from .state import (C_N, C_R, C_T, K_N, K_T, LAST_SUBSTEPS, LISTED, MU, NARROW, PAIR_I, PAIR_J, POINT_KEY, REFERENCE,
                    STEP)

#: the loops over pairs and bodies: ``range``, made numba's ``prange`` in the threaded build
prange = range


@nb.njit(cache=True, inline="always")
def _push(pair_force, p, end, body, fx, fy, px, py, pos, couple):
    """Add the force (fx, fy) acting at (px, py), and a couple, to the resultant on ``body``, the pair's
    first (``end`` 0) or second body, kept in the pair's row of ``pair_force``."""
    pair_force[p, 3 * end] += fx
    pair_force[p, 3 * end + 1] += fy
    pair_force[p, 3 * end + 2] += (px - pos[body, 0]) * fy - (py - pos[body, 1]) * fx + couple


@nb.njit(cache=True, inline="always")
def corner_pair(p, ids, constants, memory, spring_force, pair_slip, pos, vel, pair_force, wx, wy,
                wnx, wny, vstart, body, zeta_n, zeta_t, limit, dt, points, keys):
    """Corner-law forces of listed pair ``p``, into the pair's row of ``pair_force`` (resultant force
    and moment on its first body, then on its second).

    body : the model's rows per body (:mod:`.model_arrays`).  zeta_n, zeta_t : damping ratios of the points'
    dashpots (used where the pair has no explicit dashpot constants) against the pair's effective mass at each
    point.  limit : m, the deepest contact a stable run can have.  points (n, 2, 3), keys (n, 2) : scratch, the
    pair's row ``p``.  Returns ``(points in contact, depth past the limit or 0)``.
    """
    i = ids[p, PAIR_I]
    j = ids[p, PAIR_J]
    n_i = vstart[i + 1] - vstart[i]
    n_j = vstart[j + 1] - vstart[j]
    count, nx, ny, code = corner_manifold(wx, wy, wnx, wny, vstart[i], n_i, pos[i, 0], pos[i, 1], vstart[j], n_j,
                                          pos[j, 0], pos[j, 1], memory[p, REFERENCE], points, keys, p, 0.0)
    memory[p, REFERENCE] = code
    old_key0 = memory[p, POINT_KEY]
    old_key1 = memory[p, POINT_KEY + 1]
    old_force0 = spring_force[p, 0]
    old_force1 = spring_force[p, 1]
    memory[p, POINT_KEY] = -1
    memory[p, POINT_KEY + 1] = -1
    if count == 0:
        return 0, 0.0
    ref, inc = (j, i) if (code >> FACE_BITS) == 1 else (i, j)
    ref_end = 1 if ref == j else 0
    tx = -ny
    ty = nx
    slipped = 0.0
    for q in range(count):
        px = points[p, q, 0]
        py = points[p, q, 1]
        depth = points[p, q, 2]
        if depth > limit:
            return count, depth
        rix = px - pos[inc, 0]
        riy = py - pos[inc, 1]
        rrx = px - pos[ref, 0]
        rry = py - pos[ref, 1]
        # velocity of the incident body's material point relative to the reference body's, at the point
        rvx = (vel[inc, 0] - vel[inc, 2] * riy) - (vel[ref, 0] - vel[ref, 2] * rry)
        rvy = (vel[inc, 1] + vel[inc, 2] * rix) - (vel[ref, 1] + vel[ref, 2] * rrx)
        m_n = effective_mass(nx, ny, rix, riy, body[INV_MASS, inc], body[INV_INERTIA, inc], rrx, rry,
                             body[INV_MASS, ref], body[INV_INERTIA, ref])
        c_n = dashpot(constants[p, C_N], zeta_n, constants[p, K_N], m_n)
        fn = normal_force(depth, -(rvx * nx + rvy * ny), constants[p, K_N], c_n)
        v_t = rvx * tx + rvy * ty
        key = keys[p, q]
        elastic = old_force0 if old_key0 == key else (old_force1 if old_key1 == key else 0.0)
        m_t = effective_mass(tx, ty, rix, riy, body[INV_MASS, inc], body[INV_INERTIA, inc], rrx, rry,
                             body[INV_MASS, ref], body[INV_INERTIA, ref])
        c_t = dashpot(constants[p, C_T], zeta_t, constants[p, K_T], m_t)
        ft, elastic, slip = tangential_force(elastic, v_t, dt, constants[p, K_T], c_t, constants[p, MU] * fn)
        if slip:
            slipped = max(slipped, abs(v_t) * dt)
        memory[p, POINT_KEY + q] = key
        spring_force[p, q] = elastic
        fx = fn * nx + ft * tx
        fy = fn * ny + ft * ty
        _push(pair_force, p, 1 - ref_end, inc, fx, fy, px, py, pos, 0.0)
        _push(pair_force, p, ref_end, ref, -fx, -fy, px, py, pos, 0.0)
    tally_slip(p, ids, pair_slip, slipped)
    return count, 0.0


@nb.njit(cache=True, inline="always")
def overlap_pair(p, ids, constants, spring_force, pair_slip, pos, vel, pair_force, wx, wy, vstart,
                 body, dt, ox, oy, clip_work):
    """Overlap-area-law forces of listed pair ``p``, into the pair's row of ``pair_force``.

    body : the model's rows per body, CONTACT_LIMIT the largest overlap of each body a stable run can have (m^2;
    the pair's is the smaller).  ox, oy, clip_work : clipping scratch.  Returns ``(1 if the pair overlaps else 0,
    overlap past the limit or 0)``.
    """
    i = ids[p, PAIR_I]
    j = ids[p, PAIR_J]
    m = clip_convex(wx, wy, vstart[i], vstart[i + 1] - vstart[i], wx, wy, vstart[j], vstart[j + 1] - vstart[j],
                    ox, oy, clip_work)
    a = 0.0
    cx = cy = sxx = syy = sxy = 0.0
    if m >= 3:
        a, cx, cy, sxx, syy, sxy = polygon_moments(ox, oy, m)
    if a <= 0.0:
        spring_force[p, 0] = 0.0
        return 0, 0.0
    if a > min(body[CONTACT_LIMIT, i], body[CONTACT_LIMIT, j]):
        return 1, a
    tx, ty, nx, ny = contact_frame(sxx, syy, sxy, cx, cy, pos[i, 0], pos[i, 1])
    rvx = (vel[j, 0] - vel[j, 2] * (cy - pos[j, 1])) - (vel[i, 0] - vel[i, 2] * (cy - pos[i, 1]))
    rvy = (vel[j, 1] + vel[j, 2] * (cx - pos[j, 0])) - (vel[i, 1] + vel[i, 2] * (cx - pos[i, 0]))
    fn = normal_force(a, -(rvx * nx + rvy * ny), constants[p, K_N], constants[p, C_N])
    v_t = rvx * tx + rvy * ty
    ft, elastic, slip = tangential_force(spring_force[p, 0], v_t, dt, constants[p, K_T], constants[p, C_T],
                                         constants[p, MU] * fn)
    spring_force[p, 0] = elastic
    if slip:
        tally_slip(p, ids, pair_slip, abs(v_t) * dt)
    couple = 0.0
    if fn > 0.0:  # the dashpot spread evenly along the contact length l resists relative rotation
        s_min = math.inf
        s_max = -math.inf
        for q in range(m):
            s = ox[q] * tx + oy[q] * ty
            s_min = min(s_min, s)
            s_max = max(s_max, s)
        length = s_max - s_min
        couple = -constants[p, C_R] * length * length / 12.0 * (vel[j, 2] - vel[i, 2])
    fx = fn * nx + ft * tx
    fy = fn * ny + ft * ty
    _push(pair_force, p, 1, j, fx, fy, cx, cy, pos, couple)
    _push(pair_force, p, 0, i, -fx, -fy, cx, cy, pos, -couple)
    return 1, 0.0


@nb.njit(cache=True, inline="always")
def pair_forces(p, corner, ids, constants, memory, spring_force, normal_impulse, tangential_impulse, pair_slip,
                pos, vel, pair_force, pair_touching, pair_excess, wx, wy, wnx, wny, vstart, body, law,
                dt, boxes, points, keys, ox, oy, clip_work):
    """Step 1, one listed pair ``p``: if its boxes touch, its contacts under the corner or the overlap-area law and
    their forces into its row of ``pair_force``, whether it touches into ``pair_touching[p]`` and its penetration
    past the limit into ``pair_excess[p]``; if not, it forgets its contact.  A pair writes only its own rows, so
    pairs may run in parallel.  body, law : the model's rows per body and its law's
    constants (:mod:`.model_arrays`); boxes : (4, nb) m, the bodies' boxes.  (At most 30 arguments: Python passes
    more as a tuple, which numba cannot inline.)"""
    i = ids[p, PAIR_I]
    j = ids[p, PAIR_J]
    for c in range(6):
        pair_force[p, c] = 0.0
    pair_touching[p] = 0
    pair_excess[p] = 0.0
    if boxes_apart(boxes, i, j, 0.0):
        forget_pair(p, memory, spring_force, normal_impulse, tangential_impulse)
        return
    if corner:
        touching, excess = corner_pair(p, ids, constants, memory, spring_force, pair_slip, pos, vel,
                                       pair_force, wx, wy, wnx, wny, vstart, body, law[LAW_ZETA_N], law[LAW_ZETA_T],
                                       min(body[CONTACT_LIMIT, i], body[CONTACT_LIMIT, j]), dt, points, keys)
    else:
        touching, excess = overlap_pair(p, ids, constants, spring_force, pair_slip, pos, vel,
                                        pair_force, wx, wy, vstart, body, dt, ox[p], oy[p], clip_work[p])
    pair_touching[p] = touching
    pair_excess[p] = excess


@nb.njit(cache=True, inline="always")
def gather_forces(b, start, entries, pair_force, force):
    """Step 2, one body ``b``: the sum of its pairs' resultants, in one order, into ``force[b]``."""
    fx = 0.0
    fy = 0.0
    m = 0.0
    for e in range(start[b], start[b + 1]):
        row = entries[e] >> 1
        end = entries[e] & 1
        fx += pair_force[row, 3 * end]
        fy += pair_force[row, 3 * end + 1]
        m += pair_force[row, 3 * end + 2]
    force[b, 0] = fx
    force[b, 1] = fy
    force[b, 2] = m


@nb.njit(cache=True, inline="always")
def deepest_pair(pair_touching, pair_excess, listed, counters):
    """Step 2: counts the pairs in contact (``counters[NARROW]``); returns the first pair penetrating past the
    limit, or -1."""
    for p in range(listed):
        if pair_touching[p] > 0:
            counters[NARROW] += 1
        if pair_excess[p] > 0.0:
            return p
    return -1


@nb.njit(cache=True, inline="always")
def move(pos, vel, force, inv_mass, inv_inertia, gx, gy, kick, dt):
    """Step 3: central-difference update of every free body under ``force`` and the load (gx, gy) per unit mass:
    the velocities gain the acceleration times ``kick`` (s), the mean of the steps before and after this instant
    (``dt`` itself while the step does not change), and the positions move by the new velocities times the
    step ``dt`` (s)."""
    for b in range(1, pos.shape[0]):
        vel[b, 0] += kick * (force[b, 0] * inv_mass[b] + gx)
        vel[b, 1] += kick * (force[b, 1] * inv_mass[b] + gy)
        vel[b, 2] += kick * force[b, 2] * inv_inertia[b]
        pos[b, 0] += dt * vel[b, 0]
        pos[b, 1] += dt * vel[b, 1]
        pos[b, 2] += dt * vel[b, 2]


@nb.njit(cache=True, inline="always")
def explicit_parts(model, settings, state):
    """The division of a step of ``dt`` (s): ``(parts, h, kick)``.  Past a critical angle a block may lie on a
    longer face, and fallen blocks pile up: while a block is overturned (:func:`~._checks.any_block_overturned`)
    the step is taken in ``settings`` SUBSTEPS parts of ``h`` (s), else in one; ``kick`` (s) spans half the step
    or part before (``counters[LAST_SUBSTEPS]``) and half of the first one taken now."""
    dt = settings.real[DT]
    substeps = settings.integer[SUBSTEPS]
    parts = 1
    if substeps > 1 and any_block_overturned(state.pos, model.body[CRITICAL_ANGLE], model.body[Y_START],
                                             model.body[DROP_LIMIT]):
        parts = substeps
    h = dt / parts
    last = state.counters[LAST_SUBSTEPS]
    kick = 0.5 * ((dt / last if last > 0 else dt) + h)
    return parts, h, kick


@nb.njit(cache=True, inline="always")  # a compiled call, passing the run's arrays, costs more than a block's step
def explicit_part(model, settings, state, scratch, part, h, kick, load_x, load_y):
    """The explicit integrator's stage: part ``part`` of a step, ``h`` (s) long, its first part's
    velocity update spanning ``kick`` (s) (:func:`explicit_parts`), under the ground's inertial load (load_x,
    load_y) m/s^2, by the steps of the module docstring.  Returns ``(status, i, j)``: STATUS_OK, or
    STATUS_DEEP_OVERLAP and the pair's bodies."""
    pos, vel, counters = state.pos, state.vel, state.counters
    if part > 0:  # the base at the ground's velocity of the half step after this one (lead 0.5)
        vel[0, 0] = scratch.window[4, 1]
        vel[0, 1] = scratch.window[5, 1]
    corner = settings.integer[CONTACT_LAW] == CORNER
    ids, constants, memory, spring_force = state.pair_ids, state.pair_constants, state.pair_memory, state.spring_force
    normal_impulse, tangential_impulse, pair_slip = state.normal_impulse, state.tangential_impulse, state.pair_slip
    pair_force, pair_touching, pair_excess = scratch.pair_force, scratch.pair_touching, scratch.pair_excess
    wx, wy, wnx, wny = scratch.world[0], scratch.world[1], scratch.world[2], scratch.world[3]
    vstart, body, law, boxes, force = model.vstart, model.body, model.law, scratch.boxes, scratch.force
    points, keys, ox, oy = scratch.points, scratch.point_keys, scratch.clip_x, scratch.clip_y
    clip_work, start, entries = scratch.clip_work, scratch.pair_start, scratch.pair_entries
    connector_law, connector_bodies = model.connector_law, model.connector_bodies
    connector_start = model.connector_start
    connectors, step = state.connectors, counters[STEP]
    listed = counters[LISTED]
    for p in prange(listed):
        pair_forces(p, corner, ids, constants, memory, spring_force, normal_impulse, tangential_impulse, pair_slip,
                    pos, vel, pair_force, pair_touching, pair_excess, wx, wy, wnx, wny, vstart, body,
                    law, h, boxes, points, keys, ox, oy, clip_work)
        connector_forces(p, ids, pos, pair_force, connector_law, connector_bodies, connector_start, connectors, step)
    for b in prange(pos.shape[0]):
        gather_forces(b, start, entries, pair_force, force)
    deep = deepest_pair(pair_touching, pair_excess, listed, counters)
    if deep >= 0:
        return STATUS_DEEP_OVERLAP, ids[deep, PAIR_I], ids[deep, PAIR_J]
    ground_work(force, vel, body[MASS], load_x, load_y, h, state.ledger)
    move(pos, vel, force, body[INV_MASS], body[INV_INERTIA], load_x, load_y - settings.real[GRAVITY],
         kick if part == 0 else h, h)
    return STATUS_OK, 0, 0
