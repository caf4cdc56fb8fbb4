"""Compiled contact laws: per-pair parameters and the force of one contact (docs/method.md 1.3 to 1.5).

Private module: plain scalars in, plain scalars out, so that the driver's explicit stage
(:mod:`dem_core.engine._explicit`), the broad phase's new pairs, the time-step analysis
(:mod:`dem_core.engine.stability`) and the unit tests call the very same functions.  With docs/method.md, this
module is where the laws' equations are written; every other place points here.

Two laws share the tangential rule and the Coulomb cap:

* ``CORNER`` (default): at most two contact points per pair (vertex against face), each with a
  normal spring ``k_p = K_n d L / 2`` and dashpot ``c_p = 2 zeta sqrt(k_p m_p)`` (:func:`dashpot`),
  ``m_p`` the pair's effective mass at the point along the normal (:func:`effective_mass`), so that
  ``zeta`` is the damping ratio the point's own spring sees; the tangential spring
  ``k_t = kt_ratio k_p`` and its dashpot ``2 zeta_t sqrt(k_t m_t)`` with the effective mass along the
  tangent;
* ``OVERLAP_AREA`` (the thesis' law): one force ``K_n d A + C_n v_n`` at the overlap's centroid
  and a dashpot couple ``-C_r l^2 / 12 (omega_B - omega_A)`` spread along the contact length ``l``;
  ``C_n = 2 zeta_n sqrt(K_n d L m_eff)``, ``C_r`` likewise with ``zeta_r``, ``K_t = kt_ratio K_n d L``
  and ``C_t = 2 zeta_t sqrt(K_t m_eff)``, ``m_eff`` the pair's reduced mass (a block's own mass
  against the base).

Tangential rule of both: ``F_t,el += -K_t v_t dt``, ``F_t = F_t,el - C_t v_t``, ``|F_t| <= mu F_n``
(per point for the corner law; :func:`tangential_force`).  ``L`` is the smaller of the two blocks'
widths and ``d`` the smaller depth.  The law codes ``CORNER`` and ``OVERLAP_AREA`` are the positions of
the laws' names in :data:`dem_core.engine.contact.LAWS`.
"""

import math

import numba as nb

from ._build import kernel

CORNER = 0
OVERLAP_AREA = 1


@nb.njit(cache=True, inline="always")
def dashpot(given, zeta, stiffness, mass):
    """A dashpot constant (N s/m): ``given`` unless NaN, else ``2 zeta sqrt(stiffness mass)``."""
    if given == given:
        return given
    return 2.0 * zeta * math.sqrt(stiffness * mass)


@kernel()
def pair_parameters(law, kn, zeta_n, zeta_t, zeta_r, kt_ratio, cn_given, cr_given, kt_given, ct_given,
                    mass_i, mass_j, width_i, width_j, depth_i, depth_j):
    """Contact constants of one pair of bodies (``mass_i = 0`` for the base: infinitely heavy).

    law : CORNER or OVERLAP_AREA.  kn : N/m^2 per metre of depth.  zeta_n, zeta_t, zeta_r : damping
    ratios of the normal dashpot, the tangential dashpot and (overlap law) the rocking couple.
    kt_ratio : tangential over normal stiffness.  ``*_given`` : explicit values (N s/m, N s/m, N/m,
    N s/m) that replace the ratios, or NaN.  Masses in kg, widths and depths in m.

    Returns ``(k_n, c_n, k_t, c_t, c_r, m_eff, length)``: for CORNER, the per-point normal spring
    (N/m) and tangential spring, and the dashpots only where given explicitly (else NaN: they follow
    per point from the damping ratios and :func:`effective_mass`); for OVERLAP_AREA, ``k_n`` is the
    stiffness per overlap area (N/m^2, so that ``F = k_n A``), ``c_n`` the dashpot at the centroid,
    ``k_t``, ``c_t`` the tangential spring and dashpot and ``c_r`` the couple's dashpot (the couple is
    ``c_r l^2 / 12`` times the relative angular velocity), all with the pair's reduced mass ``m_eff``.
    ``m_eff`` kg, ``length`` = L m.
    """
    if mass_i == 0.0:
        m_eff = mass_j
    elif mass_j == 0.0:
        m_eff = mass_i
    else:
        m_eff = mass_i * mass_j / (mass_i + mass_j)
    length = min(width_i, width_j)
    depth = min(depth_i, depth_j)
    if law == CORNER:
        k_n = 0.5 * kn * depth * length
        k_t = kt_given if not math.isnan(kt_given) else kt_ratio * k_n
        return k_n, cn_given, k_t, ct_given, 0.0, m_eff, length
    k_n = kn * depth
    spring = kn * depth * length
    c_n = dashpot(cn_given, zeta_n, spring, m_eff)
    k_t = kt_given if not math.isnan(kt_given) else kt_ratio * spring
    c_t = dashpot(ct_given, zeta_t, k_t, m_eff)
    c_r = dashpot(cr_given, zeta_r, spring, m_eff)
    return k_n, c_n, k_t, c_t, c_r, m_eff, length


@nb.njit(cache=True, inline="always")
def effective_mass(dx, dy, rix, riy, inv_mass_i, inv_inertia_i, rjx, rjy, inv_mass_j, inv_inertia_j):
    """Effective mass (kg) of two rigid bodies at a point along the unit direction (dx, dy): the mass
    that a unit impulse there, along that direction, accelerates, ``1 / (1/m_i + 1/m_j + (r_i x d)^2 / I_i
    + (r_j x d)^2 / I_j)`` with ``r`` the point relative to each centre of mass (m) and zero inverses
    for the base."""
    ci = rix * dy - riy * dx
    cj = rjx * dy - rjy * dx
    return 1.0 / (inv_mass_i + inv_mass_j + ci * ci * inv_inertia_i + cj * cj * inv_inertia_j)


@nb.njit(cache=True, inline="always")
def normal_force(penetration, approach_speed, stiffness, damping):
    """Spring and dashpot that push only: ``max(k delta + c delta', 0)`` (N).

    penetration : m (or m^2 of overlap area for the overlap law, with ``stiffness`` per area);
    approach_speed : m/s, positive while the bodies close.
    """
    force = stiffness * penetration + damping * approach_speed
    return force if force > 0.0 else 0.0


@nb.njit(cache=True, inline="always")
def tangential_force(elastic, slip_speed, dt, stiffness, damping, cap):
    """Incremental tangential spring and dashpot capped by Coulomb friction.

    elastic : N, the spring's force carried from the previous step (along the contact tangent);
    slip_speed : m/s, relative tangential velocity; dt : s; stiffness N/m, damping N s/m;
    cap : N, ``mu F_n``.  The spring is loaded by ``-k v_t dt``; the force is spring plus dashpot,
    and when it exceeds the cap it is set to the cap and so is the spring (the contact slips).

    Returns ``(force, elastic after the step, slipped)``.
    """
    spring = elastic - stiffness * slip_speed * dt
    force = spring - damping * slip_speed
    if abs(force) > cap:
        force = cap if force > 0.0 else -cap
        return force, force, True
    return force, spring, False
