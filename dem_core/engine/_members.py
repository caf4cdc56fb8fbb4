"""Compiled: many members of one scene stepped at once by central differences, one member per GPU thread.

Private module.  :func:`member_steps` takes one member through the steps of a chunk by the stages of
:mod:`dem_core.engine._step`, in the order its CPU kernel takes them, and :data:`advance_members` is the CUDA
kernel that runs it for every member of a batch, a thread each (numba-cuda, float64).  Two things differ from
the CPU kernel, neither in the physics:

- the contact store holds every pair of bodies, set up once, so that no thread allocates; the broad phase
  (:func:`list_pairs`) lists the candidates among them by the CPU's rule, when the CPU's kernel does, in key
  order, and a pair that leaves the list forgets its contact as it does there (its slip stays in its row, where
  the CPU's list hands it to the retired pairs: a pair that leaves and comes back sums its slip in another order);
- the ground's input comes from the samples of the member's motion at unit scale, shared by every member of a
  scaled record (:func:`~dem_core.engine._ground.ground_at`), into a window of the step and the next.

The pairs are in the order of their keys in both, so a body's forces are summed in one order.  The arrays carry
the members on their first axis; :func:`member_steps` takes one member's rows.  The kernel is defined at module
level: numba's CUDA simulator replaces this module's ``cuda``, which a kernel made in a closure would not see.
The CPU builds here are not cached on disk: they inline the stages of other modules, whose changes numba's cache
would not notice (the CPU kernel has the engine's digest in its name for that).
"""

import numba as nb
from numba import cuda

from ._ground import ground_at
from ._step import (STATUS_DEEP_OVERLAP, STATUS_OK, STATUS_OVERTURNED, bounding_boxes, deepest_pair, end_step,
                    gather_forces, ground_work, move, needs_relist, output_due, pair_forces, place_base,
                    place_base_within, step_division, world_geometry, write_output)
from .state import PAIR_I, PAIR_J, POINT_FORCE, REBUILDS, STEP

#: columns of a member's real settings: dt (s), speed limit (m/s), energy tolerance and scale (J), gravity
#: (m/s^2), the base's top relative to its centre (m), the dashpots' damping ratios, the motion's scale, the
#: base's starting centre (m) and half the broad phase's skin (m)
(DT, SPEED_LIMIT, ENERGY_TOLERANCE, ENERGY_SCALE, GRAVITY, FLOOR, ZETA_N, ZETA_T, SCALE, START_X, START_Y,
 HALF_SKIN) = range(12)
REAL_SETTINGS = 12
#: columns of a member's integer settings: output stride (steps), last step, whether an overturn stops it,
#: substeps past alpha, 1 for the corner law, 1 for the inertial frame, and the row of its motion's samples
STRIDE, LAST_STEP, STOP_AT_OVERTURN, SUBSTEPS, CORNER_LAW, INERTIAL, MOTION = range(7)
INTEGER_SETTINGS = 7
#: a member's status while it can take more steps (its run's STATUS_* once it ended)
RUNNING = -1
#: threads per CUDA block
THREADS_PER_BLOCK = 64


@nb.njit(cache=True, inline="always")
def list_pairs(lo_x, hi_x, lo_y, hi_y, margin, ids, listed, in_list, memory, forces, pair_force, pair_touching,
               pair_excess, start, entries, fill):
    """Stage 3 on a store of every pair (ids (P, 4) in key order): the candidates, the pairs whose boxes grown by
    ``margin`` (m) overlap (the rule of :func:`~dem_core.engine._broadphase.candidate_keys`), their rows into
    ``listed`` (P,) in key order and their incidence into ``start`` (nb + 1,), ``entries`` (2 P,) as
    :func:`~dem_core.engine._step.incidence` gives it (``fill`` (nb,) scratch).  ``in_list`` (P,) marks the
    listed rows; a row that leaves the list forgets its contact points, their springs and its last forces.
    Returns how many pairs are listed."""
    reach = 2.0 * margin
    n_bodies = start.shape[0] - 1
    for b in range(n_bodies + 1):
        start[b] = 0
    count = 0
    for p in range(ids.shape[0]):
        i = ids[p, PAIR_I]
        j = ids[p, PAIR_J]
        if not (lo_x[j] > hi_x[i] + reach or lo_x[i] > hi_x[j] + reach or lo_y[j] > hi_y[i] + reach
                or lo_y[i] > hi_y[j] + reach):
            listed[count] = p
            count += 1
            in_list[p] = 1
            start[i + 1] += 1
            start[j + 1] += 1
        elif in_list[p] == 1:
            in_list[p] = 0
            for c in range(memory.shape[1]):
                memory[p, c] = -1
            forces[p, POINT_FORCE] = 0.0
            forces[p, POINT_FORCE + 1] = 0.0
            for c in range(pair_force.shape[1]):
                pair_force[p, c] = 0.0
            pair_touching[p] = 0
            pair_excess[p] = 0.0
    for b in range(n_bodies):
        start[b + 1] += start[b]
        fill[b] = start[b]
    for c in range(count):
        p = listed[c]
        for end in range(2):
            b = ids[p, PAIR_I + end]
            entries[fill[b]] = 2 * p + end
            fill[b] += 1
    return count


@nb.njit
def member_steps(local_x, local_y, normal_x, normal_y, vstart, mass, inv_mass, inv_inertia, radius, critical_angle,
                 y_start, drop_limit, limits, stack_id, bottom, stack_mass, foot, ids, constants, start, entries, real,
                 integer, samples, n_steps, pos, vel, memory, forces, interface_slip, peak_theta, overturn_step,
                 stack_step, ledger, counters, built_at, out_pos, out_slip, out_step, listed, in_list, n_listed, wx, wy,
                 wnx, wny, boxes, force, stack_moment, window, fill, pair_force, pair_touching, pair_excess, points,
                 keys, ox, oy, clip_scratch):
    """Up to ``n_steps`` steps of one member, in place; returns ``(status, i, j)`` as the CPU kernel does.

    Model (one member's rows): local_x, local_y, normal_x, normal_y (nv,); vstart (nb + 1,); mass, inv_mass,
    inv_inertia, radius, critical_angle, y_start, drop_limit (nb,); limits (nb,) the deepest contact (m, corner
    law) or largest overlap (m^2) a stable run has; stack_id (nb,), bottom, stack_mass (ns,), foot (ns, 2, 2).
    Pairs: ids (P, 4), constants (P, 6) of every pair of bodies in key order, start (nb + 1,) and entries (2 P,)
    their incidence (:func:`~dem_core.engine._step.incidence`).  real (REAL_SETTINGS,), integer
    (INTEGER_SETTINGS,) the member's settings by this module's columns; samples (4, n_steps + 2) of its motion
    at unit scale from the chunk's first step.  State and outputs: as the CPU kernel's, one member's, with the
    broad phase's list of :func:`list_pairs`: ``listed`` (P,), ``in_list`` (P,) and ``n_listed`` (1,) its length.
    The rest is scratch: wx, wy, wnx, wny (nv,), boxes (4, nb), force (nb, 3), stack_moment (ns,), window (6, 2),
    fill (nb,) and the pairs' buffers of :func:`~dem_core.engine._step._pair_buffers`.
    """
    dt = real[DT]
    inertial = integer[INERTIAL] == 1
    corner = integer[CORNER_LAW] == 1
    n_pairs = ids.shape[0]
    lo_x, hi_x, lo_y, hi_y = boxes[0], boxes[1], boxes[2], boxes[3]
    for k in range(n_steps + 1):
        ground_at(samples, k, real[SCALE], real[START_X], real[START_Y], dt, inertial, window, 0)
        place_base(pos, vel, window, 0)
        step = counters[STEP]
        if output_due(step, integer[STRIDE], integer[LAST_STEP], counters, out_step):
            write_output(pos, interface_slip, counters, out_pos, out_slip, out_step)
        if k == n_steps or step >= integer[LAST_STEP]:
            break
        ground_at(samples, k + 1, real[SCALE], real[START_X], real[START_Y], dt, inertial, window, 1)
        substeps, h, kick = step_division(pos, critical_angle, y_start, drop_limit, integer[SUBSTEPS], counters, dt)
        load_x = window[0, 0]
        load_y = window[1, 0]
        for sub in range(substeps):
            if sub > 0:
                place_base_within(pos, vel, window, 0, sub / substeps)
            world_geometry(pos, local_x, local_y, normal_x, normal_y, vstart, wx, wy, wnx, wny)
            bounding_boxes(wx, wy, vstart, lo_x, hi_x, lo_y, hi_y)
            if needs_relist(pos, radius, built_at, real[HALF_SKIN]):
                n_listed[0] = list_pairs(lo_x, hi_x, lo_y, hi_y, real[HALF_SKIN], ids, listed, in_list, memory, forces,
                                         pair_force, pair_touching, pair_excess, start, entries, fill)
                for b in range(pos.shape[0]):
                    for d in range(3):
                        built_at[b, d] = pos[b, d]
                counters[REBUILDS] += 1
            for c in range(n_listed[0]):
                pair_forces(listed[c], corner, ids, constants, memory, forces, interface_slip, pos, vel, pair_force,
                            pair_touching, pair_excess, wx, wy, wnx, wny, vstart, inv_mass, inv_inertia, real[ZETA_N],
                            real[ZETA_T], limits, h, boxes, points, keys, ox, oy, clip_scratch)
            for b in range(pos.shape[0]):
                gather_forces(b, start, entries, pair_force, force)
            deep = deepest_pair(pair_touching, pair_excess, n_pairs, counters)
            if deep >= 0:
                return STATUS_DEEP_OVERLAP, ids[deep, PAIR_I], ids[deep, PAIR_J]
            ground_work(force, vel, mass, load_x, load_y, h, ledger)
            move(pos, vel, force, inv_mass, inv_inertia, load_x, load_y - real[GRAVITY], kick, h)
            kick = h
        status, b = end_step(pos, vel, radius, real[FLOOR], real[SPEED_LIMIT], peak_theta, critical_angle, y_start,
                             drop_limit, mass, inv_inertia, stack_id, bottom, stack_mass, foot, overturn_step,
                             stack_step, stack_moment, counters, substeps, integer[STOP_AT_OVERTURN] == 1,
                             real[GRAVITY], ledger, real[ENERGY_TOLERANCE], real[ENERGY_SCALE])
        if status == STATUS_OVERTURNED:
            place_base(pos, vel, window, 1)
            write_output(pos, interface_slip, counters, out_pos, out_slip, out_step)
        if status != STATUS_OK:
            return status, b, b
    return STATUS_OK, 0, 0


@nb.njit
def member_chunk(m, local_x, local_y, normal_x, normal_y, vstart, mass, inv_mass, inv_inertia, radius, critical_angle,
                 y_start, drop_limit, limits, stack_id, bottom, stack_mass, foot, ids, constants, start, entries, real,
                 integer, samples, n_steps, pos, vel, memory, forces, interface_slip, peak_theta, overturn_step,
                 stack_step, ledger, counters, built_at, out_pos, out_slip, out_step, status, listed, in_list, n_listed,
                 wx, wy, wnx, wny, boxes, force, stack_moment, window, fill, pair_force, pair_touching, pair_excess,
                 points, keys, ox, oy, clip_scratch):
    """Member ``m`` through up to ``n_steps`` steps by :func:`member_steps` if it is running (``status[m, 0] ==
    RUNNING``); the arguments are the batch's arrays with the members on their first axis (``n_listed`` (M,)),
    ``samples`` (G, 4, n_steps + 2) the motions' (``integer[m, MOTION]`` the member's row).  A member that ends
    gets its run's ``(status, i, j)`` in ``status[m]``, or STATUS_OK and 0, 0 at its last step."""
    if status[m, 0] != RUNNING:
        return
    code, i, j = member_steps(
        local_x[m], local_y[m], normal_x[m], normal_y[m], vstart[m], mass[m], inv_mass[m], inv_inertia[m], radius[m],
        critical_angle[m], y_start[m], drop_limit[m], limits[m], stack_id[m], bottom[m], stack_mass[m], foot[m], ids[m],
        constants[m], start[m], entries[m], real[m], integer[m], samples[integer[m, MOTION]], n_steps, pos[m], vel[m],
        memory[m], forces[m], interface_slip[m], peak_theta[m], overturn_step[m], stack_step[m], ledger[m], counters[m],
        built_at[m], out_pos[m], out_slip[m], out_step[m], listed[m], in_list[m], n_listed[m:m + 1], wx[m], wy[m],
        wnx[m], wny[m], boxes[m], force[m], stack_moment[m], window[m], fill[m], pair_force[m], pair_touching[m],
        pair_excess[m], points[m], keys[m], ox[m], oy[m], clip_scratch[m])
    if code != STATUS_OK or counters[m, STEP] >= integer[m, LAST_STEP]:
        status[m, 0] = code
        status[m, 1] = i
        status[m, 2] = j


@cuda.jit
def advance_members(local_x, local_y, normal_x, normal_y, vstart, mass, inv_mass, inv_inertia, radius, critical_angle,
                    y_start, drop_limit, limits, stack_id, bottom, stack_mass, foot, ids, constants, start, entries,
                    real, integer, samples, n_steps, pos, vel, memory, forces, interface_slip, peak_theta,
                    overturn_step, stack_step, ledger, counters, built_at, out_pos, out_slip, out_step, status, listed,
                    in_list, n_listed, wx, wy, wnx, wny, boxes, force, stack_moment, window, fill, pair_force,
                    pair_touching, pair_excess, points, keys, ox, oy, clip_scratch):
    """The GPU kernel: thread m takes member m through the chunk (:func:`member_chunk`)."""
    m = cuda.grid(1)
    if m < pos.shape[0]:
        member_chunk(m, local_x, local_y, normal_x, normal_y, vstart, mass, inv_mass, inv_inertia, radius,
                     critical_angle, y_start, drop_limit, limits, stack_id, bottom, stack_mass, foot, ids, constants,
                     start, entries, real, integer, samples, n_steps, pos, vel, memory, forces, interface_slip,
                     peak_theta, overturn_step, stack_step, ledger, counters, built_at, out_pos, out_slip, out_step,
                     status, listed, in_list, n_listed, wx, wy, wnx, wny, boxes, force, stack_moment, window, fill,
                     pair_force, pair_touching, pair_excess, points, keys, ox, oy, clip_scratch)


@nb.njit
def advance_members_serial(members, *arrays):
    """The same chunk for each of ``members`` in turn on one CPU thread, ``arrays`` the arguments of
    :func:`member_chunk` after ``m``: the GPU kernel's code at the CPU's speed, to check it against the CPU kernel
    where there is no GPU."""
    for m in range(members):
        member_chunk(m, *arrays)
