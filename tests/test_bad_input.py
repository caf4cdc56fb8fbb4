"""Ordinary mistakes in records, scene files and geometry get an error that names the culprit.

Each test is one mistake a user can make; its docstring says what the toolkit answers instead of a raw
Python or numpy error, a wrong result or silence.
"""

import copy
import inspect
import math
import signal
from dataclasses import fields

import numpy as np
import pytest
from hypothesis import HealthCheck, given, settings
from hypothesis import strategies as st

import dem_core
from dem_core.analyses.fragility_study import stripes
from dem_core.inputs.connectors import ConnectorKind
from dem_core.engine.model import compile_model
from dem_core.simulation import RunTooLarge, Simulation
from dem_core import excitation, scenes
from dem_core.engine.geometry import rectangle
from dem_core.inputs.records import RecordError
from dem_core.inputs import scene_file
from dem_core.inputs.scene import Block, Scene, SceneError
from dem_core.inputs.scene_file import SceneFileError
from dem_core.inputs.synthetic import Scenario, synthetic_suite

AT2 = "HEAD\nEVENT\nACCELERATION TIME SERIES IN UNITS OF G\nNPTS=    4, DT= {dt} SEC\n .1 .2\n -.1 .05\n"


# --- records -----------------------------------------------------------------------------------------

@pytest.mark.parametrize("dt", [0.0, float("nan"), -0.01, 1e-9])
def test_one_column_record_with_a_meaningless_dt(tmp_path, dt):
    """A dt of zero, NaN, below zero or below the shortest sampling interval is a RecordError naming the file
    and the accepted range."""
    path = tmp_path / "one.txt"
    path.write_text("0.1\n0.2\n0.3\n0.1\n")
    with pytest.raises(RecordError, match=r"one\.txt: dt must be a finite sampling interval of at least 1e-06 s"):
        excitation.record(path, dt=dt)


def test_at2_with_a_tiny_dt(tmp_path):
    """An AT2 header's DT too small to be a sampling interval is refused naming the file and line, before the
    baseline correction is attempted."""
    path = tmp_path / "tiny.AT2"
    path.write_text(AT2.format(dt="1e-300"))
    with pytest.raises(RecordError, match=r"tiny\.AT2:4: DT must be a finite sampling interval .* got 1e-300"):
        excitation.record(path)


def test_at2_with_an_unreadable_dt(tmp_path):
    """An AT2 header's DT that is not a number is refused naming the file, the line and the text read."""
    path = tmp_path / "dots.AT2"
    path.write_text(AT2.format(dt=".01.0"))
    with pytest.raises(RecordError, match=r"dots\.AT2:4: cannot read DT '\.01\.0'"):
        excitation.record(path)


def test_baseline_correction_does_not_depend_on_the_unit_of_time():
    """The correction is the same at any time step: its equations are written in time over the record's
    length, so a tiny step leaves them well conditioned."""
    a = np.array([0.1, 0.3, -0.2, 0.05])
    np.testing.assert_allclose(excitation.baseline_correct(a, 1e-150), excitation.baseline_correct(a, 0.01))


def test_time_column_that_goes_backwards_names_its_line(tmp_path):
    """A time column that goes backwards is refused naming its line, not read as a record without a time
    column."""
    lines = [f"{0.01 * k:.2f} {math.sin(k / 10):.4f}" for k in range(400)]
    lines[300] = "2.98 0.1"
    path = tmp_path / "back.txt"
    path.write_text("# t a\n" + "\n".join(lines) + "\n")
    with pytest.raises(RecordError, match=r"back\.txt:302: time 2\.98 s does not come after 2\.99 s on line 301"):
        excitation.record(path)


def test_time_column_with_another_step_than_the_dt_given(tmp_path):
    """A time column whose step differs from the dt given is refused naming both, not read as an acceleration
    column."""
    path = tmp_path / "rec.txt"
    path.write_text("".join(f"{0.02 * k:.2f} {math.sin(k):.4f}\n" for k in range(50)))
    with pytest.raises(RecordError, match=r"dt=0\.01 was given but the time column steps by 0\.02"):
        excitation.record(path, dt=0.01)


def test_nan_in_an_array_record_is_named_at_its_own_sample():
    """A NaN in an array record is reported at its own sample: samples are checked before the baseline
    correction, which would spread it over the whole record."""
    a = np.sin(np.arange(100) / 5.0)
    a[5] = np.nan
    with pytest.raises(RecordError, match=r"array record: sample 5 is not finite \(nan\)"):
        excitation.record(a, dt=0.01)


@pytest.mark.parametrize("argument, value", [("pga", float("nan")), ("pga", -1.0), ("scale", float("inf")),
                                             ("scale", 0.0), ("pga", "3")])
def test_pga_and_scale_must_be_finite_and_positive(argument, value):
    """A pga or scale that is not a finite positive number is refused naming the record and the argument."""
    with pytest.raises(RecordError, match=rf"el_centro_1940: {argument}.* must be a finite positive number"):
        excitation.record("el_centro_1940", **{argument: value})


def test_mistyped_bundled_record_name_gets_the_close_match_and_the_list():
    """A name close to a bundled record's gets the close match and the list of bundled records."""
    with pytest.raises(RecordError) as info:
        excitation.record("el_centro_194")
    message = str(info.value)
    assert "did you mean the bundled 'el_centro_1940'?" in message
    assert "el_centro_1940, mexico_city_1985, northridge_1994, kalamata_1986" in message


def test_record_of_one_sample(tmp_path):
    path = tmp_path / "one.AT2"
    path.write_text(AT2.replace("NPTS=    4", "NPTS=    1").format(dt=".01").replace(" .2\n -.1 .05\n", "\n"))
    with pytest.raises(RecordError, match="at least 2 samples, found 1"):
        excitation.record(path)


@pytest.mark.parametrize("samples, message", [
    (np.zeros(100), "the record is zero throughout"),
    (np.full(100, 0.3), "the baseline correction leaves nothing of the record"),
    (np.linspace(-0.2, 0.4, 100), "the baseline correction leaves nothing of the record"),
])
def test_a_record_with_nothing_to_scale_is_refused_a_pga(samples, message):
    """pga= scales the corrected samples; a constant or a straight line corrects to rounding, which a factor of
    1e15 would blow up to the PGA asked for: refused, naming why."""
    with pytest.raises(RecordError, match=message):
        excitation.record(samples, dt=0.01, pga=2.0)
    if samples.any():
        uncorrected = excitation.record(samples, dt=0.01, pga=2.0, baseline=False)
        assert uncorrected.horizontal.peak_acceleration == pytest.approx(2.0, rel=1e-15)


# --- geometry ----------------------------------------------------------------------------------------

def test_tilted_stack_accepts_its_own_round_off_and_real_overlaps_are_still_refused():
    """A tilted stack whose corners meet within round-off (a 3e-18 m^2 sliver where block3 meets block4) is
    accepted; blocks that really overlap are refused by name."""
    scene = scenes.stack([(1.2, 0.8), (1.0, 0.3), (0.8, 0.5), (0.5, 0.8), (0.4, 0.02), (0.4, 0.3)], tilt=-0.277)
    assert scene.block_names[-1] == "block6"
    base = Block("base", rectangle(10, 1, -5, -1))
    slab = Block("slab", rectangle(1.0, 0.02, -0.5, 0.0))
    with pytest.raises(SceneError, match="'slab' and 'lid' overlap"):
        Scene((slab, Block("lid", rectangle(1.0, 0.02, -0.5, 0.0199))), base)


def test_block_floating_above_the_base_is_refused_by_name():
    """A block that starts clear of everything is refused by name, with the distance and the keyword that
    allows it."""
    base = Block("base", rectangle(10, 1, -5, -1))
    stone = Block("stone", rectangle(1.0, 1.0, -0.5, 2.0))
    with pytest.raises(SceneError, match=r"block 'stone' starts out of contact .*'stone' is 2 m from 'base'.*"
                                         r"allow_free_blocks=True"):
        Scene((stone,), base)
    assert Scene((stone,), base, allow_free_blocks=True).block_names == ["stone"]


def test_an_allowed_free_fall_is_not_an_overturn():
    """A block released 2 m up lands flat after sqrt(2 h / g) = 0.64 s and stays up: falling is not
    overturning, whatever the block's drop in height."""
    base = Block("base", rectangle(10, 1, -5, -1))
    stone = Block("stone", rectangle(1.0, 1.0, -0.5, 2.0))
    result = dem_core.simulate(Scene((stone,), base, allow_free_blocks=True), duration=1.0)
    assert not result.overturned
    assert result.y[-1, 0] == pytest.approx(0.5, abs=1e-3)  # resting on the base
    assert np.max(np.abs(result.theta)) < 1e-6


def test_blocks_floating_together_are_refused_and_a_settling_gap_is_not():
    base = Block("base", rectangle(10, 1, -5, -1))
    pair = (Block("lower", rectangle(1.0, 1.0, -0.5, 2.0)), Block("upper", rectangle(1.0, 1.0, -0.5, 3.0)))
    with pytest.raises(SceneError, match=r"blocks 'lower', 'upper' start out of contact"):
        Scene(pair, base)
    assert Scene((Block("stone", rectangle(1.0, 1.0, -0.5, 0.002)),), base).block_names == ["stone"]


@pytest.mark.parametrize("tolerance", [float("nan"), float("inf"), -1e-4])
def test_an_overlap_tolerance_that_is_no_fraction_is_named(tolerance):
    """NaN would pass every overlap check (a comparison with NaN is false) and a negative one refuse every
    stack; a scene JSON can carry either (Python's json reads NaN and Infinity)."""
    base = Block("base", rectangle(10, 1, -5, -1))
    with pytest.raises(SceneError, match=f"overlap_tolerance must be a finite fraction >= 0, got {tolerance}"):
        Scene((Block("stone", rectangle(1.0, 1.0, -0.5, 0.0)),), base, overlap_tolerance=tolerance)


@pytest.mark.parametrize("options, message", [
    ({"gravity": "9.81"}, "gravity must be a number, got str '9.81'"),
    ({"overlap_tolerance": None}, "overlap_tolerance must be a number, got NoneType None"),
    ({"slenderness": True}, "slenderness must be a number, got bool True"),
    ({"interface_friction": {("base", "stone"): "0.5"}},
     r"interface friction \('base', 'stone'\): mu must be a number, got str '0.5'"),
])
def test_a_scene_number_that_is_no_number_is_named(options, message):
    """A string, None or a boolean where a Scene takes a number is a SceneError naming the field and the value,
    not numpy's TypeError."""
    base = Block("base", rectangle(10, 1, -5, -1))
    with pytest.raises(SceneError, match=message):
        Scene((Block("stone", rectangle(1.0, 1.0, -0.5, 0.0)),), base, **options)


@pytest.mark.parametrize("make, message", [
    (lambda: scenes.column(n_drums=True), "n_drums must be a positive integer, got True"),
    (lambda: scenes.column(width="1.0"), "width must be a number, got str '1.0'"),
    (lambda: scenes.block(1.0, 2.0, density="2700"), "density must be a number, got str '2700'"),
    (lambda: scenes.block(1.0, 2.0, density="2" * 80), r"density must be a number, got str '2{56}\.\.\.$"),
    (lambda: scenes.colonnade(n_columns="3"), "n_columns must be an integer >= 2, got '3'"),
    (lambda: scenes.two_tier_colonnade(upper_drums=0), "upper_drums must be a positive integer, got 0"),
    (lambda: scenes.stack([(1.0, 0.05), (2.0, 1.0)], tilt=0.3), r"block2 \(2 m wide\) reaches .* below the base top"),
])
def test_builders_name_the_argument_of_the_wrong_type(make, message):
    with pytest.raises(SceneError, match=message):
        make()


# --- scene files -------------------------------------------------------------------------------------

BLOCK_FILE = '[scene]\nbuilder = "block"\nwidth = 1.0\nheight = 2.0\n'


def load_text(tmp_path, text):
    path = tmp_path / "broken.toml"
    path.write_text(text)
    return scene_file.load(path)


@pytest.mark.parametrize("text, message", [
    (BLOCK_FILE + '[simulation]\nduration = "0.1"\n',
     r"\[simulation\] duration: expected a finite number, got the string '0\.1' \(write numbers without quotes\)"),
    (BLOCK_FILE + '[simulation]\noutput_dt = "0.01"\n',
     r"\[simulation\] output_dt: expected a finite number, got the string '0\.01'"),
    (BLOCK_FILE + "[simulation]\nduration = -5.0\n",
     r"\[simulation\]: duration must be positive and finite, got -5\.0"),
    (BLOCK_FILE + "[simulation]\ntheta = 2.0\n", r"\[simulation\]: theta .* must be in \[0\.5, 1\], got 2\.0"),
    (BLOCK_FILE + '[simulation]\nintegrator = "moreu"\n',
     r"\[simulation\] integrator: expected one of 'explicit', 'moreau', got the string 'moreu' "
     r"\(did you mean 'moreau'\?\)"),
    ('[scene]\nbuilder = "column"\n[contact]\nlaw = "coner"\n',
     r"\[contact\] law: expected one of 'corner', 'overlap_area', got the string 'coner' \(did you mean 'corner'\?\)"),
    ('scene = "column"\n', r"scene must be a table .*got the string 'column'"),
    ('[scene]\nbuilder = "column"\nwidth = "1.0"\n',
     r"\[scene\] width: expected a finite number, got the string '1\.0'"),
    ('[scene]\nbuilder = "column"\n[contact]\nkn = "2e10"\n',
     r"\[contact\] kn: expected a finite number, got the string '2e10'"),
    ('[scene]\nbuilder = "column"\nn_drums = true\n',
     r"\[scene\] n_drums: expected an integer, got true \(a boolean\)"),
    ('[scene]\nbuilder = "column"\nn_drums = 2.5\n', r"\[scene\] n_drums: expected an integer, got the number 2\.5"),
    (BLOCK_FILE + '[output]\nplots = "false"\n', r"\[output\] plots: expected true or false, got the string 'false' "
                                                 r"\(write true or false without quotes\)"),
    (BLOCK_FILE + "[simulation]\nduration = nan\n",
     r"\[simulation\] duration: expected a finite number, got the number nan"),
    ('[scene]\nbuilder = "column"\ncapital = [1.2]\n', r"\[scene\] capital: expected a pair of numbers"),
    ('[scene]\nbuilder = "column"\ninterface_friction = [{between = ["base", 1], mu = 0.1}]\n',
     r"interface_friction entry 1 between: expected two block names"),
    ('[scene]\nbuilder = "block"\nwidth = 1.0\n', r"\[scene\] builder 'block' needs height"),
    (BLOCK_FILE + '[excitation]\nkind = "sine_pulse"\nduration = 0.5\n',
     r"\[excitation\] kind 'sine_pulse' needs amplitude"),
    (BLOCK_FILE + '[excitation]\nkind = "ramp"\nrate = 0.0\n', r"\[excitation\]: ramp rate must not be zero"),
    (BLOCK_FILE + '[excitation]\nkind = "record"\nsource = "el_centro_1940"\npga = "3"\n',
     r"\[excitation\] pga: expected a finite number, got the string '3'"),
    ('[scene]\nbuilder = "blocks"\n[[block]]\nname = "stone"\nvertices = [[0, 2], [1, 2], [1, 3]]\n'
     '[base]\nvertices = [[-5, -1], [5, -1], [5, 0], [-5, 0]]\n', r"block 'stone' starts out of contact"),
    ('[scene]\nbuilder = "blocks"\n[[block]]\nname = "stone"\nvertices = [[0, 0], [1, 0], ["1", 1]]\n'
     '[base]\nvertices = [[-5, -1], [5, -1], [5, 0], [-5, 0]]\n',
     r"\[\[block\]\] number 1 \(stone\) vertices: expected a list of \[x, y\] points"),
    ('[scene]\nbuilder = "column"\n[[block]]\nname = "stone"\nvertices = [[0, 0], [1, 0], [1, 1]]\n',
     r"\[\[block\]\] and \[base\] tables describe a scene block by block, with builder = \"blocks\""),
])
def test_scene_file_mistakes_name_file_table_key_type_and_value(tmp_path, text, message):
    """Each mistake is a SceneFileError that starts with the file's path and names the table, the key, the
    type expected and the value given."""
    with pytest.raises(SceneFileError, match=message) as info:
        load_text(tmp_path, text)
    assert str(info.value).startswith(str(tmp_path / "broken.toml"))


def test_scene_file_may_allow_free_blocks(tmp_path):
    spec = load_text(tmp_path, '[scene]\nbuilder = "blocks"\nallow_free_blocks = true\n'
                               '[[block]]\nname = "stone"\nvertices = [[0, 2], [1, 2], [1, 3]]\n'
                               '[base]\nvertices = [[-5, -1], [5, -1], [5, 0], [-5, 0]]\n')
    assert spec.scene.allow_free_blocks and spec.scene.block_names == ["stone"]


def test_every_key_a_scene_file_accepts_has_a_type():
    """The type tables cover every keyword of the builders, excitations, contact and simulation."""
    for builder in scene_file.BUILDERS.values():
        keywords = set(inspect.signature(builder).parameters) - scene_file.BUILDER_TABLE_KEYWORDS
        assert keywords <= set(scene_file.SCENE_TYPES)
    assert {f.name for f in fields(ConnectorKind)} <= set(scene_file.CONNECTOR_TYPES)
    for function in scene_file.EXCITATIONS.values():
        assert set(inspect.signature(function).parameters) <= set(scene_file.EXCITATION_TYPES)
    assert {f.name for f in fields(dem_core.ContactParameters)} == set(scene_file.CONTACT_TYPES)
    assert set(scene_file.SIMULATION_TYPES) <= set(inspect.signature(dem_core.simulate).parameters)


# --- run size and the stability override ---------------------------------------------------------------

def test_a_run_of_more_steps_than_can_be_meant_is_refused_naming_duration_and_step():
    """A run of 1e12 steps or more is refused before anything is allocated, naming the duration and what set the
    step, under either integrator."""
    steps = f"{1e9 / dem_core.automatic_time_step(scenes.column(8)):.3g}".replace("+", r"\+")
    with pytest.raises(RunTooLarge, match=steps + r" steps \(duration 1e\+09 s at the automatic step dt = .* set by "
                       r"the (shortest impact|stability limit)"):
        dem_core.simulate(scenes.column(8), duration=1e9, integrator="explicit")
    with pytest.raises(RunTooLarge, match=r"1e\+12 steps \(duration 1e\+09 s at Moreau-Jean's automatic step "
                       r"dt = 0.001 s\)"):
        dem_core.simulate(scenes.column(8), duration=1e9)


def test_a_huge_damping_that_collapses_the_step_is_named():
    """A damping so large that the automatic step collapses (cn = 1e15 gives about 1e-13 s) is refused naming
    the dashpots."""
    scene = scenes.column(8, contact=dem_core.ContactParameters(cn=1e15))
    with pytest.raises(RunTooLarge, match=r"explicit dashpots \(cn = 1e\+15 N s/m\)"):
        dem_core.simulate(scene, duration=1.0, integrator="explicit")


def test_outputs_that_would_not_fit_in_memory_are_refused_naming_output_dt():
    with pytest.raises(RunTooLarge, match=r"the outputs would take .* GiB.* raise output_dt"):
        Simulation(scenes.column(8), duration=1e6, output_dt=1e-9)


def test_a_long_run_is_announced_with_its_expected_wall_time():
    """A run too long to be meant (density 1e-6 kg/m^3: 1.7e9 steps for 0.5 s) is refused naming the lightest
    block; a milder one (1e-4 kg/m^3) runs with a warning that gives the expected wall time."""
    with pytest.raises(RunTooLarge, match=r"lightest block 'drum1' 7\.5e-07 kg"):
        Simulation(scenes.column(8, density=1e-6), duration=0.5, integrator="explicit")
    with pytest.warns(RuntimeWarning, match=r"a long run: [0-9.]+e\+08 steps .* lightest block 'drum1' 7\.5e-05 kg.*"
                      r"expect about [0-9.]+ minutes"):
        Simulation(scenes.column(8, density=1e-4), duration=0.5, integrator="explicit")


def test_a_run_past_the_stability_limit_says_so_in_its_result():
    """A run at a step past the stability limit (allowed with enforce_stability_limit=False) warns, and its
    result and summary say by how much; a run within the limit says neither."""
    scene = scenes.column(8)
    limit = dem_core.stability.stability_limit(compile_model(scene))
    with pytest.warns(RuntimeWarning, match=r"1\.50 times the stability limit .*enforce_stability_limit=False"):
        past = dem_core.simulate(scene, excitation.record("el_centro_1940"), duration=0.2, dt=1.5 * limit,
                                 enforce_stability_limit=False, integrator="explicit")
    assert "1.50 times the stability limit" in past.info["beyond_stability_limit"]
    assert past.summary()["beyond_stability_limit"] == past.info["beyond_stability_limit"]
    within = dem_core.simulate(scene, excitation.record("el_centro_1940"), duration=0.2, integrator="explicit")
    assert "beyond_stability_limit" not in within.info
    assert within.info["dt_over_limit"] <= 1.0


# --- fuzzing: whatever goes into a scene file or a record, the answer is a result or the toolkit's error ----

VALID_FILES = [
    {"scene": {"builder": "column", "n_drums": 3, "width": 1.0, "height": 6.0, "capital": [1.2, 0.4],
               "interface_friction": [{"between": ["base", "drum1"], "mu": 0.1}]},
     "contact": {"kn": 2e10}, "excitation": {"kind": "record", "source": "kalamata_1986", "pga": 3.0},
     "simulation": {"duration": 1.0, "output_dt": 0.01}, "output": {"format": "csv", "plots": False}},
    {"scene": {"builder": "colonnade", "n_columns": 3, "n_drums": 2, "epistyle": "b", "spacing": 2.5},
     "excitation": {"kind": "harmonic", "pga": 2.0, "frequency": 1.0}, "simulation": {"stop_at_overturn": False}},
    {"scene": {"builder": "blocks"},
     "block": [{"name": "stone", "vertices": [[-0.5, 0.0], [0.5, 0.0], [0.3, 1.0]], "density": 2500.0}],
     "base": {"vertices": [[-5.0, -1.0], [5.0, -1.0], [5.0, 0.0], [-5.0, 0.0]], "friction": 0.6},
     "excitation": {"kind": "ramp", "rate": 0.5, "peak": 3.0}},
]
toml_values = st.recursive(
    st.one_of(st.text(max_size=8), st.integers(), st.floats(), st.booleans(), st.datetimes(), st.dates(), st.times()),
    lambda inner: st.lists(inner, max_size=3) | st.dictionaries(st.text(max_size=6), inner, max_size=3),
    max_leaves=6)


def _places(data):
    """(table, key) places of a scene file where a value can go: every table, and every keyword of the
    builders, excitations, contact parameters and ``simulate`` (accepted or not)."""
    def keywords(*functions):
        return {name for function in functions for name in inspect.signature(function).parameters}

    keys = {
        "scene": keywords(*scene_file.BUILDERS.values()) | {"builder", "allow_free_blocks", "slenderness"},
        "contact": {f.name for f in fields(dem_core.ContactParameters)},
        "excitation": keywords(*scene_file.EXCITATIONS.values()) | {"kind"},
        "simulation": keywords(dem_core.simulate) - {"scene", "excitation"},
        "output": {"format", "plots"},
        "base": {"vertices", "friction", "depth"},
        "block": {"name", "vertices", "density", "friction", "depth", "angle"},
    }
    places = [(None, table) for table in keys]
    for table, names in keys.items():
        if table in data or table in ("contact", "simulation", "output"):
            places += [(table, name) for name in sorted(names)]
    return places


@settings(max_examples=60, deadline=None, suppress_health_check=[HealthCheck.function_scoped_fixture])
@given(template=st.sampled_from(VALID_FILES), choice=st.data(), value=toml_values)
def test_fuzzed_scene_files_give_a_scene_or_a_scene_file_error(tmp_path, template, choice, value):
    data = copy.deepcopy(template)
    table, key = choice.draw(st.sampled_from(_places(data)))
    if table is None:
        data[key] = value
    elif table == "block":
        data["block"][0][key] = value
    else:
        data.setdefault(table, {})[key] = value
    path = tmp_path / "fuzzed.toml"
    try:
        scene_file.from_dict(data, path)
    except SceneFileError as exc:
        assert str(exc).startswith(str(path))


numbers = st.floats(-10.0, 10.0).map(lambda x: f"{x:.4g}")
junk = st.one_of(st.sampled_from(["nan", "inf", "1e400", "x", "1,2", ";", "#", "NPTS= 3, DT= 0", "DT=.01.0", "1e-300",
                                  "", "3.0.0", "0x1p-3"]), st.text(max_size=4))
tokens = st.one_of(numbers, numbers, numbers, numbers, junk)


@st.composite
def junk_lines(draw):
    """Lines of 1 to 3 columns, mostly numbers, the first column sometimes a time column, some lines broken."""
    columns = draw(st.integers(1, 3))
    timed = draw(st.booleans())
    lines = []
    for k in range(draw(st.integers(0, 12))):
        row = draw(st.lists(tokens, min_size=columns, max_size=columns))
        if timed:
            row[0] = f"{0.01 * k + draw(st.sampled_from([0.0, 0.0, 0.0, -0.02, 0.005])):.3f}"
        lines.append(" ".join(row))
    return lines


@settings(max_examples=60, deadline=None, suppress_health_check=[HealthCheck.function_scoped_fixture])
@given(lines=junk_lines(), header=st.booleans(), dt=st.sampled_from([None, 0.01, 0.0, float("nan")]))
def test_fuzzed_records_give_a_motion_or_a_record_error(tmp_path, lines, header, dt):
    if header:
        path = tmp_path / "fuzzed.AT2"
        lines = ["HEAD", "EVENT", "ACCELERATION TIME SERIES IN UNITS OF G", *lines]
    else:
        path = tmp_path / "fuzzed.txt"
    path.write_text("\n".join(lines) + "\n", encoding="utf-8", errors="surrogatepass")
    try:
        motion = excitation.record(path, dt=dt)
    except RecordError as exc:
        assert str(path) in str(exc)
    else:
        assert np.all(np.isfinite(motion.horizontal.samples))


def test_a_count_that_is_surely_a_typo_is_refused_before_building():
    """A block count past MAX_BLOCKS is refused at once, before any block is built (the test gives up after
    5 s)."""
    def give_up(signum, frame):
        raise TimeoutError("still building after 5 s")

    previous = signal.signal(signal.SIGALRM, give_up)
    signal.alarm(5)
    try:
        with pytest.raises(SceneError, match=r"n_drums = 1000000000000 would make 1000000000000 blocks"):
            scenes.column(10**12)
    finally:
        signal.alarm(0)
        signal.signal(signal.SIGALRM, previous)


def test_run_warnings_point_at_the_line_that_started_the_run():
    """A run's warnings name the test's own line, whether the run is started by simulate() or by
    Simulation(...) directly."""
    scene = scenes.column(8)
    beyond = {"duration": 0.01, "dt": 1.5 * dem_core.stability.stability_limit(compile_model(scene)),
              "enforce_stability_limit": False}
    with pytest.warns(RuntimeWarning, match="times the stability limit") as direct:
        Simulation(scene, **beyond, integrator="explicit")
    with pytest.warns(RuntimeWarning, match="times the stability limit") as through:
        dem_core.simulate(scene, **beyond, integrator="explicit")
    with pytest.warns(RuntimeWarning, match="a long run") as long_run:
        Simulation(scenes.column(8, density=1e-4), duration=0.5, integrator="explicit")
    for record in (direct, through, long_run):
        assert [w.filename for w in record] == [__file__]


# --- issue 21: sweep keys and the ramp's rate ---------------------------------------------------------------

SWEEP_FILE = ('[scene]\nbuilder = "column"\nn_drums = 2\n[excitation]\nkind = "harmonic"\nfrequency = 1.0\n'
              'pga = 1.0\n[simulation]\nduration = 1.0\n[sweep]\nmode = "zip"\n[sweep.excitation]\npga = [1.0, 2.0]\n')


@pytest.mark.parametrize("old, new, message", [
    ('mode = "zip"', 'mdoe = "zip"', r"\[sweep\] has no key 'mdoe' \(did you mean 'mode'\?\); it takes mode, "
                                     r"time_histories and the tables \[sweep\.scene\]"),
    ('mode = "zip"', 'mode = "zpi"', r"\[sweep\] mode must be one of grid, zip, got 'zpi' \(did you mean 'zip'\?\)"),
    ("[sweep.excitation]", "[sweep.excitaton]", r"\[sweep\.excitaton\] is not a table of scene, contact, excitation, "
                                                r"simulation keys \(did you mean 'excitation'\?\)"),
    ("pga = [1.0, 2.0]", "pgaa = [1.0, 2.0]", r"has no parameter\(s\) \['pgaa'\] \(did you mean 'pga'\?\)"),
])
def test_a_misspelt_sweep_key_gets_the_nearest_valid_one(tmp_path, old, new, message):
    """A misspelt key of [sweep], a table name under it or a key it varies is named with the nearest valid one
    (``mdoe`` was taken for a table [sweep.mdoe] and ``mode`` not suggested)."""
    from dem_core.analyses.sweep import SweepError, load_sweep

    path = tmp_path / "spec.toml"
    path.write_text(SWEEP_FILE.replace(old, new))
    with pytest.raises(SweepError, match=message) as info:
        load_sweep(path)
    assert str(info.value).startswith(str(path))


@pytest.mark.parametrize("rate, shown", [(0.0, "0"), (-0.5, "-0.5"), (float("inf"), "inf"), (float("nan"), "nan")])
def test_a_ramp_rate_that_is_not_positive_is_named_with_its_unit(rate, shown):
    """``dem-core ramp --rate 0`` said "rate must be positive, got 0.0": the message names the ramp rate and its
    unit, and is refused before any run."""
    from dem_core.analyses.thresholds import onset_under_ramp

    with pytest.raises(ValueError, match=rf"ramp rate must be positive and finite, got {shown} m/s\^2 per s"):
        onset_under_ramp(scenes.column(2), rate)


@pytest.mark.parametrize("call, size, message", [
    (lambda n: stripes(n, 1.0), len, "at least 2 intensity levels"),
    (lambda n: synthetic_suite(Scenario(6.5, 20.0, 400.0), n), len, "a whole number of motions"),
    (lambda n: scenes.column(n_drums=n), lambda scene: len(scene.blocks), "n_drums must be a positive integer"),
])
def test_a_count_takes_numpys_integers_and_refuses_a_boolean(call, size, message):
    """One rule (:mod:`dem_core.inputs.number_types`) for every count: ``True`` is an int to Python but no count a
    user means, while a numpy integer (from ``np.arange``, a table) is one."""
    with pytest.raises((ValueError, SceneError), match=message):
        call(True)
    assert size(call(np.int64(3))) == 3


@pytest.mark.parametrize("value", [np.float32(2.5), 2.5, np.float32("inf"), True])
def test_a_scene_file_count_with_a_fraction_is_refused_not_cut(value):
    """A count in a scene file's dictionary (``scene_file.from_dict``, which a script may fill with numpy values) is a
    whole number: 2.5, in any float type, is refused, not cut to 2; 3.0 is 3."""
    with pytest.raises(SceneFileError, match="n_drums"):
        scene_file.from_dict({"scene": {"builder": "column", "n_drums": value}})
    spec = scene_file.from_dict({"scene": {"builder": "column", "n_drums": np.float32(3.0)}})
    assert len(spec.scene.blocks) == 3
