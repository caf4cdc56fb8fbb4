"""The arrays the compiled driver writes and reads within a step, allocated before it runs.

:func:`make_scratch` sizes them for a model, a state's stores and an integrator: nothing is allocated while a run
steps, so that the driver compiles for a GPU, where a thread cannot allocate, as it does for the CPU.  The
scratch holds nothing a later chunk needs but the sweep's order of the bodies, which any permutation starts.
"""

from typing import NamedTuple

import numpy as np

from ._active_set import BLOCK_REACH
from ._contact_law import CORNER
from ._points import N_COLUMNS, N_INTS
from .settings import MOREAU


class Scratch(NamedTuple):
    """For ``nb`` bodies, ``nv`` vertices, ``ns`` stacks and a store of ``C`` pairs (``Cc`` = C under the corner law,
    else 1; ``Co`` = C under the overlap-area law, else 1; ``Cm`` = C for Moreau-Jean, else 1).

    world : (4, nv) world vertices x, y and edge normals x, y.  boxes : (4, nb) m, lowest x, highest x, lowest y,
    highest y.  window : (6, 2) the ground's input to the step and the next (:func:`~._ground.ground_at`).
    force : (nb, 3) the bodies' contact resultants.  stack_moment : (ns,).
    sweep_order : (nb,) int64, the broad phase's order of the bodies.  candidates : (C,) int64 keys.
    pair_start, pair_entries, body_fill : (nb + 1,), (2 C,), (nb,) int64, the listed pairs' incidence.
    pair_force : (C, 6), pair_touching : (C,) int64, pair_excess : (C,): the explicit pair loop's outputs.
    points : (Cc, 2, 3), point_keys : (Cc, 2) int64: each pair's corner manifold.
    clip_x, clip_y : (Co, clip), clip_work : (Co, 2, 2, clip): each pair's overlap polygon.
    pair_order, pair_degree, pair_reached : (Cm,) int64: Moreau-Jean's order of the pairs and its scratch.
    start_vel, mid, shift, reaction : (nb, 3).  turn : (nb, 2) (:func:`~._points.block_turns`).
    base_impulse : (2,).
    point_rows : (R, N_COLUMNS), point_ints : (R, N_INTS) int64: the index set's points and the connectors' rows,
    ``R = 2 Cm + n_c`` (:mod:`._points`).
    point_status (R,) int64, point_velocity (2 R,), jacobian, response (2 R, 6), band (R, 2 BLOCK_REACH + 1, 4),
    rhs (2 R,), band_first, band_last (nb,) int64, band_end (2 R,) int64: the direct solve's
    (:func:`~._active_set.solve_statuses`).
    """

    world: np.ndarray
    boxes: np.ndarray
    window: np.ndarray
    force: np.ndarray
    stack_moment: np.ndarray
    sweep_order: np.ndarray
    candidates: np.ndarray
    pair_start: np.ndarray
    pair_entries: np.ndarray
    body_fill: np.ndarray
    pair_force: np.ndarray
    pair_touching: np.ndarray
    pair_excess: np.ndarray
    points: np.ndarray
    point_keys: np.ndarray
    clip_x: np.ndarray
    clip_y: np.ndarray
    clip_work: np.ndarray
    pair_order: np.ndarray
    pair_degree: np.ndarray
    pair_reached: np.ndarray
    start_vel: np.ndarray
    mid: np.ndarray
    shift: np.ndarray
    reaction: np.ndarray
    turn: np.ndarray
    base_impulse: np.ndarray
    point_rows: np.ndarray
    point_ints: np.ndarray
    point_status: np.ndarray
    point_velocity: np.ndarray
    jacobian: np.ndarray
    response: np.ndarray
    band: np.ndarray
    rhs: np.ndarray
    band_first: np.ndarray
    band_last: np.ndarray
    band_end: np.ndarray


def make_scratch(model, pairs: int, integrators, contact_laws) -> Scratch:
    """Scratch for runs of ``model`` (:class:`~dem_core.engine.model_arrays.ModelArrays`) with a store of ``pairs``
    pairs, under the ``integrators`` and ``contact_laws`` (collections of their codes: a batch's members may
    differ)."""
    nb = model.body.shape[1]
    nv = model.vertices.shape[1]
    ns = model.stack_bottom.shape[0]
    clip = 2 * max(3, int(np.max(np.diff(model.vstart)))) + 2
    corner = pairs if CORNER in contact_laws else 1
    overlap = pairs if any(law != CORNER for law in contact_laws) else 1
    moreau = pairs if MOREAU in integrators else 1
    rows = 2 * moreau + (model.connector_law.shape[0] if MOREAU in integrators else 0)
    return Scratch(
        world=np.zeros((4, nv)), boxes=np.zeros((4, nb)), window=np.zeros((6, 2)), force=np.zeros((nb, 3)),
        stack_moment=np.zeros(ns), sweep_order=np.arange(nb, dtype=np.int64), candidates=np.zeros(pairs, np.int64),
        pair_start=np.zeros(nb + 1, np.int64), pair_entries=np.zeros(2 * pairs, np.int64),
        body_fill=np.zeros(nb, np.int64), pair_force=np.zeros((pairs, 6)), pair_touching=np.zeros(pairs, np.int64),
        pair_excess=np.zeros(pairs), points=np.zeros((corner, 2, 3)), point_keys=np.zeros((corner, 2), np.int64),
        clip_x=np.zeros((overlap, clip)), clip_y=np.zeros((overlap, clip)), clip_work=np.zeros((overlap, 2, 2, clip)),
        pair_order=np.zeros(moreau, np.int64), pair_degree=np.zeros(moreau, np.int64),
        pair_reached=np.zeros(moreau, np.int64), start_vel=np.zeros((nb, 3)), mid=np.zeros((nb, 3)),
        shift=np.zeros((nb, 3)), reaction=np.zeros((nb, 3)), turn=np.zeros((nb, 2)), base_impulse=np.zeros(2),
        point_rows=np.zeros((rows, N_COLUMNS)), point_ints=np.zeros((rows, N_INTS), np.int64),
        point_status=np.zeros(rows, np.int64), point_velocity=np.zeros(2 * rows),
        jacobian=np.zeros((2 * rows, 6)), response=np.zeros((2 * rows, 6)),
        band=np.zeros((rows, 2 * BLOCK_REACH + 1, 4)), rhs=np.zeros(2 * rows), band_first=np.zeros(nb, np.int64),
        band_last=np.zeros(nb, np.int64), band_end=np.zeros(2 * rows, np.int64))
