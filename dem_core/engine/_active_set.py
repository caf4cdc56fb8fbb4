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
chain of blocks (a column) or a tree of a few branches (a colonnade) gives a band matrix: stored as
``band[u, v - u + HALF_BAND]`` and factorised without pivoting in O(unknowns x band^2).  A scene whose points
span a wider band is left to Gauss-Seidel.

Two points of one flush interface have the same tangential velocity, so their tangential rows are dependent:
every constrained row ``u`` gets a compliance, ``u_u + REGULARISATION W_uu P_u = target``, which makes the
solution the one of least impulse (two sticking points of a face share its friction equally) and moves a
velocity by that fraction of its own impulse's effect.
"""

import numba as nb
import numpy as np

from ._points import (FRICTION, GAP, INC, NX, NY, PN, PT, REF, RIX, RIY, RRX, RRY, SLID, TARGET, TRAVEL,
                      apply_impulse, relative_velocity)

#: widest half-band (unknowns) solved directly: a column's interfaces couple points up to 3 apart (7 unknowns), an
#: epistyle on N columns up to 2N - 1 (4N - 1 unknowns: 11 on three columns, 27 on seven), so 63 takes an epistyle
#: on sixteen columns; the work grows as the band's square only where a scene needs it
HALF_BAND = 63
#: relative compliance on the diagonal of every constrained row
REGULARISATION = 1e-9
#: relative slack on the friction cone: an impulse this close to its edge counts as on it
CONE_SLACK = 1e-9
OPEN, STICK, SLIDE_UP, SLIDE_DOWN = 0, 1, 2, 3


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
def half_band(ints, inv_mass, n, first, last):
    """The half-bandwidth (unknowns) of the ``n`` points' Delassus matrix: how far apart, in unknowns, two points
    sharing a movable block are at most.  ``first``, ``last`` (nb,) receive each movable block's first and last
    point (``last`` -1 for a block no point touches, and for fixed blocks)."""
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
def delassus_band(ints, n, width, first, last, jac, resp, delassus):
    """The ``n`` points' Delassus matrix ``W`` (1/kg) in band storage, ``delassus[u, v - u + HALF_BAND]`` the
    velocity change of unknown ``u``'s row per unit impulse of unknown ``v``: per movable block ``b`` and pair of
    points on it (among points ``first[b]`` to ``last[b]``, :func:`half_band`) the 2 x 2 block ``jac M_b^-1
    jac^T``, and its transpose below the diagonal."""
    for u in range(2 * n):
        for k in range(HALF_BAND - width, HALF_BAND + width + 1):
            delassus[u, k] = 0.0
    for b in range(first.shape[0]):
        for c in range(first[b], last[b] + 1):
            sc = 0 if ints[c, INC] == b else (3 if ints[c, REF] == b else -1)
            if sc < 0:
                continue
            for d in range(c, last[b] + 1):
                sd = 0 if ints[d, INC] == b else (3 if ints[d, REF] == b else -1)
                if sd < 0:
                    continue
                for a in range(2):
                    u = 2 * c + a
                    for e in range(2):
                        v = 2 * d + e
                        w = (jac[u, sc] * resp[v, sd] + jac[u, sc + 1] * resp[v, sd + 1]
                             + jac[u, sc + 2] * resp[v, sd + 2])
                        delassus[u, v - u + HALF_BAND] += w
                        if d != c:
                            delassus[v, u - v + HALF_BAND] += w


@nb.njit(cache=True, inline="always")
def assemble(status, rows, velocity, delassus, n, width, band, rhs):
    """The band matrix and right-hand side of the statuses' linear system in the impulses' increments from the
    present impulses ``P0`` (the rows' ``PN``, ``PT``).

    status (n,) per point; velocity (2n,) the present ``(u_n, u_t)`` per point (m/s); delassus the points'
    Delassus matrix (:func:`delassus_band`)."""
    lo = HALF_BAND - width
    hi = HALF_BAND + width + 1
    for c in range(n):
        row = rows[c]
        s = status[c]
        un = 2 * c
        ut = un + 1
        for k in range(lo, hi):
            band[un, k] = 0.0 if s == OPEN else delassus[un, k]
            band[ut, k] = delassus[ut, k] if s == STICK else 0.0
        if s == OPEN:
            band[un, HALF_BAND] = 1.0
            rhs[un] = -row[PN]
        else:
            band[un, HALF_BAND] *= 1.0 + REGULARISATION
            rhs[un] = row[TARGET] - velocity[un] - REGULARISATION * delassus[un, HALF_BAND] * row[PN]
        if s == STICK:
            band[ut, HALF_BAND] *= 1.0 + REGULARISATION
            rhs[ut] = -velocity[ut] - REGULARISATION * delassus[ut, HALF_BAND] * row[PT]
        elif s == OPEN:
            band[ut, HALF_BAND] = 1.0
            rhs[ut] = -row[PT]
        else:
            sign = 1.0 if s == SLIDE_UP else -1.0
            band[ut, HALF_BAND] = 1.0
            band[ut, HALF_BAND - 1] = -sign * row[FRICTION]
            rhs[ut] = sign * row[FRICTION] * row[PN] - row[PT]


@nb.njit(cache=True, inline="always")
def solve_band(band, rhs, size, width):
    """Solve ``A x = rhs`` in place (x into ``rhs``) for the band matrix ``A`` (``size`` unknowns, half-band
    ``width``) by Gaussian elimination without pivoting.  Returns False if a pivot is not clearly non-zero: below
    1e-12 of the largest entry of its row within the band at its turn."""
    for k in range(size):
        pivot = band[k, HALF_BAND]
        reach = min(size, k + width + 1) - k  # the row's entries from the diagonal on
        scale = 0.0
        for j in range(HALF_BAND - min(k, width), HALF_BAND + reach):
            scale = max(scale, abs(band[k, j]))
        if not abs(pivot) > 1e-12 * scale:
            return False
        inverse = 1.0 / pivot
        for i in range(k + 1, k + reach):
            at = k - i + HALF_BAND  # column k in row i
            factor = band[i, at] * inverse
            if factor == 0.0:
                continue
            for j in range(1, reach):
                band[i, at + j] -= factor * band[k, HALF_BAND + j]
            rhs[i] -= factor * rhs[k]
    for k in range(size - 1, -1, -1):
        total = rhs[k]
        for j in range(1, min(size, k + width + 1) - k):
            total -= band[k, HALF_BAND + j] * rhs[k + j]
        rhs[k] = total / band[k, HALF_BAND]
    return True


@nb.njit(cache=True, inline="always")
def revise(status, rows, velocity, n, tolerance):
    """Each point's status checked against its impulses and velocities (m/s, ``tolerance`` m/s of slack) and
    changed where it breaks Signorini's or Coulomb's law: an open point approaching faster than its target
    closes (sticks), a point pulling (``P_n < 0``) opens, a sticking point outside the cone slides along its
    impulse, a sliding point whose slip runs with its friction sticks.  Returns how many changed."""
    changed = 0
    for c in range(n):
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
def equation_error(status, rows, velocity, n):
    """The largest residual (m/s) of the statuses' velocity equations at ``velocity``: ``u_n - target`` of every
    closed point and ``u_t`` of every sticking one."""
    error = 0.0
    for c in range(n):
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
def solve_statuses(vel, inv_mass, inv_inertia, rows, ints, n, tolerance, passes, status, velocity, jac, resp, delassus,
                   band, rhs, first, last):
    """Stage 4 of :mod:`._moreau` (Gauss-Seidel follows only where the statuses do not hold): the ``n`` points'
    impulses (their rows' ``PN``, ``PT``, already applied to ``vel``) replaced by the solution of their statuses'
    linear system, the statuses revised (:func:`revise`, ``tolerance`` m/s) and the system solved again, up to
    ``passes`` times.  The statuses hold when a pass changes none and its solution meets their equations to
    ``tolerance`` (:func:`equation_error`).  The first statuses
    come from the present impulses (a point pushing sticks, or slides if its impulse is on the cone's edge) and
    else from the geometry (a point touching or approaching faster than its target sticks).  Returns ``(whether the
    statuses held, passes taken)``: not held also where the points' band is wider than ``HALF_BAND`` or a pivot
    vanished, with ``vel`` and the rows consistent either way.  Statuses that hold mark the sliding points
    (``ints[:, SLID]``)."""
    if n == 0 or passes == 0:
        return False, 0
    width = half_band(ints, inv_mass, n, first, last)
    if width > HALF_BAND:
        return False, 0
    point_velocities(vel, rows, ints, n, velocity)
    for c in range(n):
        pn = rows[c, PN]
        pt = rows[c, PT]
        if rows[c, TARGET] == -np.inf:
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
    delassus_band(ints, n, width, first, last, jac, resp, delassus)
    for done in range(1, passes + 1):
        assemble(status, rows, velocity, delassus, n, width, band, rhs)
        if not solve_band(band, rhs, 2 * n, width):
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
        if revise(status, rows, velocity, n, tolerance) == 0:
            if equation_error(status, rows, velocity, n) > tolerance:
                return False, done
            for c in range(n):
                ints[c, SLID] = 1 if status[c] >= SLIDE_UP else 0
            return True, done
    return False, passes


@nb.njit(cache=True, inline="always")
def solve_positions(rows, ints, n, slop, width, delassus, band, rhs):
    """Step 5 of :mod:`._moreau` directly: the position impulses (kg m, per point ``(normal, tangential)`` into
    ``rhs``) that bring each pushing point to its face (``GAP`` to 0), each sticking point back along its face
    (``TRAVEL`` to 0) and each other point deeper than ``slop`` m to ``-slop``, the others free, with the Delassus
    matrix of the velocity solve (:func:`delassus_band`, half-band ``width``): the linearised geometry is the
    velocity problem's, so one band solve gives what Gauss-Seidel sweeps approach.  Returns False where a pivot
    vanished."""
    lo = HALF_BAND - width
    hi = HALF_BAND + width + 1
    for c in range(n):
        row = rows[c]
        un = 2 * c
        ut = un + 1
        pushed = row[PN] > 0.0
        normal = pushed or row[GAP] < -slop
        sticks = pushed and ints[c, SLID] == 0
        for k in range(lo, hi):
            band[un, k] = delassus[un, k] if normal else 0.0
            band[ut, k] = delassus[ut, k] if sticks else 0.0
        if normal:
            band[un, HALF_BAND] *= 1.0 + REGULARISATION
            rhs[un] = -row[GAP] if pushed else -slop - row[GAP]
        else:
            band[un, HALF_BAND] = 1.0
            rhs[un] = 0.0
        if sticks:
            band[ut, HALF_BAND] *= 1.0 + REGULARISATION
            rhs[ut] = -row[TRAVEL]
        else:
            band[ut, HALF_BAND] = 1.0
            rhs[ut] = 0.0
    return solve_band(band, rhs, 2 * n, width)
