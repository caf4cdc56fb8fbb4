"""Compiled broad phase: which pairs of bodies can touch, kept as a list in key order (docs/method.md 1.2).

Private module, the driver's broad-phase stage.  Boxes around the bodies, grown by half a skin, are sorted along
the axis where the bodies spread most and swept (sort-and-sweep); the pairs whose boxes overlap on both axes
(:func:`~._world.boxes_apart`) are the candidates, listed again only when a body has moved half a skin
(:func:`needs_relist`).  The list (the state's pair store, :class:`~dem_core.engine.state.State`) is kept sorted by
``key = i * nb + j``: a pair that stays keeps its contact memory, a new pair gets its constants, and a pair that
leaves hands its slip to the retired slips, by a merge in place (:func:`relist`).  Every array is the state's or
the scratch's, of a fixed capacity: a list that would overflow its store is not made, and the driver says which
store is full.  Cost: a sort of the bodies (insertion, on last list's order), and a sweep proportional to the
bodies plus the overlaps along the sweep axis; a long epistyle overlaps many drums along x but is kept apart from
the lower drums by the y test.
"""

import numba as nb

from ._build import kernel
from ._contact_law import pair_parameters
from ._world import boxes_apart
from .model_arrays import (DEPTH, FRICTION, LAW_CN, LAW_CR, LAW_CT, LAW_KN, LAW_KT, LAW_KT_RATIO, LAW_ZETA_N,
                           LAW_ZETA_R, LAW_ZETA_T, MASS, WIDTH)
from .settings import CONTACT_LAW, HALF_SKIN, PAIR_STORE, RETIRED_STORE
from .state import C_N, C_R, C_T, K_N, K_T, LISTED, MU, PAIR_I, PAIR_INTERFACE, PAIR_J, PAIR_KEY, REBUILDS, RETIRED


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
def _spread(boxes, low, high):
    """The variance of the free bodies' box centres along the axis of rows ``low``, ``high`` of ``boxes``."""
    n = boxes.shape[1] - 1
    if n < 2:
        return 0.0
    mean = 0.0
    for b in range(1, n + 1):
        mean += 0.5 * (boxes[low, b] + boxes[high, b])
    mean /= n
    total = 0.0
    for b in range(1, n + 1):
        d = 0.5 * (boxes[low, b] + boxes[high, b]) - mean
        total += d * d
    return total / n


@nb.njit(cache=True, inline="always")
def _sort_bodies(order, boxes, low):
    """``order`` (nb,), a permutation of the bodies, sorted in place by ``boxes[low]`` (insertion: last list's
    order is nearly sorted)."""
    for a in range(1, order.shape[0]):
        b = order[a]
        value = boxes[low, b]
        c = a - 1
        while c >= 0 and boxes[low, order[c]] > value:
            order[c + 1] = order[c]
            c -= 1
        order[c + 1] = b


@nb.njit(cache=True, inline="always")
def _sort_keys(keys, count):
    """``keys[:count]`` sorted in place (heapsort: no scratch, n log n)."""
    for root in range(count // 2 - 1, -1, -1):
        _sift(keys, root, count)
    for end in range(count - 1, 0, -1):
        keys[0], keys[end] = keys[end], keys[0]
        _sift(keys, 0, end)


@nb.njit(cache=True, inline="always")
def _sift(keys, root, end):
    while True:
        child = 2 * root + 1
        if child >= end:
            return
        if child + 1 < end and keys[child + 1] > keys[child]:
            child += 1
        if keys[root] >= keys[child]:
            return
        keys[root], keys[child] = keys[child], keys[root]
        root = child


@nb.njit(cache=True, inline="always")
def candidate_keys(boxes, margin, order, keys):
    """The keys ``i * nb + j`` (i < j) of the pairs whose boxes (4, nb), each grown by ``margin`` (m), overlap, sorted
    into ``keys`` (C,); ``order`` (nb,) is the sweep's scratch, a permutation of the bodies.  Returns how many, or
    -1 if more than ``keys`` holds."""
    n = boxes.shape[1]
    low = 2 if _spread(boxes, 2, 3) > _spread(boxes, 0, 1) else 0
    _sort_bodies(order, boxes, low)
    reach = 2.0 * margin
    count = 0
    for a in range(n):
        p = order[a]
        for c in range(a + 1, n):
            q = order[c]
            if boxes[low, q] > boxes[low + 1, p] + reach:
                break
            if boxes_apart(boxes, p, q, reach):
                continue
            if count == keys.shape[0]:
                return -1
            keys[count] = min(p, q) * n + max(p, q)
            count += 1
    _sort_keys(keys, count)
    return count


@nb.njit(cache=True, inline="always")
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


@nb.njit(cache=True, inline="always")
def forget_pair(p, memory, spring_force, normal_impulse, tangential_impulse):
    """Pair ``p``'s contact memory cleared: no reference face, no points, no springs or impulses to carry on."""
    for c in range(memory.shape[1]):
        memory[p, c] = -1
    for q in range(2):
        spring_force[p, q] = 0.0
        normal_impulse[p, q] = 0.0
        tangential_impulse[p, q] = 0.0


@nb.njit(cache=True, inline="always")
def _move_pair(a, b, ids, constants, memory, spring_force, normal_impulse, tangential_impulse, slip):
    """Row ``a`` of the pair store into row ``b``."""
    for c in range(ids.shape[1]):
        ids[b, c] = ids[a, c]
    for c in range(constants.shape[1]):
        constants[b, c] = constants[a, c]
    for c in range(memory.shape[1]):
        memory[b, c] = memory[a, c]
    for q in range(2):
        spring_force[b, q] = spring_force[a, q]
        normal_impulse[b, q] = normal_impulse[a, q]
        tangential_impulse[b, q] = tangential_impulse[a, q]
    slip[b] = slip[a]


@nb.njit(cache=True, inline="always")
def _new_pair(p, key, n, body, law, contact_law, friction_keys, friction_values, interface_keys, ids, constants):
    """Row ``p`` of the pair store for the pair ``key`` of ``n`` bodies: its bodies, its recorded interface and its
    constants (:func:`~._contact_law.pair_parameters`; mu its interface's own, else the smaller of its blocks')."""
    i = key // n
    j = key - i * n
    ids[p, PAIR_I] = i
    ids[p, PAIR_J] = j
    ids[p, PAIR_KEY] = key
    ids[p, PAIR_INTERFACE] = find_sorted(interface_keys, interface_keys.shape[0], key)
    k_n, c_n, k_t, c_t, c_r, _, _ = pair_parameters(
        contact_law, law[LAW_KN], law[LAW_ZETA_N], law[LAW_ZETA_T], law[LAW_ZETA_R], law[LAW_KT_RATIO], law[LAW_CN],
        law[LAW_CR], law[LAW_KT], law[LAW_CT], body[MASS, i], body[MASS, j], body[WIDTH, i], body[WIDTH, j],
        body[DEPTH, i], body[DEPTH, j])
    f = find_sorted(friction_keys, friction_keys.shape[0], key)
    constants[p, K_N] = k_n
    constants[p, C_N] = c_n
    constants[p, K_T] = k_t
    constants[p, C_T] = c_t
    constants[p, C_R] = c_r
    constants[p, MU] = friction_values[f] if f >= 0 else min(body[FRICTION, i], body[FRICTION, j])


@nb.njit(cache=True, inline="always")
def relist(keys, count, listed, retired, body, law, contact_law, friction_keys, friction_values, interface_keys,
           ids, constants, memory, spring_force, normal_impulse, tangential_impulse, slip, retired_key, retired_slip):
    """The pair store's ``listed`` rows made the list of the sorted ``keys[:count]`` in place: the pairs that stay
    keep their rows' memory, the new ones get their constants (:func:`_new_pair`) and an empty memory, and those
    that leave hand a slip they carry to the retired slips (entries ``retired`` on).  Returns the retired slips'
    count after, or -1 - RETIRED_STORE (nothing changed) if they would not fit."""
    leaving = 0
    b = 0
    for a in range(listed):  # the leavers first, so that a list that cannot be made is not begun
        while b < count and keys[b] < ids[a, PAIR_KEY]:
            b += 1
        if not (b < count and keys[b] == ids[a, PAIR_KEY]) and slip[a] > 0.0:
            leaving += 1
    if retired + leaving > retired_key.shape[0]:
        return -1 - RETIRED_STORE
    kept = 0
    b = 0
    for a in range(listed):  # forward: the pairs that stay, packed at the front in key order
        key = ids[a, PAIR_KEY]
        while b < count and keys[b] < key:
            b += 1
        if b < count and keys[b] == key:
            _move_pair(a, kept, ids, constants, memory, spring_force, normal_impulse, tangential_impulse, slip)
            kept += 1
        elif slip[a] > 0.0:
            retired_key[retired] = key
            retired_slip[retired] = slip[a]
            retired += 1
    n = body.shape[1]
    s = kept - 1
    for p in range(count - 1, -1, -1):  # backward: each kept pair to its row in the new list, the new ones between
        if s >= 0 and ids[s, PAIR_KEY] == keys[p]:
            if s != p:
                _move_pair(s, p, ids, constants, memory, spring_force, normal_impulse, tangential_impulse, slip)
            s -= 1
        else:
            _new_pair(p, keys[p], n, body, law, contact_law, friction_keys, friction_values, interface_keys, ids,
                      constants)
            forget_pair(p, memory, spring_force, normal_impulse, tangential_impulse)
            slip[p] = 0.0
    return retired


@nb.njit(cache=True, inline="always")
def incidence(ids, listed, start, entries, fill):
    """Which listed pairs each body belongs to, compressed: body b's entries are ``entries[start[b]:start[b + 1]]``,
    each ``2 p + end`` (pair p, the body its first or second), in the pairs' order; ``fill`` (nb,) scratch."""
    n_bodies = start.shape[0] - 1
    for b in range(n_bodies + 1):
        start[b] = 0
    for p in range(listed):
        start[ids[p, PAIR_I] + 1] += 1
        start[ids[p, PAIR_J] + 1] += 1
    for b in range(n_bodies):
        start[b + 1] += start[b]
        fill[b] = start[b]
    for p in range(listed):
        for end in range(2):
            b = ids[p, PAIR_I + end]
            entries[fill[b]] = 2 * p + end
            fill[b] += 1


@kernel(_nrt=False)
def list_pairs(model, settings, state, scratch):
    """The broad-phase stage: the candidates (:func:`candidate_keys`) made the state's list (:func:`relist`), their
    incidence into the scratch (:func:`incidence`), the positions they were listed at, and the counters of listed
    pairs, retired slips and lists made.  Takes the driver's named tuples (:mod:`._driver`).  Returns -1, or the
    store (PAIR_STORE, RETIRED_STORE) that could not take the list, nothing changed."""
    count = candidate_keys(scratch.boxes, settings.real[HALF_SKIN], scratch.sweep_order, scratch.candidates)
    if count < 0:
        return PAIR_STORE
    counters = state.counters
    retired = relist(scratch.candidates, count, counters[LISTED], counters[RETIRED], model.body, model.law,
                     settings.integer[CONTACT_LAW], model.friction_keys, model.friction_values, model.interface_keys,
                     state.pair_ids, state.pair_constants, state.pair_memory, state.spring_force, state.normal_impulse,
                     state.tangential_impulse, state.pair_slip, state.retired_key, state.retired_slip)
    if retired < 0:
        return -1 - retired
    counters[LISTED] = count
    counters[RETIRED] = retired
    counters[REBUILDS] += 1
    incidence(state.pair_ids, count, scratch.pair_start, scratch.pair_entries, scratch.body_fill)
    for b in range(state.pos.shape[0]):
        for d in range(3):
            state.built_at[b, d] = state.pos[b, d]
    return -1
