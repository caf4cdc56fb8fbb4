"""The soft-contact law: parameters, their defaults, and the stable time step.

Per interface (FORMULATION section 1), with overlap area ``A`` (m^2), block
depth ``d`` (m, the smaller of the pair) and relative velocities at the
overlap centroid:

    F_n = K_n * A * d + C_n * v_n            (clamped at >= 0)
    F_t = F_t,el - C_t * v_t,  F_t,el += -K_t * v_t * dt,  |F_t| <= mu F_n

``K_n`` (N/m^2 per metre of depth) is the one scene-wide stiffness.  The
other three are per interface and, unless given explicitly, follow from it
and from the pair of blocks so that no hand tuning is needed:

* ``k = K_n * d * L`` is the interface's linear normal stiffness (N/m) for a
  flat contact of length ``L`` = the smaller of the two blocks' widths;
* ``C_n = 2 * zeta_n * sqrt(k * m_eff)`` with ``m_eff`` the pair's reduced
  mass (the block's own mass against the base): a dashpot with damping ratio
  ``zeta_n`` acting at the overlap centroid;
* a dashpot spread evenly along the contact length ``l`` (a Kelvin-Voigt
  foundation under the uniform pressure ``K_n``) also resists the relative
  rotation of the pair: the couple ``-C_r l^2 / 12 (omega_B - omega_A)`` with
  ``C_r = 2 * zeta_r * sqrt(k * m_eff)``.  Without it a soft contact rolls
  from one corner to the other with almost no loss, whatever ``C_n``: a
  dashpot at the centroid sees almost no velocity there.  By default
  ``zeta_r`` follows :func:`housner_damping_ratio` of the scene's rocking
  slenderness, calibrated so that a rocking block of that slenderness loses
  the energy Housner's impact rule predicts (FORMULATION 4.2).  It is kept
  apart from ``zeta_n`` because stiffness-proportional dashpots are what
  limit an explicit time step: a small ``zeta_n`` and ``zeta_t`` keep the
  step large;
* ``K_t = tangential_stiffness_ratio * k`` and
  ``C_t = 2 * zeta_t * sqrt(K_t * m_eff)``.

:func:`damping_ratio_for_restitution` and :func:`normal_damping` map a target
coefficient of restitution or damping ratio onto ``C_n``.
"""

import math
from dataclasses import dataclass

import numpy as np
from scipy.optimize import brentq

DEFAULT_NORMAL_STIFFNESS = 2.0e10  # N/m^2 per metre of depth
DEFAULT_NORMAL_DAMPING_RATIO = 0.3  # restitution 0.45 for a block dropped flat
DEFAULT_TANGENTIAL_DAMPING_RATIO = 0.2

#: (slenderness alpha in rad, rocking damping ratio) that reproduces
#: Housner's peak decay over the first five impacts of free rocking from
#: 0.2 alpha, with the other contact parameters at their defaults and a time
#: step converged for the impacts (0.1 of the stability limit); the worst
#: peak error there is under 0.4% up to alpha = 0.25, 0.8% at 0.3, 1.9% at
#: 0.4.  Output of ``python -m comparisons.calibrate_damping``.
HOUSNER_DAMPING = (
    (0.06, 0.189), (0.08, 0.340), (0.10, 0.472), (0.125, 0.601), (0.15, 0.697), (0.175, 0.769),
    (0.2, 0.822), (0.25, 0.896), (0.3, 0.952), (0.35, 1.004), (0.4, 1.058),
)


def housner_damping_ratio(alpha: float) -> float:
    """Contact damping ratio whose rocking impacts lose Housner's energy for slenderness ``alpha`` (rad).

    Linear interpolation in :data:`HOUSNER_DAMPING`, clamped at its ends.
    """
    table = np.array(HOUSNER_DAMPING)
    return float(np.interp(alpha, table[:, 0], table[:, 1]))


@dataclass(frozen=True)
class ContactParameters:
    """Soft-contact parameters of a scene.

    kn : N/m^2 per m depth, penalty stiffness on the overlap area.
    damping_ratio : zeta_n of every interface's normal dashpot (ignored if
        ``cn`` is given).
    rocking_damping_ratio : zeta_r of the dashpot couple that resists relative
        rotation (ignored if ``cr`` is given); None:
        :func:`housner_damping_ratio` of the scene's rocking slenderness.
    tangential_stiffness_ratio : K_t / (K_n d L) (ignored if ``kt`` is given).
    tangential_damping_ratio : zeta_t of the tangential dashpot (ignored if
        ``ct`` is given).
    cn, cr, kt, ct : explicit N s/m, N s/m, N/m, N s/m applied to every
        interface, or None for the per-interface defaults.
    """

    kn: float = DEFAULT_NORMAL_STIFFNESS
    damping_ratio: float = DEFAULT_NORMAL_DAMPING_RATIO
    rocking_damping_ratio: float | None = None
    tangential_stiffness_ratio: float = 0.5
    tangential_damping_ratio: float = DEFAULT_TANGENTIAL_DAMPING_RATIO
    cn: float | None = None
    cr: float | None = None
    kt: float | None = None
    ct: float | None = None

    def __post_init__(self):
        for name in ("kn", "tangential_stiffness_ratio"):
            v = getattr(self, name)
            if not (np.isfinite(v) and v > 0):
                raise ValueError(f"contact parameter {name} must be positive, got {v}")
        for name in ("damping_ratio", "rocking_damping_ratio", "tangential_damping_ratio", "cn", "cr", "kt", "ct"):
            v = getattr(self, name)
            if v is not None and not (np.isfinite(v) and v >= 0):
                raise ValueError(f"contact parameter {name} must be >= 0 or None, got {v}")


def restitution_for_damping_ratio(damping_ratio: float) -> float:
    """Coefficient of restitution of a flat impact on a linear spring-dashpot that cannot pull.

    The contact force ``k x + c x'`` is clamped at zero, so the bodies part
    when that force vanishes, before the spring is back at rest (Schwager and
    Poschel 2007, Phys. Rev. E 75, 051304).  With ``beta = zeta omega_0`` and
    ``omega = omega_0 sqrt(1 - zeta^2)`` the force vanishes at
    ``omega t* = pi - atan2(2 beta omega, omega_0^2 - 2 beta^2)`` and
    ``e = exp(-beta t*) |cos(omega t*) - (beta / omega) sin(omega t*)|``.
    Valid for 0 <= zeta < 1.
    """
    zeta = float(damping_ratio)
    if not 0.0 <= zeta < 1.0:
        raise ValueError(f"damping ratio must be in [0, 1), got {zeta}")
    omega = math.sqrt(1.0 - zeta * zeta)  # in units of omega_0
    t_star = (math.pi - math.atan2(2.0 * zeta * omega, 1.0 - 2.0 * zeta * zeta)) / omega
    return math.exp(-zeta * t_star) * abs(math.cos(omega * t_star) - zeta / omega * math.sin(omega * t_star))


def damping_ratio_for_restitution(restitution: float) -> float:
    """Damping ratio whose flat impact rebounds with ``restitution`` (inverse of
    :func:`restitution_for_damping_ratio`); ``e`` from 0.136 (zeta -> 1) to 1."""
    low = restitution_for_damping_ratio(0.999)
    if not low <= restitution <= 1.0:
        raise ValueError(f"restitution must be in [{low:.3f}, 1], got {restitution}")
    if restitution == 1.0:
        return 0.0
    return float(brentq(lambda z: restitution_for_damping_ratio(z) - restitution, 0.0, 0.999, xtol=1e-14))


def normal_damping(stiffness: float, mass: float, *, restitution: float | None = None,
                   damping_ratio: float | None = None) -> float:
    """Dashpot constant ``C_n = 2 zeta sqrt(k m)`` (N s/m) for a target restitution or damping ratio.

    stiffness : N/m, the interface's linear normal stiffness ``K_n d L``.
    mass : kg, the effective (reduced) mass of the pair.
    Give exactly one of ``restitution`` (0 < e <= 1) and ``damping_ratio`` (>= 0).
    """
    if (restitution is None) == (damping_ratio is None):
        raise ValueError("give exactly one of restitution and damping_ratio")
    zeta = damping_ratio_for_restitution(restitution) if restitution is not None else float(damping_ratio)
    if zeta < 0:
        raise ValueError(f"damping_ratio must be >= 0, got {zeta}")
    return 2.0 * zeta * math.sqrt(stiffness * mass)


@dataclass(frozen=True)
class InterfaceArrays:
    """Dense per-pair parameters, indexed ``[i, j]`` by body index (0 = base).

    kn : (nb, nb) N/m^2 times depth, so that ``F = kn * A``.
    cn, cr, kt, ct : (nb, nb) N s/m, N s/m, N/m, N s/m (the couple is ``cr l^2 / 12`` times
        the relative angular velocity).
    mu : (nb, nb) Coulomb coefficient.
    k_linear : (nb, nb) N/m, ``K_n d L`` (used for the stable time step).
    m_eff : (nb, nb) kg, reduced mass of the pair (the block's mass against the base).
    active : (nb, nb) bool, pairs that may interact (not base with itself).
    """

    kn: np.ndarray
    cn: np.ndarray
    cr: np.ndarray
    kt: np.ndarray
    ct: np.ndarray
    mu: np.ndarray
    k_linear: np.ndarray
    m_eff: np.ndarray
    active: np.ndarray


def rocking_damping_ratio(scene) -> float:
    """The damping ratio of the rotational dashpot couple in force for ``scene``."""
    p = scene.contact
    if p.rocking_damping_ratio is None:
        return housner_damping_ratio(scene.rocking_slenderness)
    return p.rocking_damping_ratio


def interface_arrays(scene) -> InterfaceArrays:
    """Per-interface contact parameters of ``scene`` (see the module docstring)."""
    p = scene.contact
    bodies = scene.bodies
    nb = len(bodies)
    mass = np.array([0.0] + [b.mass for b in scene.blocks])
    width = np.array([b.width for b in bodies])
    depth = np.array([b.depth for b in bodies])
    d = np.minimum.outer(depth, depth)
    length = np.minimum.outer(width, width)
    total = mass[:, None] + mass[None, :]
    total[0, 0] = 1.0  # base with itself: never in contact
    m_eff = mass[:, None] * mass[None, :] / total
    m_eff[0, :] = mass  # the base is infinitely heavy: a block meets it with its own mass
    m_eff[:, 0] = mass
    kn = p.kn * d
    k_lin = kn * length
    cn = np.full((nb, nb), p.cn) if p.cn is not None else 2.0 * p.damping_ratio * np.sqrt(k_lin * m_eff)
    cr = (np.full((nb, nb), p.cr) if p.cr is not None
          else 2.0 * rocking_damping_ratio(scene) * np.sqrt(k_lin * m_eff))
    kt = np.full((nb, nb), p.kt) if p.kt is not None else p.tangential_stiffness_ratio * k_lin
    ct = np.full((nb, nb), p.ct) if p.ct is not None else 2.0 * p.tangential_damping_ratio * np.sqrt(kt * m_eff)
    mu = np.empty((nb, nb))
    for i, a in enumerate(bodies):
        for j, b in enumerate(bodies):
            mu[i, j] = scene.friction(a.name, b.name) if i != j else 0.0
    active = np.ones((nb, nb), bool)
    np.fill_diagonal(active, False)
    active[0, 0] = False
    for arr in (cn, cr, kt, ct):
        arr[~active] = 0.0
    return InterfaceArrays(kn, cn, cr, kt, ct, mu, k_lin, m_eff, active)
