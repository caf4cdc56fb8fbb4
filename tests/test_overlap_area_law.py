"""The thesis' overlap-area law (``ContactParameters(law="overlap_area")``): what it gets right, and its
known biases, each tied to its cause.

Its force acts at the overlap's centroid, a third of a triangular overlap's length inside the corner, so
a block resists overturning with a shortened lever: rocking starts early by a bias that shrinks like
K_n^(-1/3).  Its rocking dashpot couple is calibrated against Housner's decay at the default stiffness
(``HOUSNER_DAMPING``), so free rocking is right there by construction.  Checks that are cases of
comparisons/cases/catalogue.py take their bands from the case's declaration for "dem-overlap".
"""

import warnings

import numpy as np
import pytest

import dem_core
from comparisons.cases import catalogue as cases
from comparisons.cases.catalogue import HOUSNER_HEIGHT, HOUSNER_WIDTH, STACK_SIZES, STACK_THETA0
from comparisons.cases.measures import first_exceedance, first_zero_crossing
from comparisons.references import analytical
from comparisons.references.stacked_rocking import TwoBlockStack, stack_response
from dem_core.engine.model import compile_model
from dem_core import excitation, scenes, stability
from dem_core.engine.contact import damping_ratio_for_restitution

ENGINE = "dem-overlap"
#: the stacked-block impact at 100 x K_n: measured -2.0%, the K_n^(-1/3) bias with a little to spare
STIFF_STACK_IMPACT_BAND = 0.03


def overlap_law(**kwargs):
    return dem_core.ContactParameters(law="overlap_area", **kwargs)


def test_free_rocking_matches_housner_at_the_calibrated_stiffness():
    """Against the rocking equation with Housner's impact rule: the quarter period and the peaks after five
    impacts (the calibration's own accuracy)."""
    case = cases.case("free_rocking")
    result = dem_core.simulate(case.scene().replace(contact=overlap_law()), duration=case.duration, output_dt=1e-9)
    errors = case.errors(result, case.reference())
    for metric in ("quarter_period", "peak_decay"):
        assert case.within_band(metric, ENGINE, errors[metric]), (metric, errors[metric])


def test_rocking_damping_follows_the_calibrated_slenderness_law():
    scene = cases.housner_scene(contact=overlap_law())
    alpha = np.arctan2(HOUSNER_WIDTH, HOUSNER_HEIGHT)
    assert scene.rocking_slenderness == pytest.approx(alpha)
    zeta_r = dem_core.contact.rocking_damping_ratio(scene)
    assert zeta_r == pytest.approx(dem_core.contact.housner_damping_ratio(alpha))
    assert dem_core.contact.rocking_damping_ratio(cases.housner_scene()) == 0.0  # the corner law has no couple


@pytest.mark.parametrize("name", ["sine_pulse", "sine_pulse_strong"])
def test_one_sine_pulse_peak_matches_the_rocking_equation(name):
    case = cases.case(name)
    result = dem_core.simulate(case.scene().replace(contact=overlap_law()), case.motion(), duration=case.duration,
                               output_dt=1e-3)
    assert result.peak_theta[0] == pytest.approx(case.reference().peak, rel=case.band("peak_rotation", ENGINE))


def _ramp_onset(kn):
    scene = scenes.block(cases.ONSET_WIDTH, cases.ONSET_HEIGHT, contact=overlap_law(kn=kn))
    result = dem_core.simulate(scene, excitation.ramp(cases.ONSET_RAMP_RATE), duration=4.5, output_dt=1e-3)
    return cases.ONSET_RAMP_RATE * first_exceedance(result.t, result.theta[:, 0],
                                                    scene.blocks[0].critical_angle / 30.0)


def test_early_rocking_onset_shrinks_like_the_cube_root_of_the_stiffness():
    """Each 8-fold stiffening halves the bias: the overlap's centroid sits l/3 inside the corner."""
    block = analytical.RockingBlock.from_size(cases.ONSET_WIDTH, cases.ONSET_HEIGHT)
    ode = analytical.rocking_response(block, lambda t: cases.ONSET_RAMP_RATE * t, 6.0, max_step=1e-3)
    rigid = cases.ONSET_RAMP_RATE * first_exceedance(ode.t, ode.theta, block.alpha / 30.0)
    bias = [_ramp_onset(kn) / rigid - 1.0 for kn in (2e10, 1.6e11)]
    assert -cases.case("onset_ramp").band("onset_acceleration", ENGINE) < bias[0] < bias[1] < 0.0  # measured -8.9%
    assert bias[0] / bias[1] == pytest.approx(2.0, rel=0.2)  # measured 2.03


def test_stacked_blocks_reach_the_rigid_impact_as_the_contact_stiffens():
    """Psycharis' stack: the upper block's resultant starts 0.7% of its half width inside its edge, so a
    compliant joint opens at once; measured -9.0%, -4.6%, -2.0% at K_n = 2e10, 2e11, 2e12."""
    (w1, h1), (w2, h2) = STACK_SIZES
    reference = stack_response(TwoBlockStack(w1 / 2, h1 / 2, w2 / 2, h2 / 2), STACK_THETA0, 5.0)
    errors = []
    for kn in (2e10, 2e11, 2e12):
        scene = scenes.stack(STACK_SIZES, tilt=STACK_THETA0, contact=overlap_law(kn=kn))
        result = dem_core.simulate(scene, excitation.still(), duration=0.8, output_dt=1e-4)
        errors.append(abs(first_zero_crossing(result.t, result.theta[:, 0]) / reference.impact_time - 1.0))
    assert cases.case("stacked_blocks").within_band("impact_time", ENGINE, errors[0])
    assert errors[2] < STIFF_STACK_IMPACT_BAND
    assert errors[0] > 1.6 * errors[1] > 1.6 ** 2 * errors[2]


@pytest.mark.parametrize("e", [0.3, 0.6, 0.8])
def test_a_block_dropped_flat_rebounds_with_the_target_restitution(e):
    """A flat face contact is a linear spring-dashpot (F = K_n d L delta): the mapping must hold in the simulation."""
    zeta = damping_ratio_for_restitution(e)
    resting = scenes.block(1.0, 0.5)
    dropped = dem_core.Block("block", resting.blocks[0].vertices + [0.0, 0.002])
    scene = resting.replace(blocks=(dropped,), contact=overlap_law(damping_ratio=zeta))
    # the contact lasts pi / omega_0 ~ 0.8 ms: resolve it with a step well below the automatic one
    dt = stability.stability_limit(compile_model(scene)) / 40.0
    result = dem_core.simulate(scene, duration=0.03, dt=dt, output_dt=dt, stop_at_overturn=False)
    gap = result.y[:, 0] - 0.25
    velocity = np.diff(result.y[:, 0]) / dt
    enter = np.argmax(gap < 0.0)
    leave = enter + np.argmax(gap[enter:] > 0.0)
    # gravity keeps pulling during the ~1 ms contact: it takes about 0.01 m/s off a 0.2 m/s rebound
    assert velocity[leave] / -velocity[enter - 1] == pytest.approx(e, abs=0.03)  # measured 0.282, 0.593, 0.797


def test_mirrored_runs_stay_mirror_images_up_to_the_stability_limit():
    """Up to the estimated limit a mirrored ground motion gives the mirrored response to round-off; past
    it the scheme goes unstable, which first shows as a loss of that symmetry (friction bounds the growth,
    so it would pass unnoticed: hence dt above the limit is refused)."""
    scene = scenes.block(1.0, 6.0, contact=overlap_law())
    limit = stability.stability_limit(compile_model(scene))
    for dt, symmetric in ((limit, True), (1.3 * limit, False)):
        run = {"duration": 0.6, "output_dt": 1e-3, "dt": dt, "enforce_stability_limit": False}
        with warnings.catch_warnings(record=True) as said:
            warnings.simplefilter("always")
            a = dem_core.simulate(scene, excitation.sine_pulse(3.0, 0.4), **run)
            b = dem_core.simulate(scene, excitation.sine_pulse(-3.0, 0.4), **run)
        past = [w for w in said if "times the stability limit" in str(w.message)]
        assert len(past) == (0 if symmetric else 2)  # a run past the limit says so when it starts
        asymmetry = np.max(np.abs(a.theta + b.theta)) / np.max(np.abs(a.theta))
        assert (asymmetry < 1e-9) == symmetric, (dt / limit, asymmetry)
