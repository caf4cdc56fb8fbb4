"""Compiled checks on a state: overturning of blocks and columns, mechanical energy and its balance, and a run
that has lost stability.

Private module.  :func:`end_step` is the driver's last stage each step; the overturn rule is shared with the other
engines' driver (every output, :mod:`adapters._driver`), so that every engine counts an overturn by the same rule
(docs/method.md section 3): a block overturns when it passes its critical angle or its centre of
mass falls half its smaller extent relative to the base; a column (a stack, :mod:`dem_core.engine.stacks`) when the
centre of mass of its blocks passes an end of its bottom block's base.
"""

import math

import numba as nb
import numpy as np

from ._angles import cosine, sine
from ._build import kernel
from .model_arrays import CRITICAL_ANGLE, DROP_LIMIT, INV_INERTIA, MASS, RADIUS, Y_START
from .settings import (ENERGY_CHECK_INTERVAL, ENERGY_SCALE, ENERGY_TOLERANCE, FLOOR, GRAVITY, SPEED_LIMIT,
                       STATUS_ENERGY, STATUS_FELL_OFF, STATUS_NONFINITE, STATUS_OK, STATUS_OVERTURNED,
                       STATUS_RUNAWAY, STOP_AT_OVERTURN)
from .state import LAST_SUBSTEPS, STEP, SUBSTEPPED


@nb.njit(cache=True, inline="always")
def block_overturned(pos, b, critical_angle, y_start, drop_limit):
    """Whether body ``b`` at ``pos`` (nb, 3; row 0 the base) is past its critical angle or its centre of mass has
    fallen more than ``drop_limit[b]`` (m) relative to the base: below ``y_start[b]`` moved by as much as the base
    has moved from ``y_start[0]``, so that a ground that sinks carries its blocks without a fall."""
    return abs(pos[b, 2]) > critical_angle[b] or y_start[b] - pos[b, 1] + (pos[0, 1] - y_start[0]) > drop_limit[b]


@nb.njit(cache=True, inline="always")
def any_block_overturned(pos, critical_angle, y_start, drop_limit):
    """Whether some free body at ``pos`` (nb, 3; row 0 the base) is overturned by :func:`block_overturned` now."""
    for b in range(1, pos.shape[0]):
        if block_overturned(pos, b, critical_angle, y_start, drop_limit):
            return True
    return False


@nb.njit(cache=True, inline="always")
def mark_overturns(pos, critical_angle, y_start, drop_limit, mass, stack_id, bottom, stack_mass, foot,
                   overturn_step, stack_step, moment, step):
    """Record in ``overturn_step`` (nb,) and ``stack_step`` (ns,) the bodies and stacks that have
    overturned by ``pos`` (nb, 3; row 0 the base) and were not marked yet, with ``step``.

    critical_angle, y_start, drop_limit, mass : the model's :class:`~dem_core.engine.model.Bodies`
    fields; stack_id, bottom, stack_mass, foot : its :class:`~dem_core.engine.model.Stacks`;
    moment : (ns,) scratch.  Returns the first body found overturning now (a stack reports its bottom
    body), or -1.  One pass over the bodies and one over the stacks.
    """
    first = -1
    moment[:] = 0.0
    for b in range(1, pos.shape[0]):
        k = stack_id[b]
        if k >= 0:
            moment[k] += pos[b, 0] * mass[b]
        if overturn_step[b] >= 0:
            continue
        if block_overturned(pos, b, critical_angle, y_start, drop_limit):
            overturn_step[b] = step
            if first < 0:
                first = b
    tipped = False
    for k in range(bottom.shape[0]):
        if stack_step[k] >= 0:
            continue
        com = moment[k] / stack_mass[k]
        f = bottom[k]
        c = cosine(pos[f, 2])
        s = sine(pos[f, 2])
        xa = pos[f, 0] + c * foot[k, 0, 0] - s * foot[k, 0, 1]
        xb = pos[f, 0] + c * foot[k, 1, 0] - s * foot[k, 1, 1]
        if com < min(xa, xb) or com > max(xa, xb):
            stack_step[k] = step
            tipped = True
            if first < 0:
                first = f
    if tipped:  # rare: mark the bodies of the stacks that tipped now
        for b in range(1, pos.shape[0]):
            k = stack_id[b]
            if k >= 0 and stack_step[k] == step and overturn_step[b] < 0:
                overturn_step[b] = step
    return first


@nb.njit(cache=True, inline="always")
def mechanical_energy(pos, vel, mass, inv_inertia, gravity):
    """Kinetic plus gravitational energy of the free bodies (J), with velocities ``vel`` (nb, 3)."""
    e = 0.0
    for b in range(1, pos.shape[0]):
        m = mass[b]
        e += (0.5 * m * (vel[b, 0] ** 2 + vel[b, 1] ** 2) + 0.5 * vel[b, 2] ** 2 / inv_inertia[b]
              + m * gravity * pos[b, 1])
    return e


@kernel()
def first_overturns(states, bodies, stacks):
    """First index into ``states`` (n, nb, 3; row 0 of each state the base) at which each body
    overturned and each stack tipped: ``(overturn (nb,), stack (ns,))`` int64, -1 if never."""
    overturn = np.full(states.shape[1], -1, np.int64)
    stack = np.full(stacks.bottom.shape[0], -1, np.int64)
    moment = np.empty(stacks.bottom.shape[0])
    for k in range(states.shape[0]):
        mark_overturns(states[k], bodies.critical_angle, bodies.y_start, bodies.drop_limit, bodies.mass,
                       stacks.stack_id, stacks.bottom, stacks.mass, stacks.foot, overturn, stack, moment, k)
    return overturn, stack


@nb.njit(cache=True, inline="always")
def ground_work(force, vel, mass, load_x, load_y, dt, ledger):
    """The work of the ground over a step (or part) of ``dt`` (s) into the ledger (net and gross, J): the base's
    reaction ``force[0]`` (N) against its velocity and the inertial load on every block."""
    power = -(force[0, 0] * vel[0, 0] + force[0, 1] * vel[0, 1])
    for b in range(1, vel.shape[0]):
        power += (load_x * vel[b, 0] + load_y * vel[b, 1]) * mass[b]
    ledger[1] += power * dt
    ledger[2] += abs(power) * dt


@nb.njit(cache=True, inline="always")
def check_bodies(pos, vel, radius, floor, speed_limit, peak_theta):
    """A non-finite state, a block below the base's top by more than its size (fell off), or one faster than
    ``speed_limit`` relative to the ground; follows each block's peak |theta|.  Returns ``(status, body)``,
    STATUS_OK and 0 when every block passes."""
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
    """Whether the blocks hold more energy than they started with plus the ground's net work, by more than
    ``tolerance`` of ``scale`` plus the ground's gross work."""
    energy = mechanical_energy(pos, vel, mass, inv_inertia, gravity)
    return energy - ledger[0] - ledger[1] > tolerance * (scale + ledger[2])


@nb.njit(cache=True, inline="always")
def end_step(model, settings, state, scratch, parts):
    """The driver's checks after a step taken in ``parts``: the counters, then :func:`check_bodies`, the overturns
    (:func:`mark_overturns`) and every ``ENERGY_CHECK_INTERVAL`` steps :func:`energy_gained`.  Returns ``(status,
    body)``: STATUS_OK and 0 when the run goes on, STATUS_OVERTURNED and the block when one overturned and an
    overturn ends the run (the driver writes the state as the last output), else the failed check's status."""
    pos, vel, counters, body, real = state.pos, state.vel, state.counters, model.body, settings.real
    step = counters[STEP]
    counters[LAST_SUBSTEPS] = parts
    if parts > 1:
        counters[SUBSTEPPED] += 1
    counters[STEP] = step + 1
    status, b = check_bodies(pos, vel, body[RADIUS], real[FLOOR], real[SPEED_LIMIT], state.peak_theta)
    if status != STATUS_OK:
        return status, b
    toppled = mark_overturns(pos, body[CRITICAL_ANGLE], body[Y_START], body[DROP_LIMIT], body[MASS], model.stack_id,
                             model.stack_bottom, model.stack_mass, model.stack_foot, state.overturn_step,
                             state.stack_step, scratch.stack_moment, step + 1)
    if toppled >= 0 and settings.integer[STOP_AT_OVERTURN] == 1:
        return STATUS_OVERTURNED, toppled
    if step % ENERGY_CHECK_INTERVAL == 0 and energy_gained(pos, vel, body[MASS], body[INV_INERTIA], real[GRAVITY],
                                                           state.ledger, real[ENERGY_TOLERANCE], real[ENERGY_SCALE]):
        return STATUS_ENERGY, 0
    return STATUS_OK, 0
