"""Compiled time stepping: contacts, forces, central differences, checks, outputs.

Private module: :func:`advance` takes the model's named tuples, the state's arrays and the ground
motion of the steps to take, and is called by :mod:`dem_core.simulation` in chunks (so that a
progress bar can follow a long run and the ground input never has to exist for the whole run at
once).  Central differences in velocity form (docs/method.md 1.6):
``v(t + dt/2) = v(t - dt/2) + dt M^-1 F(t)``, ``x(t + dt) = x(t) + dt v(t + dt/2)``, with the
dashpots acting on the lagging half-step velocities.  Per step, in stages, each a function of its own:

1. the base is placed by the ground motion (:func:`place_base`); an output is written when one is due
   (:func:`output_due`, :func:`write_output`);
2. world vertices, edge normals and boxes of every body (:func:`world_geometry`,
   :func:`~dem_core.engine._broadphase.bounding_boxes`);
3. the broad phase lists candidate pairs again if a body has moved half a skin (:func:`needs_relist`,
   :mod:`._broadphase`);
4. per candidate pair whose boxes overlap (:func:`pair_forces`): the corner manifold (:mod:`._manifold`) or
   the overlap polygon (:mod:`._polygon`), then the contact law (:mod:`._contact_law`)
   (:func:`corner_pair`, :func:`overlap_pair`); then per body the sum of its pairs' forces
   (:func:`gather_forces`), and a contact past the penetration limit stops the run (:func:`deepest_pair`);
5. the ground's work (:func:`ground_work`), then velocities and positions advance (:func:`move`).  While a
   block is overturned and the run goes on past overturns, stages 2 to 5 run ``run.substeps`` times a step, on
   substeps (the base between its places at the step's ends, :func:`place_base_within`);
6. checks: non-finite state, a block off the base or flying off (:func:`check_bodies`), overturns
   (:mod:`._checks`), and every ``ENERGY_CHECK_INTERVAL`` steps the energy balance (:func:`energy_gained`).

The stages take arrays and scalars, not the named tuples: numba counts references to every array of
a tuple it passes, which would cost more than the contact itself, and a stage of plain arrays and
scalars compiles for numba's CPU and CUDA targets alike.
"""

import hashlib
import math
import types
from pathlib import Path

import numba as nb
import numpy as np

from ._broadphase import bounding_boxes, candidate_keys, relist
from ._checks import any_block_overturned, mark_overturns, mechanical_energy
from ._contact_law import CORNER, dashpot, effective_mass, normal_force, tangential_force
from ._manifold import FACE_BITS, corner_manifold
from ._polygon import clip_convex, contact_frame, polygon_moments
from .state import (C_N, C_R, C_T, K_N, K_T, LAST_SUBSTEPS, MU, NARROW, OUTPUTS, PAIR_I, PAIR_INTERFACE, PAIR_J,
                    POINT_FORCE, POINT_KEY, REBUILDS, REFERENCE, SLIP, STEP, SUBSTEPPED)

STATUS_OK = 0
STATUS_NONFINITE = 1
STATUS_DEEP_OVERLAP = 2
STATUS_RUNAWAY = 3
STATUS_ENERGY = 4
STATUS_OVERTURNED = 5
STATUS_FELL_OFF = 6
ENERGY_CHECK_INTERVAL = 16  # steps between energy balance checks


@nb.njit(cache=True, inline="always")
def world_geometry(pos, local_x, local_y, normal_x, normal_y, vstart, wx, wy, wnx, wny):
    """World vertices and edge normals of every body at ``pos``."""
    for b in range(pos.shape[0]):
        c = math.cos(pos[b, 2])
        s = math.sin(pos[b, 2])
        for k in range(vstart[b], vstart[b + 1]):
            wx[k] = pos[b, 0] + c * local_x[k] - s * local_y[k]
            wy[k] = pos[b, 1] + s * local_x[k] + c * local_y[k]
            wnx[k] = c * normal_x[k] - s * normal_y[k]
            wny[k] = s * normal_x[k] + c * normal_y[k]


@nb.njit(cache=True, inline="always")
def _push(pair_force, p, end, body, fx, fy, px, py, pos, couple):
    """Add the force (fx, fy) acting at (px, py), and a couple, to the resultant on ``body``, the pair's
    first (``end`` 0) or second body, kept in the pair's row of ``pair_force``."""
    pair_force[p, 3 * end] += fx
    pair_force[p, 3 * end + 1] += fy
    pair_force[p, 3 * end + 2] += (px - pos[body, 0]) * fy - (py - pos[body, 1]) * fx + couple


@nb.njit(cache=True, inline="always")
def _add_slip(p, ids, forces, interface_slip, amount):
    if amount > 0.0:
        k = ids[p, PAIR_INTERFACE]
        if k >= 0:
            interface_slip[k] += amount
        else:
            forces[p, SLIP] += amount


@nb.njit(cache=True, inline="always")
def corner_pair(p, ids, constants, memory, forces, interface_slip, pos, vel, pair_force, wx, wy, wnx, wny, vstart,
                inv_mass, inv_inertia, zeta_n, zeta_t, limit, dt, points, keys):
    """Corner-law forces of candidate pair ``p``, into the pair's row of ``pair_force`` (resultant force
    and moment on its first body, then on its second).

    zeta_n, zeta_t : damping ratios of the points' dashpots (used where the pair has no explicit
    dashpot constants) against the pair's effective mass at each point.  limit : m, the deepest
    contact a stable run can have.  points (n, 2, 3), keys (n, 2) : scratch, the pair's row ``p``.
    Returns ``(points in contact, depth past the limit or 0)``.
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
    old_force0 = forces[p, POINT_FORCE]
    old_force1 = forces[p, POINT_FORCE + 1]
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
        m_n = effective_mass(nx, ny, rix, riy, inv_mass[inc], inv_inertia[inc], rrx, rry, inv_mass[ref],
                             inv_inertia[ref])
        c_n = dashpot(constants[p, C_N], zeta_n, constants[p, K_N], m_n)
        fn = normal_force(depth, -(rvx * nx + rvy * ny), constants[p, K_N], c_n)
        v_t = rvx * tx + rvy * ty
        key = keys[p, q]
        elastic = old_force0 if old_key0 == key else (old_force1 if old_key1 == key else 0.0)
        m_t = effective_mass(tx, ty, rix, riy, inv_mass[inc], inv_inertia[inc], rrx, rry, inv_mass[ref],
                             inv_inertia[ref])
        c_t = dashpot(constants[p, C_T], zeta_t, constants[p, K_T], m_t)
        ft, elastic, slip = tangential_force(elastic, v_t, dt, constants[p, K_T], c_t, constants[p, MU] * fn)
        if slip:
            slipped = max(slipped, abs(v_t) * dt)
        memory[p, POINT_KEY + q] = key
        forces[p, POINT_FORCE + q] = elastic
        fx = fn * nx + ft * tx
        fy = fn * ny + ft * ty
        _push(pair_force, p, 1 - ref_end, inc, fx, fy, px, py, pos, 0.0)
        _push(pair_force, p, ref_end, ref, -fx, -fy, px, py, pos, 0.0)
    _add_slip(p, ids, forces, interface_slip, slipped)
    return count, 0.0


@nb.njit(cache=True, inline="always")
def overlap_pair(p, ids, constants, forces, interface_slip, pos, vel, pair_force, wx, wy, vstart, limits, dt, ox, oy,
                 clip_scratch):
    """Overlap-area-law forces of candidate pair ``p``, into the pair's row of ``pair_force``.

    limits : (nb,) m^2, the largest overlap of each body a stable run can have (the pair's is the
    smaller).  ox, oy, clip_scratch : clipping scratch.  Returns ``(1 if the pair overlaps else 0,
    overlap past the limit or 0)``.
    """
    i = ids[p, PAIR_I]
    j = ids[p, PAIR_J]
    m = clip_convex(wx, wy, vstart[i], vstart[i + 1] - vstart[i], wx, wy, vstart[j], vstart[j + 1] - vstart[j],
                    ox, oy, clip_scratch)
    a = 0.0
    cx = cy = sxx = syy = sxy = 0.0
    if m >= 3:
        a, cx, cy, sxx, syy, sxy = polygon_moments(ox, oy, m)
    if a <= 0.0:
        forces[p, POINT_FORCE] = 0.0
        return 0, 0.0
    if a > min(limits[i], limits[j]):
        return 1, a
    tx, ty, nx, ny = contact_frame(sxx, syy, sxy, cx, cy, pos[i, 0], pos[i, 1])
    rvx = (vel[j, 0] - vel[j, 2] * (cy - pos[j, 1])) - (vel[i, 0] - vel[i, 2] * (cy - pos[i, 1]))
    rvy = (vel[j, 1] + vel[j, 2] * (cx - pos[j, 0])) - (vel[i, 1] + vel[i, 2] * (cx - pos[i, 0]))
    fn = normal_force(a, -(rvx * nx + rvy * ny), constants[p, K_N], constants[p, C_N])
    v_t = rvx * tx + rvy * ty
    ft, elastic, slip = tangential_force(forces[p, POINT_FORCE], v_t, dt, constants[p, K_T], constants[p, C_T],
                                         constants[p, MU] * fn)
    forces[p, POINT_FORCE] = elastic
    if slip:
        _add_slip(p, ids, forces, interface_slip, abs(v_t) * dt)
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


@nb.njit(cache=True)
def _pair_buffers(n_pairs, corner, clip):
    """Per-pair outputs (resultants (n, 6), points in contact, excess penetration) and the narrow
    phase's scratch: corner points (n, 2, 3) and keys (n, 2), or the clipping buffers of the overlap law."""
    rows = n_pairs if corner else 1
    polygons = 1 if corner else n_pairs
    return (np.zeros((n_pairs, 6)), np.zeros(n_pairs, np.int64), np.zeros(n_pairs), np.empty((rows, 2, 3)),
            np.empty((rows, 2), np.int64), np.empty((polygons, clip)), np.empty((polygons, clip)),
            np.empty((polygons, 2, 2, clip)))


@nb.njit(cache=True)
def incidence(ids, n_pairs, n_bodies):
    """Which pairs each body belongs to, compressed: body b's entries are ``entries[start[b]:start[b + 1]]``,
    each ``2 p + end`` (pair p, the body its first or second).  Returns ``(start, entries)``."""
    start = np.zeros(n_bodies + 1, np.int64)
    for p in range(n_pairs):
        start[ids[p, PAIR_I] + 1] += 1
        start[ids[p, PAIR_J] + 1] += 1
    for b in range(n_bodies):
        start[b + 1] += start[b]
    fill = start[:-1].copy()
    entries = np.empty(2 * n_pairs, np.int64)
    for p in range(n_pairs):
        for end in range(2):
            b = ids[p, PAIR_I + end]
            entries[fill[b]] = 2 * p + end
            fill[b] += 1
    return start, entries


@nb.njit(cache=True, inline="always")
def move(pos, vel, force, inv_mass, inv_inertia, gx, gy, kick, dt):
    """Central-difference update of every free body under ``force`` and the load (gx, gy) per unit mass: the
    velocities gain the acceleration times ``kick`` (s), the mean of the steps before and after this instant
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
def needs_relist(pos, radius, built_at, half_skin):
    """Whether a body has moved (translation plus rotation at its circumradius) half a skin since the list."""
    for b in range(pos.shape[0]):
        slack = half_skin - abs(pos[b, 2] - built_at[b, 2]) * radius[b]
        dx = pos[b, 0] - built_at[b, 0]
        dy = pos[b, 1] - built_at[b, 1]
        if not (slack >= 0.0 and dx * dx + dy * dy <= slack * slack):
            return True
    return False


@nb.njit(cache=True, inline="always")
def place_base(pos, vel, ground, k):
    """Stage 1: the base (body 0) where the ground motion puts it at step ``k`` of the chunk."""
    pos[0, 0] = ground[2, k]
    pos[0, 1] = ground[3, k]
    vel[0, 0] = ground[4, k]
    vel[0, 1] = ground[5, k]


@nb.njit(cache=True, inline="always")
def place_base_within(pos, vel, ground, k, fraction):
    """Stage 1 of a substep: the base ``fraction`` of the way from step ``k`` to step ``k + 1``, moving at the
    velocity of that step's half step."""
    pos[0, 0] = ground[2, k] + fraction * (ground[2, k + 1] - ground[2, k])
    pos[0, 1] = ground[3, k] + fraction * (ground[3, k + 1] - ground[3, k])
    vel[0, 0] = ground[4, k + 1]
    vel[0, 1] = ground[5, k + 1]


@nb.njit(cache=True, inline="always")
def output_due(step, stride, last_step, counters, out_step):
    """Stage 1: whether the state of ``step`` is an output (every ``stride`` steps and the last) not yet written."""
    written = counters[OUTPUTS]
    return (step % stride == 0 or step == last_step) and (written == 0 or out_step[written - 1] != step)


@nb.njit(cache=True, inline="always")
def write_output(pos, interface_slip, counters, out_pos, out_slip, out_step):
    """Stage 1: the state and the interfaces' slip into the next output row."""
    k = counters[OUTPUTS]
    for b in range(pos.shape[0]):
        for d in range(3):
            out_pos[k, b, d] = pos[b, d]
    for m in range(interface_slip.shape[0]):
        out_slip[k, m] = interface_slip[m]
    out_step[k] = counters[STEP]
    counters[OUTPUTS] = k + 1


@nb.njit(cache=True, inline="always")
def pair_forces(p, corner, ids, constants, memory, forces, interface_slip, pos, vel, pair_force, pair_touching,
                pair_excess, wx, wy, wnx, wny, vstart, inv_mass, inv_inertia, zeta_n, zeta_t, limits, dt, boxes, points,
                keys, ox, oy, clip_scratch):
    """Stage 4, one candidate pair ``p``: if its boxes overlap, its contacts under the corner or the
    overlap-area law and their forces into its row of ``pair_force``, whether it touches into
    ``pair_touching[p]`` and its penetration past the limit into ``pair_excess[p]``.  A pair writes only
    its own rows (and its own recorded interface), so pairs may run in parallel.  boxes : (4, nb) m, the
    bodies' boxes, rows lowest x, highest x, lowest y, highest y."""
    i = ids[p, PAIR_I]
    j = ids[p, PAIR_J]
    pair_force[p, :] = 0.0
    pair_touching[p] = 0
    pair_excess[p] = 0.0
    if boxes[1, i] < boxes[0, j] or boxes[1, j] < boxes[0, i] or boxes[3, i] < boxes[2, j] or boxes[3, j] < boxes[2, i]:
        memory[p, :] = -1
        forces[p, POINT_FORCE] = 0.0
        return
    if corner:
        touching, excess = corner_pair(p, ids, constants, memory, forces, interface_slip, pos, vel, pair_force,
                                       wx, wy, wnx, wny, vstart, inv_mass, inv_inertia, zeta_n, zeta_t,
                                       min(limits[i], limits[j]), dt, points, keys)
    else:
        touching, excess = overlap_pair(p, ids, constants, forces, interface_slip, pos, vel, pair_force, wx,
                                        wy, vstart, limits, dt, ox[p], oy[p], clip_scratch[p])
    pair_touching[p] = touching
    pair_excess[p] = excess


@nb.njit(cache=True, inline="always")
def gather_forces(b, start, entries, pair_force, force):
    """Stage 4, one body ``b``: the sum of its pairs' resultants, in one order, into ``force[b]``."""
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
def deepest_pair(pair_touching, pair_excess, n_pairs, counters):
    """Stage 4: counts the pairs in contact (``counters[NARROW]``); returns the first pair penetrating past
    the limit, or -1."""
    for p in range(n_pairs):
        if pair_touching[p] > 0:
            counters[NARROW] += 1
        if pair_excess[p] > 0.0:
            return p
    return -1


@nb.njit(cache=True, inline="always")
def ground_work(force, vel, mass, load_x, load_y, dt, ledger):
    """Stage 5: the work of the ground over the step into the ledger (net and gross, J): the base's reaction
    against its velocity and the inertial load on every block."""
    power = -(force[0, 0] * vel[0, 0] + force[0, 1] * vel[0, 1])
    for b in range(1, vel.shape[0]):
        power += (load_x * vel[b, 0] + load_y * vel[b, 1]) * mass[b]
    ledger[1] += power * dt
    ledger[2] += abs(power) * dt


@nb.njit(cache=True, inline="always")
def check_bodies(pos, vel, radius, floor, speed_limit, peak_theta):
    """Stage 6: a non-finite state, a block below the base's top by more than its size (fell off), or one
    faster than ``speed_limit`` relative to the ground; follows each block's peak |theta|.  Returns
    ``(status, body)``, STATUS_OK and 0 when every block passes."""
    for b in range(1, pos.shape[0]):
        if not (math.isfinite(pos[b, 0]) and math.isfinite(pos[b, 1]) and math.isfinite(pos[b, 2])):
            return STATUS_NONFINITE, b
        if pos[b, 1] - pos[0, 1] < floor - radius[b]:
            return STATUS_FELL_OFF, b
        rel_x = vel[b, 0] - vel[0, 0]
        rel_y = vel[b, 1] - vel[0, 1]
        spin = vel[b, 2] * radius[b]
        if rel_x * rel_x + rel_y * rel_y + spin * spin > speed_limit * speed_limit:
            return STATUS_RUNAWAY, b
        peak_theta[b] = max(peak_theta[b], abs(pos[b, 2]))
    return STATUS_OK, 0


@nb.njit(cache=True, inline="always")
def energy_gained(pos, vel, mass, inv_inertia, gravity, ledger, tolerance, scale):
    """Stage 6: whether the blocks hold more energy than they started with plus the ground's net work, by more
    than ``tolerance`` of ``scale`` plus the ground's gross work."""
    energy = mechanical_energy(pos, vel, mass, inv_inertia, gravity)
    return energy - ledger[0] - ledger[1] > tolerance * (scale + ledger[2])


@nb.njit(cache=True, inline="always")
def step_division(pos, critical_angle, y_start, drop_limit, substeps_past_alpha, counters, dt):
    """Stage 5's division of a step of ``dt`` (s): ``(substeps, h, kick)``.  Past a critical angle a block may
    lie on a longer face, and fallen blocks pile up: while a block is overturned (:func:`any_block_overturned`)
    the step is taken in ``substeps_past_alpha`` substeps of ``h`` (s), else in one; ``kick`` (s) spans half the
    step or substep before (``counters[LAST_SUBSTEPS]``) and half of the first one taken now."""
    substeps = 1
    if substeps_past_alpha > 1 and any_block_overturned(pos, critical_angle, y_start, drop_limit):
        substeps = substeps_past_alpha
    h = dt / substeps
    last = counters[LAST_SUBSTEPS]
    kick = 0.5 * ((dt / last if last > 0 else dt) + h)
    return substeps, h, kick


@nb.njit(cache=True, inline="always")
def end_step(pos, vel, radius, floor, speed_limit, peak_theta, critical_angle, y_start, drop_limit, mass, inv_inertia,
             stack_id, bottom, stack_mass, foot, overturn_step, stack_step, stack_moment, counters, substeps,
             stop_at_overturn, gravity, ledger, energy_tolerance, energy_scale):
    """Stage 6, after a step taken in ``substeps``: the counters, then :func:`check_bodies`, the overturns
    (:func:`~dem_core.engine._checks.mark_overturns`) and every ``ENERGY_CHECK_INTERVAL`` steps
    :func:`energy_gained`.  Returns ``(status, body)``: STATUS_OK and 0 when the run goes on, STATUS_OVERTURNED
    and the block when one overturned and ``stop_at_overturn`` (the caller writes the state as the last
    output), else the failed check's status."""
    step = counters[STEP]
    counters[LAST_SUBSTEPS] = substeps
    if substeps > 1:
        counters[SUBSTEPPED] += 1
    counters[STEP] = step + 1
    status, b = check_bodies(pos, vel, radius, floor, speed_limit, peak_theta)
    if status != STATUS_OK:
        return status, b
    toppled = mark_overturns(pos, critical_angle, y_start, drop_limit, mass, stack_id, bottom, stack_mass, foot,
                             overturn_step, stack_step, stack_moment, step + 1)
    if toppled >= 0 and stop_at_overturn:
        return STATUS_OVERTURNED, toppled
    if step % ENERGY_CHECK_INTERVAL == 0 and energy_gained(pos, vel, mass, inv_inertia, gravity, ledger,
                                                           energy_tolerance, energy_scale):
        return STATUS_ENERGY, 0
    return STATUS_OK, 0


def _advance(model, run, pos, vel, contacts, retired, tracking, ground, n_steps, out_pos, out_slip, out_step):
    """Take up to ``n_steps`` steps from the state (``pos``, ``vel``, ``contacts``, ``retired``,
    ``tracking``), in place.

    model : :class:`~dem_core.engine.model.Model`.  run : :class:`~dem_core.simulation.RunSettings`
    (dt, output stride, last step, limits).  ground : (6, n_steps + 1) for these steps: inertial load
    per unit mass x, y (m/s^2, entries ``[:n_steps]``), base position x, y (m) at each step and base
    velocity x, y (m/s) at the half step before it.  out_pos (n_out, nb, 3), out_slip (n_out, n_if),
    out_step (n_out,) take the outputs (the state every ``run.stride`` steps and at ``run.last_step``).

    Each step runs the stages of the module docstring, in order: :func:`place_base` and
    :func:`write_output`; :func:`world_geometry` and the boxes; the broad phase's list when
    :func:`needs_relist`; :func:`pair_forces` per pair, :func:`gather_forces` per body and
    :func:`deepest_pair`; :func:`ground_work` and :func:`move`; :func:`check_bodies`, the overturns and,
    every ``ENERGY_CHECK_INTERVAL`` steps, :func:`energy_gained`.

    Returns ``(status, i, j, contacts, retired)``: the status (STATUS_*), the bodies concerned and
    the contact store and retired slips (new arrays if the list was made again).  The step the run
    stopped at is ``tracking.counters[STEP]``.
    """
    bodies = model.bodies
    law = model.law
    local_x, local_y, normal_x, normal_y = bodies.local_x, bodies.local_y, bodies.normal_x, bodies.normal_y
    vstart, mass, inv_mass, inv_inertia = bodies.vstart, bodies.mass, bodies.inv_mass, bodies.inv_inertia
    radius = bodies.radius
    critical_angle, y_start, drop_limit = bodies.critical_angle, bodies.y_start, bodies.drop_limit
    stack_id, bottom, stack_mass, foot = model.stacks.stack_id, model.stacks.bottom, model.stacks.mass, model.stacks.foot
    overturn_step, stack_step = tracking.overturn_step, tracking.stack_step
    counters, ledger, interface_slip = tracking.counters, tracking.ledger, tracking.interface_slip
    peak_theta, built_at = tracking.peak_theta, tracking.built_at
    nb_ = pos.shape[0]
    nv = local_x.shape[0]
    wx = np.empty(nv)
    wy = np.empty(nv)
    wnx = np.empty(nv)
    wny = np.empty(nv)
    boxes = np.empty((4, nb_))
    lo_x, hi_x, lo_y, hi_y = boxes[0], boxes[1], boxes[2], boxes[3]
    force = np.zeros((nb_, 3))
    stack_moment = np.empty(bottom.shape[0])
    largest = 3
    for b in range(nb_):
        largest = max(largest, vstart[b + 1] - vstart[b])
    clip = 2 * largest + 2
    corner = law.law == CORNER
    # deepest corner contact (m) or largest overlap (m^2) of each body a stable run can have
    limits = law.max_penetration * (bodies.size if corner else bodies.area)
    dt = run.dt
    gravity = model.gravity
    half_skin = 0.5 * law.skin
    # scalars, not fields of a tuple, inside the parallel loop: numba fails to lower a prange body that
    # reads a named tuple's fields when the kernel compiles in parallel before any serial compilation
    zeta_n = law.zeta_n
    zeta_t = law.zeta_t
    ids, constants, memory, forces = contacts.ids, contacts.constants, contacts.memory, contacts.forces
    n_pairs = contacts.count[0]
    # per-pair outputs and scratch: the pair loop may run in parallel, each pair touching only its own rows
    pair_force, pair_touching, pair_excess, points, keys, ox, oy, clip_scratch = _pair_buffers(n_pairs, corner, clip)
    start, entries = incidence(ids, n_pairs, nb_)

    for k in range(n_steps + 1):
        place_base(pos, vel, ground, k)
        step = counters[STEP]
        if output_due(step, run.stride, run.last_step, counters, out_step):
            write_output(pos, interface_slip, counters, out_pos, out_slip, out_step)
        if k == n_steps or step >= run.last_step:
            break

        substeps, h, kick = step_division(pos, critical_angle, y_start, drop_limit, run.substeps, counters, dt)
        load_x = ground[0, k]
        load_y = ground[1, k]
        for sub in range(substeps):
            if sub > 0:
                place_base_within(pos, vel, ground, k, sub / substeps)
            world_geometry(pos, local_x, local_y, normal_x, normal_y, vstart, wx, wy, wnx, wny)
            bounding_boxes(wx, wy, vstart, lo_x, hi_x, lo_y, hi_y)
            if needs_relist(pos, radius, built_at, half_skin):
                candidates = candidate_keys(lo_x, hi_x, lo_y, hi_y, half_skin)
                contacts, retired = relist(bodies, law, model.interface_keys, contacts, retired, candidates)
                ids, constants, memory, forces = contacts.ids, contacts.constants, contacts.memory, contacts.forces
                n_pairs = contacts.count[0]
                pair_force, pair_touching, pair_excess, points, keys, ox, oy, clip_scratch = _pair_buffers(
                    n_pairs, corner, clip)
                start, entries = incidence(ids, n_pairs, nb_)
                built_at[:, :] = pos
                counters[REBUILDS] += 1

            for p in nb.prange(n_pairs):  # prange runs as range in the serial kernel
                pair_forces(p, corner, ids, constants, memory, forces, interface_slip, pos, vel, pair_force,
                            pair_touching, pair_excess, wx, wy, wnx, wny, vstart, inv_mass, inv_inertia, zeta_n, zeta_t,
                            limits, h, boxes, points, keys, ox, oy, clip_scratch)
            for b in nb.prange(nb_):
                gather_forces(b, start, entries, pair_force, force)
            deep = deepest_pair(pair_touching, pair_excess, n_pairs, counters)
            if deep >= 0:
                return STATUS_DEEP_OVERLAP, ids[deep, PAIR_I], ids[deep, PAIR_J], contacts, retired

            ground_work(force, vel, mass, load_x, load_y, h, ledger)
            move(pos, vel, force, inv_mass, inv_inertia, load_x, load_y - gravity, kick, h)
            kick = h
        status, b = end_step(pos, vel, radius, model.floor, run.speed_limit, peak_theta, critical_angle, y_start,
                             drop_limit, mass, inv_inertia, stack_id, bottom, stack_mass, foot, overturn_step,
                             stack_step, stack_moment, counters, substeps, run.stop_at_overturn, gravity, ledger,
                             run.energy_tolerance, run.energy_scale)
        if status == STATUS_OVERTURNED:
            place_base(pos, vel, ground, k + 1)
            write_output(pos, interface_slip, counters, out_pos, out_slip, out_step)
        if status != STATUS_OK:
            return status, b, b, contacts, retired
    return STATUS_OK, 0, 0, contacts, retired


def renamed(function, name):
    """``function`` under another name.  Numba's on-disk cache files a kernel by its name, line and bytecode,
    not by its compile options: two dispatchers of one function, serial and parallel, under one name would
    load each other's machine code, so each gets a name of its own."""
    clone = types.FunctionType(function.__code__, function.__globals__, name, function.__defaults__,
                               function.__closure__)
    clone.__qualname__ = name
    clone.__doc__ = function.__doc__
    return clone


def _engine_digest() -> str:
    """A digest of the engine's source.  Numba checks only the kernel's own file before loading it from
    its cache, but the kernel inlines the stages of the other modules (the manifold, the contact law, the
    checks): with the digest in the kernel's name, editing any of them compiles the kernel afresh."""
    digest = hashlib.sha256()
    for path in sorted(Path(__file__).parent.glob("*.py")):
        digest.update(path.read_bytes())
    return digest.hexdigest()[:10]


ENGINE_DIGEST = _engine_digest()
#: the stepping kernel, serial; it releases the GIL, so that a batch runs members on several Python threads
advance = nb.njit(cache=True, nogil=True)(renamed(_advance, f"_advance_{ENGINE_DIGEST}"))
#: the same kernel with the pair loop and the gather spread over numba's threads
advance_parallel = nb.njit(cache=True, parallel=True)(renamed(_advance, f"_advance_parallel_{ENGINE_DIGEST}"))
