"""Scene description: builders for docs/method.md section 3 and errors that name the block at fault."""

import numpy as np
import pytest

from dem_core import Block, Scene, SceneError, scenes
from dem_core.engine.geometry import rectangle


def test_column_drums_stack_without_overlap_and_keep_the_mass():
    col = scenes.column(8, width=1.0, height=6.0, density=2700.0)
    assert [b.name for b in col.blocks] == [f"drum{k}" for k in range(1, 9)]
    assert sum(b.mass for b in col.blocks) == pytest.approx(2700.0 * 6.0)
    tapered = scenes.column(8, width=1.0, height=6.0, taper=0.3, density=2700.0)
    assert sum(b.mass for b in tapered.blocks) == pytest.approx(2700.0 * 6.0)
    assert tapered.blocks[0].width > tapered.blocks[-1].width
    top = scenes.column(3, capital=(1.4, 0.4))
    assert top.blocks[-1].name == "capital" and top.blocks[-1].width == pytest.approx(1.4)


def test_drum_inertia_is_the_polygon_value():
    drum = scenes.column(8).blocks[0]  # 1 x 0.75 m rectangle, depth 1 m
    assert drum.inertia == pytest.approx(drum.mass * (1.0**2 + 0.75**2) / 12.0, rel=1e-12)


def test_block_tilt_rests_on_the_corner():
    s = scenes.block(0.25, 1.0, tilt=0.05)
    v = s.blocks[0].vertices
    assert v[:, 1].min() == pytest.approx(0.0, abs=1e-15)
    assert v[np.argmin(v[:, 1]), 0] == pytest.approx(-0.125)
    assert s.blocks[0].critical_angle == pytest.approx(np.arctan(0.25), rel=1e-12)
    s = scenes.block(0.25, 1.0, tilt=-0.05)
    assert s.blocks[0].vertices[np.argmin(s.blocks[0].vertices[:, 1]), 0] == pytest.approx(0.125)


@pytest.mark.parametrize("kind, names, span", [
    ("a", ["epistyle"], (-3.0, 3.0)),
    ("b", ["epistyle1", "epistyle2"], (-3.0, 3.0)),
    ("c", ["epistyle"], (-2.5, 2.5)),
    ("d", ["epistyle1", "epistyle2"], (-2.5, 2.5)),
])
def test_colonnade_epistyle_types(kind, names, span):
    s = scenes.colonnade(3, 2, spacing=2.5, epistyle=kind, epistyle_density=8000.0, width=1.0)
    epi = [b for b in s.blocks if b.name.startswith("epistyle")]
    assert [b.name for b in epi] == names
    xs = np.concatenate([b.vertices[:, 0] for b in epi])
    assert (xs.min(), xs.max()) == pytest.approx(span)
    assert all(b.density == 8000.0 for b in epi)
    if len(epi) == 2:  # they meet over the middle column
        assert epi[0].vertices[:, 0].max() == pytest.approx(0.0) == epi[1].vertices[:, 0].min()


def test_two_epistyles_need_a_middle_column():
    with pytest.raises(SceneError, match="odd number of columns"):
        scenes.colonnade(4, 2, epistyle="b")


def test_two_tier_colonnade_has_both_rows_and_epistyles():
    s = scenes.two_tier_colonnade(3)
    names = s.block_names
    assert "lower_epistyle" in names and "upper_epistyle" in names
    assert sum(n.startswith("upper_c") for n in names) == 3 * 2


def test_interface_friction_overrides_the_default():
    s = scenes.column(4, friction=0.48, interface_friction={("base", "drum1"): 0.05})
    assert s.friction("drum1", "base") == 0.05
    assert s.friction("drum1", "drum2") == 0.48
    assert s.with_interface_friction("drum2", "drum3", 0.2).friction("drum3", "drum2") == 0.2


@pytest.mark.parametrize("make, message", [
    (lambda: Block("drum3", [[0, 0], [2, 0], [1, 0.2], [2, 2], [0, 2]]), "drum3.*not convex"),
    (lambda: Block("drum3", [[0, 0], [1, 0], [2, 0]]), "drum3.*degenerate"),
    (lambda: Block("drum3", rectangle(1, 1), density=0.0), "drum3.*density must be positive"),
    (lambda: Block("drum3", rectangle(1, 1), depth=-1.0), "drum3.*depth must be positive"),
    (lambda: Block("drum3", rectangle(1, 1), friction=-0.1), "drum3.*friction must be >= 0"),
    (lambda: scenes.column(3, width=-1.0), "width must be positive"),
    (lambda: scenes.column(0), "n_drums"),
    (lambda: scenes.column(3, interface_friction={("base", "drum9"): 0.1}), "no block named 'drum9'"),
])
def test_bad_input_names_the_culprit(make, message):
    with pytest.raises(SceneError, match=message):
        make()


def test_overlapping_blocks_are_refused_by_name():
    base = Block("base", rectangle(10, 1, -5, -1))
    a = Block("drum1", rectangle(1, 1, -0.5, 0))
    b = Block("drum2", rectangle(1, 1, -0.5, 0.9))
    with pytest.raises(SceneError, match="'drum1' and 'drum2' overlap"):
        Scene((a, b), base)
    with pytest.raises(SceneError, match="used twice"):
        Scene((a, Block("drum1", rectangle(1, 1, -0.5, 1.0))), base)


def test_scene_is_immutable():
    s = scenes.column(2)
    with pytest.raises(ValueError, match="read-only"):
        s.blocks[0].vertices[0, 0] = 5.0
    with pytest.raises(AttributeError):
        s.gravity = 1.0


def test_every_builder_takes_the_scene_options_with_their_defaults():
    """The fields of SceneOptions are keyword-only parameters of every builder, with the same defaults (scene
    files read them from the signature), and reach the blocks and the base."""
    import inspect
    from dataclasses import fields

    options = {f.name: f.default for f in fields(scenes.SceneOptions)}
    for builder in (scenes.block, scenes.stack, scenes.column, scenes.loaded_column, scenes.colonnade,
                    scenes.two_tier_colonnade):
        parameters = inspect.signature(builder).parameters
        assert {name: parameters[name].default for name in options} == options
        assert {parameters[name].kind for name in options} == {inspect.Parameter.KEYWORD_ONLY}
    s = scenes.colonnade(3, 2, density=2000.0, friction=0.5, depth=0.8, base_width=20.0, epistyle_density=9000.0)
    assert {(b.density, b.friction, b.depth) for b in s.blocks if "epistyle" not in b.name} == {(2000.0, 0.5, 0.8)}
    assert s.blocks[-1].density == 9000.0 and (s.base.friction, s.base.depth) == (0.5, 0.8)
    assert np.ptp(s.base.vertices[:, 0]) == pytest.approx(20.0)
    with pytest.raises(TypeError, match="unexpected keyword argument 'options'"):
        scenes.column(2, options=scenes.SceneOptions())
