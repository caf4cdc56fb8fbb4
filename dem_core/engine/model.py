"""What a scene compiles to: the immutable arrays the kernels read (after MuJoCo's model / data split).

:func:`compile_model` turns a :class:`~dem_core.inputs.scene.Scene` into a :class:`Model`, a few
named tuples of arrays and scalars; where the bodies are during a run lives apart, in
:class:`~dem_core.engine.state.State`.  Body 0 is the base, then the scene's blocks in order.
What the compiled driver reads of a model is packed into a few arrays by :mod:`.model_arrays`.
"""

from typing import NamedTuple

import numpy as np

from . import geometry
from ._connector_law import (ANCHOR_AX, ANCHOR_AY, ANCHOR_BX, ANCHOR_BY, AXIAL_K, AXIAL_STRENGTH, AXIS_X, AXIS_Y,
                             BACK_LIMIT, CLEARANCE, HARDENING, N_LAW, SHEAR_K, SLIP_CAPACITY, YIELD_FORCE)
from ._interfaces import A_X, A_Y, B_X, B_Y, HALF_WIDTH, N_GEOMETRY, T_X, T_Y, TURN0, follow_interfaces
from .contact import LAWS, rocking_damping_ratio
from .stacks import find_stacks, top_face
from .state import interface_offsets

#: a corner-law contact deeper than this fraction of the smaller block's smaller extent stops the run
MAX_PENETRATION_FRACTION = 0.05
#: an overlap-area-law overlap larger than this fraction of the smaller block's area stops the run
MAX_OVERLAP_FRACTION = 0.05
#: the broad phase lists pairs whose boxes come within this fraction of the smallest block's smaller extent
SKIN_FRACTION = 0.1


class Bodies(NamedTuple):
    """Per body (``nb`` bodies, base first) and per vertex (``nv`` in all).

    local_x, local_y : (nv,) m, vertices about the centre of mass with the starting angle undone.
    normal_x, normal_y : (nv,) outward unit normal of edge k (vertex k to k + 1), same frame.
    vstart : (nb + 1,) int64, where each body's vertices start.
    mass, inertia : (nb,) kg, kg m^2 about the centre of mass; zero for the base.
    inv_mass, inv_inertia : (nb,) 1/kg, 1/(kg m^2); zero for the base.
    radius : (nb,) m, largest distance from the centre of mass to a vertex.  longest_edge : (nb,) m.
    area : (nb,) m^2.  width : (nb,) m, horizontal extent at the start.  size : (nb,) m, the smaller
    of width and height.  depth : (nb,) m.  friction : (nb,) the blocks' own coefficients.
    critical_angle : (nb,) rad, atan(b/h) of each block.  y_start : (nb,) m, height of the centre of
    mass at the start (the base's, ``y_start[0]``, where the base starts).  drop_limit : (nb,) m, a centre of mass
    this far below its start, relative to the base, has fallen (inf for a block that starts free,
    :attr:`~dem_core.Scene.free_bodies`).
    angle0 : (nb,) rad, starting angles.  centroid0 : (nb, 2) m, starting centres of mass.
    """

    local_x: np.ndarray
    local_y: np.ndarray
    normal_x: np.ndarray
    normal_y: np.ndarray
    vstart: np.ndarray
    mass: np.ndarray
    inertia: np.ndarray
    inv_mass: np.ndarray
    inv_inertia: np.ndarray
    radius: np.ndarray
    longest_edge: np.ndarray
    area: np.ndarray
    width: np.ndarray
    size: np.ndarray
    depth: np.ndarray
    friction: np.ndarray
    critical_angle: np.ndarray
    y_start: np.ndarray
    drop_limit: np.ndarray
    angle0: np.ndarray
    centroid0: np.ndarray


class Law(NamedTuple):
    """The contact law and its scene-wide constants (see :mod:`dem_core.engine.contact`).

    law : CORNER or OVERLAP_AREA.  kn : N/m^2 per m depth.  zeta_n, zeta_t, zeta_r : damping ratios.
    kt_ratio : tangential over normal spring.  cn, cr, kt, ct : explicit values or NaN.
    friction_keys : (k,) int64 sorted ``i * nb + j`` (i < j) of the interfaces with their own
    coefficient, friction_values : (k,) those coefficients.
    max_penetration : fraction of the smaller block's size (corner law) or area (overlap law) past
    which a contact means the run has lost stability.  skin : m, the broad phase's margin.
    restitution : Newton's coefficient of the Moreau-Jean integrator's impacts (0 unless given: plastic).
    """

    law: int
    kn: float
    zeta_n: float
    zeta_t: float
    zeta_r: float
    kt_ratio: float
    cn: float
    cr: float
    kt: float
    ct: float
    friction_keys: np.ndarray
    friction_values: np.ndarray
    max_penetration: float
    skin: float
    restitution: float


class Stacks(NamedTuple):
    """The columns (:mod:`dem_core.engine.stacks`) as the kernel checks them.

    stack_id : (nb,) int64, the stack of each body or -1.  bottom : (ns,) int64 bottom body.
    mass : (ns,) kg.  foot : (ns, 2, 2) m, the ends of the bottom body's base in its own frame.
    """

    stack_id: np.ndarray
    bottom: np.ndarray
    mass: np.ndarray
    foot: np.ndarray


class Faces(NamedTuple):
    """The pairs of bodies touching at the start (:meth:`~dem_core.Scene.touching_pairs`), ``F`` of them.

    i, j : (F,) int64 bodies, i < j.  centroid : (F, 2) m, the contact's point.  normal, tangent : (F, 2)
    unit vectors of the contact.  extent : (F,) m, the smaller of the two bodies' extents along the tangent.
    """

    i: np.ndarray
    j: np.ndarray
    centroid: np.ndarray
    normal: np.ndarray
    tangent: np.ndarray
    extent: np.ndarray


class Connectors(NamedTuple):
    """The scene's connectors (:mod:`dem_core.inputs.connectors`), ``n_c`` of them, in the order of the interfaces
    they cross.

    law : (n_c, N_LAW) their rows of :mod:`._connector_law`.  bodies : (n_c, 2) int64 the two bodies of each, in
    the order of its interface's key.  start : (n_if + 1,) int64, interface k's connectors are ``start[k]`` to
    ``start[k + 1]``.  order : (n_c,) int64, each one's place in ``scene.connectors``.
    """

    law: np.ndarray
    bodies: np.ndarray
    start: np.ndarray
    order: np.ndarray


class Model(NamedTuple):
    """A compiled scene: ``bodies``, ``law``, ``stacks``, the ``faces`` touching at the start;
    ``interface_keys`` (n_if,) int64 sorted ``i * nb + j`` of those faces' pairs, whose slip is recorded
    over time, and ``interface_geometry`` (n_if, 8) their rows in that order (:mod:`._interfaces`); ``gravity``
    m/s^2; ``floor`` m, the lower end of the base's top face (:func:`~.stacks.top_face`; its top, on a level base)
    relative to its centre of mass; ``top`` m, the highest block vertex above that end at the start; ``connectors``
    across the interfaces."""

    bodies: Bodies
    law: Law
    stacks: Stacks
    faces: Faces
    interface_keys: np.ndarray
    interface_geometry: np.ndarray
    gravity: float
    floor: float
    top: float
    connectors: Connectors


def _edge_normals(vertices: np.ndarray, vstart: np.ndarray) -> np.ndarray:
    """(nv, 2) outward unit normals of every polygon's edges (edge k from vertex k to the next)."""
    following = np.arange(1, len(vertices) + 1)
    following[vstart[1:] - 1] = vstart[:-1]  # each polygon's last vertex is followed by its first
    edges = vertices[following] - vertices
    normals = np.column_stack([edges[:, 1], -edges[:, 0]])
    return normals / np.hypot(normals[:, 0], normals[:, 1])[:, None]


def compile_bodies(scene) -> Bodies:
    """The :class:`Bodies` of ``scene`` (base first)."""
    bodies = scene.bodies
    centroids = np.array([b.centroid for b in bodies])
    angle0 = np.array([b.angle for b in bodies])
    local = [geometry.transform(b.vertices - c, -a) for b, c, a in zip(bodies, centroids, angle0)]
    allv = np.concatenate(local)
    vstart = np.zeros(len(bodies) + 1, np.int64)
    vstart[1:] = np.cumsum([len(v) for v in local])
    normals = _edge_normals(allv, vstart)
    mass = np.array([0.0] + [b.mass for b in scene.blocks])
    inertia = np.array([0.0] + [b.inertia for b in scene.blocks])
    with np.errstate(divide="ignore"):
        inv_mass = np.where(mass > 0, 1.0 / np.where(mass > 0, mass, 1.0), 0.0)
        inv_inertia = np.where(inertia > 0, 1.0 / np.where(inertia > 0, inertia, 1.0), 0.0)
    edges = [np.roll(b.vertices, -1, axis=0) - b.vertices for b in bodies]
    size = np.array([min(b.width, b.height) for b in bodies])
    drop_limit = 0.5 * size
    drop_limit[list(scene.free_bodies)] = np.inf  # a block released in the air falls; it has not overturned
    return Bodies(
        local_x=np.ascontiguousarray(allv[:, 0]), local_y=np.ascontiguousarray(allv[:, 1]),
        normal_x=np.ascontiguousarray(normals[:, 0]), normal_y=np.ascontiguousarray(normals[:, 1]),
        vstart=vstart, mass=mass, inertia=inertia, inv_mass=inv_mass, inv_inertia=inv_inertia,
        radius=np.array([b.circumradius for b in bodies]),
        longest_edge=np.array([float(np.max(np.hypot(e[:, 0], e[:, 1]))) for e in edges]),
        area=np.array([b.area for b in bodies]),
        width=np.array([b.width for b in bodies]), size=size, depth=np.array([b.depth for b in bodies]),
        friction=np.array([b.friction for b in bodies]),
        critical_angle=np.array([b.critical_angle for b in bodies]), y_start=centroids[:, 1].copy(),
        drop_limit=drop_limit, angle0=angle0, centroid0=centroids)


def compile_law(scene, bodies: Bodies) -> Law:
    """The :class:`Law` of ``scene``."""
    p = scene.contact
    law = LAWS.index(p.law)
    index = {b.name: k for k, b in enumerate(scene.bodies)}
    n = len(scene.bodies)
    overrides = sorted((min(index[a], index[b]) * n + max(index[a], index[b]), mu)
                       for (a, b), mu in scene.interface_friction.items())

    def given(value):
        return float("nan") if value is None else float(value)

    return Law(
        law=law, kn=float(p.kn), zeta_n=p.normal_damping_ratio, zeta_t=p.tangential_damping,
        zeta_r=rocking_damping_ratio(scene), kt_ratio=float(p.tangential_stiffness_ratio),
        cn=given(p.cn), cr=given(p.cr), kt=given(p.kt), ct=given(p.ct),
        friction_keys=np.array([k for k, _ in overrides], np.int64),
        friction_values=np.array([mu for _, mu in overrides], float),
        max_penetration=MAX_PENETRATION_FRACTION if p.law == "corner" else MAX_OVERLAP_FRACTION,
        skin=SKIN_FRACTION * float(bodies.size[1:].min()),
        restitution=p.impact_restitution)


def compile_stacks(scene, stacks=None) -> Stacks:
    """The :class:`Stacks` of ``scene`` (``stacks`` from :func:`~dem_core.engine.stacks.find_stacks`)."""
    stacks = find_stacks(scene) if stacks is None else stacks
    stack_id = np.full(len(scene.bodies), -1, np.int64)
    for k, st in enumerate(stacks):
        stack_id[np.array(st.blocks) + 1] = k
    masses = np.array([b.mass for b in scene.blocks])
    return Stacks(stack_id=stack_id, bottom=np.array([st.blocks[0] + 1 for st in stacks], np.int64),
                  mass=np.array([masses[list(st.blocks)].sum() for st in stacks], float),
                  foot=np.array([st.foot_local for st in stacks], float).reshape(len(stacks), 2, 2))


def compile_faces(scene) -> Faces:
    """The :class:`Faces` of ``scene``."""
    touching = scene.touching_pairs()
    extent = [min(np.ptp(scene.bodies[i].vertices @ touch.tangent), np.ptp(scene.bodies[j].vertices @ touch.tangent))
              for i, j, touch in touching]
    return Faces(i=np.array([i for i, _, _ in touching], np.int64), j=np.array([j for _, j, _ in touching], np.int64),
                 centroid=np.array([t.centroid for _, _, t in touching], float).reshape(-1, 2),
                 normal=np.array([t.normal for _, _, t in touching], float).reshape(-1, 2),
                 tangent=np.array([t.tangent for _, _, t in touching], float).reshape(-1, 2),
                 extent=np.array(extent, float))


def _facing_edge(vertices: np.ndarray, direction: np.ndarray) -> tuple:
    """The ends (2, 2) of the edge of the counter-clockwise polygon ``vertices`` whose outward normal points most
    along ``direction``."""
    following = np.roll(vertices, -1, axis=0)
    edges = following - vertices
    normals = np.column_stack([edges[:, 1], -edges[:, 0]]) / np.hypot(edges[:, 0], edges[:, 1])[:, None]
    k = int(np.argmax(normals @ direction))
    return vertices[k], following[k]


def interface_geometry(scene, bodies: Bodies, faces: Faces, keys: np.ndarray) -> np.ndarray:
    """(n_if, N_GEOMETRY) the rows of :mod:`._interfaces` of the interfaces ``keys`` (``i * nb + j``, sorted).

    Each interface is the first body's face turned to the second and the second's face turned back, which touch
    at the start, flush or (a block tilted onto a corner) at an end.  The touching point is the centre of the
    two faces' overlap along the tangent ``t = (n_y, -n_x)``, on each face's line, in each body's frame; half the
    interface's width is half the shorter face, the distance from that point to the end a block rocks on; the
    starting turn is the bodies' relative angle less the second face's tilt from flush."""
    n = len(bodies.mass)
    face_of = {int(i) * n + int(j): f for f, (i, j) in enumerate(zip(faces.i, faces.j))}
    rows = np.zeros((len(keys), N_GEOMETRY))
    for k, key in enumerate(keys):
        f = face_of[int(key)]
        a, b = divmod(int(key), n)
        face_a = _facing_edge(scene.bodies[a].vertices, faces.normal[f])
        tangent = (face_a[0] - face_a[1]) / np.hypot(*(face_a[0] - face_a[1]))  # (n_y, -n_x), n the face's normal
        normal = np.array([-tangent[1], tangent[0]])
        face_b = _facing_edge(scene.bodies[b].vertices, -normal)
        along_a = sorted(float(p @ tangent) for p in face_a)
        along_b = sorted(float(p @ tangent) for p in face_b)
        middle = 0.5 * (max(along_a[0], along_b[0]) + min(along_a[1], along_b[1]))
        points = []
        for (p, q) in (face_a, face_b):
            u = (middle - p @ tangent) / ((q - p) @ tangent)
            points.append(p + u * (q - p))
        edge_b = face_b[0] - face_b[1] if (face_b[0] - face_b[1]) @ tangent > 0 else face_b[1] - face_b[0]
        tilt = float(np.arctan2(edge_b @ normal, edge_b @ tangent))
        rows[k, [A_X, A_Y]] = geometry.transform((points[0] - bodies.centroid0[a])[None, :], -bodies.angle0[a])[0]
        rows[k, [B_X, B_Y]] = geometry.transform((points[1] - bodies.centroid0[b])[None, :], -bodies.angle0[b])[0]
        rows[k, [T_X, T_Y]] = geometry.transform(tangent[None, :], -bodies.angle0[a])[0]
        rows[k, HALF_WIDTH] = 0.5 * min(np.hypot(*(face_a[1] - face_a[0])), np.hypot(*(face_b[1] - face_b[0])))
        rows[k, TURN0] = bodies.angle0[b] - bodies.angle0[a] - tilt
    return rows


def connector_terms(kind) -> np.ndarray:
    """(N_LAW,) a connector's row of :mod:`._connector_law` with the terms of its
    :class:`~dem_core.inputs.connectors.ConnectorKind` ``kind`` (the anchors and the axis zero)."""
    row = np.zeros(N_LAW)
    row[SHEAR_K] = kind.shear_stiffness
    row[YIELD_FORCE] = np.inf if kind.yield_force is None else kind.yield_force
    row[HARDENING] = kind.hardening
    ultimate = kind.ultimate_force if kind.ultimate_force is not None else row[YIELD_FORCE]
    row[BACK_LIMIT] = ultimate - row[YIELD_FORCE] if np.isfinite(ultimate) else 0.0
    row[CLEARANCE] = kind.clearance
    row[SLIP_CAPACITY] = kind.slip_capacity
    row[AXIAL_K] = kind.axial_stiffness
    row[AXIAL_STRENGTH] = np.inf if kind.axial_strength is None else kind.axial_strength
    return row


def compile_connectors(scene, bodies: Bodies, keys: np.ndarray, rows: np.ndarray) -> Connectors:
    """The :class:`Connectors` of ``scene`` across its interfaces ``keys`` (sorted ``i * nb + j``), whose geometry
    ``rows`` (:func:`interface_geometry`) place them: each anchor ``position`` along its interface's tangent from
    the point where the two bodies touch, in the first body's frame, and the same point in the second's."""
    n = len(bodies.mass)
    index = {b.name: k for k, b in enumerate(scene.bodies)}
    placed = []
    for k, connector in enumerate(scene.connectors):
        a, b = sorted(index[name] for name in connector.between)
        placed.append((int(np.searchsorted(keys, a * n + b)), k, a, b))
    placed.sort()
    law = np.zeros((len(placed), N_LAW))
    for row, (f, k, a, b) in zip(law, placed):
        connector = scene.connectors[k]
        kind = connector.kind
        tangent = rows[f, [T_X, T_Y]]
        anchor_a = rows[f, [A_X, A_Y]] + connector.position * tangent
        world = bodies.centroid0[a] + geometry.transform(anchor_a[None, :], bodies.angle0[a])[0]
        row[[ANCHOR_AX, ANCHOR_AY]] = anchor_a
        row[[ANCHOR_BX, ANCHOR_BY]] = geometry.transform((world - bodies.centroid0[b])[None, :], -bodies.angle0[b])[0]
        row[[AXIS_X, AXIS_Y]] = -tangent[1], tangent[0]
        row[SHEAR_K:] = connector_terms(kind)[SHEAR_K:]
    start = np.searchsorted(np.array([f for f, *_ in placed], np.int64), np.arange(len(keys) + 1)).astype(np.int64)
    return Connectors(law=law, bodies=np.array([(a, b) for _, _, a, b in placed], np.int64).reshape(-1, 2),
                      start=start, order=np.array([k for _, k, _, _ in placed], np.int64))


def compile_model(scene, stacks=None) -> Model:
    """The :class:`Model` of ``scene`` (``stacks``: its stacks, if already found)."""
    bodies = compile_bodies(scene)
    faces = compile_faces(scene)
    n = len(scene.bodies)
    base_top = top_face(scene.base)[0][:, 1].min()
    keys = np.array(sorted(faces.i * n + faces.j), np.int64)
    rows = interface_geometry(scene, bodies, faces, keys)
    return Model(bodies=bodies, law=compile_law(scene, bodies), stacks=compile_stacks(scene, stacks), faces=faces,
                 interface_keys=keys, interface_geometry=rows, connectors=compile_connectors(scene, bodies, keys, rows),
                 gravity=float(scene.gravity), floor=float(base_top - scene.base.centroid[1]),
                 top=float(max(b.vertices[:, 1].max() for b in scene.blocks) - base_top))


def interface_pairs(model: Model) -> list:
    """``(i, j)`` body indices of the recorded interfaces, in the order of ``interface_keys``."""
    n = len(model.bodies.mass)
    return [(int(k // n), int(k % n)) for k in model.interface_keys]


def interface_history(model: Model, states: np.ndarray) -> tuple[np.ndarray, np.ndarray]:
    """``(offset, travel)``, each (n, n_if) m, of each recorded interface at each of the ``n`` states of a history,
    ``states`` (n, nb, 3) every body's x, y, theta (the base first, :func:`result_states`): its offset
    (:mod:`._interfaces`) from the first state's, and its slip, the travel of that offset, taken by the driver's own
    stage (:func:`~._interfaces.follow_interfaces`) at the history's interval."""
    states = np.ascontiguousarray(states, float)
    offsets = np.zeros((len(states), len(model.interface_keys)))
    travels = np.zeros_like(offsets)
    if len(states):
        first = interface_offsets(model, states[0])
        offset, travel = first.copy(), np.zeros(offsets.shape[1])
        for k, state in enumerate(states):
            follow_interfaces(state, model.interface_keys, model.interface_geometry, offset, travel)
            offsets[k] = offset - first
            travels[k] = travel
    return offsets, travels


def result_states(model: Model, result) -> np.ndarray:
    """(n, nb, 3) every body's x, y, theta at each output of ``result`` (a :class:`~.result.Result` of ``model``'s
    scene), the base first (its centroid moved by the ground's displacement)."""
    states = np.zeros((len(result.t), len(model.bodies.mass), 3))
    states[:, 0, :2] = model.bodies.centroid0[0] + np.column_stack([result.base_x, result.base_y])
    states[:, 0, 2] = model.bodies.angle0[0]
    states[:, 1:] = np.stack([result.x, result.y, result.theta], axis=-1)
    return states
