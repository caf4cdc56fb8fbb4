"""A standalone column carrying its share of an epistyle (the thesis' loaded column, section 7.1)."""

import numpy as np
import pytest

from dem_core import scenes
from dem_core.inputs.scene import SceneError


def test_a_load_on_a_column_lowers_its_uplift_acceleration_to_g_b_over_the_centre_height():
    bare = scenes.column(1)
    loaded = scenes.loaded_column((2.0, 0.8, 2700.0), 1)
    mass, load_mass = 1.0 * 6.0 * 2700.0, 2.0 * 0.8 * 2700.0
    centre = (mass * 3.0 + load_mass * 6.4) / (mass + load_mass)
    assert loaded.rocking_slenderness == pytest.approx(np.arctan(0.5 / centre), rel=1e-12)
    assert loaded.rocking_slenderness < bare.rocking_slenderness
    assert [b.name for b in loaded.blocks] == ["drum1", "load"]


def test_a_load_must_be_a_width_height_density_triple():
    with pytest.raises(SceneError, match="load"):
        scenes.loaded_column((2.0, 0.8), 1)
    with pytest.raises(SceneError, match="load_density"):
        scenes.loaded_column((2.0, 0.8, -1.0), 1)
