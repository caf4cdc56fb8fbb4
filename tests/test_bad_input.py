"""Ordinary mistakes in records, scene files and geometry get an error that names the culprit.

Each test is one mistake a new user made; the old behaviour is in its docstring.
"""

import math

import numpy as np
import pytest

from dem_core import excitation, scenes
from dem_core.engine.geometry import rectangle
from dem_core.inputs.records import RecordError
from dem_core.inputs.scene import Block, Scene, SceneError

AT2 = "HEAD\nEVENT\nACCELERATION TIME SERIES IN UNITS OF G\nNPTS=    4, DT= {dt} SEC\n .1 .2\n -.1 .05\n"


# --- records -----------------------------------------------------------------------------------------

@pytest.mark.parametrize("dt", [0.0, float("nan"), -0.01, 1e-9])
def test_one_column_record_with_a_meaningless_dt(tmp_path, dt):
    """Was ZeroDivisionError for dt = 0 and 'cannot convert float NaN to integer' for NaN."""
    path = tmp_path / "one.txt"
    path.write_text("0.1\n0.2\n0.3\n0.1\n")
    with pytest.raises(RecordError, match=r"one\.txt: dt must be a finite sampling interval of at least 1e-06 s"):
        excitation.record(path, dt=dt)


def test_at2_with_a_tiny_dt(tmp_path):
    """Was LinAlgError: Singular matrix, from the baseline correction."""
    path = tmp_path / "tiny.AT2"
    path.write_text(AT2.format(dt="1e-300"))
    with pytest.raises(RecordError, match=r"tiny\.AT2:4: DT must be a finite sampling interval .* got 1e-300"):
        excitation.record(path)


def test_at2_with_an_unreadable_dt(tmp_path):
    """Was a bare "could not convert string to float: '.01.0'" naming no file."""
    path = tmp_path / "dots.AT2"
    path.write_text(AT2.format(dt=".01.0"))
    with pytest.raises(RecordError, match=r"dots\.AT2:4: cannot read DT '\.01\.0'"):
        excitation.record(path)


def test_baseline_correction_does_not_depend_on_the_unit_of_time():
    """Was a singular system for small steps: its equations were written in powers of t_end."""
    a = np.array([0.1, 0.3, -0.2, 0.05])
    np.testing.assert_allclose(excitation.baseline_correct(a, 1e-150), excitation.baseline_correct(a, 0.01))


def test_time_column_that_goes_backwards_names_its_line(tmp_path):
    """Was taken quietly as 'no time column'."""
    lines = [f"{0.01 * k:.2f} {math.sin(k / 10):.4f}" for k in range(400)]
    lines[300] = "2.98 0.1"
    path = tmp_path / "back.txt"
    path.write_text("# t a\n" + "\n".join(lines) + "\n")
    with pytest.raises(RecordError, match=r"back\.txt:302: time 2\.98 s does not come after 2\.99 s on line 301"):
        excitation.record(path)


def test_time_column_with_another_step_than_the_dt_given(tmp_path):
    """Was read as two acceleration columns, the time column taken as the motion."""
    path = tmp_path / "rec.txt"
    path.write_text("".join(f"{0.02 * k:.2f} {math.sin(k):.4f}\n" for k in range(50)))
    with pytest.raises(RecordError, match=r"dt=0\.01 was given but the time column steps by 0\.02"):
        excitation.record(path, dt=0.01)


def test_nan_in_an_array_record_is_named_at_its_own_sample():
    """Was 'sample 0 is not finite': the baseline correction had spread the NaN first."""
    a = np.sin(np.arange(100) / 5.0)
    a[5] = np.nan
    with pytest.raises(RecordError, match=r"array record: sample 5 is not finite \(nan\)"):
        excitation.record(a, dt=0.01)


@pytest.mark.parametrize("argument, value", [("pga", float("nan")), ("pga", -1.0), ("scale", float("inf")),
                                             ("scale", 0.0), ("pga", "3")])
def test_pga_and_scale_must_be_finite_and_positive(argument, value):
    """Was 'el_centro_1940: sample 0 is not finite', naming neither pga nor scale."""
    with pytest.raises(RecordError, match=rf"el_centro_1940: {argument}.* must be a finite positive number"):
        excitation.record("el_centro_1940", **{argument: value})


def test_mistyped_bundled_record_name_gets_the_close_match_and_the_list():
    """Was 'el_centro_194: no such record file'."""
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


# --- geometry ----------------------------------------------------------------------------------------

def test_tilted_stack_accepts_its_own_round_off_and_real_overlaps_are_still_refused():
    """Was refused: a 3e-18 m^2 sliver where block3 meets block4 read as a 7 mm mean penetration."""
    scene = scenes.stack([(1.2, 0.8), (1.0, 0.3), (0.8, 0.5), (0.5, 0.8), (0.4, 0.02), (0.4, 0.3)], tilt=-0.277)
    assert scene.block_names[-1] == "block6"
    base = Block("base", rectangle(10, 1, -5, -1))
    slab = Block("slab", rectangle(1.0, 0.02, -0.5, 0.0))
    with pytest.raises(SceneError, match="'slab' and 'lid' overlap"):
        Scene((slab, Block("lid", rectangle(1.0, 0.02, -0.5, 0.0199))), base)


def test_block_floating_above_the_base_is_refused_by_name():
    """Was accepted, and its free fall reported as 'overturned at t = 0.319 s'."""
    base = Block("base", rectangle(10, 1, -5, -1))
    stone = Block("stone", rectangle(1.0, 1.0, -0.5, 2.0))
    with pytest.raises(SceneError, match=r"block 'stone' starts out of contact .*'stone' is 2 m from 'base'.*"
                                         r"allow_free_blocks=True"):
        Scene((stone,), base)
    assert Scene((stone,), base, allow_free_blocks=True).block_names == ["stone"]


def test_blocks_floating_together_are_refused_and_a_settling_gap_is_not():
    base = Block("base", rectangle(10, 1, -5, -1))
    pair = (Block("lower", rectangle(1.0, 1.0, -0.5, 2.0)), Block("upper", rectangle(1.0, 1.0, -0.5, 3.0)))
    with pytest.raises(SceneError, match=r"blocks 'lower', 'upper' start out of contact"):
        Scene(pair, base)
    assert Scene((Block("stone", rectangle(1.0, 1.0, -0.5, 0.002)),), base).block_names == ["stone"]


@pytest.mark.parametrize("make, message", [
    (lambda: scenes.column(n_drums=True), "n_drums must be a positive integer, got True"),
    (lambda: scenes.column(width="1.0"), "width must be a number, got '1.0'"),
    (lambda: scenes.block(1.0, 2.0, density="2700"), "density must be a number, got '2700'"),
    (lambda: scenes.colonnade(n_columns="3"), "n_columns must be an integer >= 2, got '3'"),
    (lambda: scenes.two_tier_colonnade(upper_drums=0), "upper_drums must be a positive integer, got 0"),
    (lambda: scenes.stack([(1.0, 0.05), (2.0, 1.0)], tilt=0.3), r"block2 \(2 m wide\) reaches .* below the base top"),
])
def test_builders_name_the_argument_of_the_wrong_type(make, message):
    with pytest.raises(SceneError, match=message):
        make()
