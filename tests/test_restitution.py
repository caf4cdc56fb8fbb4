"""Impacts the user chooses: Newton's coefficient of a point impact, the same parameter in both integrators
(docs/method.md 1.8), against the rigid closed forms of a single-point, a rocking and a two-point impact."""

import dataclasses

import numpy as np
import pytest

import dem_core
from comparisons.benchmarks.restitution import joint_slips
from dem_core import scenes, stability
from dem_core.engine.contact import EXPLICIT_LEAST_RESTITUTION
from dem_core.engine.geometry import rectangle, transform
from dem_core.engine.model import compile_model

#: Moreau-Jean's step in these tests, fine enough to time a rebound (s)
MOREAU_STEP = 1e-5
#: the explicit core's step as a fraction of its stability limit, to resolve a ~1 ms contact finely
EXPLICIT_FRACTION = 0.025


def run_fine(scene, integrator: str, duration: float):
    """``scene`` run for ``duration`` s with an output every step."""
    if integrator == "moreau":
        dt = MOREAU_STEP
    else:
        dt = EXPLICIT_FRACTION * stability.stability_limit(compile_model(scene))
    return dem_core.simulate(scene, None, duration, dt=dt, output_dt=dt, integrator=integrator,
                             stop_at_overturn=False)


def lifted(scene, height: float):
    """``scene`` with every block raised ``height`` m, free to fall."""
    blocks = [dataclasses.replace(b, vertices=b.vertices + [0.0, height]) for b in scene.blocks]
    return dataclasses.replace(scene, blocks=blocks, allow_free_blocks=True)


def rebounds(y: np.ndarray, t: np.ndarray) -> np.ndarray:
    """(n_blocks,) the largest upward speed of each block after the first block's fastest fall, over the fastest
    fall's speed."""
    v = np.diff(y, axis=0) / np.diff(t)[:, None]
    hit = int(np.argmin(v[:, 0]))
    return v[hit:].max(axis=0) / -v[hit, 0]


@pytest.mark.parametrize("integrator, e", [("moreau", 0.0), ("moreau", 0.1), ("moreau", 0.5), ("explicit", 0.0),
                                           ("explicit", 0.1), ("explicit", 0.5)])
def test_a_corner_impact_rebounds_with_the_restitution_asked(integrator, e):
    """A square dropped onto the corner right below its centre of mass meets the base at one point, whose
    effective mass is the block's: it rebounds at e times the speed it landed with, in either integrator (the
    explicit core at its least restitution where a plastic impact is asked)."""
    corner_up = np.sqrt(0.5)
    diamond = dem_core.Block("block", transform(rectangle(1.0, 1.0, -0.5, -0.5), np.pi / 4, (0.0, corner_up)),
                             angle=np.pi / 4)
    scene = scenes.block(1.0, 1.0).replace(blocks=(diamond,), contact=dem_core.ContactParameters(restitution=e),
                                           allow_free_blocks=True)
    result = run_fine(lifted(scene, 0.01), integrator, 0.1)
    given = e if integrator == "moreau" else max(e, EXPLICIT_LEAST_RESTITUTION)
    assert rebounds(result.y, result.t)[0] == pytest.approx(given, abs=0.002)  # measured within 0.0013


@pytest.mark.parametrize("integrator, e", [("moreau", 0.0), ("moreau", 0.2), ("moreau", 0.5), ("explicit", 0.0)])
def test_a_rocking_impact_keeps_the_rigid_share_of_its_angular_velocity(integrator, e):
    """A rigid block rocking onto its other corner, which rebounds by Newton's law while the first corner lifts,
    keeps its angular momentum about the new corner: ``omega+ / omega- = 1 - 1.5 (1 + e) sin^2(alpha)``, Housner's
    rule for ``e = 0``.  Angular velocities from straight-line fits over 5 ms before and 3 ms after the impact
    (the impacting corner's flight lasts longer); the explicit core at its least restitution, where the rule with
    that restitution holds within 5e-4 (measured 3.2e-4; Moreau-Jean within 5e-5)."""
    width, height = 1.0, 6.0
    sin2 = width**2 / (width**2 + height**2)
    scene = scenes.block(width, height, tilt=0.1, contact=dem_core.ContactParameters(restitution=e))
    result = run_fine(scene, integrator, 1.2)
    t, theta = result.t, result.theta[:, 0]
    impact = t[np.argmax(theta <= 0.0)]
    omega = np.gradient(theta, t)
    before = (t > impact - 0.006) & (t < impact - 0.001)
    after = (t > impact + 0.002) & (t < impact + 0.005)
    ratio = (np.polyval(np.polyfit(t[after], omega[after], 1), impact)
             / np.polyval(np.polyfit(t[before], omega[before], 1), impact))
    given, band = (e, 2e-4) if integrator == "moreau" else (max(e, EXPLICIT_LEAST_RESTITUTION), 5e-4)
    assert ratio == pytest.approx(1.0 - 1.5 * (1.0 + given) * sin2, abs=band)


def test_a_flat_drop_on_two_points_rebounds_by_newtons_law_in_moreau_jean():
    """Two drums dropped flat land on two points each at once: Moreau-Jean's impact law, simultaneous at every
    point, sends both up at e times their speed with the joint shut, the rigid answer."""
    e = 0.2
    result = run_fine(lifted(scenes.stack(((1.0, 0.75), (1.0, 0.75)),
                                          contact=dem_core.ContactParameters(restitution=e)), 0.005), "moreau", 0.05)
    np.testing.assert_allclose(rebounds(result.y, result.t), e, atol=0.002)


def test_the_explicit_cores_two_drums_rebound_falls_towards_the_rigid_answer_with_e():
    """The same drop in the explicit core: its contacts are springs, so the impact runs up the stack as a wave and
    the upper drum leaves faster than the lower, unlike the rigid answer (both at e): measured 2.5 e and 1.4 e at
    e = 0.2, 3.1 e and 1.7 e at 0.1, 3.7 e and 2.0 e at 0.05.  Both fall with e, towards the rigid answer of a
    plastic impact that the explicit core's dashpots cannot give."""
    upper = []
    for e in (0.2, 0.1, 0.05):
        drums = scenes.stack(((1.0, 0.75), (1.0, 0.75)), contact=dem_core.ContactParameters(restitution=e))
        result = run_fine(lifted(drums, 0.005), "explicit", 0.05)
        lower, top = rebounds(result.y, result.t)
        assert e < lower < top < 4.0 * e
        upper.append(top)
    assert upper[0] > upper[1] > upper[2]


def test_the_explicit_core_refuses_a_restitution_below_its_least():
    scene = scenes.block(1.0, 2.0, contact=dem_core.ContactParameters(restitution=0.5 * EXPLICIT_LEAST_RESTITUTION))
    with pytest.raises(ValueError, match="the explicit core's dashpots give at least"):
        dem_core.simulate(scene, None, 0.01, integrator="explicit")
    dem_core.simulate(scene, None, 0.01, integrator="moreau")


@pytest.mark.slow
@pytest.mark.filterwarnings("ignore:a long run")  # a hundred times K_n: 2.2e7 steps, said and meant
def test_the_explicit_cores_joint_slips_converge_in_stiffness_at_a_plastic_impact():
    """The bundled default (the 8-drum column under 20 s of El Centro) with plastic impacts asked, so at the
    explicit core's least restitution: every joint's slip at ten times K_n within a tenth of the largest joint's at a
    hundred times (docs/method.md 1.8 gives the figures)."""
    slips = {factor: np.array(joint_slips(dem_core.contact.stiffer(dem_core.ContactParameters(), factor), "explicit",
                                          20.0)[1]) for factor in (10.0, 100.0)}
    assert np.max(np.abs(slips[10.0] - slips[100.0])) <= 0.1 * np.max(slips[100.0])
