"""Compiled: the connectors across joints in both integrators (docs/method.md 1.12).

Private module.  A connector belongs to a recorded interface (ModelArrays ``connector_start``, per interface its
connectors' range) and acts while that interface's pair is listed, whether or not its blocks touch.  Its anchors,
one in each body, coincide at the start; :func:`connector_geometry` gives the second's place relative to the
first's along the joint and across it, whose laws are :mod:`._connector_law`'s.

* Central differences (:func:`connector_forces`): the law at the present positions gives a force, added to the
  pair's resultants; the connector's state moves with each step.
* Moreau-Jean: a connector is a row of the contact problem (:mod:`._points`), after its pair's points
  (:func:`connector_rows`).  Over a part of ``h`` s the law is taken at the part's end, ``delta+ = delta +
  h ((1 - theta) u + theta u+)``, so that each unknown's impulse ``P = -h F(delta+)`` on the branch it is on is
  affine in ``u+``: compliant, ``u+ + C P = target`` with ``C = 1 / (h^2 theta k)``, or fixed where the branch
  has no stiffness (apart, perfectly plastic).  The solve finds each unknown's branch as it finds the points'
  statuses (:func:`update_branches`); a stiff bar is then as stable at Moreau-Jean's step as a rigid contact.
  After the part the state moves to ``delta+`` (:func:`commit_connectors`).
"""

import numba as nb

from ._angles import cosine, sine
from ._connector_law import (ANCHOR_AX, ANCHOR_AY, ANCHOR_BX, ANCHOR_BY, AXIAL_K, AXIS_X, AXIS_Y, IMPULSE_N, IMPULSE_T,
                             SHEAR_FORCE, TENSION, commit, intact, shear_affine, shear_branch, tension_affine)
from ._points import (BRANCH, COMPLIANCE_N, COMPLIANCE_T, CONNECTOR, FIXED, FIXED_N, FIXED_T, FRICTION, GAP, INC,
                      KEY, NX, NY, OPENING0, PAIR, PART, PART_THETA, PN, PT, REACH_N, REACH_T, REF, RIX, RIY, RRX, RRY,
                      SLID, SLIP0, SLOT, TARGET, TARGET_T, U0, U0_T, WNN, WTT, apply_impulse, relative_velocity)
from .state import PAIR_INTERFACE

#: Gauss-Seidel's tries of a connector unknown on the branches its solutions lead to
BRANCH_TRIES = 4


@nb.njit(cache=True, inline="always")
def connector_geometry(pos, a, b, law):
    """``(slip, opening, nx, ny, rbx, rby, rax, ray)`` of a connector between bodies ``a`` and ``b`` at ``pos``
    (nb, 3): its second anchor relative to its first along ``t = (-n_y, n_x)`` and along the joint's normal ``n``
    (m), that normal in the world, and each anchor from its body's centre of mass (m)."""
    ca = cosine(pos[a, 2])
    sa = sine(pos[a, 2])
    cb = cosine(pos[b, 2])
    sb = sine(pos[b, 2])
    rax = ca * law[ANCHOR_AX] - sa * law[ANCHOR_AY]
    ray = sa * law[ANCHOR_AX] + ca * law[ANCHOR_AY]
    rbx = cb * law[ANCHOR_BX] - sb * law[ANCHOR_BY]
    rby = sb * law[ANCHOR_BX] + cb * law[ANCHOR_BY]
    nx = ca * law[AXIS_X] - sa * law[AXIS_Y]
    ny = sa * law[AXIS_X] + ca * law[AXIS_Y]
    dx = pos[b, 0] + rbx - pos[a, 0] - rax
    dy = pos[b, 1] + rby - pos[a, 1] - ray
    return -dx * ny + dy * nx, dx * nx + dy * ny, nx, ny, rbx, rby, rax, ray


@nb.njit(cache=True, inline="always")
def connectors_of(p, ids, start):
    """``(first, end)``: the range of listed pair ``p``'s connectors, those of its recorded interface (empty where
    it has none)."""
    interface = ids[p, PAIR_INTERFACE]
    if interface < 0:
        return 0, 0
    return start[interface], start[interface + 1]


@nb.njit(cache=True, inline="always")
def connector_forces(p, ids, pos, pair_force, law, bodies, start, states, step):
    """Central differences, listed pair ``p``: each intact connector of its interface taken to the present positions
    (:func:`~._connector_law.commit`) and its force added to the pair's row of ``pair_force`` (resultant force and
    moment on the pair's first body, then on its second), as the contact forces are."""
    first, end = connectors_of(p, ids, start)
    for c in range(first, end):
        state = states[c]
        if not intact(state):
            continue
        slip, opening, nx, ny, rbx, rby, rax, ray = connector_geometry(pos, bodies[c, 0], bodies[c, 1], law[c])
        if commit(slip, opening, law[c], state, step):
            continue
        fx = -(state[TENSION] * nx - state[SHEAR_FORCE] * ny)  # on the second body: -(F_a n + F_s t)
        fy = -(state[TENSION] * ny + state[SHEAR_FORCE] * nx)
        pair_force[p, 3] += fx
        pair_force[p, 4] += fy
        pair_force[p, 5] += rbx * fy - rby * fx
        pair_force[p, 0] -= fx
        pair_force[p, 1] -= fy
        pair_force[p, 2] -= rax * fy - ray * fx


@nb.njit(cache=True, inline="always")
def connector_rows(p, ids, pos, vel, law, bodies, start, states, rows, ints, n):
    """Moreau-Jean, listed pair ``p``: each intact connector of its interface into ``rows``/``ints`` from row
    ``n``, with its opening, slip and velocities at the part's start and last step's impulses.  Returns the rows
    filled after it."""
    first, end = connectors_of(p, ids, start)
    for c in range(first, end):
        state = states[c]
        if not intact(state):
            continue
        a = bodies[c, 0]
        b = bodies[c, 1]
        slip, opening, nx, ny, rbx, rby, rax, ray = connector_geometry(pos, a, b, law[c])
        u_n, u_t = relative_velocity(vel, b, a, rbx, rby, rax, ray, nx, ny)
        row = rows[n]
        row[NX] = nx
        row[NY] = ny
        row[RIX] = rbx
        row[RIY] = rby
        row[RRX] = rax
        row[RRY] = ray
        row[FRICTION] = 0.0
        row[GAP] = 0.0
        row[U0] = u_n
        row[U0_T] = u_t
        row[OPENING0] = opening
        row[SLIP0] = slip
        row[PN] = state[IMPULSE_N]
        row[PT] = state[IMPULSE_T]
        ints[n, INC] = b
        ints[n, REF] = a
        ints[n, PAIR] = p
        ints[n, SLOT] = -1
        ints[n, KEY] = -1
        ints[n, SLID] = 0
        ints[n, CONNECTOR] = c
        ints[n, BRANCH] = -1
        n += 1
    return n


@nb.njit(cache=True, inline="always")
def unknown_coefficients(k, f0, reach, h, h_theta):
    """``(compliance, target, fixed)`` of an unknown whose force is ``F = k delta+ + f0`` with ``delta+ = reach +
    h_theta u+`` over a part of ``h`` s: ``u+ + C P = target`` where ``k > 0``, else the impulse fixed at
    ``-h f0``."""
    if k > 0.0:
        return 1.0 / (h * h_theta * k), -(reach + f0 / k) / h_theta, 0.0
    return FIXED, 0.0, -h * f0


@nb.njit(cache=True, inline="always")
def set_branches(row, ints, c, axial, shear, law, state):
    """Connector row ``c`` put on tension branch ``axial`` (1: taut, 0: slack) and shear branch ``shear``
    (:func:`~._connector_law.shear_branch`): its unknowns' coefficients (:func:`unknown_coefficients`)."""
    ka = law[AXIAL_K] if axial == 1 else 0.0
    row[COMPLIANCE_N], row[TARGET], row[FIXED_N] = unknown_coefficients(ka, 0.0, row[REACH_N], row[PART],
                                                                        row[PART_THETA])
    ks, fs = shear_affine(shear, law, state)
    row[COMPLIANCE_T], row[TARGET_T], row[FIXED_T] = unknown_coefficients(ks, fs, row[REACH_T], row[PART],
                                                                          row[PART_THETA])
    ints[c, BRANCH] = 2 * shear + axial


@nb.njit(cache=True, inline="always")
def update_branches(rows, ints, c, u_n, u_t, law, states):
    """Connector row ``c``'s branches where its velocities ``u_n``, ``u_t`` (m/s) take it by the part's end, set if
    they changed (:func:`set_branches`).  Returns whether they changed."""
    row = rows[c]
    k = ints[c, CONNECTOR]
    opening = row[REACH_N] + row[PART_THETA] * u_n
    ka, _ = tension_affine(opening, law[k])
    axial = 1 if ka > 0.0 else 0
    shear = shear_branch(row[REACH_T] + row[PART_THETA] * u_t, law[k], states[k])
    if 2 * shear + axial == ints[c, BRANCH]:
        return False
    set_branches(row, ints, c, axial, shear, law[k], states[k])
    return True


@nb.njit(cache=True, inline="always")
def connector_coefficients(vel, rows, ints, n, h, theta, law, states):
    """Every connector row among the ``n`` for a part of ``h`` s: where its opening and slip reach at its start
    velocities alone, ``delta + h (1 - theta) u``, and its branches at the velocities ``vel``."""
    for c in range(n):
        if ints[c, CONNECTOR] < 0:
            continue
        row = rows[c]
        row[PART] = h
        row[PART_THETA] = h * theta
        row[REACH_N] = row[OPENING0] + h * (1.0 - theta) * row[U0]
        row[REACH_T] = row[SLIP0] + h * (1.0 - theta) * row[U0_T]
        ints[c, BRANCH] = -1
        u_n, u_t = relative_velocity(vel, ints[c, INC], ints[c, REF], row[RIX], row[RIY], row[RRX], row[RRY],
                                     row[NX], row[NY])
        update_branches(rows, ints, c, u_n, u_t, law, states)


@nb.njit(cache=True, inline="always")
def unknown_impulse(own, compliance, target, fixed, rest):
    """The impulse (N s) of one unknown with the others fixed: its velocity is ``rest + own P`` (``own`` its
    Delassus entry, 1/kg), compliant or fixed."""
    if compliance == FIXED:
        return fixed
    return (target - rest) / (own + compliance)


@nb.njit(cache=True, inline="always")
def commit_connectors(rows, ints, n, vel, law, states, step):
    """After a part: every connector row's state taken to where its velocities ``vel`` take it by the part's end
    (:func:`~._connector_law.commit`), its impulses kept for the next part's warm start."""
    for c in range(n):
        k = ints[c, CONNECTOR]
        if k < 0:
            continue
        row = rows[c]
        u_n, u_t = relative_velocity(vel, ints[c, INC], ints[c, REF], row[RIX], row[RIY], row[RRX], row[RRY],
                                     row[NX], row[NY])
        state = states[k]
        state[IMPULSE_N] = row[PN]
        state[IMPULSE_T] = row[PT]
        commit(row[REACH_T] + row[PART_THETA] * u_t, row[REACH_N] + row[PART_THETA] * u_n, law[k], state, step)


@nb.njit(cache=True, inline="always")
def free_unknowns(rows, c):
    """``(tension free, shear free)``: which of connector row ``c``'s unknowns are compliant."""
    return rows[c, COMPLIANCE_N] != FIXED, rows[c, COMPLIANCE_T] != FIXED


@nb.njit(cache=True, inline="always")
def connector_error(rows, c, u_n, u_t):
    """The largest residual (m/s) of connector row ``c``'s compliant equations at its velocities."""
    row = rows[c]
    error = 0.0
    if row[COMPLIANCE_N] != FIXED:
        error = abs(u_n + row[COMPLIANCE_N] * row[PN] - row[TARGET])
    if row[COMPLIANCE_T] != FIXED:
        error = max(error, abs(u_t + row[COMPLIANCE_T] * row[PT] - row[TARGET_T]))
    return error


@nb.njit(cache=True, inline="always")
def connector_sweep(vel, inv_mass, inv_inertia, rows, ints, c, relaxation, law, states):
    """Gauss-Seidel on connector row ``c``: its tension, then its shear impulse, each solved with everything else
    fixed (:func:`unknown_impulse`) on its branch, taken again on the branch that solution leads to (BRANCH_TRIES
    times at most), and moved ``relaxation`` of the way there.  Returns the largest change of its velocities (m/s)."""
    row = rows[c]
    i = ints[c, INC]
    r = ints[c, REF]
    change = 0.0
    for unknown in range(2):
        for _ in range(BRANCH_TRIES):
            u_n, u_t = relative_velocity(vel, i, r, row[RIX], row[RIY], row[RRX], row[RRY], row[NX], row[NY])
            if unknown == 0:
                own, before, u = row[WNN], row[PN], u_n
                after = unknown_impulse(own, row[COMPLIANCE_N], row[TARGET], row[FIXED_N], u - own * before)
            else:
                own, before, u = row[WTT], row[PT], u_t
                after = unknown_impulse(own, row[COMPLIANCE_T], row[TARGET_T], row[FIXED_T], u - own * before)
            step = relaxation * (after - before)
            if step != 0.0:
                dn = step if unknown == 0 else 0.0
                dt_ = step if unknown == 1 else 0.0
                apply_impulse(vel, inv_mass, inv_inertia, i, r, row[RIX], row[RIY], row[RRX], row[RRY],
                              dn * row[NX] - dt_ * row[NY], dn * row[NY] + dt_ * row[NX])
                row[PN] += dn
                row[PT] += dt_
                change = max(change, abs(own * step))
            u_n, u_t = relative_velocity(vel, i, r, row[RIX], row[RIY], row[RRX], row[RRY], row[NX], row[NY])
            if not update_branches(rows, ints, c, u_n, u_t, law, states):
                break
    return change
