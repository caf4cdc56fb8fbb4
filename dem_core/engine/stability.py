"""The time step: the stability limit of the explicit scheme and the duration of impacts (docs/method.md 1.7).

Central differences with the damping force taken at the lagging half step are stable only below a
limit set by the stiffest, most damped mode; impacts must moreover last several steps for the
energy they take to converge.  Both are computed from the contacts present at the start, with the
per-pair constants the kernel uses (:func:`dem_core.engine._contact_law.pair_parameters`).
"""

from typing import NamedTuple

import numpy as np
from scipy.linalg import eigh

from ._connector_law import ANCHOR_AX, ANCHOR_AY, AXIAL_K, AXIS_X, AXIS_Y, SHEAR_K
from ._contact_law import CORNER, dashpot, pair_parameters
from .model import Model


def _pair(model: Model, i: int, j: int):
    """(k_n, c_n, k_t, c_t, c_r, m_eff, length) of bodies i, j under the model's law."""
    b, law = model.bodies, model.law
    return pair_parameters(law.law, law.kn, law.zeta_n, law.zeta_t, law.zeta_r, law.kt_ratio, law.cn, law.cr,
                           law.kt, law.ct, b.mass[i], b.mass[j], b.width[i], b.width[j], b.depth[i], b.depth[j])


#: scenes of at most this many blocks get the dense analysis; larger ones the linear-time bound
DENSE_BLOCKS = 100
METHODS = ("amplification", "energy", "bound")


class Springs(NamedTuple):
    """Linearised contacts, each a spring and a dashpot along one constraint row that touches at most
    two blocks: ``dof`` (S, 6) int64 the degrees of freedom (3 per block, -1 for the base), ``row``
    (S, 6) the row's entries there, ``k`` (S,) N/m (or N m/rad), ``c`` (S,) N s/m."""

    dof: np.ndarray
    row: np.ndarray
    k: np.ndarray
    c: np.ndarray


def stability_limit(model: Model, toppled: bool = False, method: str | None = None) -> float:
    """Largest time step (s) at which the central-difference scheme stays stable.

    Linearises the contacts present at the start (pairs that touch within a hair's breadth) as flat
    faces of length ``L`` (the smaller of the two blocks' extents along the contact):

    * corner law: a normal spring ``k_p`` and dashpot ``c_p`` and a tangential spring and dashpot at
      each end of the face;
    * overlap-area law: the normal spring ``K_n d L`` and dashpot ``C_n`` at the face centre or a
      quarter of the face aside (a triangular overlap of extent ``l`` has normal stiffness
      ``K_n d l`` acting ``L/2 - l/3`` from the centre, and ``l (L/2 - l/3)^2 <= L^3 / 18``: the
      lever of the full stiffness at ``L / sqrt(18) ~ 0.24 L``), the tangential spring at the corner,
      and the rotational stiffness ``K_n d L^3 / 12`` with the couple ``C_r L^2 / 12``.

    Central differences with the damping on the lagging half step are stable on the linearised
    system while ``lambda_max(dt^2 K~ + 2 dt C~) <= 4``, with ``K~ = M^-1/2 K M^-1/2`` and ``C~``
    likewise (for one mode this is the damped limit ``(2/omega)(sqrt(1 + zeta^2) - zeta)``; the
    dashpots have their own limit, ``dt c / m`` about 2, which a bound on the undamped frequency
    misses).  ``method``:

    * ``"energy"`` (default up to ``DENSE_BLOCKS`` blocks): that largest eigenvalue, dense, and the dt
      that makes it 4;
    * ``"bound"`` (default above): block Gershgorin bounds of it, in time linear in the contacts, a
      step below the ``"energy"`` one (1.0 to 1.9 times below on the project's scenes);
    * ``"amplification"``: the spectral radius of the scheme's one-step amplification matrix,
      ``v' = v + dt M^-1 (-K x - C v)``, ``x' = x + dt v'``, and the largest dt that keeps it at 1,
      by bisection: the definition, slow, used by the tests to check the other two.

    Contacts that form later can be stiffer: a toppled block lying on its long side presses a longer
    face.  ``toppled=True`` allows for that by scaling the limit with ``sqrt(width / longest edge)``
    of the block where that ratio is smallest (the stiffness grows with the face length).
    ``model`` : the compiled scene (:func:`~dem_core.engine.model.compile_model`).
    """
    b = model.bodies
    n_blocks = len(b.mass) - 1
    mass = np.column_stack([b.mass[1:], b.mass[1:], b.inertia[1:]]).ravel()
    if len(model.faces.i) == 0:  # nothing touches yet: the stiffest contact that can form is a face on the base
        worst = np.inf
        for i in range(1, n_blocks + 1):
            k_n, c_n, *_rest, m_eff, length = _pair(model, 0, i)
            spring = k_n * (2.0 if model.law.law == CORNER else length)
            omega = np.sqrt(spring * (1.0 / b.mass[i] + b.radius[i] ** 2 / b.inertia[i]))
            worst = min(worst, float(_damped_limit(omega, _damping_ratio(model, 0, i))))
        return worst
    lying = min(b.width[i] / b.longest_edge[i] for i in range(1, n_blocks + 1)) if toppled else 1.0
    method = method or ("energy" if n_blocks <= DENSE_BLOCKS else "bound")
    if method not in METHODS:
        raise ValueError(f"method must be one of {', '.join(METHODS)}, got {method!r}")
    limit = {"amplification": _amplification_limit, "energy": _energy_limit, "bound": _bound_limit}[method]
    dt = np.inf
    shifts = (0.0,) if model.law.law == CORNER else (-1.0, 0.0, 1.0)
    for side in shifts:
        dt = min(dt, limit(linearised_springs(model, 0.25 * side, 0.5 * side), mass))
    return float(np.sqrt(lying) * dt)


def _bound_limit(springs: Springs, mass) -> float:
    """A lower bound of the limit in time linear in the contacts.

    The scheme is stable while ``lambda_max(dt^2 K~ + 2 dt C~) <= 4`` (for one mode this is the
    damped limit above; it reproduces the exact analysis to 1e-3 on every scene tried).  Block
    Gershgorin bounds that largest eigenvalue by the largest over blocks b of
    ``lambda_max(A_bb) + sum over its neighbours b' of ||A_bb'||`` for ``A = dt^2 K~ + 2 dt C~``
    (3 x 3 blocks; Frobenius norms off the diagonal); the largest dt that keeps the bound at 4 is
    found by bisection.
    """
    n_blocks = len(mass) // 3
    scale = np.where(springs.dof >= 0, 1.0 / np.sqrt(mass[np.maximum(springs.dof, 0)]), 0.0)
    scaled = springs.row * scale  # (S, 6): the mass-scaled rows, 3 entries per end
    body = np.where(springs.dof[:, ::3] >= 0, springs.dof[:, ::3] // 3, -1)  # (S, 2): the block at each end
    both = (body[:, 0] >= 0) & (body[:, 1] >= 0)
    pairs, which = np.unique(np.sort(body[both], axis=1), axis=0, return_inverse=True)
    forward = (body[both, 0] < body[both, 1])[:, None, None]
    parts = []
    for weights in (springs.k, springs.c):
        own = np.zeros((n_blocks, 3, 3))
        for end in (0, 1):
            on = body[:, end] >= 0
            v = scaled[on, 3 * end:3 * end + 3]
            np.add.at(own, body[on, end], weights[on, None, None] * v[:, :, None] * v[:, None, :])
        cross = weights[both, None, None] * scaled[both, 0:3, None] * scaled[both, None, 3:6]
        coupling = np.zeros((len(pairs), 3, 3))
        np.add.at(coupling, which.ravel(), np.where(forward, cross, np.transpose(cross, (0, 2, 1))))
        parts.append((own, coupling))

    def bound(dt):
        own = dt * dt * parts[0][0] + 2.0 * dt * parts[1][0]
        coupling = np.linalg.norm(dt * dt * parts[0][1] + 2.0 * dt * parts[1][1], axis=(1, 2))
        total = np.linalg.eigvalsh(own)[:, -1]
        np.add.at(total, pairs[:, 0], coupling)
        np.add.at(total, pairs[:, 1], coupling)
        return float(np.max(total))

    hi = 1.0
    while bound(hi) <= 4.0:
        hi *= 2.0
    return _largest_stable(lambda dt: bound(dt) <= 4.0, 0.0, hi, 1e-4)


def _largest_stable(stable, lo: float, hi: float, tolerance: float) -> float:
    """Bisection between a stable ``lo`` and an unstable ``hi`` step until they are ``tolerance`` (relative)
    apart; returns the stable end."""
    for _ in range(60):
        mid = 0.5 * (lo + hi)
        lo, hi = (mid, hi) if stable(mid) else (lo, mid)
        if hi - lo < tolerance * hi:
            break
    return lo


def _dense(springs: Springs, n_dof: int):
    """(n_dof, n_dof) stiffness and damping matrices of ``springs``."""
    stiffness = np.zeros((n_dof, n_dof))
    damping = np.zeros((n_dof, n_dof))
    for dof, row, k, c in zip(springs.dof, springs.row, springs.k, springs.c):
        used = dof >= 0
        outer = np.outer(row[used], row[used])
        stiffness[np.ix_(dof[used], dof[used])] += k * outer
        damping[np.ix_(dof[used], dof[used])] += c * outer
    return stiffness, damping


def _scaled(springs: Springs, mass):
    """The dense mass-scaled stiffness and damping, ``M^-1/2 K M^-1/2`` and ``M^-1/2 C M^-1/2``."""
    stiffness, damping = _dense(springs, len(mass))
    scale = 1.0 / np.sqrt(mass)
    return stiffness * scale[:, None] * scale[None, :], damping * scale[:, None] * scale[None, :]


def _energy_limit(springs: Springs, mass) -> float:
    """The dt at which ``lambda_max(dt^2 K~ + 2 dt C~)`` reaches 4 (it grows with dt), by bisection."""
    k_mod, c_mod = _scaled(springs, mass)

    def largest(dt):
        return eigh(dt * dt * k_mod + 2.0 * dt * c_mod, eigvals_only=True, subset_by_index=[len(mass) - 1] * 2)[0]

    omega = np.sqrt(eigh(k_mod, eigvals_only=True, subset_by_index=[len(mass) - 1] * 2)[0])
    # the undamped limit 2 / omega is the most damping can leave
    return _largest_stable(lambda dt: largest(dt) <= 4.0, 0.0, 2.0 / omega, 1e-5)


def _amplification_limit(springs: Springs, mass) -> float:
    """Largest dt for which central differences with lagged damping are stable on (M, C, K): the
    spectral radius of the one-step amplification matrix, by bisection."""
    k_mod, c_mod = _scaled(springs, mass)
    lam, modes = np.linalg.eigh(k_mod)
    keep = lam > 1e-12 * lam[-1]
    omega = np.sqrt(lam[keep])
    zeta = np.einsum("ik,ij,jk->k", modes[:, keep], c_mod, modes[:, keep]) / (2.0 * omega)
    modal = float(np.min(_damped_limit(omega, zeta)))
    n = len(mass)
    eye = np.eye(n)

    def stable(dt):
        a_k = dt * k_mod
        a_c = eye - dt * c_mod
        amp = np.block([[eye - dt * a_k, dt * a_c], [-a_k, a_c]])
        return np.max(np.abs(np.linalg.eigvals(amp))) <= 1.0 + 1e-9

    lo, hi = 0.25 * modal, 2.0 / omega[-1]
    if stable(hi):
        return hi
    while not stable(lo):
        lo *= 0.5
    return _largest_stable(stable, lo, hi, 1e-3)


def impact_duration(model: Model) -> float:
    """Shortest impact duration ``pi sqrt(m_eff / k)`` (s) of the face contacts touching at the start.

    Half a period of the face's spring: ``k = K_n d L`` of the whole face (both corner springs of the
    corner law, or the overlap law's face stiffness) and ``m_eff`` the pair's reduced mass.  Without
    touching faces, the blocks' contacts with the base count.
    """
    b, faces = model.bodies, model.faces
    pairs = [(int(i), int(j), float(extent)) for i, j, extent in zip(faces.i, faces.j, faces.extent)] or [
        (0, i, min(b.width[0], b.width[i])) for i in range(1, len(b.mass))]
    durations = []
    for i, j, extent in pairs:
        m_eff = _pair(model, i, j)[5]
        durations.append(np.pi * np.sqrt(m_eff / (model.law.kn * min(b.depth[i], b.depth[j]) * extent)))
    return float(min(durations))


def _damped_limit(omega, zeta):
    return 2.0 / omega * (np.sqrt(1.0 + zeta**2) - zeta)


def _damping_ratio(model: Model, i: int, j: int) -> float:
    """Largest damping ratio of the pair's dashpots against its own springs and reduced mass."""
    k_n, c_n, k_t, c_t, c_r, m_eff, length = _pair(model, i, j)
    if model.law.law == CORNER:
        c_n = dashpot(c_n, model.law.zeta_n, k_n, m_eff)
        c_t = dashpot(c_t, model.law.zeta_t, k_t, m_eff)
    spring = k_n if model.law.law == CORNER else k_n * length
    ratios = [max(c_n, c_r) / (2.0 * np.sqrt(spring * m_eff))]
    if k_t > 0:
        ratios.append(c_t / (2.0 * np.sqrt(k_t * m_eff)))
    return float(max(ratios))


def linearised_springs(model: Model, shift_n: float, shift_t: float) -> Springs:
    """The :class:`Springs` of the faces touching at the start (``model.faces``), built for all at once.

    Corner law: a normal and a tangential spring at both ends of each face, their dashpots from the
    damping ratios and the effective mass at each end (as the kernel computes them).  Overlap law:
    the normal and tangential springs with ``shift_n``, ``shift_t`` moving their points of action
    along the tangent by that fraction of the face length, and the rocking couple.
    """
    b, f = model.bodies, model.faces
    i, j, centroid, normal, tangent, extent = f.i, f.j, f.centroid, f.normal, f.tangent, f.extent
    constants = np.array([_pair(model, a, c)[:5] for a, c in zip(i, j)])  # k_n, c_n, k_t, c_t, c_r per face
    k_n, c_n, k_t, c_t, c_r = constants.T
    springs = []  # (point (F, 2), direction (F, 2), k (F,), c (F,)) per family of springs
    if model.law.law == CORNER:
        for end in (-0.5, 0.5):
            point = centroid + end * extent[:, None] * tangent
            for direction, k, given, zeta in ((normal, k_n, c_n, model.law.zeta_n),
                                              (tangent, k_t, c_t, model.law.zeta_t)):
                mass = 1.0 / _inverse_effective_mass(b, i, j, point, direction)
                springs.append((point, direction, k, np.array([dashpot(g, zeta, kk, m) for g, kk, m in
                                                               zip(given, k, mass)])))
    else:
        springs.append((centroid + shift_n * extent[:, None] * tangent, normal, k_n * extent, c_n))
        springs.append((centroid + shift_t * extent[:, None] * tangent, tangent, k_t, c_t))
    dofs, rows, ks, cs = [], [], [], []
    for point, direction, k, c in springs:
        dof, row = _rows(b, i, j, point, direction)
        dofs.append(dof)
        rows.append(row)
        ks.append(k)
        cs.append(c)
    if model.law.law != CORNER:  # the couple: relative rotation, k = K_n d L^3 / 12
        dof, row = _rows(b, i, j, centroid, normal)
        row[:, [0, 1, 3, 4]] = 0.0
        row[:, [2, 5]] = [-1.0, 1.0]
        dofs.append(dof)
        rows.append(row)
        ks.append(k_n * extent**3 / 12.0)
        cs.append(c_r * extent**2 / 12.0)
    for point, direction, k in _connector_springs(model):
        dof, row = _rows(b, model.connectors.bodies[:, 0], model.connectors.bodies[:, 1], point, direction)
        dofs.append(dof)
        rows.append(row)
        ks.append(k)
        cs.append(np.zeros_like(k))
    return Springs(np.concatenate(dofs), np.concatenate(rows), np.concatenate(ks), np.concatenate(cs))


def _connector_springs(model: Model) -> list:
    """``(point, direction, k)`` of the connectors' shear and tension springs (each (n_c, 2), (n_c, 2), (n_c,)) at
    their anchors at the start, the tension's as if the joint were open."""
    law, first = model.connectors.law, model.connectors.bodies[:, 0]
    if not len(law):
        return []
    angle = model.bodies.angle0[first]
    c, s = np.cos(angle), np.sin(angle)
    anchor, axis = law[:, [ANCHOR_AX, ANCHOR_AY]], law[:, [AXIS_X, AXIS_Y]]
    point = model.bodies.centroid0[first] + np.column_stack([c * anchor[:, 0] - s * anchor[:, 1],
                                                             s * anchor[:, 0] + c * anchor[:, 1]])
    normal = np.column_stack([c * axis[:, 0] - s * axis[:, 1], s * axis[:, 0] + c * axis[:, 1]])
    tangent = np.column_stack([-normal[:, 1], normal[:, 0]])
    return [(point, tangent, law[:, SHEAR_K]), (point, normal, law[:, AXIAL_K])]


def _inverse_effective_mass(b, i, j, point, direction):
    """(F,) ``1/m_i + 1/m_j + (r_i x d)^2 / I_i + (r_j x d)^2 / I_j`` at each face's point."""
    total = b.inv_mass[i] + b.inv_mass[j]
    for body in (i, j):
        r = point - b.centroid0[body]
        total = total + (r[:, 0] * direction[:, 1] - r[:, 1] * direction[:, 0]) ** 2 * b.inv_inertia[body]
    return total


def _rows(b, i, j, point, direction):
    """``(dof (F, 6), row (F, 6))`` of springs along ``direction`` at ``point`` between bodies i and j (the base,
    index 0, has no degrees of freedom: -1)."""
    dof = np.full((len(i), 6), -1, np.int64)
    row = np.zeros((len(i), 6))
    for slot, (body, sign) in enumerate(((i, -1.0), (j, 1.0))):
        r = point - b.centroid0[body]
        moving = body > 0
        dof[moving, 3 * slot:3 * slot + 3] = 3 * body[moving, None] - 3 + np.arange(3)
        entries = sign * np.column_stack([direction[:, 0], direction[:, 1],
                                          r[:, 0] * direction[:, 1] - r[:, 1] * direction[:, 0]])
        row[moving, 3 * slot:3 * slot + 3] = entries[moving]
    return dof, row
