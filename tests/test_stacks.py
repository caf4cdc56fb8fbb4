"""Columns as stacks: which blocks form one, and the overturn of the column as a whole."""

import numpy as np
import pytest

import adapters
import dem_core
from dem_core.engine.model import compile_model
from dem_core import excitation, scenes
from dem_core.engine.stacks import find_stacks, first_overturns


def _names(scene):
    return [[scene.blocks[b].name for b in st.blocks] for st in find_stacks(scene)]


def test_stacks_are_the_columns_without_shared_epistyles():
    assert _names(scenes.column(3, capital=(1.4, 0.5))) == [["drum1", "drum2", "drum3", "capital"]]
    assert _names(scenes.colonnade(3, 2, epistyle="b")) == [[f"c{c}_drum1", f"c{c}_drum2"] for c in (1, 2, 3)]
    assert _names(scenes.block(1.0, 6.0)) == []
    # the upper row of a two-tier colonnade stands on an epistyle, not on the base
    assert all(names[0].startswith("lower_") for names in _names(scenes.two_tier_colonnade()))


@pytest.mark.parametrize("fraction, falls", [(0.9, False), (1.1, True)])
def test_two_drum_column_released_past_its_critical_tilt_falls_at_once(fraction, falls):
    alpha = np.arctan(1.0 / 6.0)
    scene = scenes.stack([(1.0, 3.0), (1.0, 3.0)], tilt=fraction * alpha)
    result = dem_core.simulate(scene, excitation.still(), duration=1.0, output_dt=1e-3, integrator="explicit")
    assert result.overturned == falls
    if falls:
        assert result.time_of_overturn < 2 * result.dt  # its centre of mass starts past the corner
        assert "tipped past its base" in result.info["ended_at_overturn"]
    else:  # the drums never pass their own critical angle (0.32 rad) either
        assert np.max(np.abs(result.theta)) < alpha


@pytest.mark.slow
def test_kernel_and_output_checks_agree_and_come_before_the_drums_topple():
    scene = scenes.column(8)
    motion = excitation.record("el_centro_1940", pga=6.0)
    result = dem_core.simulate(scene, motion, duration=8.0, output_dt=1e-3, stop_at_overturn=False,
                               integrator="explicit")
    (kernel_time,) = result.info["tipped_stacks"].values()
    relative = result.x - result.base_x[:, None], result.y - result.base_y[:, None], result.theta
    from_outputs = result.t[first_overturns(compile_model(scene), *relative)[1][0]]
    assert from_outputs == pytest.approx(kernel_time, abs=1e-3)
    drum_critical = np.arctan(1.0 / 0.75)
    assert np.max(np.abs(np.interp(kernel_time, result.t, result.theta[:, 0]))) < drum_critical / 2


def test_other_engines_flag_the_column_at_the_same_criterion():
    scene = scenes.column(8)
    motion = excitation.record("el_centro_1940", pga=6.0)
    native = dem_core.simulate(scene, motion, duration=8.0, integrator="explicit").time_of_overturn
    for engine in ("pymunk", "mujoco"):
        other = adapters.simulate(scene, motion, 8.0, engine=engine).time_of_overturn
        assert other == pytest.approx(native, abs=0.1), engine  # measured 5.01, 4.99 against 4.95 s
