"""Drawing runs: block outlines follow the rigid motion, animations and snapshot strips are written."""

import numpy as np
import pytest
from PIL import Image

import dem_core
from dem_core import excitation, geometry, scenes
from dem_core.pictures import animation


@pytest.fixture(scope="module")
def colonnade_run():
    scene = scenes.colonnade(3, 2, spacing=2.5, epistyle="b")
    motion = excitation.harmonic(pga=3.0, frequency=1.5)
    return scene, motion, dem_core.simulate(scene, motion, duration=1.0, output_dt=0.04)


def test_outlines_start_on_the_scene_and_move_rigidly(colonnade_run):
    scene, _, result = colonnade_run
    for outline, block in zip(animation.block_outlines(scene, result, 0), scene.blocks):
        np.testing.assert_allclose(outline, block.vertices, atol=1e-12)
    for outline, block in zip(animation.block_outlines(scene, result, len(result.t) - 1), scene.blocks):
        assert geometry.polygon_properties(outline).area == pytest.approx(block.area, rel=1e-12)
        moved = outline - outline.mean(axis=0)
        original = block.vertices - block.vertices.mean(axis=0)
        np.testing.assert_allclose(np.linalg.norm(moved, axis=1), np.linalg.norm(original, axis=1), rtol=1e-12)


def test_gif_has_a_frame_per_playback_tick(colonnade_run, tmp_path):
    scene, motion, result = colonnade_run
    path = animation.animate(scene, result, tmp_path / "run.gif", excitation=motion, fps=25, speed=1.0)
    with Image.open(path) as gif:
        assert gif.n_frames == int(result.t[-1] * 25) + 1  # 1 s played at 25 frames per second


def test_mp4_without_ffmpeg_says_what_to_do(colonnade_run, tmp_path, monkeypatch):
    scene, _, result = colonnade_run
    monkeypatch.setattr(animation, "_ffmpeg", lambda: None)
    with pytest.raises(RuntimeError, match="ffmpeg"):
        animation.animate(scene, result, tmp_path / "run.mp4")
    with pytest.raises(ValueError, match=r"\.gif or \.mp4"):
        animation.animate(scene, result, tmp_path / "run.avi")


def test_snapshot_strip_has_a_panel_per_time(colonnade_run):
    scene, _, result = colonnade_run
    figure = animation.snapshot_strip(scene, result, [0.0, 0.5, 1.0])
    assert len(figure.axes) == 3
    assert [a.get_title() for a in figure.axes] == ["t = 0.00 s", "t = 0.52 s", "t = 1.00 s"]
