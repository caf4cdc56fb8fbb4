"""A compiled model as the driver reads it: a few arrays whose rows and columns this module names.

:func:`model_arrays` packs a :class:`~dem_core.engine.model.Model`'s bodies, stacks and contact law into
:class:`ModelArrays`, which a run shares with every other run of its scene and a GPU batch stacks member by member.
"""

from typing import NamedTuple

import numpy as np

from ._contact_law import CORNER

#: rows of ModelArrays.vertices
LOCAL_X, LOCAL_Y, NORMAL_X, NORMAL_Y = range(4)
#: rows of ModelArrays.body: mass (kg), inverse mass and inertia, circumradius (m), critical angle (rad), the
#: centre's starting height (m) and the drop past which a block has fallen (m), the deepest corner contact (m) or
#: largest overlap (m^2) a stable run can have, width and depth (m) and the block's own friction coefficient
(MASS, INV_MASS, INV_INERTIA, RADIUS, CRITICAL_ANGLE, Y_START, DROP_LIMIT, CONTACT_LIMIT, WIDTH, DEPTH,
 FRICTION) = range(11)
#: columns of ModelArrays.law: the scene-wide constants of :class:`Law` that the pairs' constants come from
LAW_KN, LAW_ZETA_N, LAW_ZETA_T, LAW_ZETA_R, LAW_KT_RATIO, LAW_CN, LAW_CR, LAW_KT, LAW_CT = range(9)
#: a friction key that matches no pair (pads the keys of members with fewer overrides in a batch)
NO_KEY = np.iinfo(np.int64).max


class ModelArrays(NamedTuple):
    """A :class:`Model` as the compiled driver reads it (``nb`` bodies, ``nv`` vertices, ``ns`` stacks).

    vertices : (4, nv) rows LOCAL_X, LOCAL_Y, NORMAL_X, NORMAL_Y (:class:`Bodies`).  vstart : (nb + 1,) int64.
    body : (11, nb) rows MASS ... FRICTION.  stack_id : (nb,) int64.  stack_bottom : (ns,) int64.
    stack_mass : (ns,) kg.  stack_foot : (ns, 2, 2) m.  law : (9,) columns LAW_KN ... LAW_CT.
    friction_keys, friction_values : the interfaces with a coefficient of their own, keys sorted (NO_KEY pads).
    interface_keys : (n_if,) int64 sorted keys of the recorded interfaces.  interface_geometry : (n_if, 8) their
    rows of :mod:`._interfaces`.  connector_law (n_c, N_LAW), connector_bodies (n_c, 2) int64, connector_start
    (n_if + 1,) int64: the connectors (:class:`~dem_core.engine.model.Connectors`).
    """

    vertices: np.ndarray
    vstart: np.ndarray
    body: np.ndarray
    stack_id: np.ndarray
    stack_bottom: np.ndarray
    stack_mass: np.ndarray
    stack_foot: np.ndarray
    law: np.ndarray
    friction_keys: np.ndarray
    friction_values: np.ndarray
    interface_keys: np.ndarray
    interface_geometry: np.ndarray
    connector_law: np.ndarray
    connector_bodies: np.ndarray
    connector_start: np.ndarray


def model_arrays(model) -> ModelArrays:
    """The :class:`ModelArrays` of ``model`` (:class:`~dem_core.engine.model.Model`)."""
    b, law = model.bodies, model.law
    limit = law.max_penetration * (b.size if law.law == CORNER else b.area)
    body = np.array([b.mass, b.inv_mass, b.inv_inertia, b.radius, b.critical_angle, b.y_start, b.drop_limit, limit,
                     b.width, b.depth, b.friction], float)
    friction_keys, friction_values = law.friction_keys, law.friction_values
    if len(friction_keys) == 0:  # an array the driver can index, which no pair matches
        friction_keys, friction_values = np.array([NO_KEY], np.int64), np.array([np.nan])
    return ModelArrays(
        vertices=np.array([b.local_x, b.local_y, b.normal_x, b.normal_y], float), vstart=b.vstart.astype(np.int64),
        body=body, stack_id=model.stacks.stack_id, stack_bottom=model.stacks.bottom, stack_mass=model.stacks.mass,
        stack_foot=np.ascontiguousarray(model.stacks.foot, float),
        law=np.array([law.kn, law.zeta_n, law.zeta_t, law.zeta_r, law.kt_ratio, law.cn, law.cr, law.kt, law.ct],
                     float),
        friction_keys=np.ascontiguousarray(friction_keys, np.int64),
        friction_values=np.ascontiguousarray(friction_values, float),
        interface_keys=np.ascontiguousarray(model.interface_keys, np.int64),
        interface_geometry=np.ascontiguousarray(model.interface_geometry, float).reshape(-1, 8),
        connector_law=np.ascontiguousarray(model.connectors.law, float),
        connector_bodies=np.ascontiguousarray(model.connectors.bodies, np.int64),
        connector_start=np.ascontiguousarray(model.connectors.start, np.int64))
