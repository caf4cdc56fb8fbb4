"""Two stacked blocks released from a tilt (Psycharis 1990, docs/method.md 4.7): the rigid reference and the core."""

import numpy as np
import pytest

import dem_core
from comparisons.cases import catalogue as cases
from comparisons.cases.catalogue import STACK_SIZES, STACK_THETA0
from comparisons.cases.measures import first_zero_crossing
from comparisons.references import analytical
from comparisons.references.stacked_rocking import TwoBlockStack, stack_response
from dem_core import excitation, scenes
from dem_core.engine.contact import ContactParameters

# The corner law: the upper block tips about the lower block's corner itself, as the rigid stack does
# (measured +0.018% at the default K_n, +0.023% at 100 x K_n); the band is the case's.
IMPACT_BAND = cases.case("stacked_blocks").band("impact_time", "dem")
STIFFNESS_FACTORS = (1.0, pytest.param(100.0, marks=pytest.mark.slow))


@pytest.fixture(scope="module")
def stack():
    (w1, h1), (w2, h2) = STACK_SIZES
    return TwoBlockStack(w1 / 2, h1 / 2, w2 / 2, h2 / 2)


@pytest.fixture(scope="module")
def reference(stack):
    return stack_response(stack, STACK_THETA0, 5.0)


def test_reference_conserves_energy_through_its_mode_change(stack, reference):
    assert [m for _, m in reference.modes] == ["locked", "both"]
    energy = np.array([stack.energy(*s) for s in zip(reference.theta1, reference.theta2, reference.omega1,
                                                       reference.omega2, reference.pivot1, reference.pivot2)])
    assert np.ptp(energy) < 1e-9 * abs(energy[0])


def test_reference_keeps_its_pivots_through_theta_zero(stack, reference):
    """At the ground impact theta1 is zero give or take round-off; the corners are state, so the energy
    there does not depend on which side of zero the round-off fell."""
    assert reference.impact == "ground" and abs(reference.theta1[-1]) < 1e-12
    last = (reference.theta2[-1], reference.omega1[-1], reference.omega2[-1], reference.pivot1[-1],
            reference.pivot2[-1])
    at_zero = [stack.energy(theta1, *last) for theta1 in (-1e-17, 0.0, 1e-17)]
    np.testing.assert_allclose(at_zero, at_zero[1], rtol=1e-14)
    # and the corner is the one it rocked on since the release, not the one the sign of theta1 suggests
    assert set(reference.pivot1) == {1}


def test_mirror_image_release_mirrors_the_reference(stack, reference):
    mirror = stack_response(stack, -STACK_THETA0, 5.0)
    assert mirror.impact_time == pytest.approx(reference.impact_time, rel=1e-12)
    assert set(mirror.pivot1) == {-1} and mirror.pivot2[-1] == -reference.pivot2[-1]
    np.testing.assert_allclose(mirror.theta2[-1], -reference.theta2[-1], rtol=1e-9)


@pytest.mark.slow
def test_reference_of_equal_widths_is_one_rocking_block():
    stack = TwoBlockStack(1.25, 1.25, 1.25, 2.5)
    history = stack_response(stack, 0.1, 2.0)
    block = analytical.RockingBlock(1.25, 3.75)
    exact = analytical.rocking_response(block, lambda t: 0.0, 2.0, theta0=0.1, max_step=1e-4)
    assert [m for _, m in history.modes] == ["locked"]
    assert history.impact_time == pytest.approx(exact.impacts[0], rel=1e-6)


def _impact_error(reference, factor):
    contact = dem_core.contact.stiffer(ContactParameters(), factor)
    scene = scenes.stack(STACK_SIZES, tilt=STACK_THETA0, contact=contact)
    result = dem_core.simulate(scene, excitation.still(), duration=0.8, output_dt=1e-4, integrator="explicit")
    return first_zero_crossing(result.t, result.theta[:, 0]) / reference.impact_time - 1.0, result


@pytest.mark.parametrize("factor", STIFFNESS_FACTORS)
def test_first_impact_comes_when_the_rigid_stack_says(reference, factor):
    error, result = _impact_error(reference, factor)
    assert abs(error) < IMPACT_BAND
    # the upper block tipped on its own before the impact, as the reference's mode change says
    assert np.max(np.abs(result.theta[:, 1] - result.theta[:, 0])) > 1e-3


def test_stack_rocks_without_sliding(reference):
    _, result = _impact_error(reference, 1.0)
    # the lower block's pivot corner stays where it was up to the impact
    before = result.t <= 0.95 * reference.impact_time
    theta = result.theta[before, 0]
    corner_x = result.x[before, 0] - 1.25 * np.cos(theta) + 1.25 * np.sin(theta)
    assert np.ptp(corner_x) < 1e-5
    assert np.all(result.theta[before, 1] - result.theta[before, 0] >= -1e-4)  # the upper block tips to the left
