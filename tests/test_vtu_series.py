"""The run's blocks as a VTU time series: ``dem-core run --vtu`` on the bundled default writes files that meshio
reads back, a PVD that lists them with their times, and polygons that are the blocks moved rigidly (each keeps its
area, and its centroid is the run's position of the block at that time)."""

import re
from xml.etree import ElementTree

import numpy as np
import pandas as pd
import pytest

from dem_core.cli import default_scene_path, main
from dem_core.inputs.scene_file import load
from dem_core.vtu_series import COLLECTION, FRAMES_PER_SECOND, frame_indices

meshio = pytest.importorskip("meshio")

DURATION = 3.0


def polygon_area_and_centroid(points: np.ndarray) -> tuple:
    """Shoelace area (m^2) and centroid (m) of a polygon's vertices (n, 2), counter-clockwise."""
    x, y = points[:, 0], points[:, 1]
    cross = x * np.roll(y, -1) - np.roll(x, -1) * y
    area = cross.sum() / 2.0
    return area, np.array([((x + np.roll(x, -1)) * cross).sum(), ((y + np.roll(y, -1)) * cross).sum()]) / (6 * area)


def test_the_default_runs_series_reads_back_as_the_blocks_moved_rigidly(tmp_path, capsys):
    out = tmp_path / "run"
    assert main(["run", "--out", str(out), "--duration", str(DURATION), "--vtu", "--format", "parquet"]) == 0
    assert "vtu/blocks.pvd" in capsys.readouterr().out
    history = pd.read_parquet(out / "time_history.parquet")
    t = np.unique(history.t.to_numpy())
    frames = frame_indices(t)
    datasets = ElementTree.parse(out / "vtu" / COLLECTION).getroot().find("Collection").findall("DataSet")
    assert len(datasets) == len(frames) == int(DURATION * FRAMES_PER_SECOND) + 1
    times = np.array([float(d.get("timestep")) for d in datasets])
    np.testing.assert_allclose(times, t[frames], rtol=0, atol=1e-12)
    scene = load(default_scene_path()).scene
    areas = [polygon_area_and_centroid(block.vertices)[0] for block in scene.blocks]
    start = history[history.t == t[0]].set_index("block")
    for dataset, time in zip(datasets[::15], times[::15]):
        mesh = meshio.read(out / "vtu" / dataset.get("file"))
        (polygons,) = [cells.data for cells in mesh.cells if cells.type == "polygon"]
        assert len(polygons) == len(scene.blocks)
        at = history[np.isclose(history.t, time, rtol=0, atol=1e-12)].set_index("block")
        for b, vertices in enumerate(polygons):
            area, centroid = polygon_area_and_centroid(mesh.points[vertices, :2])
            assert area == pytest.approx(areas[b], rel=1e-12)
            name = scene.blocks[b].name
            np.testing.assert_allclose(centroid, at.loc[name, ["x", "y"]].to_numpy(float), rtol=0, atol=1e-9)
            assert mesh.cell_data["theta_rad"][0][b] == pytest.approx(at.loc[name, "theta"], rel=0, abs=1e-15)
            assert mesh.cell_data["block"][0][b] == b
            moved = at.loc[name, "x_rel"] - start.loc[name, "x_rel"]  # from where it stood on the base at t = 0
            assert mesh.cell_data["x_rel_m"][0][b] == pytest.approx(moved, rel=0, abs=1e-15)
        assert np.all(mesh.points[:, 2] == 0.0)
    assert re.fullmatch(r"blocks_\d{2}\.vtu", datasets[-1].get("file"))


def test_frames_are_every_output_at_most_the_rate_and_always_the_last():
    t = np.arange(0.0, 1.0 + 1e-9, 0.01)
    np.testing.assert_array_equal(frame_indices(t, 25.0), [*range(0, 100, 4), 100])
    np.testing.assert_array_equal(frame_indices(t[:3], 25.0), [0, 2])
    np.testing.assert_array_equal(frame_indices(np.array([0.0, 0.5, 1.0]), 25.0), [0, 1, 2])
    with pytest.raises(ValueError, match="frames per second"):
        frame_indices(t, 0.0)
