"""Compiled Moreau-Jean time stepping on the corner manifold (docs/method.md 1.8).

Private module: :func:`advance` takes what :func:`dem_core.engine._step.advance` takes and advances the
state at the velocity level, with no contact stiffness (Moreau 1988; Jean 1999; Acary and Brogliato 2008,
ch. 10).  Over a step ``h`` from ``(q, v)`` to ``(q+, v+)``, theta in [0.5, 1]:

    M (v+ - v) = h f + H^T P,        q+ = q + h ((1 - theta) v + theta v+),

``f`` gravity and the inertial load of the ground (constant over the step), ``H`` the contact points'
normal and tangential directions, and per point of the index set (the corner manifold's points that are
touching or close within the step) the impulses ``P = (P_n, P_t)`` obey

* Signorini with Newton's impact law at the velocity level: ``0 <= u_n+ - target ⊥ P_n >= 0``, the target
  ``-e u_n`` at a touching point (e the restitution, 0 by default: plastic, Housner's rule), and at a point
  still apart by a gap ``g`` the approach that closes it at the step's end (a speculative contact, as Box2D
  does), so that an impact falls where the corner meets the face, not a step early;
* Coulomb's law on the exact 2D cone: ``|P_t| <= mu P_n``, ``u_t+ = 0`` while inside, and ``P_t = -mu P_n
  sign(u_t+)`` while sliding.

The points are solved directly, by statuses (open, sticking, sliding: :mod:`._active_set`), from the last step's
impulses under the points' feature keys (the keys that carry the explicit law's tangential springs).  Where the
statuses do not settle, projected Gauss-Seidel finishes the solve from there, each point's 2 x 2 problem exactly
(:func:`point_impulse`).  A point left inside its face by the step is pushed out at the position level
(:func:`project_positions`): positions move, velocities do not, so the correction adds no kinetic energy.

Stages per step: :func:`~._step.place_base` and the outputs; the world geometry, boxes and candidate list
(shared with the explicit kernel; on a new list the pairs' order, :func:`._active_set.pair_order`);
:func:`collect_points` (the manifold of every candidate pair and the index set); :func:`free_velocities`;
:func:`warm_start`; :func:`._active_set.solve_statuses`, and where its statuses did not hold :func:`point_blocks`
and :func:`solve_points`; :func:`integrate`; :func:`project_positions`; the ground's work; the checks of the
explicit kernel (non-finite, runaway, fell off, overturns, energy).
"""

import math

import numba as nb
import numpy as np

from ._active_set import pair_order, solve_statuses, workspace
from ._broadphase import bounding_boxes, candidate_keys, relist
from ._checks import mark_overturns
from ._manifold import FACE_BITS, corner_manifold
from ._step import (STATUS_ENERGY, STATUS_OK, STATUS_OVERTURNED, ENERGY_CHECK_INTERVAL, needs_relist, renamed,
                    ENGINE_DIGEST, check_bodies, energy_gained, ground_work, output_due, place_base, world_geometry,
                    write_output)
from ._points import (FRICTION, GAP, INC, KEY, N_COLUMNS, NX, NY, PAIR, PN, PT, REF, RIX, RIY, RRX, RRY, SLID, SLOT,
                      TARGET, U0, WNN, WNT, WTT, apply_impulse, delassus, relative_velocity)
from .state import (IMPULSE_N, MU, NARROW, OUTPUTS, PAIR_I, PAIR_INTERFACE, PAIR_J, POINT_FORCE, POINT_KEY,
                    REBUILDS, REFERENCE, SLIP, STATUS_FALLBACKS, STATUS_PASSES, STEP, SOLVER_SWEEPS,
                    UNCONVERGED)

STATUS_UNCONVERGED = 7


@nb.njit(cache=True, inline="always")
def point_impulse(wnn, wnt, wtt, mu, bn, bt, target):
    """The exact solution of one point's problem with the other points' impulses fixed.

    bn, bt : m/s, the point's velocity without its own impulse.  Returns ``(P_n, P_t, sliding)``: the impulse that
    makes ``u_n = bn + wnn P_n + wnt P_t`` meet ``target`` (or leaves the point apart with none) and, inside the
    cone, ``u_t = 0``; on its edge ``P_t = -mu P_n sign``, the sign the one that opposes the slip."""
    rn = target - bn
    if rn <= 0.0:  # apart, or approaching no faster than the target allows, with no impulse
        return 0.0, 0.0, False
    det = wnn * wtt - wnt * wnt
    pn = (rn * wtt + bt * wnt) / det
    pt = (-bt * wnn - rn * wnt) / det
    if pn > 0.0 and abs(pt) <= mu * pn:
        return pn, pt, False
    s = 1.0 if pt > 0.0 else -1.0  # the tangential impulse pushes along s; the point slides against it
    pn = rn / (wnn + s * mu * wnt)
    if pn <= 0.0:
        return 0.0, 0.0, False
    return pn, s * mu * pn, True


@nb.njit(cache=True, inline="always")
def collect_points(p, ids, constants, memory, forces, pos, vel, wx, wy, wnx, wny, vstart, inv_mass, inv_inertia,
                   margin, active_gap, restitution, h, theta, points, keys, rows, ints, n):
    """Stage 2, one candidate pair ``p``: its corner manifold with the points up to ``margin`` m apart, and into
    ``rows``/``ints`` from row ``n`` the points of the index set (touching, or closing within ``active_gap`` by the
    step's end at the start's velocity), each with its target and warm start (the last step's impulses under its
    feature key).  Returns the rows filled after it."""
    i = ids[p, PAIR_I]
    j = ids[p, PAIR_J]
    count, nx, ny, code = corner_manifold(wx, wy, wnx, wny, vstart[i], vstart[i + 1] - vstart[i], pos[i, 0],
                                          pos[i, 1], vstart[j], vstart[j + 1] - vstart[j], pos[j, 0], pos[j, 1],
                                          memory[p, REFERENCE], points, keys, p, margin)
    memory[p, REFERENCE] = code
    old_key0 = memory[p, POINT_KEY]
    old_key1 = memory[p, POINT_KEY + 1]
    memory[p, POINT_KEY] = -1
    memory[p, POINT_KEY + 1] = -1
    old_impulses = (forces[p, IMPULSE_N], forces[p, IMPULSE_N + 1], forces[p, POINT_FORCE], forces[p, POINT_FORCE + 1])
    forces[p, IMPULSE_N] = 0.0
    forces[p, IMPULSE_N + 1] = 0.0
    forces[p, POINT_FORCE] = 0.0
    forces[p, POINT_FORCE + 1] = 0.0
    if count == 0:
        return n
    ref, inc = (j, i) if (code >> FACE_BITS) == 1 else (i, j)
    for q in range(count):
        px = points[p, q, 0]
        py = points[p, q, 1]
        gap = -points[p, q, 2]
        rix = px - pos[inc, 0]
        riy = py - pos[inc, 1]
        rrx = px - pos[ref, 0]
        rry = py - pos[ref, 1]
        u_n, _ = relative_velocity(vel, inc, ref, rix, riy, rrx, rry, nx, ny)
        if gap + h * min(u_n, 0.0) > active_gap:
            continue
        key = keys[p, q]
        slot = 0 if old_key0 == key else (1 if old_key1 == key else -1)
        memory[p, POINT_KEY + q] = key
        row = rows[n]
        row[NX] = nx
        row[NY] = ny
        row[RIX] = rix
        row[RIY] = riy
        row[RRX] = rrx
        row[RRY] = rry
        row[FRICTION] = constants[p, MU]
        row[GAP] = gap
        row[U0] = u_n
        if gap > active_gap:  # apart: no constraint within the step, which ends before the point meets its face
            row[TARGET] = -math.inf
        else:
            row[TARGET] = -restitution * min(u_n, 0.0)
        row[PN] = old_impulses[slot] if slot >= 0 else 0.0
        row[PT] = old_impulses[2 + slot] if slot >= 0 else 0.0
        ints[n, INC] = inc
        ints[n, REF] = ref
        ints[n, PAIR] = p
        ints[n, SLOT] = q
        ints[n, KEY] = key
        ints[n, SLID] = 0
        n += 1
    return n


@nb.njit(cache=True, inline="always")
def point_blocks(rows, ints, inv_mass, inv_inertia, n):
    """Stages 4 and 6: each of the ``n`` points' own 2 x 2 Delassus block (1/kg) into its row's WNN, WNT, WTT,
    which Gauss-Seidel and the position sweeps use and the direct solve does not."""
    for c in range(n):
        row = rows[c]
        i = ints[c, INC]
        r = ints[c, REF]
        nx = row[NX]
        ny = row[NY]
        rix, riy, rrx, rry = row[RIX], row[RIY], row[RRX], row[RRY]
        im_i, ii_i, im_r, ii_r = inv_mass[i], inv_inertia[i], inv_mass[r], inv_inertia[r]
        row[WNN] = delassus(nx, ny, nx, ny, rix, riy, im_i, ii_i, rrx, rry, im_r, ii_r)
        row[WNT] = delassus(nx, ny, -ny, nx, rix, riy, im_i, ii_i, rrx, rry, im_r, ii_r)
        row[WTT] = delassus(-ny, nx, -ny, nx, rix, riy, im_i, ii_i, rrx, rry, im_r, ii_r)


@nb.njit(cache=True, inline="always")
def point_buffers(n_pairs, n_bodies):
    """Per candidate pair its manifold's points (x, y, depth) and feature keys, and for the index set (two points a
    pair at most) the point rows of :mod:`._points` and the scratch of :func:`._active_set.solve_statuses`."""
    size = max(n_pairs, 1)
    return (np.empty((size, 2, 3)), np.empty((size, 2), np.int64), np.empty((2 * size, N_COLUMNS)),
            np.empty((2 * size, 6), np.int64), workspace(2 * size, n_bodies))


@nb.njit(cache=True, inline="always")
def forget_pair(p, memory, forces):
    """Stage 2: pair ``p``'s contact memory cleared (its boxes are apart)."""
    memory[p, :] = -1
    forces[p, POINT_FORCE] = 0.0
    forces[p, POINT_FORCE + 1] = 0.0
    forces[p, IMPULSE_N] = 0.0
    forces[p, IMPULSE_N + 1] = 0.0


@nb.njit(cache=True, inline="always")
def first_meeting(rows, n, remaining, active_gap, shortest):
    """Stage 2: how long (s) to step so that no point apart by more than ``active_gap`` meets its face inside the
    step: the earliest time a point's gap closes at its present approach, if that is within ``remaining`` and no
    shorter than ``shortest``; else ``remaining``.  A step split there has each impact at its start, where
    Newton's law meets the velocity of the instant, and the reactions of the points in contact act until then."""
    tau = remaining
    for c in range(n):
        gap = rows[c, GAP]
        u_n = rows[c, U0]
        if gap > active_gap and u_n < 0.0:
            meet = -gap / u_n
            if meet < tau:
                tau = meet
    return max(tau, shortest) if tau < remaining else remaining


@nb.njit(cache=True, inline="always")
def free_velocities(vel, inv_mass, load_x, load_y, base_vx, base_vy, h):
    """Stage 3: every block's velocity after the smooth impulse of the step (gravity and the ground's inertial
    load, per unit mass); the base moving with the ground's velocity over the step."""
    vel[0, 0] = base_vx
    vel[0, 1] = base_vy
    vel[0, 2] = 0.0
    for b in range(1, vel.shape[0]):
        vel[b, 0] += h * load_x
        vel[b, 1] += h * load_y


@nb.njit(cache=True, inline="always")
def warm_start(vel, inv_mass, inv_inertia, rows, ints, n):
    """Stage 4: the ``n`` points' warm-start impulses applied to ``vel``."""
    for c in range(n):
        row = rows[c]
        nx = row[NX]
        ny = row[NY]
        apply_impulse(vel, inv_mass, inv_inertia, ints[c, INC], ints[c, REF], row[RIX], row[RIY], row[RRX], row[RRY],
                      row[PN] * nx - row[PT] * ny, row[PN] * ny + row[PT] * nx)


@nb.njit(cache=True, inline="always")
def solve_points(vel, inv_mass, inv_inertia, rows, ints, n, tolerance, max_sweeps):
    """Stage 4: projected Gauss-Seidel over the ``n`` points from their present impulses (already in ``vel``).  A
    sweep, forward and backward in turn, solves each point exactly with the others fixed (:func:`point_impulse`);
    the solve ends when no point's velocity moved by more than ``tolerance`` m/s in a sweep.  Returns ``(sweeps,
    largest change in the last sweep (m/s; infinite if ``max_sweeps`` is 0 and there are points), the incident
    block of the point that changed most)``."""
    change = math.inf if n > 0 else 0.0  # without a sweep, no measure of convergence
    worst = ints[0, INC] if n > 0 else 0
    sweeps = 0
    while sweeps < max_sweeps:
        sweeps += 1
        change = 0.0
        for e in range(n):
            c = e if sweeps % 2 == 1 else n - 1 - e  # forward, then backward: a stack's weight travels both ways
            row = rows[c]
            i = ints[c, INC]
            r = ints[c, REF]
            nx = row[NX]
            ny = row[NY]
            u_n, u_t = relative_velocity(vel, i, r, row[RIX], row[RIY], row[RRX], row[RRY], nx, ny)
            wnn = row[WNN]
            wnt = row[WNT]
            wtt = row[WTT]
            pn0 = row[PN]
            pt0 = row[PT]
            pn, pt, slid = point_impulse(wnn, wnt, wtt, row[FRICTION], u_n - wnn * pn0 - wnt * pt0,
                                         u_t - wnt * pn0 - wtt * pt0, row[TARGET])
            dn = pn - pn0
            dt_ = pt - pt0
            if dn != 0.0 or dt_ != 0.0:
                apply_impulse(vel, inv_mass, inv_inertia, i, r, row[RIX], row[RIY], row[RRX], row[RRY],
                              dn * nx - dt_ * ny, dn * ny + dt_ * nx)
                moved = max(abs(wnn * dn + wnt * dt_), abs(wnt * dn + wtt * dt_))
                if moved > change:
                    change = moved
                    worst = i
            row[PN] = pn
            row[PT] = pt
            ints[c, SLID] = 1 if slid else 0
        if change <= tolerance:
            break
    return sweeps, change, worst


@nb.njit(cache=True, inline="always")
def integrate(pos, start_vel, vel, mid, h, theta):
    """Stage 5: ``q+ = q + h v_theta`` with ``v_theta = (1 - theta) v + theta v+`` (kept in ``mid``) for every
    block."""
    for b in range(pos.shape[0]):
        for d in range(3):
            mid[b, d] = (1.0 - theta) * start_vel[b, d] + theta * vel[b, d]
    for b in range(1, pos.shape[0]):
        pos[b, 0] += h * mid[b, 0]
        pos[b, 1] += h * mid[b, 1]
        pos[b, 2] += h * mid[b, 2]


@nb.njit(cache=True, inline="always")
def project_positions(pos, mid, inv_mass, inv_inertia, rows, ints, n, h, slop, sweeps, shift, blocks_ready):
    """Stage 6: the points' gaps after the step (followed to first order along ``h`` times the normal velocity of
    ``mid``) brought back to the contact's geometry by Gauss-Seidel sweeps on the positions alone (``shift``
    (nb, 3) scratch): a point that carried an impulse ends on its face (Signorini's complementarity: a point
    that pushes touches), one left deeper than ``slop`` m inside is pushed out.  Velocities do not change, so no
    kinetic energy is added.  ``blocks_ready``: whether the rows hold their Delassus blocks (:func:`point_blocks`).
    Returns whether any point needed it."""
    off = False
    for c in range(n):
        row = rows[c]
        u_n, _ = relative_velocity(mid, ints[c, INC], ints[c, REF], row[RIX], row[RIY], row[RRX], row[RRY], row[NX],
                                   row[NY])
        row[GAP] += h * u_n
        row[U0] = 0.0  # the point's position impulse
        if row[GAP] < -slop or (row[PN] > 0.0 and row[GAP] > slop):
            off = True
    if not off:
        return False
    if not blocks_ready:
        point_blocks(rows, ints, inv_mass, inv_inertia, n)
    shift[:, :] = 0.0
    for _ in range(sweeps):
        for c in range(n):
            row = rows[c]
            i = ints[c, INC]
            r = ints[c, REF]
            s_n, _ = relative_velocity(shift, i, r, row[RIX], row[RIY], row[RRX], row[RRY], row[NX], row[NY])
            gap = row[GAP] + s_n
            if row[PN] > 0.0:
                lam = row[U0] - gap / row[WNN]
            else:
                lam = max(row[U0] + (-slop - gap) / row[WNN], 0.0) if gap < -slop or row[U0] > 0.0 else row[U0]
            d = lam - row[U0]
            if d != 0.0:
                apply_impulse(shift, inv_mass, inv_inertia, i, r, row[RIX], row[RIY], row[RRX], row[RRY],
                              d * row[NX], d * row[NY])
                row[U0] = lam
    for b in range(1, pos.shape[0]):
        pos[b, 0] += shift[b, 0]
        pos[b, 1] += shift[b, 1]
        pos[b, 2] += shift[b, 2]
    return True


@nb.njit(cache=True, inline="always")
def keep_impulses(rows, ints, n, forces, interface_slip, ids, base_impulse, vel, h):
    """Stage 7: each point's impulses into its pair's contact memory (the next step's warm start), the slip of the
    points that slid (|u_t+| h, the largest of a pair's) into the pair's or its interface's tally, and the total
    impulse on the base into ``base_impulse`` (2,)."""
    base_impulse[0] = 0.0
    base_impulse[1] = 0.0
    last = -1
    slipped = 0.0
    for c in range(n):
        row = rows[c]
        p = ints[c, PAIR]
        if p != last:
            if last >= 0:
                _tally_slip(last, ids, forces, interface_slip, slipped)
            last = p
            slipped = 0.0
        q = ints[c, SLOT]
        forces[p, IMPULSE_N + q] = row[PN]
        forces[p, POINT_FORCE + q] = row[PT]
        px = row[PN] * row[NX] - row[PT] * row[NY]
        py = row[PN] * row[NY] + row[PT] * row[NX]
        if ints[c, INC] == 0:
            base_impulse[0] += px
            base_impulse[1] += py
        elif ints[c, REF] == 0:
            base_impulse[0] -= px
            base_impulse[1] -= py
        if ints[c, SLID] == 1:
            _, u_t = relative_velocity(vel, ints[c, INC], ints[c, REF], row[RIX], row[RIY], row[RRX], row[RRY],
                                       row[NX], row[NY])
            slipped = max(slipped, abs(u_t) * h)
    if last >= 0:
        _tally_slip(last, ids, forces, interface_slip, slipped)


@nb.njit(cache=True, inline="always")
def _tally_slip(p, ids, forces, interface_slip, amount):
    if amount > 0.0:
        k = ids[p, PAIR_INTERFACE]
        if k >= 0:
            interface_slip[k] += amount
        else:
            forces[p, SLIP] += amount


def _advance(model, run, pos, vel, contacts, retired, tracking, ground, n_steps, out_pos, out_slip, out_step):
    """Take up to ``n_steps`` Moreau-Jean steps from the state, in place: the arguments and the return of
    :func:`dem_core.engine._step.advance`, with ``vel`` the velocities at the steps (not half a step before) and
    ``ground`` rows 0-1 the ground's mean inertial load over each step ``[t_k, t_k+1]``; the base moves over step
    k with the velocity of column ``k + 1``.  ``run.theta`` weights the new velocity in the positions' update.
    Per step the stages of the module docstring, in order."""
    bodies = model.bodies
    law = model.law
    local_x, local_y, normal_x, normal_y = bodies.local_x, bodies.local_y, bodies.normal_x, bodies.normal_y
    vstart, mass, inv_mass, inv_inertia = bodies.vstart, bodies.mass, bodies.inv_mass, bodies.inv_inertia
    radius = bodies.radius
    critical_angle, y_start, drop_limit = bodies.critical_angle, bodies.y_start, bodies.drop_limit
    stacks = model.stacks
    stack_id, bottom, stack_mass, foot = stacks.stack_id, stacks.bottom, stacks.mass, stacks.foot
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
    start_vel = np.empty((nb_, 3))
    mid = np.empty((nb_, 3))
    shift = np.empty((nb_, 3))
    reaction = np.zeros((nb_, 3))
    base_impulse = np.zeros(2)
    stack_moment = np.empty(bottom.shape[0])
    h = run.dt
    theta = run.theta
    gravity = model.gravity
    half_skin = 0.5 * law.skin
    smallest = bodies.size[1:].min()
    active_gap = run.active_gap * smallest
    slop = run.slop * smallest
    tolerance = run.solver_tolerance * gravity * h
    restitution = law.restitution
    ids, constants, memory, forces = contacts.ids, contacts.constants, contacts.memory, contacts.forces
    n_pairs = contacts.count[0]
    points, keys, rows, ints, work = point_buffers(n_pairs, nb_)
    order = pair_order(ids, n_pairs, inv_mass)

    for k in range(n_steps + 1):
        place_base(pos, vel, ground, k)
        step = counters[STEP]
        if output_due(step, run.stride, run.last_step, counters, out_step):
            write_output(pos, interface_slip, counters, out_pos, out_slip, out_step)
        if k == n_steps or step >= run.last_step:
            break

        remaining = h
        for sub in range(run.max_substeps):
            world_geometry(pos, local_x, local_y, normal_x, normal_y, vstart, wx, wy, wnx, wny)
            bounding_boxes(wx, wy, vstart, lo_x, hi_x, lo_y, hi_y)
            if needs_relist(pos, radius, built_at, half_skin):
                candidates = candidate_keys(lo_x, hi_x, lo_y, hi_y, half_skin)
                contacts, retired = relist(bodies, law, model.interface_keys, contacts, retired, candidates)
                ids, constants, memory, forces = contacts.ids, contacts.constants, contacts.memory, contacts.forces
                n_pairs = contacts.count[0]
                points, keys, rows, ints, work = point_buffers(n_pairs, nb_)
                order = pair_order(ids, n_pairs, inv_mass)
                built_at[:, :] = pos
                counters[REBUILDS] += 1
            n = 0
            for e in range(n_pairs):
                p = order[e]
                i = ids[p, PAIR_I]
                j = ids[p, PAIR_J]
                if (hi_x[i] + half_skin < lo_x[j] or hi_x[j] + half_skin < lo_x[i] or hi_y[i] + half_skin < lo_y[j]
                        or hi_y[j] + half_skin < lo_y[i]):
                    forget_pair(p, memory, forces)
                    continue
                n = collect_points(p, ids, constants, memory, forces, pos, vel, wx, wy, wnx, wny, vstart, inv_mass,
                                   inv_inertia, half_skin, active_gap, restitution, remaining, theta, points, keys,
                                   rows, ints, n)
            counters[NARROW] += n
            tau = remaining
            if sub + 1 < run.max_substeps:
                tau = first_meeting(rows, n, remaining, active_gap, run.shortest_substep * h)
            start_vel[:, :] = vel
            load_x = ground[0, k]
            load_y = ground[1, k]
            free_velocities(vel, inv_mass, load_x, load_y - gravity, ground[4, k + 1], ground[5, k + 1], tau)
            warm_start(vel, inv_mass, inv_inertia, rows, ints, n)
            held, passes = solve_statuses(vel, inv_mass, inv_inertia, rows, ints, n, tolerance * tau / h,
                                          run.status_passes, work)
            counters[STATUS_PASSES] += passes
            counters[STATUS_FALLBACKS] += n > 0 and run.status_passes > 0 and not held
            sweeps, change, worst = 0, 0.0, 0
            if not held and n > 0:
                point_blocks(rows, ints, inv_mass, inv_inertia, n)
                sweeps, change, worst = solve_points(vel, inv_mass, inv_inertia, rows, ints, n, tolerance * tau / h,
                                                     run.max_sweeps)
            if change > tolerance * tau / h:
                counters[UNCONVERGED] += 1
                failure = run.solver_failure * gravity * tau
                if change > failure:  # far from a solution: sweep on, and stop the run if that does not get there
                    more, change, worst = solve_points(vel, inv_mass, inv_inertia, rows, ints, n, failure,
                                                       run.rescue_sweeps)
                    sweeps += more
                    if change > failure:
                        counters[SOLVER_SWEEPS] += sweeps
                        return STATUS_UNCONVERGED, worst, worst, contacts, retired
            counters[SOLVER_SWEEPS] += sweeps
            integrate(pos, start_vel, vel, mid, tau, theta)
            project_positions(pos, mid, inv_mass, inv_inertia, rows, ints, n, tau, slop, run.projection_sweeps,
                              shift, not held)
            keep_impulses(rows, ints, n, forces, interface_slip, ids, base_impulse, vel, tau)
            reaction[0, 0] = base_impulse[0] / tau
            reaction[0, 1] = base_impulse[1] / tau
            ground_work(reaction, mid, mass, load_x, load_y, tau, ledger)
            remaining -= tau
            if remaining <= 0.0:
                break
        counters[STEP] = step + 1

        status, b = check_bodies(pos, vel, radius, model.floor, run.speed_limit, peak_theta)
        if status != STATUS_OK:
            return status, b, b, contacts, retired
        toppled = mark_overturns(pos, critical_angle, y_start, drop_limit, mass, stack_id, bottom, stack_mass, foot,
                                 overturn_step, stack_step, stack_moment, step + 1)
        if toppled >= 0 and run.stop_at_overturn:
            place_base(pos, vel, ground, k + 1)
            write_output(pos, interface_slip, counters, out_pos, out_slip, out_step)
            return STATUS_OVERTURNED, toppled, toppled, contacts, retired
        if step % ENERGY_CHECK_INTERVAL == 0 and energy_gained(pos, vel, mass, inv_inertia, gravity, ledger,
                                                               run.energy_tolerance, run.energy_scale):
            return STATUS_ENERGY, 0, 0, contacts, retired
    return STATUS_OK, 0, 0, contacts, retired


#: the Moreau-Jean kernel (serial: its Gauss-Seidel sweeps are sequential); it releases the GIL, as the explicit one
advance = nb.njit(cache=True, nogil=True)(renamed(_advance, f"_advance_moreau_{ENGINE_DIGEST}"))
