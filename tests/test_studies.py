"""The study scripts build the scenes their titles promise (running them takes minutes: not done here)."""

import numpy as np
import pandas as pd
import pytest

from dem_core.analyses.fragility_study import FragilityStudy


def test_small_scale_column_is_seven_48_by_29_mm_blocks(load_study):
    study = load_study("frequency_response")
    spec = study.small_column({"mu": 0.68, "pga": 3.0, "frequency": 5.0})
    assert len(spec.scene.blocks) == 7
    for block in spec.scene.blocks:
        assert block.width == pytest.approx(0.048) and block.height == pytest.approx(0.029)
        assert block.depth == pytest.approx(0.048)
    assert spec.scene.friction("base", "drum1") == 0.68
    assert np.max(np.abs(spec.excitation.acceleration(np.linspace(0, 1, 1001))[0])) == pytest.approx(3.0, rel=1e-3)


def test_weak_interface_gets_its_friction_and_the_others_0_48(load_study):
    study = load_study("interface_friction")
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
def test_colonnade_study_scenes(load_study, builder, params, blocks):
    spec = getattr(load_study("colonnades"), builder)(params)
    assert len(spec.scene.blocks) == blocks


def test_thesis_tables_use_the_thesis_set_up(load_study):
    study = load_study("thesis_tables")
    systems = {key: (build, reference, thesis) for key, _, _, build, reference, thesis in study.systems()}
    thesis_law = study.LAWS["overlap-area 1e8"]
    assert (thesis_law.law, thesis_law.kn, thesis_law.cn, thesis_law.cr) == ("overlap_area", 1e8, 1e3, 0.0)
    colonnade = systems["colonnade_2"][0](thesis_law)
    assert [b.name for b in colonnade.blocks].count("epistyle") == 1 and len(colonnade.blocks) == 3 * 2 + 1
    loaded = systems["loaded_3"][0](thesis_law)
    load = [b for b in loaded.blocks if b.name == "load"][0]
    epistyle = [b for b in colonnade.blocks if b.name == "epistyle"][0]
    assert load.mass == pytest.approx(epistyle.mass / 3)  # one column's share of the epistyle
    assert loaded.friction("drum1", "drum2") == colonnade.friction("base", "c1_drum1") == 0.485
    assert systems["loaded_1"][2]["mexico_city_1985"] == 1.15 and systems["column_8"][2]["kalamata_1986"] == 18.7
    mexico = study.motion_for("mexico_city_1985")(1.0)
    assert np.max(np.abs(mexico.horizontal.samples)) == pytest.approx(1.0, rel=1e-3)  # after baseline correction
    from dem_core import excitation
    north_south = excitation.record("mexico_city_1985", component=1).horizontal.peak_acceleration
    assert north_south == pytest.approx(0.0995 * 9.80665, rel=2e-3)  # the thesis' 0.98 m/s^2


def test_rigid_references_of_the_studies(load_study):
    rigid = load_study("_rigid")
    from comparisons.references.analytical import RockingBlock
    from dem_core import scenes
    monolith = RockingBlock.from_size(1.0, 6.0)
    block, restitution = rigid.rigid_body(scenes.column(1))
    assert block.p == pytest.approx(monolith.p) and block.alpha == pytest.approx(monolith.alpha)
    assert restitution == pytest.approx(monolith.restitution)
    frame, e = rigid.rocking_frame(monolith, 3, 1.0, 0.0)  # no beam: three free columns
    assert frame.p == pytest.approx(monolith.p) and e == pytest.approx(monolith.restitution)
    heavy, _ = rigid.rocking_frame(monolith, 3, 1.0, 3.0)  # gamma = 1: p^2 (1 + 2) / (1 + 3)
    assert heavy.p == pytest.approx(monolith.p * np.sqrt(3.0 / 4.0)) and heavy.alpha == pytest.approx(monolith.alpha)


def test_restoration_says_which_fragility_runs_it_read_from_its_log(load_study):
    """Runs resumed from the study's log took no time in this invocation: the README names them as read, so that
    a rerun from the cache is not reported as 2,560 runs in 2 s."""
    study = load_study("restoration")

    def variant(runs, resumed):
        return FragilityStudy(pd.DataFrame({"level": np.zeros(runs)}), {}, "pga", resumed=resumed)

    all_read = study.fragility_cost({"plain": variant(4, 4), "bars": variant(6, 6)}, 2.0)
    assert all_read == ("10 fragility runs read from `.study_cache/restoration/`, where an earlier invocation "
                        "logged them")
    some_read = study.fragility_cost({"plain": variant(4, 4), "bars": variant(6, 0)}, 30.0)
    assert some_read.startswith("6 fragility runs in 30 s (4 read from `.study_cache/restoration/`")
    assert study.fragility_cost({"plain": variant(4, 0)}, 30.0) == "4 fragility runs in 30 s"
