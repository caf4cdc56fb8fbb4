"""Sliding of a squat block against Newmark's pulse and the exact rigid-plastic integration (docs/method.md 4.4, 4.5, 4.8).

The bands are those the cases of comparisons/cases/catalogue.py declare for the native core ("dem").
"""

import numpy as np
import pytest

import dem_core
from comparisons.cases import catalogue as cases
from comparisons.references import analytical
from dem_core.engine.model import compile_model
from dem_core import excitation, thresholds

NEWMARK_BAND = cases.case("newmark").band("max_slip", "dem")
RECORD_SLIDING = cases.case("record_sliding")
#: the largest slip's band also bounds the total slip, which the cases do not measure
RECORD_BAND = RECORD_SLIDING.band("max_slip", "dem")
G = analytical.G
squat_block = cases.sliding_block


def slip_history(result):
    return result.relative_x[:, 0] - result.relative_x[0, 0]


@pytest.mark.parametrize("ratio", [1.25, 1.5, 2.0, 3.0, 4.0])
def test_newmark_rectangular_pulse_slip(ratio):
    mu, t_p = 0.3, 0.3
    a_p = ratio * mu * G
    reference = analytical.newmark_max_slip(a_p, t_p, mu)
    stop = a_p * t_p / (mu * G)  # the slip stops when the relative velocity returns to zero
    result = dem_core.simulate(squat_block(mu), excitation.rectangular_pulse(a_p, t_p), duration=stop + 0.3,
                               output_dt=1e-3, integrator="explicit")
    assert np.max(np.abs(slip_history(result))) == pytest.approx(reference, rel=NEWMARK_BAND)


def test_newmark_slip_is_self_similar():
    """u_max / (a_p T_p^2) depends only on a_p / (mu g)."""
    values = []
    for mu, t_p in ((0.2, 0.2), (0.5, 0.4)):
        a_p = 2.0 * mu * G
        result = dem_core.simulate(squat_block(mu), excitation.rectangular_pulse(a_p, t_p), duration=3 * t_p,
                                   output_dt=1e-3, integrator="explicit")
        values.append(np.max(np.abs(slip_history(result))) / (a_p * t_p**2))
    assert values[0] == pytest.approx(values[1], rel=2e-3)
    assert values[0] == pytest.approx(0.5 * (2.0 - 1.0), rel=NEWMARK_BAND)


@pytest.fixture(scope="module")
def record_sliding():
    mu, duration = 0.1, 35.0
    motion = excitation.record("el_centro_1940")
    result = dem_core.simulate(squat_block(mu), motion, duration=duration, output_dt=0.005, integrator="explicit")
    reference = analytical.rigid_plastic_sliding(motion.horizontal.samples, motion.horizontal.dt, mu,
                                                 t_end=duration)
    return result, reference


def test_sliding_under_the_bundled_record_matches_the_rigid_plastic_reference(record_sliding):
    result, reference = record_sliding
    slip = slip_history(result)
    assert reference.max_slip > 0.01  # the case does slide
    assert np.max(np.abs(slip)) == pytest.approx(reference.max_slip, rel=RECORD_BAND)
    # the residual is a small difference of large excursions (4.8 mm after 110 mm of sliding back and
    # forth): judge it on the scale of the motion
    assert abs(slip[-1] - reference.residual) < RECORD_SLIDING.band("residual_slip", "dem") * reference.max_slip
    assert result.total_sliding == pytest.approx(reference.total_slip, rel=RECORD_BAND)
    on_reference_grid = np.interp(reference.t, result.t, slip)
    rms = np.sqrt(np.mean((on_reference_grid - reference.u) ** 2))
    assert rms < RECORD_SLIDING.band("rms_slip", "dem") * reference.max_slip


@pytest.mark.parametrize("vertical", [False, True], ids=["horizontal", "with vertical"])
def test_sliding_under_horizontal_and_vertical_motion(vertical):
    """The vertical component changes the friction capacity, mu (g + a_v): the slip follows it."""
    mu, duration = 0.1, 60.0
    motion = excitation.record("mexico_city_1985", vertical=vertical or None, pga=2.5)
    reference = analytical.rigid_plastic_sliding(
        motion.horizontal.samples, motion.horizontal.dt, mu, t_end=duration,
        vertical=motion.vertical.samples if vertical else None)
    result = dem_core.simulate(squat_block(mu), motion, duration=duration, output_dt=0.01, integrator="explicit")
    slip = slip_history(result)
    assert np.max(np.abs(slip)) == pytest.approx(reference.max_slip, rel=RECORD_BAND)
    assert result.total_sliding == pytest.approx(reference.total_slip, rel=RECORD_BAND)
    assert abs(slip[-1] - reference.residual) < RECORD_SLIDING.band("residual_slip", "dem") * reference.max_slip


def test_sliding_converges_as_dt_shrinks():
    """The slip under a pulse converges as dt is refined below the automatic step (the converged
    value differs from Newmark's rigid-plastic one by the contact's own stick-slip, 6e-4 relative)."""
    mu, t_p = 0.3, 0.3
    a_p = 1.5 * mu * G
    scene = squat_block(mu)
    limit = dem_core.stability.stability_limit(compile_model(scene))

    def max_slip(dt):
        result = dem_core.simulate(scene, excitation.rectangular_pulse(a_p, t_p), duration=0.8, dt=dt, output_dt=dt,
                                   integrator="explicit")
        return np.max(np.abs(slip_history(result)))

    converged = max_slip(0.9 * limit / 64)
    errors = [abs(max_slip(0.9 * limit / f) / converged - 1.0) for f in (1, 4, 16)]
    assert errors[0] > errors[1] > errors[2]  # measured 1.1e-3, 4.9e-4, 3.0e-5
    assert errors[0] < 2e-3
    assert abs(converged / analytical.newmark_max_slip(a_p, t_p, mu) - 1.0) < NEWMARK_BAND


@pytest.mark.parametrize("mu", [0.3, 0.6])
def test_block_on_an_incline_slides_only_beyond_the_friction_angle(mu):
    """docs/method.md 4.8.  A slope beta is a steady ground acceleration g tan(beta) (the tilted gravity);
    it is reached by a slow ramp so that no transient overshoots."""
    for factor in (0.95, 1.05):
        slope = np.arctan(factor * mu)
        a_hold = G * np.tan(slope)
        motion = excitation.ramp(a_hold / 1.0, peak=a_hold)
        result = dem_core.simulate(squat_block(mu), motion, duration=3.0, output_dt=1e-3, integrator="explicit")
        slid = np.max(np.abs(slip_history(result))) > 1e-3
        assert slid == analytical.slides_on_incline(slope, mu), (mu, factor)


@pytest.mark.parametrize("name, expected", [("slide_rock_below", "rocking"), ("slide_rock_above", "slide-rock")])
def test_pulse_starts_rocking_or_slide_rock_as_zhang_makris_predict(name, expected):
    """The cases sit SLIDE_ROCK_MARGIN (12%) below and above the threshold: the soft contact lets the corner
    slip a little later than the rigid criterion (measured between 1.05 and 1.08 times it)."""
    case = cases.case(name)
    assert case.reference() == expected
    result = dem_core.simulate(case.scene(), case.motion(), duration=case.duration, output_dt=1e-3,
                               integrator="explicit")
    assert thresholds.motion_mode(case.scene(), result, slip=cases.SLIDE_ROCK_SLIP) == expected
    assert case.within_band("mode_mismatch", "dem", case.errors(result, case.reference())["mode_mismatch"])
