"""Drawing runs: block outlines follow the rigid motion (exaggerated on request), animations and
snapshot strips are written."""

import sys

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


def test_exaggeration_moves_and_turns_the_outlines_k_times_as_far(colonnade_run):
    scene, _, result = colonnade_run
    k, factor = len(result.t) - 1, 10.0
    drum = result.index("c1_drum2")
    rel_x, rel_y = result.x - result.base_x[:, None], result.y - result.base_y[:, None]
    assert abs(rel_x[k, drum] - rel_x[0, drum]) > 1e-3  # the run moves it enough to tell
    # without the scene, about each block's centre: the centre moves K times as far from the moving base
    x, y, _ = animation.drawn_poses(result, factor)
    centre = np.array([x[k, drum] - result.base_x[k], y[k, drum] - result.base_y[k]])
    true_centre = np.array([rel_x[k, drum], rel_y[k, drum]])
    first = np.array([rel_x[0, drum], rel_y[0, drum]])
    np.testing.assert_allclose(centre - first, factor * (true_centre - first), atol=1e-9)
    # with it, on what each block rests on: every rotation is still K times the true one
    true = animation.block_outlines(scene, result, k)[drum]
    drawn = animation.block_outlines(scene, result, k, exaggerate=factor)[drum]
    start = scene.blocks[drum].vertices

    def edge_angle(outline):
        return np.arctan2(*(outline[1] - outline[0])[::-1])

    turned = edge_angle(drawn) - edge_angle(start)
    assert turned == pytest.approx(factor * (edge_angle(true) - edge_angle(start)), abs=1e-9)
    assert geometry.polygon_properties(drawn).area == pytest.approx(scene.blocks[drum].area, rel=1e-12)


def rocking_column(n_drums=2, angle=0.02, steps=21, corner=+1):
    """(scene, result): a column of ``n_drums`` drums rocking as one rigid body on its right (``corner`` +1: turning
    clockwise) or left (-1) base corner, by up to ``angle`` rad, the drums touching throughout (exact kinematics)."""
    scene = scenes.column(n_drums)
    pivot = np.array([corner * 0.5 * np.ptp(scene.blocks[0].vertices[:, 0]) + scene.blocks[0].centroid[0], 0.0])
    turns = np.linspace(0.0, -corner * angle, steps)
    centres = np.array([b.centroid for b in scene.blocks])
    x, y = np.empty((steps, n_drums)), np.empty((steps, n_drums))
    for i, turn in enumerate(turns):
        moved = geometry.transform(centres - pivot, turn, pivot)
        x[i], y[i] = moved[:, 0], moved[:, 1]
    theta = np.tile(turns[:, None], (1, n_drums))
    n = np.arange(steps)
    result = dem_core.Result(0.01 * n, x, y, theta, np.zeros(steps), np.zeros(steps), tuple(scene.block_names),
                             np.abs(theta).max(axis=0), np.full(n_drums, np.nan), {}, 1e-4)
    return scene, result


@pytest.mark.parametrize("corner", [+1, -1])
def test_an_exaggerated_drum_rocking_on_a_corner_still_stands_on_the_ground(corner):
    """A column rocking on a corner, drawn 10 times exaggerated: its bottom drum's lowest corner stays on the
    ground line (scaling the motion about each drum's centre would carry it below or part the drums), and the
    drum above still rests on the one below."""
    scene, result = rocking_column(corner=corner)
    last = len(result.t) - 1
    for factor in (10.0, 30.0):
        bottom, top = animation.block_outlines(scene, result, last, exaggerate=factor)
        assert bottom[:, 1].min() == pytest.approx(0.0, abs=1e-12)  # on the ground, not below it
        assert np.arctan2(*(bottom[1] - bottom[0])[::-1]) == pytest.approx(-factor * corner * 0.02)
        # the upper drum's bottom corners lie on the lower drum's top face
        face = bottom[2] - bottom[3]
        normal = np.array([-face[1], face[0]]) / np.hypot(*face)
        np.testing.assert_allclose((top[:2] - bottom[3]) @ normal, 0.0, atol=1e-12)
    assert animation.supports(scene) == [-1, 0]
def test_gif_has_a_frame_per_playback_tick(colonnade_run, tmp_path):
    scene, motion, result = colonnade_run
    path = animation.animate(scene, result, tmp_path / "run.gif", excitation=motion, fps=25, speed=1.0)
    with Image.open(path) as gif:
        assert gif.n_frames == int(result.t[-1] * 25) + 1  # 1 s played at 25 frames per second
        assert sum(gif.seek(i) or gif.info["duration"] for i in range(gif.n_frames)) == pytest.approx(1040, abs=10)
    assert len(animation.frame_indices(result, 10, 2.0)) == 6  # 1 s at 5 frames per simulated second


def test_exaggerated_frames_say_so_and_differ(colonnade_run, tmp_path):
    scene, motion, result = colonnade_run
    frames = {}
    for factor in (1.0, 20.0):
        path = animation.animate(scene, result, tmp_path / f"x{factor:g}.gif", excitation=motion, fps=5,
                                 exaggerate=factor)
        with Image.open(path) as gif:
            gif.seek(gif.n_frames - 1)
            frames[factor] = np.asarray(gif.convert("RGB"))
    assert frames[1.0].shape != frames[20.0].shape or np.any(frames[1.0] != frames[20.0])
    assert animation.exaggeration_note(20) == ("rotations and displacements \u00d7 20\n"
                                               "(each block's on what it rests on)")
    strip = animation.snapshot_strip(scene, result, [0.0, 1.0], title="run", exaggerate=20)
    assert strip._suptitle.get_text() == ("run, rotations and displacements \u00d7 20 (each block's on what it rests "
                                          "on);\na block on two supports follows one: it may part from or overlap "
                                          "the other")  # the epistyles, each on two capitals
    with pytest.raises(ValueError, match="exaggerate"):
        animation.drawn_poses(result, 0.0)


def test_mp4_frames_are_piped_raw_to_ffmpeg(colonnade_run, tmp_path, monkeypatch):
    scene, motion, result = colonnade_run
    fake = tmp_path / "ffmpeg"
    fake.write_text(f"#!{sys.executable}\nimport sys\nopen(sys.argv[-1], 'wb').write(sys.stdin.buffer.read())\n"
                    "open(sys.argv[-1] + '.args', 'w').write(' '.join(sys.argv[1:]))\n")
    fake.chmod(0o755)
    monkeypatch.setattr(animation, "_ffmpeg", lambda: str(fake))
    path = animation.animate(scene, result, tmp_path / "run.mp4", excitation=motion, fps=10)
    arguments = next(tmp_path.glob("run.mp4*.args")).read_text().split()  # written beside the file being encoded
    width, height = map(int, arguments[arguments.index("-s") + 1].split("x"))
    assert path.stat().st_size == 11 * width * height * 3  # 1 s at 10 frames per second, 3 bytes a pixel


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


def test_clock_tells_time_ground_and_overturn(colonnade_run):
    _, _, result = colonnade_run
    assert animation.clock_text(result, 0) == "t =   0.00 s   ground +0.000 m"
    toppled = dem_core.Result(**{**result.__dict__, "overturn_time": np.full(result.n_blocks, 0.5)})
    last = len(result.t) - 1
    assert animation.clock_text(toppled, last).endswith("\noverturned at 0.50 s")
    assert "overturned" not in animation.clock_text(toppled, 0)
