"""The time step: the stability limit of the explicit scheme and the duration of impacts.

Central differences with the damping force taken at the lagging half step
are stable only below a limit set by the stiffest, most damped mode; impacts
must moreover last several steps for the energy they take to converge.
"""

import numpy as np

from .contact import InterfaceArrays, interface_arrays


def stability_limit(scene, interfaces: InterfaceArrays | None = None, toppled: bool = False) -> float:
    """Largest time step (s) at which the central-difference scheme stays stable.

    Linearises the contacts present at the start (pairs that touch within a
    hair's breadth) as flat faces of length ``L`` (the smaller of the two
    blocks' extents along the contact): normal spring ``k = K_n d L`` and
    dashpot ``C_n``, tangential ``K_t`` and ``C_t``, rotational stiffness
    ``k L^2 / 12`` and the dashpot couple ``C_n L^2 / 12``.  The contacts act
    at the centres of the faces or, as in rocking, off centre: the normal
    spring a quarter of the face length aside (a triangular overlap of extent
    ``l`` has normal stiffness ``K_n d l`` acting ``L/2 - l/3`` from the face
    centre, and ``l (L/2 - l/3)^2 <= L^3 / 18``: the lever of the full
    stiffness at ``L / sqrt(18) ~ 0.24 L``) and the tangential spring, whose
    stiffness does not shrink with the overlap, at the corner.

    For each case the one-step amplification matrix of the scheme,
    ``v' = v + dt M^-1 (-K x - C v)``, ``x' = x + dt v'`` (damping on the
    lagging half-step velocity), is formed and the largest dt with spectral
    radius <= 1 found by bisection; the smallest over the cases is returned.
    This catches the dashpots' own limit (explicit damping is stable only
    while ``dt c / m`` stays below about 2), which a bound on the undamped
    frequency misses: a tall block's tangential dashpot acts on its rocking
    through a lever of its full height.  Above 60 blocks the per-mode bound
    ``(2 / omega) (sqrt(1 + zeta^2) - zeta)`` with the modal damping ratios
    replaces the bisection.

    Contacts that form later can be stiffer: a toppled block lying on its
    long side presses a longer face.  ``toppled=True`` allows for that by
    scaling the limit with ``sqrt(width / longest edge)`` of the block where
    that ratio is smallest (the stiffness grows with the face length).
    """
    ia = interface_arrays(scene) if interfaces is None else interfaces
    mass = np.array([[b.mass, b.mass, b.inertia] for b in scene.blocks]).ravel()
    faces = _touching_faces(scene, ia)
    if not faces:  # nothing touches yet: the stiffest contact that can form is a face on the base
        lam = max(ia.k_linear[0, i] * (1.0 / b.mass + b.circumradius**2 / b.inertia) for i, b in
                  enumerate(scene.blocks, start=1))
        return float(_damped_limit(np.sqrt(lam), _largest_damping_ratio(scene, ia)))
    lying = min(b.width / _longest_edge(b.vertices) for b in scene.blocks) if toppled else 1.0
    dt = np.inf
    for side in (-1.0, 0.0, 1.0):
        stiffness, damping = _linearised_matrices(scene, ia, faces, 0.25 * side, 0.5 * side)
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


def impact_duration(scene, interfaces: InterfaceArrays | None = None) -> float:
    """Shortest impact duration ``pi sqrt(m_eff / k)`` (s) of the face contacts touching at the start.

    Half a period of the face's spring: ``k = K_n d L`` of the face and
    ``m_eff`` the pair's reduced mass.  Without touching faces, the blocks'
    contacts with the base count.
    """
    ia = interface_arrays(scene) if interfaces is None else interfaces
    faces = _touching_faces(scene, ia)
    if faces:
        stiffness = [(ia.kn[i, j] * extent, ia.m_eff[i, j]) for i, j, _, _, _, extent in faces]
    else:
        stiffness = [(ia.k_linear[0, i], ia.m_eff[0, i]) for i in range(1, len(scene.bodies))]
    return float(min(np.pi * np.sqrt(m / k) for k, m in stiffness))


def _longest_edge(vertices) -> float:
    edges = np.roll(vertices, -1, axis=0) - vertices
    return float(np.max(np.hypot(edges[:, 0], edges[:, 1])))


def _damped_limit(omega, zeta):
    return 2.0 / omega * (np.sqrt(1.0 + zeta**2) - zeta)


def _touching_faces(scene, ia: InterfaceArrays) -> list:
    """``(i, j, centroid, normal, tangent, L)`` of every interacting pair touching at the start."""
    faces = []
    for i, j, touch in scene.touching_pairs():
        if ia.active[i, j]:
            p, q = scene.bodies[i], scene.bodies[j]
            t = touch.tangent
            extent = min(np.ptp(p.vertices @ t), np.ptp(q.vertices @ t))
            faces.append((i, j, touch.centroid, touch.normal, t, extent))
    return faces


def _linearised_matrices(scene, ia: InterfaceArrays, faces: list, shift_n: float, shift_t: float):
    """(3 n, 3 n) stiffness and damping of the touching faces, n = number of blocks.

    ``shift_n``, ``shift_t`` move the points of action of the normal and the
    tangential spring along the tangent by that fraction of the face length.
    """
    bodies = scene.bodies
    n = len(scene.blocks)
    stiffness = np.zeros((3 * n, 3 * n))
    damping = np.zeros((3 * n, 3 * n))
    for i, j, centroid, normal, t, extent in faces:
        k_n = ia.kn[i, j] * extent
        rows = []
        for direction, k, c, shift in ((normal, k_n, ia.cn[i, j], shift_n), (t, ia.kt[i, j], ia.ct[i, j], shift_t)):
            point = centroid + shift * extent * t
            row = np.zeros(3 * n)
            for body, sign in ((i, -1.0), (j, 1.0)):
                if body:
                    r = point - bodies[body].centroid
                    row[3 * body - 3:3 * body] = sign * np.array(
                        [direction[0], direction[1], r[0] * direction[1] - r[1] * direction[0]])
            rows.append((row, k, c))
        rot = np.zeros(3 * n)
        for body, sign in ((i, -1.0), (j, 1.0)):
            if body:
                rot[3 * body - 1] = sign
        rows.append((rot, k_n * extent**2 / 12.0, ia.cr[i, j] * extent**2 / 12.0))
        for row, k, c in rows:
            outer = np.outer(row, row)
            stiffness += k * outer
            damping += c * outer
    return stiffness, damping


def _largest_damping_ratio(scene, ia: InterfaceArrays) -> float:
    m_eff = ia.m_eff[ia.active]
    zn = np.maximum(ia.cn[ia.active], ia.cr[ia.active]) / (2.0 * np.sqrt(ia.k_linear[ia.active] * m_eff))
    with np.errstate(invalid="ignore", divide="ignore"):
        zt = np.where(ia.kt[ia.active] > 0, ia.ct[ia.active] / (2.0 * np.sqrt(ia.kt[ia.active] * m_eff)), 0.0)
    return float(max(zn.max(), zt.max(), 0.0))
