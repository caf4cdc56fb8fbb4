"""Compiled: Moreau-Jean's stage, time stepping on the corner manifold at the velocity level (docs/method.md 1.8).

Private module: :func:`moreau_part`, the driver's integrator stage under ``MOREAU`` (:mod:`._driver`), advances
the state with no contact stiffness (Moreau 1988; Jean 1999; Acary and Brogliato 2008, ch. 10); the driver's
other stages (ground, outputs, geometry, broad phase, checks) are those of the explicit integrator, and the
velocities are those at the steps, not half a step before.  Over a step ``h`` from ``(q, v)`` to ``(q+, v+)``,
theta in [0.5, 1]:

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
(:func:`point_impulse`).  A point left inside its face by the step is pushed out at the position level, and a
sticking point is put back where it stuck (:func:`project_positions`): positions move, velocities do not, so the
correction adds no kinetic energy and moves no block along a face it sticks to.

A part of a step, in order (the pairs in the order of :func:`~._active_set.pair_order`, made with each list):

1. per listed pair, its corner manifold and the points of the index set (:func:`collect_points`; a pair whose
   boxes are apart forgets its contact), then its connectors' rows (:func:`~._connectors.connector_rows`), and
   the part's length: the step, or split where a point apart meets its face (:func:`first_meeting`);
2. the smooth impulse (:func:`free_velocities`);
3. the contact impulses: warm start (:func:`warm_start`), the connectors' branches for the part
   (:func:`~._connectors.connector_coefficients`), the direct solve by statuses
   (:func:`~._active_set.solve_statuses`), and where its statuses did not hold Gauss-Seidel
   (:func:`point_blocks`, :func:`solve_points`), which sweeps on where it is far from a solution; where that
   fails too, steps 2 and 3 again from the part's start, cold, at half its length, with more passes by statuses
   and Gauss-Seidel relaxed (MOREAU_RETRIES times at most), and then the run stops;
4. the positions (:func:`integrate`);
5. the points left inside their faces pushed out, and the sticking points put back where they stuck
   (:func:`project_positions`);
6. the impulses kept for the next step's warm start and the slips tallied (:func:`keep_impulses`), the
   connectors' states moved (:func:`~._connectors.commit_connectors`), then the ground's work
   (:func:`~._checks.ground_work`).
"""

import math

import numba as nb

from ._active_set import HALF_BAND, half_band, responses, solve_positions, solve_statuses
from ._broadphase import forget_pair
from ._build import kernel
from ._checks import ground_work
from ._connectors import commit_connectors, connector_coefficients, connector_rows, connector_sweep
from ._ground import ground_before_end
from ._manifold import FACE_BITS, corner_manifold
from ._points import (CONNECTOR, FIXED_N, FIXED_T, FRICTION, GAP, INC, KEY, NX, NY, PAIR, PN, POSITION_IMPULSE, PT,
                      REF, RIX, RIY, RRX, RRY, SLID, SLOT, TARGET, TRAVEL, U0, WNN, WNT, WTT, apply_impulse, delassus,
                      block_turns, point_travel, relative_velocity)
from ._tally import tally_slip
from ._world import boxes_apart
from .model_arrays import INV_INERTIA, INV_MASS, MASS
from .settings import (ACTIVE_GAP, DT, GRAVITY, THETA, HALF_SKIN, MAX_SUBSTEPS, MAX_SWEEPS, MOREAU_MAX_PARTS,
                       MOREAU_RELAXATION, MOREAU_RETRIES, MOREAU_RETRY_PASSES, PROJECTION_SWEEPS, RESCUE_SWEEPS,
                       RESTITUTION, SHORTEST_SUBSTEP, SLOP, SOLVER_FAILURE, SOLVER_TOLERANCE, STATUS_OK, STATUS_PASSES,
                       STATUS_UNCONVERGED)
from .state import (LISTED, MU, NARROW, PAIR_I, PAIR_J, POINT_KEY, REFERENCE, SHORTENED, SOLVER_SWEEPS,
                    STATUS_FALLBACKS, STEP, UNCONVERGED)
from .state import STATUS_PASSES as PASSES_DONE


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
def collect_points(p, ids, constants, memory, normal_impulse, tangential_impulse, pos, vel, wx, wy, wnx, wny, vstart,
                   margin, active_gap, restitution, h, points, keys, rows, ints, n):
    """Step 1, one listed pair ``p``: its corner manifold with the points up to ``margin`` m apart, and into
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
    old_impulses = (normal_impulse[p, 0], normal_impulse[p, 1], tangential_impulse[p, 0], tangential_impulse[p, 1])
    for q in range(2):
        normal_impulse[p, q] = 0.0
        tangential_impulse[p, q] = 0.0
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
        row[FIXED_N] = 0.0
        row[FIXED_T] = 0.0
        ints[n, CONNECTOR] = -1
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
    """Steps 3 and 5: each of the ``n`` points' own 2 x 2 Delassus block (1/kg) into its row's WNN, WNT, WTT,
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
def first_meeting(rows, n, remaining, active_gap, shortest):
    """Step 1: how long (s) to step so that no point apart by more than ``active_gap`` meets its face inside the
    step: the earliest time a point's gap closes at its present approach, but no shorter than ``shortest`` unless
    less than that is left of the step, and never past its end (``remaining``).  A step split there has each impact
    at its start, where Newton's law meets the velocity of the instant, and the reactions of the points in contact
    act until then."""
    tau = remaining
    for c in range(n):
        gap = rows[c, GAP]
        u_n = rows[c, U0]
        if gap > active_gap and u_n < 0.0:
            meet = -gap / u_n
            if meet < tau:
                tau = meet
    return min(max(tau, shortest), remaining)


@nb.njit(cache=True, inline="always")
def free_velocities(vel, inv_mass, load_x, load_y, base_vx, base_vy, h):
    """Step 2: every block's velocity after the smooth impulse of the part (gravity and the ground's inertial
    load, per unit mass); the base at the ground's velocity (base_vx, base_vy) of the part's end."""
    vel[0, 0] = base_vx
    vel[0, 1] = base_vy
    vel[0, 2] = 0.0
    for b in range(1, vel.shape[0]):
        vel[b, 0] += h * load_x
        vel[b, 1] += h * load_y


@nb.njit(cache=True, inline="always")
def warm_start(vel, inv_mass, inv_inertia, rows, ints, n):
    """Step 3: the ``n`` points' warm-start impulses applied to ``vel``."""
    for c in range(n):
        row = rows[c]
        nx = row[NX]
        ny = row[NY]
        apply_impulse(vel, inv_mass, inv_inertia, ints[c, INC], ints[c, REF], row[RIX], row[RIY], row[RRX], row[RRY],
                      row[PN] * nx - row[PT] * ny, row[PN] * ny + row[PT] * nx)


@nb.njit(cache=True, inline="always")
def solve_points(vel, inv_mass, inv_inertia, rows, ints, n, tolerance, max_sweeps, relaxation, connector_law,
                 connectors):
    """Step 3: projected Gauss-Seidel over the ``n`` points from their present impulses (already in ``vel``).  A
    sweep, forward and backward in turn, solves each point exactly with the others fixed (:func:`point_impulse`;
    a connector's unknowns by :func:`~._connectors.connector_sweep`)
    and moves its impulses by ``relaxation`` (at most 1) of the way there, which keeps them in the cone; the solve
    ends when no point's velocity moved by more than ``tolerance`` m/s in a sweep.  Returns ``(sweeps,
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
            if ints[c, CONNECTOR] >= 0:
                moved = connector_sweep(vel, inv_mass, inv_inertia, rows, ints, c, relaxation, connector_law,
                                        connectors)
                if moved > change:
                    change = moved
                    worst = i
                continue
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
            if relaxation != 1.0:
                pn = pn0 + relaxation * (pn - pn0)
                pt = pt0 + relaxation * (pt - pt0)
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
    """Step 4: ``q+ = q + h v_theta`` with ``v_theta = (1 - theta) v + theta v+`` (kept in ``mid``) for every
    block."""
    for b in range(pos.shape[0]):
        for d in range(3):
            mid[b, d] = (1.0 - theta) * start_vel[b, d] + theta * vel[b, d]
    for b in range(1, pos.shape[0]):
        pos[b, 0] += h * mid[b, 0]
        pos[b, 1] += h * mid[b, 1]
        pos[b, 2] += h * mid[b, 2]


@nb.njit(cache=True, inline="always")
def project_positions(pos, mid, turn, inv_mass, inv_inertia, rows, ints, n, h, slop, sweeps, shift, blocks_ready,
                      responses_ready, status, jac, resp, band, rhs, first, last, end):
    """Step 5: the points' gaps and tangential travels after the step (the rigid motion of ``h`` times the
    velocities of ``mid``, turns exact: :func:`~._points.point_travel`) brought back to the contact's geometry by
    position impulses (``shift`` (nb, 3) scratch, the positions' change; ``turn`` (nb, 2) scratch, the bodies'
    turns).  A point that carried an impulse ends on its face (Signorini's complementarity: a point that pushes
    touches), and one that stuck where it started the step (a sticking point does not move along its face); one left
    deeper than ``slop`` m inside is pushed out.
    Where the points' Delassus matrix fits the band (``responses_ready``: whether the velocity solve made the
    points' Jacobians, else they are made here) one direct solve gives the impulses
    (:func:`~._active_set.solve_positions`); else ``sweeps`` Gauss-Seidel sweeps on the positions, a sticking
    point's 2 x 2 problem solved exactly, the others' along the normal.  Velocities do not change, so no kinetic
    energy is added.  ``blocks_ready``: whether the rows hold their Delassus blocks (:func:`point_blocks`).
    status, jac, resp, band, rhs, first, last, end: the direct solve's scratch (:mod:`._active_set`).
    Returns whether any point needed it."""
    off = False
    block_turns(mid, h, turn)
    for c in range(n):
        row = rows[c]
        if ints[c, CONNECTOR] >= 0:
            continue
        d_n, d_t = point_travel(mid, h, turn, ints[c, INC], ints[c, REF], row[RIX], row[RIY], row[RRX], row[RRY],
                                row[NX], row[NY])
        row[GAP] += d_n
        row[TRAVEL] = d_t
        row[POSITION_IMPULSE] = 0.0
        pushed = row[PN] > 0.0
        if row[GAP] < -slop or (pushed and (row[GAP] > slop or (ints[c, SLID] == 0 and abs(d_t) > slop))):
            off = True
    if not off:
        return False
    for b in range(shift.shape[0]):
        for d in range(3):
            shift[b, d] = 0.0
    width = half_band(ints, inv_mass, n, first, last, end)
    width = width if width <= HALF_BAND else -1
    if width >= 0 and not responses_ready:
        responses(rows, ints, inv_mass, inv_inertia, n, jac, resp)
    if width >= 0 and solve_positions(rows, ints, inv_mass, n, slop, end, status, jac, resp, band, rhs):
        for c in range(n):
            row = rows[c]
            dn = rhs[2 * c]
            dt_ = rhs[2 * c + 1]
            apply_impulse(shift, inv_mass, inv_inertia, ints[c, INC], ints[c, REF], row[RIX], row[RIY], row[RRX],
                          row[RRY], dn * row[NX] - dt_ * row[NY], dn * row[NY] + dt_ * row[NX])
    else:
        if not blocks_ready:
            point_blocks(rows, ints, inv_mass, inv_inertia, n)
        for _ in range(sweeps):
            for c in range(n):
                row = rows[c]
                if ints[c, CONNECTOR] >= 0:
                    continue
                i = ints[c, INC]
                r = ints[c, REF]
                s_n, s_t = relative_velocity(shift, i, r, row[RIX], row[RIY], row[RRX], row[RRY], row[NX], row[NY])
                gap = row[GAP] + s_n
                dt_ = 0.0
                if row[PN] > 0.0 and ints[c, SLID] == 0:
                    wnn, wnt, wtt = row[WNN], row[WNT], row[WTT]
                    det = wnn * wtt - wnt * wnt
                    travel = row[TRAVEL] + s_t
                    dn = (-gap * wtt + travel * wnt) / det
                    dt_ = (gap * wnt - travel * wnn) / det
                elif row[PN] > 0.0:
                    dn = -gap / row[WNN]
                elif gap < -slop or row[POSITION_IMPULSE] > 0.0:
                    dn = max(row[POSITION_IMPULSE] + (-slop - gap) / row[WNN], 0.0) - row[POSITION_IMPULSE]
                else:
                    dn = 0.0
                if dn != 0.0 or dt_ != 0.0:
                    apply_impulse(shift, inv_mass, inv_inertia, i, r, row[RIX], row[RIY], row[RRX], row[RRY],
                                  dn * row[NX] - dt_ * row[NY], dn * row[NY] + dt_ * row[NX])
                    row[POSITION_IMPULSE] += dn
    for b in range(1, pos.shape[0]):
        pos[b, 0] += shift[b, 0]
        pos[b, 1] += shift[b, 1]
        pos[b, 2] += shift[b, 2]
    return True


@nb.njit(cache=True, inline="always")
def keep_impulses(rows, ints, n, normal_impulse, tangential_impulse, pair_slip, ids, base_impulse, vel, h):
    """Step 6: each point's impulses into its pair's contact memory (the next step's warm start), the slip of the
    points that slid (|u_t+| h, the largest of a pair's) into the pair's tally (:func:`~._tally.tally_slip`), and
    the total impulse on the base, the connectors' too, into ``base_impulse`` (2,)."""
    base_impulse[0] = 0.0
    base_impulse[1] = 0.0
    last = -1
    slipped = 0.0
    for c in range(n):
        row = rows[c]
        p = ints[c, PAIR]
        if p != last:
            if last >= 0:
                tally_slip(last, ids, pair_slip, slipped)
            last = p
            slipped = 0.0
        q = ints[c, SLOT]
        if q >= 0:
            normal_impulse[p, q] = row[PN]
            tangential_impulse[p, q] = row[PT]
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
        tally_slip(last, ids, pair_slip, slipped)


@nb.njit(cache=True, inline="always")
def contact_impulses(settings, scratch, counters, vel, inv_mass, inv_inertia, n, tau, left, load_x, load_y,
                     relaxation, passes, connector_law, connectors):
    """Steps 2 and 3 over a part of ``tau`` s that leaves ``left`` s of the step after it (a moving base then moves
    at the ground's velocity there, on the line between the step's ends): the smooth impulse, the warm start, the
    connectors' coefficients for the part (:func:`~._connectors.connector_coefficients`), the direct solve by
    statuses (``passes`` at most) and, where its statuses did not hold, Gauss-Seidel (``relaxation`` of each
    update), which sweeps on where it is far from a solution.  Returns ``(whether the statuses held, whether the
    solve failed, the block where it changed most)``; the counters count passes, fallbacks, sweeps and unconverged
    solves."""
    real, integer = settings.real, settings.integer
    rows, ints = scratch.point_rows, scratch.point_ints
    tolerance = real[SOLVER_TOLERANCE] * tau / real[DT]
    base_vx = ground_before_end(scratch.window, 4, left, real[DT])
    base_vy = ground_before_end(scratch.window, 5, left, real[DT])
    free_velocities(vel, inv_mass, load_x, load_y - real[GRAVITY], base_vx, base_vy, tau)
    warm_start(vel, inv_mass, inv_inertia, rows, ints, n)
    connector_coefficients(vel, rows, ints, n, tau, real[THETA], connector_law, connectors)
    held, done = solve_statuses(vel, inv_mass, inv_inertia, rows, ints, n, tolerance, passes, scratch.point_status,
                                scratch.point_velocity, scratch.jacobian, scratch.response, scratch.band,
                                scratch.rhs, scratch.band_first, scratch.band_last, scratch.band_end, connector_law,
                                connectors)
    counters[PASSES_DONE] += done
    counters[STATUS_FALLBACKS] += n > 0 and integer[STATUS_PASSES] > 0 and not held
    sweeps, change, worst = 0, 0.0, 0
    if not held and n > 0:
        point_blocks(rows, ints, inv_mass, inv_inertia, n)
        sweeps, change, worst = solve_points(vel, inv_mass, inv_inertia, rows, ints, n, tolerance,
                                             integer[MAX_SWEEPS], relaxation, connector_law, connectors)
    failed = False
    if change > tolerance:
        counters[UNCONVERGED] += 1
        failure = real[SOLVER_FAILURE] * real[GRAVITY] * tau
        if change > failure:  # far from a solution: sweep on; a try that does not get there has failed
            more, change, worst = solve_points(vel, inv_mass, inv_inertia, rows, ints, n, failure,
                                               integer[RESCUE_SWEEPS], relaxation, connector_law, connectors)
            sweeps += more
            failed = change > failure
    counters[SOLVER_SWEEPS] += sweeps
    return held, failed, worst


@kernel(_nrt=False)
def moreau_part(model, settings, state, scratch, part, remaining, load_x, load_y):
    """Moreau-Jean's stage: part ``part`` of a step, ``remaining`` (s) of it left, under the ground's inertial load
    (load_x, load_y) m/s^2 over the step, by the steps of the module docstring.  Returns ``(status, i, j, tau)``:
    STATUS_OK and the part's length ``tau`` (s), or STATUS_UNCONVERGED and the block where the solve failed.  The
    scratch's point rows hold two points a listed pair, the most a pair has."""
    real, integer, counters = settings.real, settings.integer, state.counters
    pos, vel, ids = state.pos, state.vel, state.pair_ids
    inv_mass, inv_inertia = model.body[INV_MASS], model.body[INV_INERTIA]
    rows, ints, order = scratch.point_rows, scratch.point_ints, scratch.pair_order
    wx, wy, wnx, wny = scratch.world[0], scratch.world[1], scratch.world[2], scratch.world[3]
    h = real[DT]
    half_skin = real[HALF_SKIN]
    n = 0
    connector_law, connectors = model.connector_law, state.connectors
    for e in range(counters[LISTED]):
        p = order[e]
        if boxes_apart(scratch.boxes, ids[p, PAIR_I], ids[p, PAIR_J], half_skin):
            forget_pair(p, state.pair_memory, state.spring_force, state.normal_impulse, state.tangential_impulse)
        else:
            n = collect_points(p, ids, state.pair_constants, state.pair_memory, state.normal_impulse,
                               state.tangential_impulse, pos, vel, wx, wy, wnx, wny, model.vstart, half_skin,
                               real[ACTIVE_GAP], real[RESTITUTION], remaining, scratch.points, scratch.point_keys,
                               rows, ints, n)
        n = connector_rows(p, ids, pos, vel, connector_law, model.connector_bodies, model.connector_start, connectors,
                           rows, ints, n)
    counters[NARROW] += n
    tau = remaining
    if part + 1 < integer[MAX_SUBSTEPS]:
        tau = first_meeting(rows, n, remaining, real[ACTIVE_GAP], real[SHORTEST_SUBSTEP] * h)
    start_vel = scratch.start_vel
    for b in range(pos.shape[0]):
        for d in range(3):
            start_vel[b, d] = vel[b, d]
    tries = MOREAU_RETRIES + 1 if part + 1 < MOREAU_MAX_PARTS else 1
    for attempt in range(tries):
        relaxation = 1.0
        passes_allowed = integer[STATUS_PASSES]
        if attempt > 0:  # the last try failed: the part again from its start, cold, half as long, with more
            tau *= 0.5  # passes by statuses and Gauss-Seidel relaxed
            relaxation = MOREAU_RELAXATION
            passes_allowed *= MOREAU_RETRY_PASSES
            counters[SHORTENED] += 1
            for b in range(pos.shape[0]):
                for d in range(3):
                    vel[b, d] = start_vel[b, d]
            for c in range(n):
                rows[c, PN] = 0.0
                rows[c, PT] = 0.0
        held, failed, worst = contact_impulses(settings, scratch, counters, vel, inv_mass, inv_inertia, n, tau,
                                               remaining - tau, load_x, load_y, relaxation, passes_allowed,
                                               connector_law, connectors)
        if not failed:
            break
        if attempt + 1 == tries:
            return STATUS_UNCONVERGED, worst, worst, tau
    mid = scratch.mid
    integrate(pos, start_vel, vel, mid, tau, real[THETA])
    project_positions(pos, mid, scratch.turn, inv_mass, inv_inertia, rows, ints, n, tau, real[SLOP],
                      integer[PROJECTION_SWEEPS], scratch.shift, not held, integer[STATUS_PASSES] > 0,
                      scratch.point_status, scratch.jacobian, scratch.response, scratch.band, scratch.rhs,
                      scratch.band_first, scratch.band_last, scratch.band_end)
    keep_impulses(rows, ints, n, state.normal_impulse, state.tangential_impulse, state.pair_slip, ids,
                  scratch.base_impulse, vel, tau)
    commit_connectors(rows, ints, n, vel, connector_law, connectors, counters[STEP])
    reaction = scratch.reaction
    reaction[0, 0] = scratch.base_impulse[0] / tau
    reaction[0, 1] = scratch.base_impulse[1] / tau
    ground_work(reaction, mid, model.body[MASS], load_x, load_y, tau, state.ledger)
    return STATUS_OK, 0, 0, tau
