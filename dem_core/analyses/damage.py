"""How much a run damaged its blocks: how near each came to overturning, by the critical angle that governs it
(docs/method.md section 3), and what the run left: the drums' residual dislocation and the residual tilt."""

import numpy as np

from ..engine.model import compile_model, result_states
from ..engine.residual import dislocations, leans


def critical_angles(result) -> np.ndarray:
    """(n_blocks,) rad: the rotation at which each block of ``result`` is judged to overturn: for a column's
    drums the column's critical angle, for every other block its own (:meth:`~dem_core.Result.governing_angles`)."""
    return result.governing_angles()


def residual_dislocation(scene, result) -> float:
    """m: the largest offset, at the run's end, of a block over the one it rested on at the start (or the base),
    along their joint (:func:`~dem_core.engine.residual.dislocations`): the dislocation of drums a survey measures.
    The offset is a function of the two bodies' positions, so the first and last outputs give it; 0 for a scene
    without joints."""
    model = compile_model(scene)
    first, last = result_states(model, result)[[0, -1]]
    offsets = dislocations(model, first, last)
    return float(np.max(np.abs(offsets))) if offsets.size else 0.0


def residual_tilt(result) -> float:
    """rad: the largest lean, at the run's end, that the run added (:func:`~dem_core.engine.residual.leans`): for
    each column the change in the angle between the line through its bottom and top blocks' centres of mass and its
    bottom block's axis (a column still rocking as one body adds nothing), for every other block the change in its
    own rotation."""
    first, last = np.stack([result.x, result.y, result.theta], axis=-1).astype(float)[[0, -1]]
    return float(max(leans(result.columns, result.names, first, last).values(), default=0.0))


def still_at_end(result, speed: float, window: float = 0.25) -> bool:
    """Whether every block of ``result`` moved slower than ``speed`` (m/s, its centre of mass relative to the ground,
    between each two outputs) over the run's last ``window`` s: whether what the run leaves is a resting state (a
    column at the turning point of its rocking is still for an instant only)."""
    last = np.flatnonzero(result.t >= result.t[-1] - window)
    if len(result.t) < 2 or len(last) < 2:
        return False
    x = np.asarray(result.x, dtype=float)[last] - np.asarray(result.base_x, dtype=float)[last, None]
    y = np.asarray(result.y, dtype=float)[last] - np.asarray(result.base_y, dtype=float)[last, None]
    step = np.diff(np.asarray(result.t, dtype=float)[last])[:, None]
    return bool(np.all(np.hypot(np.diff(x, axis=0), np.diff(y, axis=0)) / step < speed))
