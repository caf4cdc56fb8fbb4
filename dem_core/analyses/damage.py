"""How near each block of a run came to overturning: the critical angle that governs it (docs/method.md section 3)."""

import numpy as np


def critical_angles(result) -> np.ndarray:
    """(n_blocks,) rad: the rotation at which each block of ``result`` is judged to overturn: for a column's
    drums the column's critical angle, for every other block its own."""
    if result.critical_angle is None:
        raise ValueError("the result carries no critical angles (an engine that does not report them)")
    alpha = np.array(result.critical_angle, dtype=float)
    for column in result.columns:
        for name in column.blocks:
            alpha[result.index(name)] = column.critical_angle
    return alpha
