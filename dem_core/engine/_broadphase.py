"""Compiled broad phase: which pairs of bodies can touch (docs/method.md 1.2).

Private module.  Boxes around the bodies, grown by half a skin, are sorted along the axis where the
bodies spread most and swept (sort-and-sweep); the pairs whose boxes overlap on both axes are the
candidates, listed again only when a body has moved half a skin.  The list is kept sorted by
``key = i * nb + j``, which lets the contact memory of pairs that stay carry over by a merge and
lets per-pair lookups (friction overrides, recorded interfaces) be binary searches.  Cost: a sort,
and a sweep proportional to the bodies plus the overlaps along the sweep axis; a long epistyle
overlaps many drums along x but is kept apart from the lower drums by the y test.
"""

import math

import numba as nb
import numpy as np

from ._contact_law import pair_parameters
from .state import C_N, C_R, C_T, K_N, K_T, MU, PAIR_I, PAIR_INTERFACE, PAIR_J, PAIR_KEY, SLIP, Retired, empty_contacts


@nb.njit(cache=True)
def bounding_boxes(wx, wy, vstart, lo_x, hi_x, lo_y, hi_y):
    """Axis-aligned boxes (m) of every body from its world vertices."""
    for b in range(vstart.shape[0] - 1):
        x0 = math.inf
        x1 = -math.inf
        y0 = math.inf
        y1 = -math.inf
        for k in range(vstart[b], vstart[b + 1]):
            x0 = min(x0, wx[k])
            x1 = max(x1, wx[k])
            y0 = min(y0, wy[k])
            y1 = max(y1, wy[k])
        lo_x[b] = x0
        hi_x[b] = x1
        lo_y[b] = y0
        hi_y[b] = y1


@nb.njit(cache=True)
def candidate_keys(lo_x, hi_x, lo_y, hi_y, margin):
    """Sorted int64 keys ``i * n + j`` (i < j) of the pairs whose boxes, each grown by ``margin`` (m),
    overlap."""
    n = lo_x.shape[0]
    spread_x = 0.0
    spread_y = 0.0
    if n > 1:
        cx = 0.5 * (lo_x + hi_x)
        cy = 0.5 * (lo_y + hi_y)
        spread_x = np.var(cx[1:]) if n > 2 else 0.0
        spread_y = np.var(cy[1:]) if n > 2 else 0.0
    if spread_y > spread_x:
        lo_a, hi_a, lo_b, hi_b = lo_y, hi_y, lo_x, hi_x
    else:
        lo_a, hi_a, lo_b, hi_b = lo_x, hi_x, lo_y, hi_y
    order = np.argsort(lo_a)
    keys = np.empty(4 * n + 4, np.int64)
    m = 0
    reach = 2.0 * margin
    for a in range(n):
        p = order[a]
        for c in range(a + 1, n):
            q = order[c]
            if lo_a[q] > hi_a[p] + reach:
                break
            if lo_b[q] > hi_b[p] + reach or lo_b[p] > hi_b[q] + reach:
                continue
            if m == keys.shape[0]:
                grown = np.empty(2 * keys.shape[0], np.int64)
                grown[:m] = keys[:m]
                keys = grown
            keys[m] = min(p, q) * n + max(p, q)
            m += 1
    return np.sort(keys[:m])


@nb.njit(cache=True)
def find_sorted(keys, count, key):
    """Index of ``key`` in the sorted ``keys[:count]``, or -1."""
    lo = 0
    hi = count
    while lo < hi:
        mid = (lo + hi) >> 1
        if keys[mid] < key:
            lo = mid + 1
        else:
            hi = mid
    if lo < count and keys[lo] == key:
        return lo
    return -1


@nb.njit(cache=True)
def _grow_i(a, count, capacity):
    out = np.full(capacity, -1, np.int64)
    out[:count] = a[:count]
    return out


@nb.njit(cache=True)
def _grow_f(a, count, capacity):
    out = np.zeros(capacity)
    out[:count] = a[:count]
    return out


@nb.njit(cache=True)
def retire(retired, key, slip):
    """Keep the slip of a pair leaving the list; returns the (possibly grown) :class:`Retired`."""
    c = retired.count[0]
    if c == retired.key.shape[0]:
        retired = Retired(_grow_i(retired.key, c, 2 * c + 4), _grow_f(retired.slip, c, 2 * c + 4), retired.count)
    retired.key[c] = key
    retired.slip[c] = slip
    retired.count[0] = c + 1
    return retired


@nb.njit(cache=True)
def relist(bodies, law, interface_keys, contacts, retired, keys):
    """A new candidate list for the sorted ``keys``, carrying over the memory of the pairs that stay in
    ``contacts`` and computing the constants of the new ones; pairs that leave hand their slip to
    ``retired``.  Returns ``(contacts, retired)``."""
    n = bodies.mass.shape[0]
    m = keys.shape[0]
    new = empty_contacts(max(m, 1))
    old_ids = contacts.ids
    n_old = contacts.count[0]
    a = 0
    for p in range(m):
        key = keys[p]
        while a < n_old and old_ids[a, PAIR_KEY] < key:
            if contacts.forces[a, SLIP] > 0.0:
                retired = retire(retired, old_ids[a, PAIR_KEY], contacts.forces[a, SLIP])
            a += 1
        i = key // n
        j = key - i * n
        new.ids[p, PAIR_I] = i
        new.ids[p, PAIR_J] = j
        new.ids[p, PAIR_KEY] = key
        new.ids[p, PAIR_INTERFACE] = find_sorted(interface_keys, interface_keys.shape[0], key)
        if a < n_old and old_ids[a, PAIR_KEY] == key:
            new.memory[p, :] = contacts.memory[a, :]
            new.forces[p, :] = contacts.forces[a, :]
            a += 1
        else:
            new.forces[p, :] = 0.0
        k_n, c_n, k_t, c_t, c_r, _, _ = pair_parameters(
            law.law, law.kn, law.zeta_n, law.zeta_t, law.zeta_r, law.kt_ratio, law.cn, law.cr, law.kt, law.ct,
            bodies.mass[i], bodies.mass[j], bodies.width[i], bodies.width[j], bodies.depth[i], bodies.depth[j])
        f = find_sorted(law.friction_keys, law.friction_keys.shape[0], key)
        mu = law.friction_values[f] if f >= 0 else min(bodies.friction[i], bodies.friction[j])
        c = new.constants
        c[p, K_N] = k_n
        c[p, C_N] = c_n
        c[p, K_T] = k_t
        c[p, C_T] = c_t
        c[p, C_R] = c_r
        c[p, MU] = mu
    while a < n_old:
        if contacts.forces[a, SLIP] > 0.0:
            retired = retire(retired, old_ids[a, PAIR_KEY], contacts.forces[a, SLIP])
        a += 1
    new.count[0] = m
    return new, retired
