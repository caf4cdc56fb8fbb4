"""Compiled direct solve of Moreau-Jean's contact problem by statuses (an active-set method).

Private module, a stage of :mod:`._moreau`.  With every point of the index set given a status, open (no impulse),
sticking (``u_n = target``, ``u_t = 0``) or sliding along ``s`` (``u_n = target``, ``P_t = s mu P_n``), the
impulses solve a linear system in ``P = (P_n, P_t)`` per point, ``u = u0 + W (P - P0)`` with ``W = H M^-1 H^T``
the Delassus matrix of the points.  :func:`solve_statuses` solves it, checks each point against Signorini's and
Coulomb's laws, changes the statuses of the points that break them and solves again (Kostreva's active-set
iteration for LCPs; Acary and Brogliato 2008, section 12.4), a few passes at most.  Statuses that hold give the
step's impulses; where they do not settle, Gauss-Seidel (:func:`._moreau.solve_points`) finishes the solve from
the last pass.

Unknown ``2c`` is point ``c``'s normal impulse and ``2c + 1`` its tangential one.  Two points couple through a
block they share, so with the pairs in the breadth-first order of :func:`pair_order` (Cuthill and McKee 1969) a
chain of blocks (a column) or a tree of a few branches (a colonnade) gives a band matrix of 2 x 2 blocks, one per
pair of points: stored as ``band[c, d - c + BLOCK_REACH]`` (the block's four entries row by row) within the
envelope of each point's last coupled point, built straight from the points' Jacobians with the statuses applied
(:func:`statuses_matrix`) and factorised by blocks without pivoting in O(points x reach^2), the open points' known
impulses carried to the right-hand side, and over the upper triangle alone where no point slides (the matrix is
then symmetric).  A scene whose points span a wider band is left to Gauss-Seidel.

Two points of one flush interface have the same tangential velocity, so their tangential rows are dependent:
every constrained row ``u`` gets a compliance, ``u_u + REGULARISATION W_uu P_u = target``, which makes the
solution the one of least impulse (two sticking points of a face share its friction equally) and moves a
velocity by that fraction of its own impulse's effect.

A connector's row (:mod:`._connectors`) has a status of its own: both unknowns compliant (CONNECTOR_BOTH, its
compliances on the diagonal), one of them (CONNECTOR_TENSION, CONNECTOR_SHEAR: the other's row replaced by its
fixed impulse), or neither (OPEN, both known).  Its statuses follow its branches, revised as the points' are.
"""

import numba as nb
import numpy as np

from ._connectors import connector_error, free_unknowns, update_branches
from ._points import (COMPLIANCE_N, COMPLIANCE_T, CONNECTOR, FIXED_N, FIXED_T, FRICTION, GAP, INC, NX, NY, PN, PT, REF,
                      RIX, RIY, RRX, RRY, SLID, TARGET, TARGET_T, TRAVEL, WNN, WNT, WTT, apply_impulse,
                      relative_velocity)

#: widest half-band (unknowns) solved directly: a column's interfaces couple points up to 3 apart (7 unknowns), an
#: epistyle on N columns up to 2N - 1 (4N - 1 unknowns: 11 on three columns, 27 on seven), so 63 takes an epistyle
#: on sixteen columns; the work grows as the band's square only where a scene needs it
HALF_BAND = 63
#: the same in points: how far apart the points of two coupled 2 x 2 blocks may be
BLOCK_REACH = (HALF_BAND - 1) // 2
#: relative compliance on the diagonal of every constrained row
REGULARISATION = 1e-9
#: relative slack on the friction cone: an impulse this close to its edge counts as on it
CONE_SLACK = 1e-9
OPEN, STICK, SLIDE_UP, SLIDE_DOWN, CONNECTOR_BOTH, CONNECTOR_TENSION, CONNECTOR_SHEAR = range(7)


@nb.njit(cache=True, inline="always")
def pair_order(ids, listed, inv_mass, start, entries, degree, reached, order):
    """The ``listed`` pairs in breadth-first order over the graph whose edges join pairs sharing a movable block,
    each search starting from the first pair not yet reached and taking a pair's neighbours fewest-first
    (Cuthill and McKee 1969), into ``order`` (C,).  ids (C, >= 2) the pairs' blocks; start, entries their
    incidence (:func:`~._broadphase.incidence`); degree, reached (C,) int64 scratch."""
    for p in range(listed):
        degree[p] = 0
        reached[p] = 0
        for k in range(2):
            b = ids[p, k]
            if inv_mass[b] > 0.0:
                degree[p] += start[b + 1] - start[b] - 1
    found = 0
    head = 0
    for seed in range(listed):
        if reached[seed] == 1:
            continue
        reached[seed] = 1
        order[found] = seed
        found += 1
        while head < found:
            p = order[head]
            head += 1
            first_new = found
            for k in range(2):
                b = ids[p, k]
                if inv_mass[b] == 0.0:
                    continue
                for e in range(start[b], start[b + 1]):
                    q = entries[e] >> 1
                    if reached[q] == 0:
                        reached[q] = 1
                        order[found] = q
                        found += 1
            for a in range(first_new + 1, found):  # fewest neighbours first: insertion sort of the new ones
                q = order[a]
                b = a - 1
                while b >= first_new and degree[order[b]] > degree[q]:
                    order[b + 1] = order[b]
                    b -= 1
                order[b + 1] = q


@nb.njit(cache=True, inline="always")
def half_band(ints, inv_mass, n, first, last, end):
    """The half-bandwidth (unknowns) of the ``n`` points' Delassus matrix: how far apart, in unknowns, two points
    sharing a movable block are at most.  ``first``, ``last`` (nb,) receive each movable block's first and last
    point (``last`` -1 for a block no point touches, and for fixed blocks); ``end`` (2n,) the matrix's envelope,
    per unknown the last unknown that it or an earlier one couples to (a running maximum, so that elimination
    fills nothing beyond it)."""
    first[:] = n
    last[:] = -1
    for c in range(n):
        for b in (ints[c, INC], ints[c, REF]):
            if inv_mass[b] > 0.0:
                first[b] = min(first[b], c)
                last[b] = max(last[b], c)
    width = 0
    for b in range(first.shape[0]):
        if last[b] >= 0:
            width = max(width, 2 * (last[b] - first[b]) + 1)
    reach = 0
    for c in range(n):
        for b in (ints[c, INC], ints[c, REF]):
            if inv_mass[b] > 0.0:
                reach = max(reach, 2 * last[b] + 1)
        reach = max(reach, 2 * c + 1)
        end[2 * c] = reach
        end[2 * c + 1] = reach
    return width


@nb.njit(cache=True, inline="always")
def responses(rows, ints, inv_mass, inv_inertia, n, jac, resp):
    """Per unknown ``u`` its Jacobian rows on its point's incident and reference blocks, ``jac[u] = (a, r_i x a,
    -a, -r_r x a)`` (a the direction: the normal, or the tangent ``(-n_y, n_x)``), and the velocity changes of a
    unit impulse along it, ``resp[u] = M^-1 jac[u]`` (per block: m/s and rad/s per N s)."""
    for c in range(n):
        row = rows[c]
        i = ints[c, INC]
        r = ints[c, REF]
        for d in range(2):
            u = 2 * c + d
            ax = row[NX] if d == 0 else -row[NY]
            ay = row[NY] if d == 0 else row[NX]
            jac[u, 0] = ax
            jac[u, 1] = ay
            jac[u, 2] = row[RIX] * ay - row[RIY] * ax
            jac[u, 3] = -ax
            jac[u, 4] = -ay
            jac[u, 5] = -(row[RRX] * ay - row[RRY] * ax)
            resp[u, 0] = inv_mass[i] * jac[u, 0]
            resp[u, 1] = inv_mass[i] * jac[u, 1]
            resp[u, 2] = inv_inertia[i] * jac[u, 2]
            resp[u, 3] = inv_mass[r] * jac[u, 3]
            resp[u, 4] = inv_mass[r] * jac[u, 4]
            resp[u, 5] = inv_inertia[r] * jac[u, 5]


@nb.njit(cache=True, inline="always")
def block(band, c, d):
    """Block ``(c, d)`` of a band matrix of 2 x 2 blocks, point ``c``'s rows and point ``d``'s columns:
    ``(a00, a01, a10, a11)``."""
    k = BLOCK_REACH + d - c
    return band[c, k, 0], band[c, k, 1], band[c, k, 2], band[c, k, 3]


@nb.njit(cache=True, inline="always")
def set_block(band, c, d, a00, a01, a10, a11):
    """Block ``(c, d)`` of a band matrix of 2 x 2 blocks set to ``(a00, a01, a10, a11)``."""
    k = BLOCK_REACH + d - c
    band[c, k, 0] = a00
    band[c, k, 1] = a01
    band[c, k, 2] = a10
    band[c, k, 3] = a11


@nb.njit(cache=True, inline="always")
def first_coupled(c, end):
    """The first point whose envelope (:func:`half_band`) reaches point ``c``."""
    low = c
    while low > 0 and end[2 * (low - 1)] >= 2 * c:
        low -= 1
    return low


@nb.njit(cache=True, inline="always")
def put_block(band, c, d, a00, a01, a10, a11, normal_row, tangential_row, slope):
    """Block ``(c, d)`` of ``W`` into point ``c``'s rows of a statuses' matrix: each row as it is where it is an
    equation in the velocities (``normal_row``, ``tangential_row``), else replaced by one in the impulses alone:
    the normal row by ``P_n`` (a connector's fixed tension), the tangential row by the sliding law's
    ``P_t - slope P_n`` (a fixed shear: slope 0), on the diagonal block, nothing elsewhere."""
    if not normal_row:
        a00, a01 = (1.0, 0.0) if c == d else (0.0, 0.0)
    if not tangential_row:
        a10, a11 = (slope, 1.0) if c == d else (0.0, 0.0)
    set_block(band, c, d, a00, a01, a10, a11)


@nb.njit(cache=True, inline="always")
def equation_rows(status):
    """``(normal, tangential)``: which of a row's two equations, under ``status``, are in the velocities."""
    if status == CONNECTOR_TENSION:
        return True, False
    if status == CONNECTOR_SHEAR:
        return False, True
    return True, status == STICK or status == CONNECTOR_BOTH


@nb.njit(cache=True, inline="always")
def connector_status(rows, c):
    """The status of connector row ``c`` from which of its unknowns are compliant."""
    tension, shear = free_unknowns(rows, c)
    if tension and shear:
        return CONNECTOR_BOTH
    if tension:
        return CONNECTOR_TENSION
    return CONNECTOR_SHEAR if shear else OPEN


@nb.njit(cache=True, inline="always")
def statuses_matrix(status, rows, ints, inv_mass, n, end, friction, jac, resp, band):
    """The band matrix of the statuses' linear system in the impulses (:func:`solve_blocks`), built straight from
    the points' Delassus matrix ``W = H M^-1 H^T`` (1/kg) within the envelope ``end`` (:func:`half_band`): block
    ``(c, d)``, the velocity changes of point ``c``'s (normal, tangential) per unit impulse of point ``d``'s, is
    ``sum_b jac_c M_b^-1 jac_d^T`` over the movable blocks ``b`` the two points share (jac, resp:
    :func:`responses`).  A closed point's normal row is ``W``'s, its tangential row ``W``'s if it sticks, else the
    sliding law's (:func:`put_block`, slope ``-sign friction mu``); every diagonal kept is made compliant by
    ``REGULARISATION``, a connector's compliant unknowns by their compliance; an open point has no rows.  Each
    point's own block, uncompliant, into its row's WNN, WNT, WTT."""
    for c in range(n):
        u = 2 * c
        closed_c = status[c] != OPEN
        for d in range(c, end[u] // 2 + 1):
            closed_d = status[d] != OPEN
            if not (closed_c or closed_d):
                continue
            v = 2 * d
            w00 = w01 = w10 = w11 = 0.0
            for sc in (0, 3):
                b = ints[c, INC] if sc == 0 else ints[c, REF]
                sd = 0 if ints[d, INC] == b else (3 if ints[d, REF] == b else -1)
                if sd < 0 or not inv_mass[b] > 0.0:
                    continue
                a0, a1, a2 = jac[u, sc], jac[u, sc + 1], jac[u, sc + 2]
                t0, t1, t2 = jac[u + 1, sc], jac[u + 1, sc + 1], jac[u + 1, sc + 2]
                p0, p1, p2 = resp[v, sd], resp[v, sd + 1], resp[v, sd + 2]
                q0, q1, q2 = resp[v + 1, sd], resp[v + 1, sd + 1], resp[v + 1, sd + 2]
                w00 += a0 * p0 + a1 * p1 + a2 * p2
                w01 += a0 * q0 + a1 * q1 + a2 * q2
                w10 += t0 * p0 + t1 * p1 + t2 * p2
                w11 += t0 * q0 + t1 * q1 + t2 * q2
            if d == c:
                rows[c, WNN] = w00
                rows[c, WNT] = w01
                rows[c, WTT] = w11
                normal, tangential = equation_rows(status[c])
                if ints[c, CONNECTOR] >= 0:
                    slope = 0.0
                    w00 += rows[c, COMPLIANCE_N] if normal else 0.0
                    w11 += rows[c, COMPLIANCE_T] if tangential else 0.0
                else:
                    slope = -friction * rows[c, FRICTION] * (1.0 if status[c] == SLIDE_UP else -1.0)
                    w00 *= 1.0 + REGULARISATION
                    w11 *= 1.0 + REGULARISATION
                put_block(band, c, c, w00, w01, w10, w11, normal, tangential, slope)
                continue
            if closed_c:
                normal, tangential = equation_rows(status[c])
                put_block(band, c, d, w00, w01, w10, w11, normal, tangential, 0.0)
            if closed_d:
                normal, tangential = equation_rows(status[d])
                put_block(band, d, c, w00, w10, w01, w11, normal, tangential, 0.0)


@nb.njit(cache=True, inline="always")
def statuses_rhs(status, rows, velocity, n, rhs):
    """The right-hand side of the statuses' linear system in the impulses' increments from the present impulses
    ``P0`` (the rows' ``PN``, ``PT``), with the matrix of :func:`statuses_matrix` (friction 1, which fills the
    rows' WNN, WTT): an open point's rows are its known increments ``-P0`` (a connector's, to its fixed impulses).
    status (n,) per point; velocity (2n,) the present ``(u_n, u_t)`` per point (m/s)."""
    for c in range(n):
        row = rows[c]
        s = status[c]
        un = 2 * c
        ut = un + 1
        if s == OPEN:
            rhs[un] = row[FIXED_N] - row[PN]
            rhs[ut] = row[FIXED_T] - row[PT]
            continue
        if s >= CONNECTOR_BOTH:
            normal, tangential = equation_rows(s)
            rhs[un] = (row[TARGET] - velocity[un] - row[COMPLIANCE_N] * row[PN] if normal
                       else row[FIXED_N] - row[PN])
            rhs[ut] = (row[TARGET_T] - velocity[ut] - row[COMPLIANCE_T] * row[PT] if tangential
                       else row[FIXED_T] - row[PT])
            continue
        rhs[un] = row[TARGET] - velocity[un] - REGULARISATION * row[WNN] * row[PN]
        if s == STICK:
            rhs[ut] = -velocity[ut] - REGULARISATION * row[WTT] * row[PT]
        else:
            sign = 1.0 if s == SLIDE_UP else -1.0
            rhs[ut] = sign * row[FRICTION] * row[PN] - row[PT]


@nb.njit(cache=True, inline="always")
def solve_blocks(status, band, rhs, n, end, symmetric):
    """Solve the statuses' system (:func:`statuses_matrix`, :func:`statuses_rhs`) in place, the solution into ``rhs``
    (2n,): the open points' known increments carried to the others' right-hand sides, then block Gaussian
    elimination over the other points' 2 x 2 blocks without pivoting, within the envelope ``end``; in a
    ``symmetric`` matrix over its upper triangle alone (``LDL^T``: half the work).  Returns False if a pivot
    block is not clearly regular: its determinant below 1e-12 of its terms."""
    for c in range(n):
        if status[c] != OPEN:
            continue
        xn = rhs[2 * c]
        xt = rhs[2 * c + 1]
        for d in range(first_coupled(c, end), end[2 * c] // 2 + 1):
            if d == c or status[d] == OPEN:
                continue
            w00, w01, w10, w11 = block(band, d, c)
            rhs[2 * d] -= w00 * xn + w01 * xt
            rhs[2 * d + 1] -= w10 * xn + w11 * xt
    for c in range(n):
        if status[c] == OPEN:
            continue
        last = end[2 * c] // 2
        p00, p01, p10, p11 = block(band, c, c)
        det = p00 * p11 - p01 * p10
        if not abs(det) > 1e-12 * max(abs(p00 * p11), abs(p01 * p10)):
            return False
        i00 = p11 / det
        i01 = -p01 / det
        i10 = -p10 / det
        i11 = p00 / det
        r0 = rhs[2 * c]
        r1 = rhs[2 * c + 1]
        for d in range(c + 1, last + 1):
            if status[d] == OPEN:
                continue
            if symmetric:
                a00, a10, a01, a11 = block(band, c, d)
            else:
                a00, a01, a10, a11 = block(band, d, c)
            if a00 == 0.0 and a01 == 0.0 and a10 == 0.0 and a11 == 0.0:
                continue
            l00 = a00 * i00 + a01 * i10
            l01 = a00 * i01 + a01 * i11
            l10 = a10 * i00 + a11 * i10
            l11 = a10 * i01 + a11 * i11
            for e in range(d if symmetric else c + 1, last + 1):
                if status[e] == OPEN:
                    continue
                b00, b01, b10, b11 = block(band, c, e)
                f00, f01, f10, f11 = block(band, d, e)
                set_block(band, d, e, f00 - (l00 * b00 + l01 * b10), f01 - (l00 * b01 + l01 * b11),
                          f10 - (l10 * b00 + l11 * b10), f11 - (l10 * b01 + l11 * b11))
            rhs[2 * d] -= l00 * r0 + l01 * r1
            rhs[2 * d + 1] -= l10 * r0 + l11 * r1
    for c in range(n - 1, -1, -1):
        if status[c] == OPEN:
            continue
        r0 = rhs[2 * c]
        r1 = rhs[2 * c + 1]
        for e in range(c + 1, end[2 * c] // 2 + 1):
            if status[e] == OPEN:
                continue
            b00, b01, b10, b11 = block(band, c, e)
            r0 -= b00 * rhs[2 * e] + b01 * rhs[2 * e + 1]
            r1 -= b10 * rhs[2 * e] + b11 * rhs[2 * e + 1]
        p00, p01, p10, p11 = block(band, c, c)
        det = p00 * p11 - p01 * p10
        rhs[2 * c] = (p11 * r0 - p01 * r1) / det
        rhs[2 * c + 1] = (p00 * r1 - p10 * r0) / det
    return True


@nb.njit(cache=True, inline="always")
def revise(status, rows, ints, velocity, n, tolerance, connector_law, connectors):
    """Each point's status checked against its impulses and velocities (m/s, ``tolerance`` m/s of slack) and
    changed where it breaks Signorini's or Coulomb's law: an open point approaching faster than its target
    closes (sticks), a point pulling (``P_n < 0``) opens, a sticking point outside the cone slides along its
    impulse, a sliding point whose slip runs with its friction sticks; a connector takes the branches its
    velocities lead to (:func:`~._connectors.update_branches`).  Returns how many changed."""
    changed = 0
    for c in range(n):
        if ints[c, CONNECTOR] >= 0:
            if update_branches(rows, ints, c, velocity[2 * c], velocity[2 * c + 1], connector_law, connectors):
                status[c] = connector_status(rows, c)
                changed += 1
            continue
        s = status[c]
        pn = rows[c, PN]
        pt = rows[c, PT]
        new = s
        if s == OPEN:
            if velocity[2 * c] < rows[c, TARGET] - tolerance:
                new = STICK
        elif pn < 0.0:
            new = OPEN
        elif s == STICK:
            if abs(pt) > rows[c, FRICTION] * pn * (1.0 + CONE_SLACK):
                new = SLIDE_UP if pt > 0.0 else SLIDE_DOWN
        else:
            sign = 1.0 if s == SLIDE_UP else -1.0
            if sign * velocity[2 * c + 1] > tolerance:
                new = STICK
        if new != s:
            status[c] = new
            changed += 1
    return changed


@nb.njit(cache=True, inline="always")
def equation_error(status, rows, ints, velocity, n):
    """The largest residual (m/s) of the statuses' velocity equations at ``velocity``: ``u_n - target`` of every
    closed point, ``u_t`` of every sticking one and a connector's compliant equations."""
    error = 0.0
    for c in range(n):
        if ints[c, CONNECTOR] >= 0:
            error = max(error, connector_error(rows, c, velocity[2 * c], velocity[2 * c + 1]))
            continue
        if status[c] != OPEN:
            error = max(error, abs(velocity[2 * c] - rows[c, TARGET]))
        if status[c] == STICK:
            error = max(error, abs(velocity[2 * c + 1]))
    return error


@nb.njit(cache=True, inline="always")
def point_velocities(vel, rows, ints, n, velocity):
    """``velocity`` (2n,): each point's ``(u_n, u_t)`` (m/s) at the velocities ``vel``."""
    for c in range(n):
        row = rows[c]
        velocity[2 * c], velocity[2 * c + 1] = relative_velocity(vel, ints[c, INC], ints[c, REF], row[RIX], row[RIY],
                                                                 row[RRX], row[RRY], row[NX], row[NY])


@nb.njit(cache=True, inline="always")
def solve_statuses(vel, inv_mass, inv_inertia, rows, ints, n, tolerance, passes, status, velocity, jac, resp, band,
                   rhs, first, last, end, connector_law, connectors):
    """Stage 4 of :mod:`._moreau` (Gauss-Seidel follows only where the statuses do not hold): the ``n`` points'
    impulses (their rows' ``PN``, ``PT``, already applied to ``vel``) replaced by the solution of their statuses'
    linear system, the statuses revised (:func:`revise`, ``tolerance`` m/s) and the system solved again, up to
    ``passes`` times.  The statuses hold when a pass changes none and its solution meets their equations to
    ``tolerance`` (:func:`equation_error`).  The first statuses
    come from the present impulses (a point pushing sticks, or slides if its impulse is on the cone's edge) and
    else from the geometry (a point touching or approaching faster than its target sticks); a connector's from its
    branches (connector_law, connectors: the model's and the state's rows).  Returns ``(whether the
    statuses held, passes taken)``: not held also where the points' band is wider than ``HALF_BAND`` or a pivot
    vanished, with ``vel`` and the rows consistent either way.  Statuses that hold mark the sliding points
    (``ints[:, SLID]``)."""
    if n == 0 or passes == 0:
        return False, 0
    width = half_band(ints, inv_mass, n, first, last, end)
    if width > HALF_BAND:
        return False, 0
    point_velocities(vel, rows, ints, n, velocity)
    for c in range(n):
        pn = rows[c, PN]
        pt = rows[c, PT]
        if ints[c, CONNECTOR] >= 0:
            status[c] = connector_status(rows, c)
        elif rows[c, TARGET] == -np.inf:
            status[c] = OPEN
        elif pn > 0.0:
            status[c] = STICK
            if abs(pt) >= rows[c, FRICTION] * pn * (1.0 - CONE_SLACK):
                status[c] = SLIDE_UP if pt > 0.0 else SLIDE_DOWN
        elif rows[c, GAP] <= 0.0 or velocity[2 * c] < rows[c, TARGET] - tolerance:
            status[c] = STICK
        else:
            status[c] = OPEN
    responses(rows, ints, inv_mass, inv_inertia, n, jac, resp)
    for done in range(1, passes + 1):
        symmetric = True
        for c in range(n):
            symmetric = symmetric and (status[c] <= STICK or status[c] == CONNECTOR_BOTH)
        statuses_matrix(status, rows, ints, inv_mass, n, end, 1.0, jac, resp, band)
        statuses_rhs(status, rows, velocity, n, rhs)
        if not solve_blocks(status, band, rhs, n, end, symmetric):
            return False, done
        for c in range(n):
            row = rows[c]
            dn = rhs[2 * c]
            dt_ = rhs[2 * c + 1]
            apply_impulse(vel, inv_mass, inv_inertia, ints[c, INC], ints[c, REF], row[RIX], row[RIY], row[RRX],
                          row[RRY], dn * row[NX] - dt_ * row[NY], dn * row[NY] + dt_ * row[NX])
            row[PN] += dn
            row[PT] += dt_
        point_velocities(vel, rows, ints, n, velocity)
        if revise(status, rows, ints, velocity, n, tolerance, connector_law, connectors) == 0:
            if equation_error(status, rows, ints, velocity, n) > tolerance:
                return False, done
            for c in range(n):
                ints[c, SLID] = 1 if status[c] == SLIDE_UP or status[c] == SLIDE_DOWN else 0
            return True, done
    return False, passes


@nb.njit(cache=True, inline="always")
def solve_positions(rows, ints, inv_mass, n, slop, end, status, jac, resp, band, rhs):
    """Step 5 of :mod:`._moreau` directly: the position impulses (kg m, per point ``(normal, tangential)`` into
    ``rhs``) that bring each pushing point to its face (``GAP`` to 0), each sticking point back along its face
    (``TRAVEL`` to 0) and each other point deeper than ``slop`` m to ``-slop``, the others free, with the Delassus
    matrix of the velocity solve (its Jacobians ``jac``, ``resp``: :func:`responses`; envelope ``end``): the
    linearised geometry is the velocity problem's, so one solve (:func:`solve_blocks`) gives what Gauss-Seidel
    sweeps approach.  ``status`` (n,) scratch: each point's part in it, a free point open, a pushing point that
    slid free along its face.  Returns False where a pivot vanished."""
    symmetric = True
    for c in range(n):
        row = rows[c]
        pushed = row[PN] > 0.0 and ints[c, CONNECTOR] < 0
        sticks = pushed and ints[c, SLID] == 0
        status[c] = STICK if sticks else (SLIDE_UP if pushed or row[GAP] < -slop else OPEN)
        symmetric = symmetric and status[c] != SLIDE_UP
        rhs[2 * c] = 0.0 if status[c] == OPEN else (-row[GAP] if pushed else -slop - row[GAP])
        rhs[2 * c + 1] = -row[TRAVEL] if sticks else 0.0
    statuses_matrix(status, rows, ints, inv_mass, n, end, 0.0, jac, resp, band)
    return solve_blocks(status, band, rhs, n, end, symmetric)
