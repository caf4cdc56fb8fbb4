"""Scene files map one to one onto the builders; mistakes name the file and the key."""

import textwrap
from pathlib import Path

import pytest

import dem_core
from dem_core import scenes
from dem_core.cli import default_scene_path
from dem_core.inputs.scene_file import SceneFileError, load


def write(tmp_path, text, name="scene.toml"):
    path = tmp_path / name
    path.write_text(textwrap.dedent(text))
    return path


def test_bundled_default_scene_loads():
    spec = load(default_scene_path())
    assert len(spec.scene.blocks) == 8
    assert spec.excitation.horizontal.end_time > 50.0


def test_file_maps_onto_the_builder(tmp_path):
    path = write(tmp_path, """
        [scene]
        builder = "colonnade"
        n_columns = 3
        n_drums = 2
        spacing = 3.0
        epistyle = "d"
        epistyle_density = 9000.0
        interface_friction = [{between = ["base", "c2_drum1"], mu = 0.05}]
        [contact]
        kn = 1e10
        [excitation]
        kind = "harmonic"
        amplitude = 0.1
        frequency = 1.0
        [simulation]
        duration = 2.0
    """)
    spec = load(path)
    built = scenes.colonnade(3, 2, spacing=3.0, epistyle="d", epistyle_density=9000.0)
    assert spec.scene.block_names == built.block_names
    assert spec.scene.contact.kn == 1e10
    assert spec.scene.friction("c2_drum1", "base") == 0.05
    assert spec.simulation == {"duration": 2.0}


def test_record_path_is_relative_to_the_scene_file(tmp_path):
    (tmp_path / "rec.txt").write_text("0.0 0.1\n0.01 0.2\n0.02 0.3\n")
    path = write(tmp_path, """
        [scene]
        builder = "block"
        width = 1.0
        height = 2.0
        [excitation]
        kind = "record"
        source = "rec.txt"
    """)
    assert load(path).excitation.horizontal.dt == pytest.approx(0.01)


def test_explicit_blocks(tmp_path):
    path = write(tmp_path, """
        [scene]
        builder = "blocks"
        [[block]]
        name = "stone"
        vertices = [[-0.5, 0.0], [0.5, 0.0], [0.3, 1.0], [-0.3, 1.0]]
        density = 2500.0
        [base]
        vertices = [[-5.0, -1.0], [5.0, -1.0], [5.0, 0.0], [-5.0, 0.0]]
    """)
    scene = load(path).scene
    assert scene.block_names == ["stone"]
    assert scene.blocks[0].mass == pytest.approx(2500.0 * 0.8)


@pytest.mark.parametrize("text, message", [
    ("[scene]\nbuilder = 'pyramid'\n", "unknown builder 'pyramid'"),
    ("[scene]\nbuilder = 'column'\nn_drum = 3\n", r"no parameter\(s\) \['n_drum'\]"),
    ("[scene]\nbuilder = 'column'\nwidth = -1.0\n", "width must be positive"),
    ("[scene]\nbuilder = 'column'\n[excitation]\nkind = 'earthquake'\n", "unknown kind 'earthquake'"),
    ("[scene]\nbuilder = 'column'\n[simulation]\nsteps = 3\n", r"\[simulation\] has unknown key"),
    ("[scene]\nbuilder = 'column'\n[contact]\nkn = -1.0\n", r"\[contact\].*kn must be positive"),
    ("[scene]\nbuilder = 'column'\nwidth = \n", "not valid TOML"),
    ("[scene]\nbuilder = 'column'\n[excitation]\nkind = 'record'\nsource = 'missing.txt'\n", "no such record file"),
])
def test_mistakes_name_the_file_and_the_key(tmp_path, text, message):
    path = write(tmp_path, text, name="broken.toml")
    with pytest.raises(SceneFileError, match=message) as info:
        load(path)
    assert "broken.toml" in str(info.value)


@pytest.mark.parametrize("example", sorted((Path(__file__).parent.parent / "examples").glob("*.toml")),
                         ids=lambda p: p.stem)
def test_examples_load_and_run_briefly(example):
    spec = load(example)
    result = dem_core.simulate(spec.scene, spec.excitation, duration=0.05, output_dt=0.01)
    assert result.n_blocks == len(spec.scene.blocks)
