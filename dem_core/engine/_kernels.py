"""Compiled time stepping of the soft-contact DEM (FORMULATION section 1).

Private module: :func:`integrate` takes arrays and scalars only and is called
by :mod:`dem_core.engine.simulation`.  Body 0 is the base; it follows the prescribed
ground motion and has no dynamics.  State is structure-of-arrays:
``pos[:, 0:3] = (x, y, theta)`` of each centre of mass and ``vel`` at the
half step (central differences in velocity form:
``v(t+dt/2) = v(t-dt/2) + dt M^-1 F(t)``, ``x(t+dt) = x(t) + dt v(t+dt/2)``).

Broad phase: a Verlet list of pairs whose bounding circles come within a skin
distance, rebuilt only when some body has moved half the skin, then an
axis-aligned box test each step before the exact polygon clipping.
"""

import math

import numba as nb
import numpy as np

from ._polygon import MAX_OVERLAP_VERTICES, clip_convex, contact_frame, polygon_moments

STATUS_OK = 0
STATUS_NONFINITE = 1
STATUS_DEEP_OVERLAP = 2
STATUS_RUNAWAY = 3
STATUS_ENERGY = 4
STATUS_OVERTURNED = 5
STATUS_FELL_OFF = 6
ENERGY_CHECK_INTERVAL = 16  # steps between energy balance checks


@nb.njit(cache=True)
def _world_vertices(pos, local_x, local_y, vstart, wx, wy):
    for b in range(pos.shape[0]):
        c = math.cos(pos[b, 2])
        s = math.sin(pos[b, 2])
        for k in range(vstart[b], vstart[b + 1]):
            wx[k] = pos[b, 0] + c * local_x[k] - s * local_y[k]
            wy[k] = pos[b, 1] + s * local_x[k] + c * local_y[k]


@nb.njit(cache=True)
def _build_pairs(pos, radius, skin, active, pairs):
    nb_ = pos.shape[0]
    n = 0
    for i in range(nb_):
        for j in range(i + 1, nb_):
            if not active[i, j]:
                continue
            dx = pos[j, 0] - pos[i, 0]
            dy = pos[j, 1] - pos[i, 1]
            reach = radius[i] + radius[j] + skin
            if dx * dx + dy * dy <= reach * reach:
                pairs[n, 0] = i
                pairs[n, 1] = j
                n += 1
    return n


@nb.njit(cache=True)
def integrate(pos, vel, local_x, local_y, vstart, inv_mass, inv_inertia, radius, area,
              pair_kn, pair_cn, pair_cr, pair_kt, pair_ct, pair_mu, active,
              ft_el, slip, gravity, load_x, load_y, base_x, base_y, base_vx, base_vy,
              dt, n_steps, stride, out_pos, crit_angle, y_start, drop_limit,
              peak_theta, overturn_step, max_overlap_fraction, skin, speed_limit,
              energy_tolerance, stop_at_overturn, floor, stack_id, stack_bottom, stack_mass, stack_foot,
              stack_step, if_i, if_j, out_slip):
    """Advance the scene ``n_steps`` steps of ``dt`` from the state in ``pos``, ``vel``.

    Shapes (nb bodies including the base at index 0, nv vertices in all):
    pos, vel (nb, 3); local_x, local_y (nv,) vertices about each centre of
    mass; vstart (nb + 1,) vertex offsets; inv_mass, inv_inertia, radius,
    area (nb,); pair_* (nb, nb) contact parameters (see ``dem_core.engine.contact``); ft_el, slip (nb, nb) tangential elastic
    force (N, along the contact tangent) and accumulated slip (m) per pair,
    updated in place; load_x, load_y (n_steps,) inertial loads per unit mass
    (m/s^2) at each step; base_x, base_y (n_steps + 1,) base position at step
    times; base_vx, base_vy (n_steps + 1,) base velocity at half steps
    (index k is t_k - dt/2); out_pos (n_out, nb, 3) filled every ``stride``
    steps starting with the initial state, and with the final state.  Tracking per body: peak |theta|
    into ``peak_theta``, the first step where |theta| exceeds
    ``crit_angle`` or the centre of mass falls ``drop_limit`` below
    ``y_start`` into ``overturn_step`` (-1 if never).  Stacks (``dem_core.engine.stacks``): ``stack_id``
    (nb,) the stack of each body or -1; per stack ``stack_bottom`` (body), ``stack_mass`` (kg),
    ``stack_foot`` (ns, 2, 2) the ends of the bottom body's base in its own frame; the first step
    where a stack's centre of mass is past an end of that base goes into ``stack_step`` (-1 if
    never) and, for its bodies, into ``overturn_step``.  Interfaces followed over time: pairs
    ``(if_i[k], if_j[k])``; their accumulated slip goes into ``out_slip`` (n_out, n_interfaces) with
    every output.

    Returns ``(status, step, i, j, n_out_written, n_narrow)``, ``n_narrow``
    the number of exact polygon overlaps computed (pairs that passed the
    broad phase), and status 0 on success,
    1 if the state became non-finite (i = body), 2 if pair (i, j)
    overlapped by more than ``max_overlap_fraction`` of the smaller block's
    area, 3 if a point of body i moved faster than ``speed_limit`` (m/s)
    relative to the ground, 4 if the mechanical energy (kinetic plus
    gravitational) exceeded its start value plus the work of the ground by
    more than ``energy_tolerance`` times the potential energy scale
    ``sum m g R`` plus the gross ground work: contacts only dissipate, so
    energy that appears from nowhere is the signature of an unstable step;
    5 (i = body) if ``stop_at_overturn`` and a block overturned, after
    writing the state at that step as the last output; 6 (i = body) if a
    block's centre of mass fell more than its circumradius below ``floor``
    (the top of the base, relative to the base's position): it left the base.
    """
    nb_ = pos.shape[0]
    nv = local_x.shape[0]
    wx = np.empty(nv)
    wy = np.empty(nv)
    force = np.zeros((nb_, 3))
    cap = MAX_OVERLAP_VERTICES
    ox = np.empty(cap)
    oy = np.empty(cap)
    scratch = np.empty((2, 2, cap))
    lo_x = np.empty(nb_)
    hi_x = np.empty(nb_)
    lo_y = np.empty(nb_)
    hi_y = np.empty(nb_)
    pairs = np.empty((nb_ * (nb_ - 1) // 2 + 1, 2), np.int64)
    built_at = pos.copy()
    n_pairs = _build_pairs(pos, radius, skin, active, pairs)
    half_skin2 = 0.25 * skin * skin
    n_out = 0
    n_narrow = 0
    energy0 = _mechanical_energy(pos, vel, inv_mass, inv_inertia, gravity)
    energy_scale = 0.0
    for b in range(1, nb_):
        energy_scale += gravity * radius[b] / inv_mass[b]
    work_in = 0.0
    work_gross = 0.0
    n_stacks = stack_bottom.shape[0]
    stack_moment = np.zeros(n_stacks)

    for step in range(n_steps + 1):
        pos[0, 0] = base_x[step]
        pos[0, 1] = base_y[step]
        vel[0, 0] = base_vx[step]
        vel[0, 1] = base_vy[step]
        if (step % stride == 0 or step == n_steps) and n_out < out_pos.shape[0]:
            _write_output(pos, slip, if_i, if_j, out_pos, out_slip, n_out)
            n_out += 1
        if step == n_steps:
            break

        rebuild = False
        for b in range(nb_):
            dx = pos[b, 0] - built_at[b, 0]
            dy = pos[b, 1] - built_at[b, 1]
            if dx * dx + dy * dy > half_skin2:
                rebuild = True
                break
        if rebuild:
            n_pairs = _build_pairs(pos, radius, skin, active, pairs)
            for b in range(nb_):
                built_at[b, 0] = pos[b, 0]
                built_at[b, 1] = pos[b, 1]

        _world_vertices(pos, local_x, local_y, vstart, wx, wy)
        for b in range(nb_):
            lo_x[b] = np.inf
            hi_x[b] = -np.inf
            lo_y[b] = np.inf
            hi_y[b] = -np.inf
            for k in range(vstart[b], vstart[b + 1]):
                lo_x[b] = min(lo_x[b], wx[k])
                hi_x[b] = max(hi_x[b], wx[k])
                lo_y[b] = min(lo_y[b], wy[k])
                hi_y[b] = max(hi_y[b], wy[k])
            force[b, 0] = 0.0
            force[b, 1] = 0.0
            force[b, 2] = 0.0

        for p in range(n_pairs):
            i = pairs[p, 0]
            j = pairs[p, 1]
            if hi_x[i] < lo_x[j] or hi_x[j] < lo_x[i] or hi_y[i] < lo_y[j] or hi_y[j] < lo_y[i]:
                ft_el[i, j] = 0.0
                continue
            n_narrow += 1
            m = clip_convex(wx, wy, vstart[i], vstart[i + 1] - vstart[i], wx, wy, vstart[j], vstart[j + 1] - vstart[j],
                            ox, oy, scratch)
            if m < 3:
                ft_el[i, j] = 0.0
                continue
            a, cx, cy, sxx, syy, sxy = polygon_moments(ox, oy, m)
            if a <= 0.0:
                ft_el[i, j] = 0.0
                continue
            if a > max_overlap_fraction * min(area[i], area[j]):
                return STATUS_DEEP_OVERLAP, step, i, j, n_out, n_narrow
            tx, ty, nx, ny = contact_frame(sxx, syy, sxy, cx, cy, pos[i, 0], pos[i, 1])
            # velocities of the material points of i and j at C
            rix = cx - pos[i, 0]
            riy = cy - pos[i, 1]
            rjx = cx - pos[j, 0]
            rjy = cy - pos[j, 1]
            vix = vel[i, 0] - vel[i, 2] * riy
            viy = vel[i, 1] + vel[i, 2] * rix
            vjx = vel[j, 0] - vel[j, 2] * rjy
            vjy = vel[j, 1] + vel[j, 2] * rjx
            rvx = vjx - vix
            rvy = vjy - viy
            v_n = -(rvx * nx + rvy * ny)  # approach positive
            v_t = rvx * tx + rvy * ty  # slip of j relative to i
            fn = pair_kn[i, j] * a + pair_cn[i, j] * v_n
            fn = max(fn, 0.0)
            fe = ft_el[i, j] - pair_kt[i, j] * v_t * dt
            f_t = fe - pair_ct[i, j] * v_t
            cap_t = pair_mu[i, j] * fn
            if abs(f_t) > cap_t:
                f_t = cap_t if f_t > 0.0 else -cap_t
                fe = f_t
                slip[i, j] += abs(v_t) * dt
            ft_el[i, j] = fe
            fx = fn * nx + f_t * tx  # force on j; i gets the opposite
            fy = fn * ny + f_t * ty
            couple = 0.0
            if fn > 0.0:
                # the dashpot spread evenly along the contact length l resists relative rotation
                s_min = np.inf
                s_max = -np.inf
                for q in range(m):
                    s = ox[q] * tx + oy[q] * ty
                    s_min = min(s_min, s)
                    s_max = max(s_max, s)
                length = s_max - s_min
                couple = -pair_cr[i, j] * length * length / 12.0 * (vel[j, 2] - vel[i, 2])
            force[j, 0] += fx
            force[j, 1] += fy
            force[j, 2] += rjx * fy - rjy * fx + couple
            force[i, 0] -= fx
            force[i, 1] -= fy
            force[i, 2] -= rix * fy - riy * fx + couple

        gx = load_x[step]
        gy = load_y[step] - gravity
        toppled = -1
        power = -(force[0, 0] * vel[0, 0] + force[0, 1] * vel[0, 1])
        for b in range(1, nb_):
            power += (load_x[step] * vel[b, 0] + load_y[step] * vel[b, 1]) / inv_mass[b]
        work_in += power * dt
        work_gross += abs(power) * dt
        for b in range(1, nb_):
            vel[b, 0] += dt * (force[b, 0] * inv_mass[b] + gx)
            vel[b, 1] += dt * (force[b, 1] * inv_mass[b] + gy)
            vel[b, 2] += dt * force[b, 2] * inv_inertia[b]
            pos[b, 0] += dt * vel[b, 0]
            pos[b, 1] += dt * vel[b, 1]
            pos[b, 2] += dt * vel[b, 2]
            if not (math.isfinite(pos[b, 0]) and math.isfinite(pos[b, 1]) and math.isfinite(pos[b, 2])):
                return STATUS_NONFINITE, step, b, b, n_out, n_narrow
            if pos[b, 1] - pos[0, 1] < floor - radius[b]:
                return STATUS_FELL_OFF, step, b, b, n_out, n_narrow
            rel_x = vel[b, 0] - vel[0, 0]
            rel_y = vel[b, 1] - vel[0, 1]
            spin = vel[b, 2] * radius[b]
            if rel_x * rel_x + rel_y * rel_y + spin * spin > speed_limit * speed_limit:
                return STATUS_RUNAWAY, step, b, b, n_out, n_narrow
            rot = abs(pos[b, 2])
            peak_theta[b] = max(peak_theta[b], rot)
            if overturn_step[b] < 0 and (abs(pos[b, 2]) > crit_angle[b] or y_start[b] - pos[b, 1] > drop_limit[b]):
                overturn_step[b] = step + 1
                if stop_at_overturn:
                    toppled = b
        if n_stacks > 0:
            _check_stacks(pos, inv_mass, stack_id, stack_bottom, stack_mass, stack_foot, stack_moment, stack_step,
                          overturn_step, step + 1)
            if stop_at_overturn and toppled < 0:
                for k in range(n_stacks):
                    if stack_step[k] == step + 1:
                        toppled = stack_bottom[k]
        if toppled >= 0:
            if n_out < out_pos.shape[0]:
                _write_output(pos, slip, if_i, if_j, out_pos, out_slip, n_out)
                n_out += 1
            return STATUS_OVERTURNED, step + 1, toppled, toppled, n_out, n_narrow
        if step % ENERGY_CHECK_INTERVAL == 0:
            energy = _mechanical_energy(pos, vel, inv_mass, inv_inertia, gravity)
            if energy - energy0 - work_in > energy_tolerance * (energy_scale + work_gross):
                return STATUS_ENERGY, step, 0, 0, n_out, n_narrow
    return STATUS_OK, n_steps, 0, 0, n_out, n_narrow


@nb.njit(cache=True)
def _write_output(pos, slip, if_i, if_j, out_pos, out_slip, k):
    for b in range(pos.shape[0]):
        for d in range(3):
            out_pos[k, b, d] = pos[b, d]
    for m in range(if_i.shape[0]):
        out_slip[k, m] = slip[if_i[m], if_j[m]]


@nb.njit(cache=True)
def _check_stacks(pos, inv_mass, stack_id, stack_bottom, stack_mass, stack_foot, moment, stack_step,
                  overturn_step, step):
    """Mark the stacks whose centre of mass has passed an end of their bottom body's base at ``step``."""
    moment[:] = 0.0
    for b in range(1, pos.shape[0]):
        if stack_id[b] >= 0:
            moment[stack_id[b]] += pos[b, 0] / inv_mass[b]
    for k in range(stack_bottom.shape[0]):
        if stack_step[k] >= 0:
            continue
        f = stack_bottom[k]
        c, s = math.cos(pos[f, 2]), math.sin(pos[f, 2])
        xa = pos[f, 0] + c * stack_foot[k, 0, 0] - s * stack_foot[k, 0, 1]
        xb = pos[f, 0] + c * stack_foot[k, 1, 0] - s * stack_foot[k, 1, 1]
        com = moment[k] / stack_mass[k]
        if com < min(xa, xb) or com > max(xa, xb):
            stack_step[k] = step
            for b in range(1, pos.shape[0]):
                if stack_id[b] == k and overturn_step[b] < 0:
                    overturn_step[b] = step


@nb.njit(cache=True)
def _mechanical_energy(pos, vel, inv_mass, inv_inertia, gravity):
    """Kinetic plus gravitational energy of the free bodies, J."""
    e = 0.0
    for b in range(1, pos.shape[0]):
        m = 1.0 / inv_mass[b]
        e += 0.5 * m * (vel[b, 0] ** 2 + vel[b, 1] ** 2) + 0.5 * vel[b, 2] ** 2 / inv_inertia[b] + m * gravity * pos[b, 1]
    return e
