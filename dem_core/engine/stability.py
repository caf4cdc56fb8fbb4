"""The time step: the stability limit of the explicit scheme and the duration of impacts (docs/method.md 1.7).

Central differences with the damping force taken at the lagging half step are stable only below a
limit set by the stiffest, most damped mode; impacts must moreover last several steps for the
energy they take to converge.  Both are computed from the contacts present at the start, with the
per-pair constants the kernel uses (:func:`dem_core.engine._contact_law.pair_parameters`).
"""

import numpy as np

from ._contact_law import CORNER, dashpot, effective_mass, pair_parameters
from .model import Model, compile_model


def _pair(model: Model, i: int, j: int):
    """(k_n, c_n, k_t, c_t, c_r, m_eff, length) of bodies i, j under the model's law."""
    b, law = model.bodies, model.law
    return pair_parameters(law.law, law.kn, law.zeta_n, law.zeta_t, law.zeta_r, law.kt_ratio, law.cn, law.cr,
                           law.kt, law.ct, b.mass[i], b.mass[j], b.width[i], b.width[j], b.depth[i], b.depth[j])


def stability_limit(scene, model: Model | None = None, toppled: bool = False) -> float:
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

    For each case the one-step amplification matrix of the scheme, ``v' = v + dt M^-1 (-K x - C v)``,
    ``x' = x + dt v'`` (damping on the lagging half-step velocity), is formed and the largest dt with
    spectral radius <= 1 found by bisection; the smallest over the cases is returned.  This catches
    the dashpots' own limit (explicit damping is stable only while ``dt c / m`` stays below about
    2), which a bound on the undamped frequency misses.  Above 60 blocks the per-mode bound
    ``(2 / omega) (sqrt(1 + zeta^2) - zeta)`` with the modal damping ratios replaces the bisection.

    Contacts that form later can be stiffer: a toppled block lying on its long side presses a longer
    face.  ``toppled=True`` allows for that by scaling the limit with ``sqrt(width / longest edge)``
    of the block where that ratio is smallest (the stiffness grows with the face length).
    ``model`` : the compiled scene, if already compiled.
    """
    touching = scene.touching_pairs()
    model = compile_model(scene) if model is None else model
    mass = np.array([[b.mass, b.mass, b.inertia] for b in scene.blocks]).ravel()
    faces = _touching_faces(scene, touching)
    if not faces:  # nothing touches yet: the stiffest contact that can form is a face on the base
        worst = np.inf
        for i, b in enumerate(scene.blocks, start=1):
            k_n, c_n, *_rest, m_eff, length = _pair(model, 0, i)
            spring = k_n * (2.0 if model.law.law == CORNER else length)
            omega = np.sqrt(spring * (1.0 / b.mass + b.circumradius ** 2 / b.inertia))
            worst = min(worst, float(_damped_limit(omega, _damping_ratio(model, 0, i))))
        return worst
    lying = min(b.width / _longest_edge(b.vertices) for b in scene.blocks) if toppled else 1.0
    dt = np.inf
    shifts = (0.0,) if model.law.law == CORNER else (-1.0, 0.0, 1.0)
    for side in shifts:
        stiffness, damping = _linearised_matrices(scene, model, faces, 0.25 * side, 0.5 * side)
        dt = min(dt, _scheme_limit(stiffness, damping, mass))
    return float(np.sqrt(lying) * dt)


def _scheme_limit(stiffness, damping, mass) -> float:
    """Largest dt for which central differences with lagged damping are stable on (M, C, K)."""
    scale = 1.0 / np.sqrt(mass)
    k_mod = stiffness * scale[:, None] * scale[None, :]
    c_mod = damping * scale[:, None] * scale[None, :]
    lam, modes = np.linalg.eigh(k_mod)
    keep = lam > 1e-12 * lam[-1]
    omega = np.sqrt(lam[keep])
    zeta = np.einsum("ik,ij,jk->k", modes[:, keep], c_mod, modes[:, keep]) / (2.0 * omega)
    modal = float(np.min(_damped_limit(omega, zeta)))
    n = len(mass)
    if n > 180:
        return modal
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
    for _ in range(30):
        mid = 0.5 * (lo + hi)
        lo, hi = (mid, hi) if stable(mid) else (lo, mid)
        if hi - lo < 1e-3 * lo:
            break
    return lo


def impact_duration(scene, model: Model | None = None) -> float:
    """Shortest impact duration ``pi sqrt(m_eff / k)`` (s) of the face contacts touching at the start.

    Half a period of the face's spring: ``k = K_n d L`` of the whole face (both corner springs of the
    corner law, or the overlap law's face stiffness) and ``m_eff`` the pair's reduced mass.  Without
    touching faces, the blocks' contacts with the base count.
    """
    model = compile_model(scene) if model is None else model
    faces = _touching_faces(scene, scene.touching_pairs())
    pairs = [(i, j, extent) for i, j, _, _, _, extent in faces] or [
        (0, i, min(scene.base.width, b.width)) for i, b in enumerate(scene.blocks, start=1)]
    durations = []
    for i, j, extent in pairs:
        m_eff = _pair(model, i, j)[5]
        durations.append(np.pi * np.sqrt(m_eff / (model.law.kn * min(scene.bodies[i].depth, scene.bodies[j].depth)
                                                   * extent)))
    return float(min(durations))


def _longest_edge(vertices) -> float:
    edges = np.roll(vertices, -1, axis=0) - vertices
    return float(np.max(np.hypot(edges[:, 0], edges[:, 1])))


def _damped_limit(omega, zeta):
    return 2.0 / omega * (np.sqrt(1.0 + zeta**2) - zeta)


def _point_mass(model: Model, i: int, j: int, point, direction) -> float:
    """Effective mass (kg) of bodies i and j at ``point`` along ``direction``, as the kernel computes it."""
    b = model.bodies
    ri = point - b.centroid0[i]
    rj = point - b.centroid0[j]
    return effective_mass(direction[0], direction[1], ri[0], ri[1], b.inv_mass[i], b.inv_inertia[i], rj[0], rj[1],
                          b.inv_mass[j], b.inv_inertia[j])


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


def _touching_faces(scene, touching) -> list:
    """``(i, j, centroid, normal, tangent, L)`` of every pair touching at the start."""
    faces = []
    for i, j, touch in touching:
        p, q = scene.bodies[i], scene.bodies[j]
        t = touch.tangent
        extent = min(np.ptp(p.vertices @ t), np.ptp(q.vertices @ t))
        faces.append((i, j, touch.centroid, touch.normal, t, extent))
    return faces


def _row(scene, i, j, point, direction):
    """The constraint row of a spring along ``direction`` at ``point`` between bodies i and j."""
    n = len(scene.blocks)
    row = np.zeros(3 * n)
    for body, sign in ((i, -1.0), (j, 1.0)):
        if body:
            r = point - scene.bodies[body].centroid
            row[3 * body - 3:3 * body] = sign * np.array(
                [direction[0], direction[1], r[0] * direction[1] - r[1] * direction[0]])
    return row


def _linearised_matrices(scene, model: Model, faces: list, shift_n: float, shift_t: float):
    """(3 n, 3 n) stiffness and damping of the touching faces, n = number of blocks.

    Corner law: springs at both ends of each face.  Overlap law: ``shift_n``, ``shift_t`` move the
    points of action of the normal and the tangential spring along the tangent by that fraction of
    the face length.
    """
    n = len(scene.blocks)
    stiffness = np.zeros((3 * n, 3 * n))
    damping = np.zeros((3 * n, 3 * n))
    for i, j, centroid, normal, t, extent in faces:
        k_n, c_n, k_t, c_t, c_r, _, _ = _pair(model, i, j)
        rows = []
        if model.law.law == CORNER:
            for end in (-0.5, 0.5):
                point = centroid + end * extent * t
                for direction, k, given, zeta in ((normal, k_n, c_n, model.law.zeta_n), (t, k_t, c_t, model.law.zeta_t)):
                    mass = _point_mass(model, i, j, point, direction)
                    rows.append((_row(scene, i, j, point, direction), k, dashpot(given, zeta, k, mass)))
        else:
            spring = k_n * extent
            rows.append((_row(scene, i, j, centroid + shift_n * extent * t, normal), spring, c_n))
            rows.append((_row(scene, i, j, centroid + shift_t * extent * t, t), k_t, c_t))
            rot = np.zeros(3 * n)
            for body, sign in ((i, -1.0), (j, 1.0)):
                if body:
                    rot[3 * body - 1] = sign
            rows.append((rot, spring * extent**2 / 12.0, c_r * extent**2 / 12.0))
        for row, k, c in rows:
            outer = np.outer(row, row)
            stiffness += k * outer
            damping += c * outer
    return stiffness, damping
