"""A run's blocks as a VTU time series, for ParaView and other VTK readers.

:func:`write_vtu_series` writes one VTU file per frame, each block a polygon at its pose at that time (in m, the
ground's travel included, z = 0), with the block's index, rotation (rad) and displacement relative to the base (m)
as cell data, and a PVD collection that gives each file its time: ParaView opens ``blocks.pvd`` as one data set
that plays the run.  The files are written by meshio (a well-kept reader and writer of VTK's formats); the PVD, a
list of files and times, is a few lines of XML.
"""

from __future__ import annotations

from pathlib import Path
from xml.sax.saxutils import quoteattr

import numpy as np

from .output_files import replacing
from .pictures.animation import BlockOutlines

#: frames per simulated second at most (every output where the outputs are sparser): the animation's default rate
FRAMES_PER_SECOND = 25.0
#: the collection's file, in the folder
COLLECTION = "blocks.pvd"


def frame_indices(t: np.ndarray, frames_per_second: float = FRAMES_PER_SECOND) -> np.ndarray:
    """The outputs of times ``t`` (s) that make the frames: the first, then each first output at least
    1/``frames_per_second`` s after the last frame taken, and the last."""
    if not frames_per_second > 0:
        raise ValueError(f"frames per second must be positive, got {frames_per_second!r}")
    if len(t) == 0:
        return np.zeros(0, dtype=int)
    taken, next_time = [], -np.inf
    for k, time in enumerate(t):
        if time >= next_time - 1e-12:
            taken.append(k)
            next_time = time + 1.0 / frames_per_second
    if taken[-1] != len(t) - 1:
        taken.append(len(t) - 1)
    return np.asarray(taken)


def write_vtu_series(scene, result, folder, *, frames_per_second: float = FRAMES_PER_SECOND) -> Path:
    """Write ``folder``/blocks_<n>.vtu for each frame of ``result`` (:func:`frame_indices`) and ``folder``/
    blocks.pvd; returns the PVD's path.  ``scene`` is the run's :class:`~dem_core.Scene`.

    Each VTU: the points (P, 3) of every block's vertices at the frame (m); a ``polygon`` cell per block, in the
    scene's order; cell data ``block`` (its index in the scene), ``theta_rad`` and ``x_rel_m`` (its horizontal
    displacement relative to the base).  Every file is written whole or not at all."""
    import meshio

    folder = Path(folder)
    folder.mkdir(parents=True, exist_ok=True)
    frames = frame_indices(result.t, frames_per_second)
    digits = len(str(max(len(frames) - 1, 0)))
    sizes = [len(block.vertices) for block in scene.blocks]
    starts = np.concatenate(([0], np.cumsum(sizes)[:-1]))
    cells = [("polygon", (start + np.arange(size)).reshape(1, -1)) for start, size in zip(starts, sizes)]
    relative = result.relative_x - result.relative_x[0]
    outlines = BlockOutlines(scene, result)
    entries = []
    for n, k in enumerate(frames):
        points = np.concatenate(outlines(int(k)))
        mesh = meshio.Mesh(np.column_stack([points, np.zeros(len(points))]), cells, cell_data={
            "block": [np.array([b]) for b in range(len(sizes))],
            "theta_rad": [np.array([result.theta[k, b]]) for b in range(len(sizes))],
            "x_rel_m": [np.array([relative[k, b]]) for b in range(len(sizes))]})
        name = f"blocks_{n:0{digits}d}.vtu"
        with replacing(folder / name) as tmp:
            meshio.write(tmp, mesh, file_format="vtu")
        entries.append(f'    <DataSet timestep="{float(result.t[k])!r}" file={quoteattr(name)}/>')
    collection = folder / COLLECTION
    with replacing(collection) as tmp:
        Path(tmp).write_text('<?xml version="1.0"?>\n<VTKFile type="Collection" version="0.1">\n  <Collection>\n'
                             + "\n".join(entries) + "\n  </Collection>\n</VTKFile>\n", encoding="utf-8")
    return collection
