"""Scene files map one to one onto the builders; mistakes name the file and the key."""

import textwrap
from pathlib import Path

import pytest

import dem_core
from dem_core import scenes
from dem_core.cli import default_scene_path
from dem_core.inputs.scene_file import SceneFileError, from_dict, load, read_toml


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


# --- issue 21: records, sizes and misspelt keys ------------------------------------------------------------

TWO_DRUMS = "[scene]\nbuilder = 'column'\nn_drums = 2\n"


def test_an_uneven_record_with_dt_is_refused_then_resampled_on_request(tmp_path):
    """kind = "record" with an uneven time column and dt = 0.01: refused naming the file, the line of its largest
    gap and the key that resamples it (it was read with the time column as accelerations); with resample = true
    it loads onto the dt given."""
    (tmp_path / "jitter.txt").write_text("0 0.1\n0.01 0.2\n0.03 -0.1\n0.04 0.05\n0.05 0.0\n")
    text = TWO_DRUMS + "[excitation]\nkind = 'record'\nsource = 'jitter.txt'\ndt = 0.01\n"
    with pytest.raises(SceneFileError, match=r"scene\.toml: \[excitation\]: .*jitter\.txt:3: time step 0\.02 s .*"
                                             r"largest gap .*give resample = true"):
        load(write(tmp_path, text))
    motion = load(write(tmp_path, text + "resample = true\n")).excitation
    assert motion.horizontal.dt == 0.01
    assert len(motion.horizontal.samples) == 6


@pytest.mark.parametrize("text, message", [
    (TWO_DRUMS + "[excitation]\nkind = 'harmonic'\nfrequency = 1.0\npga = 1e6\n",
     r"\[excitation\] pga = 1000000\.0, frequency = 1\.0: the ground motion 'harmonic .*' would peak at 1e\+06 m/s\^2 "
     r"\(1\.02e\+05 g\), beyond the 50 g a stone block can meet"),
    (TWO_DRUMS + "[excitation]\nkind = 'harmonic'\nfrequency = 100.0\namplitude = 1.0\n",
     r"\[excitation\] amplitude = 1\.0, frequency = 100\.0: .* \(4\.03e\+04 g\)"),
    (TWO_DRUMS + "[excitation]\nkind = 'record'\nsource = 'el_centro_1940'\nscale = 1000.0\n",
     r"\[excitation\] scale = 1000\.0: the ground motion 'el_centro_1940 x1000' would peak at .* \(281 g\)"),
    (TWO_DRUMS + "[excitation]\nkind = 'sine_pulse'\namplitude = 1e4\nduration = 0.5\n",
     r"\[excitation\] amplitude = 10000\.0: .* \(1\.02e\+03 g\)"),
    (TWO_DRUMS + "[excitation]\nkind = 'ramp'\nrate = 1000.0\n[simulation]\nduration = 1.0\n",
     r"\[excitation\] rate = 1000\.0: the ground motion 'ramp 1000 m/s\^3' would peak at 1e\+03 m/s\^2"),
])
def test_a_motion_beyond_what_a_block_can_meet_is_refused_naming_its_keys(tmp_path, text, message):
    with pytest.raises(SceneFileError, match=message):
        load(write(tmp_path, text))


def test_amplitude_and_pga_together_name_both_keys(tmp_path):
    """A scene file's amplitude with the pga a threshold search adds: the error names both keys as given and
    carries them, for the command line to say which it set."""
    path = write(tmp_path, TWO_DRUMS + "[excitation]\nkind = 'harmonic'\nfrequency = 1.0\namplitude = 0.05\n")
    data = read_toml(path)
    data["excitation"]["pga"] = 2.0  # what threshold --parameter pga does
    with pytest.raises(SceneFileError, match=r"scene\.toml: \[excitation\]: harmonic: give exactly one of amplitude "
                                             r"\(m\) and pga \(m/s\^2\), got both: amplitude = 0\.05 and pga = 2\.0"
                       ) as info:
        from_dict(data, path)
    assert info.value.keys == ("amplitude", "pga")


@pytest.mark.parametrize("text, message", [
    ("[scene]\nbuilder = 'colum'\n", r"unknown builder 'colum' \(did you mean 'column'\?\)"),
    (TWO_DRUMS + "widht = 1.0\n", r"no parameter\(s\) \['widht'\] \(did you mean 'width'\?\)"),
    (TWO_DRUMS + "[simulaton]\nduration = 1.0\n",
     r"unknown table\(s\) \['simulaton'\] \(did you mean 'simulation'\?\)"),
    (TWO_DRUMS + "[simulation]\ndurations = 1.0\n", r"\[simulation\] has unknown key\(s\) \['durations'\] "
                                                    r"\(did you mean 'duration'\?\)"),
    (TWO_DRUMS + "[contact]\nkN = 1e10\n", r"\[contact\] has unknown key\(s\) \['kN'\] \(did you mean 'kn'\?\)"),
    (TWO_DRUMS + "[output]\nfromat = 'csv'\n", r"\(did you mean 'format'\?\)"),
    (TWO_DRUMS + "[excitation]\nknd = 'harmonic'\n", r"without a kind takes no other keys \(did you mean 'kind'\?\)"),
    (TWO_DRUMS + "[excitation]\nkind = 'harmnic'\n", r"unknown kind 'harmnic' \(did you mean 'harmonic'\?\)"),
    (TWO_DRUMS + "[excitation]\nkind = 'harmonic'\nfrequncy = 1.0\npga = 1.0\n",
     r"kind 'harmonic' has no parameter\(s\) \['frequncy'\] \(did you mean 'frequency'\?\)"),
    (TWO_DRUMS + "[excitation]\nkind = 'record'\nsource = 'el_centro_1940'\nresampel = true\n",
     r"\(did you mean 'resample'\?\)"),
    (TWO_DRUMS + "interface_friction = [{between = ['base', 'drum1'], nu = 0.1}]\n", r"\(did you mean 'mu'\?\)"),
    ("[scene]\nbuilder = 'blocks'\n[[block]]\nname = 'a'\nvertice = [[0, 0], [1, 0], [1, 1]]\n",
     r"\[\[block\]\] number 1 \(a\) has unknown key\(s\) \['vertice'\] \(did you mean 'vertices'\?\)"),
    ("[scene]\nbuilder = 'blocks'\n[base]\nvertics = [[0, 0], [1, 0], [1, 1]]\n",
     r"\[base\] has unknown key\(s\) \['vertics'\] \(did you mean 'vertices'\?\)"),
])
def test_a_misspelt_name_gets_the_nearest_valid_one(tmp_path, text, message):
    with pytest.raises(SceneFileError, match=message):
        load(write(tmp_path, text))


def test_a_scene_file_that_is_not_there_is_refused_with_the_close_names_beside_it(tmp_path):
    """The TOML files beside it are suggested, not other files, and nothing where its folder is not there."""
    (tmp_path / "isolated_column.toml").write_text("")
    (tmp_path / "colonnade.csv").write_text("")
    with pytest.raises(SceneFileError, match=r"isolated_colum.toml: no such scene file "
                                             r"\(did you mean 'isolated_column.toml'\?\)$"):
        load(tmp_path / "isolated_colum.toml")
    for missing in (tmp_path / "colonnade.toml", tmp_path / "no_folder" / "isolated_column.toml"):
        with pytest.raises(SceneFileError, match=r"no such scene file$"):
            load(missing)
