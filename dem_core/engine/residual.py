"""What a run leaves at a moment, against where it started, from the bodies' positions at the two: each recorded
interface's dislocation and each column's lean (docs/method.md section 3).

:func:`residual_state` gives both; :func:`dislocations` and :func:`leans` each hold one rule, which the damage
measures of :mod:`dem_core.analyses.damage` and the events of a sequence of ground motions read alike.
"""

from typing import NamedTuple

import numpy as np

from .state import interface_offsets


class Residual(NamedTuple):
    """What a run left: ``dislocation`` (n_if,) m, each recorded interface's :func:`dislocations`, in the model's
    order of interfaces; ``tilt`` {label: rad}, the :func:`leans`."""

    dislocation: np.ndarray
    tilt: dict


def dislocations(model, start: np.ndarray, end: np.ndarray) -> np.ndarray:
    """(n_if,) m: each recorded interface's offset (:mod:`._interfaces`) with the bodies at ``end`` less its offset
    at ``start`` ((nb, 3) x, y, theta, the base first): how far a block moved along its joint with the one it rested
    on at the start (or the base), rocking without slip aside; the dislocation of drums a survey measures."""
    return interface_offsets(model, end) - interface_offsets(model, start)


def leans(columns, names, start: np.ndarray, end: np.ndarray) -> dict:
    """{label: rad} the lean added from the blocks at ``start`` to the blocks at ``end`` ((n_blocks, 3) x, y, theta
    in the order of ``names``): for each column of more than one block (:class:`~.stacks.Column`, labelled
    ``"bottom..top"``) the change in the angle between the line through its bottom and top blocks' centres of mass
    and its bottom block's axis (the lean that dislocated drums leave; a column rocking as one body adds none), for
    every block outside a column (labelled by its name) the change in its own rotation."""
    index = {name: k for k, name in enumerate(names)}
    found, in_columns = {}, set()
    for column in columns:
        in_columns.update(column.blocks)
        bottom, top = index[column.blocks[0]], index[column.blocks[-1]]
        if bottom != top:
            found[f"{column.blocks[0]}..{column.blocks[-1]}"] = abs(float(_lean(end, bottom, top)
                                                                          - _lean(start, bottom, top)))
    found.update({name: abs(float(end[k, 2] - start[k, 2])) for k, name in enumerate(names) if name not in in_columns})
    return found


def _lean(blocks: np.ndarray, bottom: int, top: int) -> float:
    """rad: the angle between the line from block ``bottom``'s centre of mass to block ``top``'s and ``bottom``'s
    axis, the blocks at ``blocks`` (n_blocks, 3)."""
    return np.arctan2(blocks[top, 0] - blocks[bottom, 0], blocks[top, 1] - blocks[bottom, 1]) + blocks[bottom, 2]


def residual_state(model, columns, names, start: np.ndarray, end: np.ndarray) -> Residual:
    """The :class:`Residual` of the bodies at ``end`` against ``start`` ((nb, 3) x, y, theta, the base first) in
    ``model``, whose blocks are ``names`` and stand in ``columns``."""
    return Residual(dislocations(model, start, end), leans(columns, names, start[1:], end[1:]))
