"""The same scenes in pymunk, PyBullet and MuJoCo: every builder runs, and each engine is measured
against the analytical references with the band its case declares for it (comparisons/cases/catalogue.py, where
the measured values are)."""

import warnings

import numpy as np
import pytest

import adapters
import dem_core
from adapters import _geometry as geometry
from adapters._driver import EngineRun, product_friction, run
from comparisons.cases import catalogue as cases
from comparisons.references import analytical
from dem_core import excitation, scenes
from dem_core.engine.geometry import polygon_properties, rectangle, transform

ENGINES = ["pymunk", "pybullet", "mujoco"]

BUILDERS = {
    "block": lambda: scenes.block(0.5, 1.5),
    "tilted block": lambda: scenes.block(0.5, 1.5, tilt=-0.05),
    "tapered column with capital": lambda: scenes.column(4, taper=0.2, capital=(1.3, 0.4)),
    "colonnade a": lambda: scenes.colonnade(3, 2, epistyle="a"),
    "colonnade b": lambda: scenes.colonnade(3, 2, epistyle="b", epistyle_density=8000.0),
    "colonnade c": lambda: scenes.colonnade(3, 2, epistyle="c"),
    "colonnade d": lambda: scenes.colonnade(3, 2, epistyle="d"),
    "two-tier colonnade": lambda: scenes.two_tier_colonnade(3),
    "per-interface friction": lambda: scenes.column(3, friction=0.6, interface_friction={("base", "drum1"): 0.1}),
}


@pytest.fixture(autouse=True)
def _quiet_friction_warnings():
    with warnings.catch_warnings():
        warnings.filterwarnings("ignore", message=".*product of their coefficients")
        yield


@pytest.mark.parametrize("engine", ENGINES + ["dem"])
@pytest.mark.parametrize("builder", BUILDERS)
def test_every_engine_builds_and_runs_every_scene(engine, builder):
    scene = BUILDERS[builder]()
    result = adapters.simulate(scene, excitation.sine_pulse(2.0, 0.3), duration=0.3, engine=engine, output_dt=0.05)
    assert result.names == tuple(scene.block_names)
    assert result.theta.shape == (len(result.t), len(scene.blocks))
    assert np.all(np.isfinite(result.x)) and np.all(np.isfinite(result.theta))
    assert result.t[-1] == pytest.approx(0.3, abs=result.dt)
    # nothing has had time to move far: the blocks are where the scene put them
    start = np.array([b.centroid for b in scene.blocks])
    assert np.max(np.abs(result.relative_x[0] - start[:, 0])) < 1e-9
    assert np.max(np.abs(result.y[-1] - start[:, 1])) < 0.01


@pytest.mark.slow
@pytest.mark.parametrize("engine", ENGINES)
def test_resting_column_does_not_drift(engine):
    statics = cases.case("statics")
    r = adapters.simulate(scenes.column(8), duration=10.0, engine=engine)
    assert np.max(np.abs(r.x - r.x[0])) < statics.band("drift_m", engine)
    assert np.max(np.abs(r.theta)) < statics.band("rotation_rad", engine)
    assert np.max(np.abs(r.y[-1] - r.y[len(r.t) // 10])) < 1e-6  # settled after the first second


@pytest.mark.parametrize("engine", ENGINES)
def test_free_rocking_against_housner(engine):
    """The quarter period and the peaks after impacts 1-5 against the rocking equation with Housner's impact rule."""
    case = cases.case("free_rocking")
    r = adapters.simulate(case.scene(), duration=case.duration, engine=engine, output_dt=case.output_dt)
    errors = case.errors(r, case.reference())
    for metric in ("quarter_period", "peak_decay"):
        assert case.within_band(metric, engine, errors[metric]), (metric, errors[metric])


@pytest.mark.parametrize("engine", ENGINES)
@pytest.mark.parametrize("ratio", [1.5, 3.0])
def test_newmark_sliding_pulse(engine, ratio):
    mu, t_p = 0.3, 0.3
    a_p = ratio * mu * analytical.G
    scene = scenes.block(1.0, 0.5, friction=mu, base_width=40.0)
    r = adapters.simulate(scene, excitation.rectangular_pulse(a_p, t_p), duration=a_p * t_p / (mu * analytical.G) + 0.3,
                          engine=engine, output_dt=1e-3)
    slip = np.max(np.abs(r.relative_x[:, 0] - r.relative_x[0, 0]))
    band = cases.case("newmark").band("max_slip", engine)
    assert slip == pytest.approx(analytical.newmark_max_slip(a_p, t_p, mu), rel=band)


@pytest.mark.slow
@pytest.mark.parametrize("engine", ENGINES + ["dem"])
def test_low_friction_base_isolates_the_column(engine):
    """A sliding isolator at the base (mu = 0.05) stops the rocking and lets the column slide."""
    motion = excitation.record("el_centro_1940", pga=4.0)
    runs = {}
    for mu_base in (None, 0.05):
        scene = scenes.column(4, friction=0.7, interface_friction={("base", "drum1"): mu_base} if mu_base else None)
        runs[mu_base] = adapters.simulate(scene, motion, duration=10.0, engine=engine)
    fixed, isolated = runs[None], runs[0.05]
    assert np.max(isolated.peak_theta) < 0.1 * np.max(fixed.peak_theta)
    # slip at the base: the bottom centre of drum1, which rocking about a corner hardly moves sideways
    half_height = 0.75
    slide = {k: np.max(np.abs(r.relative_x[:, 0] + half_height * np.sin(r.theta[:, 0]) - r.relative_x[0, 0]))
             for k, r in runs.items()}
    assert slide[0.05] > 0.05 and slide[0.05] > 3.0 * slide[None], slide


def test_product_friction_is_exact_at_touching_interfaces_or_refuses():
    scene = scenes.column(4, interface_friction={("base", "drum1"): 0.05})
    pairs = [(i, j) for i, j, _ in scene.touching_pairs()]
    values = product_friction("test", scene, pairs)
    for i, j in pairs:
        a, b = scene.bodies[i].name, scene.bodies[j].name
        assert values[i] * values[j] == pytest.approx(scene.friction(a, b), rel=1e-9)
    loop = scenes.colonnade(3, 2, interface_friction={("c1_drum2", "epistyle"): 0.2})
    with pytest.raises(ValueError, match="multiplies.*interface"):
        product_friction("pybullet", loop, [(i, j) for i, j, _ in loop.touching_pairs()])


def test_pybullet_refuses_friction_it_cannot_represent_and_pymunk_falls_back_to_per_contact():
    loop = scenes.colonnade(3, 2, interface_friction={("c1_drum2", "epistyle"): 0.2})
    with pytest.raises(ValueError, match="pybullet multiplies"):
        adapters.simulate(loop, duration=0.01, engine="pybullet")
    r = adapters.simulate(loop, duration=0.01, engine="pymunk")
    assert r.info["friction"] == "per contact"


@pytest.mark.parametrize("engine", ENGINES)
def test_a_restitution_the_peers_do_not_model_is_refused(engine):
    """The adapters build plastic impacts; a scene asking another restitution is refused, not run without it."""
    bouncing = scenes.block(1.0, 2.0, contact=dem_core.ContactParameters(restitution=0.3))
    with pytest.raises(ValueError, match=f"{engine}: the scene asks a restitution of 0.3"):
        adapters.simulate(bouncing, duration=0.01, engine=engine)


def test_unknown_engine_and_option_are_named():
    with pytest.raises(ValueError, match="unknown engine 'bullet'.*pybullet"):
        adapters.simulate(scenes.block(1, 1), duration=0.1, engine="bullet")
    for engine in ENGINES:
        with pytest.raises(TypeError, match=f"{engine}: unknown option"):
            adapters.simulate(scenes.block(1, 1), duration=0.1, engine=engine, warp_speed=9)


def test_an_engine_that_goes_unstable_is_stopped_with_engine_time_and_block():
    scene = scenes.column(2)
    states = iter([np.array([[0.0, 0.375, 0.0], [0.0, 1.125, 0.0]])] * 3 + [np.array([[0.0, 0.375, 0.0],
                                                                                        [np.nan, 1.125, 0.0]])])
    fake = EngineRun(lambda gx, gy: None, lambda: None, lambda: next(states), {})
    with pytest.raises(dem_core.SimulationUnstable, match=r"fake: unstable at t = 0\.03 s .*block 'drum2'") as info:
        run("fake", scene, None, 1.0, 0.01, 0.01, lambda: fake)
    assert len(info.value.partial.t) == 3


def test_a_rotated_rectangle_is_a_rectangle_and_a_trapezoid_is_not():
    turned = transform(rectangle(0.5, 1.5), 0.3, (2.0, 1.0))
    box = geometry.rectangle(turned)
    assert box is not None and not box.axis_aligned()
    np.testing.assert_allclose(box.half_extents, [0.25, 0.75], rtol=1e-14)
    assert box.angle == pytest.approx(0.3, abs=1e-14)
    np.testing.assert_allclose(box.centre, polygon_properties(turned).centroid, atol=1e-14)
    assert geometry.rectangle([[0.0, 0.0], [2.0, 0.0], [1.5, 1.0], [0.5, 1.0]]) is None
    # the tolerance is relative to the size: a corner 1e-6 rad off square is not a rectangle, 1e-11 rad is
    for skew, expected in ((1e-6, False), (1e-11, True)):
        sheared = np.array([[0.0, 0.0], [1.0, 0.0], [1.0 + 2.0 * skew, 2.0], [2.0 * skew, 2.0]])
        assert (geometry.rectangle(sheared) is not None) is expected
    # listed from a vertical edge, an axis-aligned rectangle still has its x and y half extents
    upright = geometry.rectangle(np.roll(rectangle(0.5, 1.5), -1, axis=0))
    assert upright.axis_aligned()
    np.testing.assert_array_equal(upright.half_extents_on_axes(), [0.25, 0.75])


HEXAGON = np.column_stack([np.cos(np.arange(6) * np.pi / 3), np.sin(np.arange(6) * np.pi / 3)])


@pytest.mark.parametrize("outline", [rectangle(0.5, 1.5), transform(rectangle(0.5, 1.5), 0.3),
                                     np.array([[0.0, 0.0], [2.0, 0.0], [1.5, 1.0], [0.5, 1.0]]), HEXAGON])
def test_the_prism_holds_area_times_depth(outline):
    depth, margin = 0.7, 1e-3
    prism = geometry.prism(outline, depth)
    assert prism.vertices.shape == (2 * len(outline), 3) and prism.faces.shape == (4 * len(outline) - 4, 3)
    assert prism.volume == pytest.approx(polygon_properties(outline).area * depth, rel=1e-12)
    inset = geometry.prism(outline, depth, inset_by=margin)
    assert inset.volume == pytest.approx(polygon_properties(geometry.inset(outline, margin)).area
                                         * (depth - 2 * margin), rel=1e-12)
    assert inset.volume < prism.volume


@pytest.mark.parametrize("builder", ["tilted block", "tapered column with capital", "colonnade b"])
def test_the_start_pose_reproduces_the_blocks(builder):
    scene = BUILDERS[builder]()
    states = geometry.start_states(scene.blocks)
    for blk, state in zip(scene.blocks, states, strict=True):
        pose = geometry.start_pose(blk)
        np.testing.assert_array_equal(state, [*pose.centroid, pose.angle])
        np.testing.assert_allclose(transform(geometry.outline_in_reference(blk), pose.angle, pose.centroid),
                                   blk.vertices, atol=1e-14)
        np.testing.assert_allclose(geometry.outline_at_start(blk) + pose.centroid, blk.vertices, atol=1e-15)
