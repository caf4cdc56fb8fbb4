"""The study scripts build the scenes their titles promise (running them takes minutes: not done here)."""

import importlib.util
import sys
from pathlib import Path

import numpy as np
import pytest

STUDIES = Path(__file__).parents[1] / "examples" / "studies"


def _load(name):
    sys.path.insert(0, str(STUDIES))
    try:
        spec = importlib.util.spec_from_file_location(name, STUDIES / f"{name}.py")
        module = importlib.util.module_from_spec(spec)
        spec.loader.exec_module(module)
        return module
    finally:
        sys.path.remove(str(STUDIES))


def test_small_scale_column_is_seven_48_by_29_mm_blocks():
    study = _load("frequency_response")
    spec = study.small_column({"mu": 0.68, "pga": 3.0, "frequency": 5.0})
    assert len(spec.scene.blocks) == 7
    for block in spec.scene.blocks:
        assert block.width == pytest.approx(0.048) and block.height == pytest.approx(0.029)
        assert block.depth == pytest.approx(0.048)
    assert spec.scene.friction("base", "drum1") == 0.68
    assert np.max(np.abs(spec.excitation.acceleration(np.linspace(0, 1, 1001))[0])) == pytest.approx(3.0, rel=1e-3)


def test_weak_interface_gets_its_friction_and_the_others_0_48():
    study = _load("interface_friction")
    spec = study.column({"blocks": 4, "interface": 2, "mu": 0.05})
    assert spec.scene.friction("drum2", "drum3") == 0.05
    assert spec.scene.friction("base", "drum1") == spec.scene.friction("drum3", "drum4") == 0.48
    pga = np.max(np.abs(spec.excitation.acceleration(np.linspace(0, 4, 4001))[0]))
    assert pga == pytest.approx(0.3 * (2 * np.pi * 0.5) ** 2, rel=1e-3)


@pytest.mark.parametrize("builder, params, blocks", [
    ("epistyles", {"epistyle": "d", "density": 10000.0, "frequency": 1.0}, 3 * 3 + 2),
    ("layout", {"n_columns": 5, "spacing": 1.5, "frequency": 0.5}, 5 * 3 + 1),
    ("taper", {"taper": 0.3, "frequency": 2.0}, 3 * 3 + 1),
    ("two_tier", {"pga": 3.0, "frequency": 1.0}, 3 * 3 + 1 + 3 * 2 + 1),
])
def test_colonnade_study_scenes(builder, params, blocks):
    spec = getattr(_load("colonnades"), builder)(params)
    assert len(spec.scene.blocks) == blocks
