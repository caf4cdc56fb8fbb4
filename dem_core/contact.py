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
  ``zeta_n``.  The default ``zeta_n`` is calibrated so that a rocking block
  loses the energy Housner's impact rule predicts (FORMULATION 4.2), see
  ``comparisons/calibrate_damping.py``;
* ``K_t = tangential_stiffness_ratio * k`` and
  ``C_t = 2 * zeta_t * sqrt(K_t * m_eff)``.

:func:`damping_ratio_for_restitution` and :func:`normal_damping` map a target
coefficient of restitution or damping ratio onto ``C_n``.
"""

import math
from dataclasses import dataclass

import numpy as np

from .geometry import contact_geometry

# Calibrated against Housner's impact loss, see the module docstring.
DEFAULT_DAMPING_RATIO = 0.6
DEFAULT_NORMAL_STIFFNESS = 1.0e10  # N/m^2 per metre of depth


@dataclass(frozen=True)
class ContactParameters:
    """Soft-contact parameters of a scene.

    kn : N/m^2 per m depth, penalty stiffness on the overlap area.
    damping_ratio : zeta_n of every interface's normal dashpot (ignored if ``cn`` is given).
    tangential_stiffness_ratio : K_t / (K_n d L) (ignored if ``kt`` is given).
    tangential_damping_ratio : zeta_t of the tangential dashpot (ignored if ``ct`` is given).
    cn, kt, ct : explicit N s/m, N/m, N s/m applied to every interface, or None
        for the per-interface defaults.
    """

    kn: float = DEFAULT_NORMAL_STIFFNESS
    damping_ratio: float = DEFAULT_DAMPING_RATIO
    tangential_stiffness_ratio: float = 0.5
    tangential_damping_ratio: float = DEFAULT_DAMPING_RATIO
    cn: float | None = None
    kt: float | None = None
    ct: float | None = None

    def __post_init__(self):
        for name in ("kn", "tangential_stiffness_ratio"):
            v = getattr(self, name)
            if not (np.isfinite(v) and v > 0):
                raise ValueError(f"contact parameter {name} must be positive, got {v}")
        for name in ("damping_ratio", "tangential_damping_ratio"):
            v = getattr(self, name)
            if not (np.isfinite(v) and v >= 0):
                raise ValueError(f"contact parameter {name} must be >= 0, got {v}")
        for name in ("cn", "kt", "ct"):
            v = getattr(self, name)
            if v is not None and not (np.isfinite(v) and v >= 0):
                raise ValueError(f"contact parameter {name} must be >= 0 or None, got {v}")


def damping_ratio_for_restitution(restitution: float) -> float:
    """Damping ratio of a linear spring-dashpot whose impact rebounds with ``restitution``.

    For ``m x'' + c x' + k x = 0`` over one contact half-cycle,
    ``e = exp(-zeta pi / sqrt(1 - zeta^2))``, so
    ``zeta = -ln e / sqrt(pi^2 + ln^2 e)``.  ``restitution`` in (0, 1].
    """
    if not 0.0 < restitution <= 1.0:
        raise ValueError(f"restitution must be in (0, 1], got {restitution}")
    log_e = math.log(restitution)
    return -log_e / math.sqrt(math.pi**2 + log_e**2)


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
    cn, kt, ct : (nb, nb) N s/m, N/m, N s/m.
    mu : (nb, nb) Coulomb coefficient.
    k_linear : (nb, nb) N/m, ``K_n d L`` (used for the stable time step).
    m_eff : (nb, nb) kg, reduced mass of the pair (the block's mass against the base).
    active : (nb, nb) bool, pairs that may interact (not base with itself).
    """

    kn: np.ndarray
    cn: np.ndarray
    kt: np.ndarray
    ct: np.ndarray
    mu: np.ndarray
    k_linear: np.ndarray
    m_eff: np.ndarray
    active: np.ndarray


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
    kt = np.full((nb, nb), p.kt) if p.kt is not None else p.tangential_stiffness_ratio * k_lin
    ct = np.full((nb, nb), p.ct) if p.ct is not None else 2.0 * p.tangential_damping_ratio * np.sqrt(kt * m_eff)
    mu = np.empty((nb, nb))
    for i, a in enumerate(bodies):
        for j, b in enumerate(bodies):
            mu[i, j] = scene.friction(a.name, b.name) if i != j else 0.0
    active = np.ones((nb, nb), bool)
    np.fill_diagonal(active, False)
    active[0, 0] = False
    for arr in (cn, kt, ct):
        arr[~active] = 0.0
    return InterfaceArrays(kn, cn, kt, ct, mu, k_lin, m_eff, active)


def stability_limit(scene, interfaces: InterfaceArrays | None = None) -> float:
    """Largest time step (s) at which the central-difference scheme stays stable.

    Linearises the contacts present at the start (pairs that touch within a
    hair's breadth) as flat faces of length ``L`` (the smaller of the two
    blocks' extents along the contact): normal stiffness ``k = K_n d L`` and
    tangential ``K_t`` at the contact point, rotational stiffness
    ``k L^2 / 12``.  The contact point is taken at the centre and at either
    end of each face (rocking), and the stiffest case counts:
    ``omega_max^2`` is the largest eigenvalue of ``M^-1 K`` (a Gershgorin
    bound above 300 blocks).  The limit of central differences with the
    damping force taken at the previous half step,
    ``dt = (2 / omega_max) (sqrt(1 + zeta^2) - zeta)``, then applies with the
    largest damping ratio of the scene's interfaces.  Measured against runs
    that blow up (``comparisons/stability_probe.py``) this estimate is within
    a factor 1.1 to 2.5 of the true limit, hence the default safety factor of
    :func:`dem_core.simulate`.
    Contacts that form later (a toppled block lying on its side) can be
    stiffer: the simulation's stability checks catch those.
    """
    ia = interface_arrays(scene) if interfaces is None else interfaces
    mass = np.array([[b.mass, b.mass, b.inertia] for b in scene.blocks]).ravel()
    scale = 1.0 / np.sqrt(mass)
    faces = _touching_faces(scene, ia)
    if not faces:  # nothing touches yet: the stiffest contact that can form is a face on the base
        lam = max(ia.k_linear[0, i] * (1.0 / b.mass + b.circumradius**2 / b.inertia) for i, b in
                  enumerate(scene.blocks, start=1))
        return _damped_limit(np.sqrt(lam), _largest_damping_ratio(scene, ia))
    lam = 0.0
    for shift in (-0.5, 0.0, 0.5):
        k_mod = _linearised_stiffness(scene, ia, faces, shift) * scale[:, None] * scale[None, :]
        if len(mass) <= 900:
            lam = max(lam, float(np.linalg.eigvalsh(k_mod)[-1]))
        else:
            lam = max(lam, float(np.max(np.sum(np.abs(k_mod), axis=1))))
    return _damped_limit(np.sqrt(lam), _largest_damping_ratio(scene, ia))


def _damped_limit(omega, zeta):
    return 2.0 / omega * (np.sqrt(1.0 + zeta**2) - zeta)


def _touching_faces(scene, ia: InterfaceArrays) -> list:
    """``(i, j, centroid, normal, tangent, L)`` of every pair touching at the start."""
    bodies = scene.bodies
    faces = []
    for i in range(len(bodies)):
        for j in range(i + 1, len(bodies)):
            p, q = bodies[i], bodies[j]
            gap = q.centroid - p.centroid
            dist = np.hypot(*gap)
            if not ia.active[i, j] or dist > p.circumradius + q.circumradius:
                continue
            nudge = 1e-6 * min(p.width, p.height, q.width, q.height)
            touch = contact_geometry(p.vertices, q.vertices - nudge * gap / dist)
            if touch is None:
                continue
            t = touch.tangent
            extent = min(np.ptp(p.vertices @ t), np.ptp(q.vertices @ t))
            faces.append((i, j, touch.centroid, touch.normal, t, extent))
    return faces


def _linearised_stiffness(scene, ia: InterfaceArrays, faces: list, shift: float) -> np.ndarray:
    """(3 n, 3 n) stiffness of the touching faces, n = number of blocks.

    ``shift`` moves every contact point along its tangent by that fraction
    of the face length (-0.5 and 0.5: all contacts at a corner, as in rocking).
    """
    bodies = scene.bodies
    n = len(scene.blocks)
    stiffness = np.zeros((3 * n, 3 * n))
    for i, j, centroid, normal, t, extent in faces:
        point = centroid + shift * extent * t
        k_n = ia.kn[i, j] * extent
        rows = []
        for direction, k in ((normal, k_n), (t, ia.kt[i, j])):
            row = np.zeros(3 * n)
            for body, sign in ((i, -1.0), (j, 1.0)):
                if body:
                    r = point - bodies[body].centroid
                    row[3 * body - 3:3 * body] = sign * np.array(
                        [direction[0], direction[1], r[0] * direction[1] - r[1] * direction[0]])
            rows.append((row, k))
        rot = np.zeros(3 * n)
        for body, sign in ((i, -1.0), (j, 1.0)):
            if body:
                rot[3 * body - 1] = sign
        rows.append((rot, k_n * extent**2 / 12.0))
        for row, k in rows:
            stiffness += k * np.outer(row, row)
    return stiffness


def _largest_damping_ratio(scene, ia: InterfaceArrays) -> float:
    m_eff = ia.m_eff[ia.active]
    zn = ia.cn[ia.active] / (2.0 * np.sqrt(ia.k_linear[ia.active] * m_eff))
    with np.errstate(invalid="ignore", divide="ignore"):
        zt = np.where(ia.kt[ia.active] > 0, ia.ct[ia.active] / (2.0 * np.sqrt(ia.kt[ia.active] * m_eff)), 0.0)
    return float(max(zn.max(), zt.max(), 0.0))
