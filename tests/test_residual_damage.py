"""What a run leaves (dem_core.analyses.damage): residual dislocation and tilt against sliding blocks whose slip has
a closed form, and residual damage states in a fragility study."""

import math
import warnings

import numpy as np
import pytest

from dem_core import scenes, simulate
from dem_core.analyses.damage import residual_dislocation, residual_tilt, still_at_end
from dem_core.analyses.fragility_study import RESIDUAL_REST, STILL_SPEED, fragility_study, state_label, stripes
from dem_core.inputs.excitation import extended, record, rectangular_pulse, scaled, strong_motion
from dem_core.inputs.scene import STANDARD_GRAVITY

G = STANDARD_GRAVITY
#: a rigid block's slip under a rectangular pulse a_p of T_p on friction mu (Newmark; docs/method.md 4.4)
PULSE, LENGTH = 1.0, 0.2  # m/s^2, s


def newmark_slip(a_p: float, t_p: float, mu: float) -> float:
    return a_p * t_p ** 2 / 2.0 * (a_p / (mu * G) - 1.0)


def test_a_sliding_blocks_residual_dislocation_is_its_slip():
    """A squat block (1 x 0.5 m: it rocks only above 2 g) on friction 0.3 under 4 m/s^2 for 0.3 s slides and
    stops at 0.41 s: it is left the closed-form slip from where it stood (within 0.1%: the pulse's ends fall on
    Moreau-Jean's 1e-3 s steps), with no tilt; mid-slide it is not at rest."""
    scene = scenes.block(1.0, 0.5, friction=0.3)
    motion = rectangular_pulse(4.0, 0.3)
    done = simulate(scene, motion, duration=1.0, integrator="moreau")
    assert residual_dislocation(scene, done) == pytest.approx(newmark_slip(4.0, 0.3, 0.3), rel=1e-3)
    assert residual_tilt(done) < 1e-6 and still_at_end(done, STILL_SPEED)
    assert not still_at_end(simulate(scene, motion, duration=0.35, integrator="moreau"), STILL_SPEED)


def test_a_drum_that_slides_on_the_one_below_leaves_its_dislocation_and_the_lean_it_makes():
    """A 2-drum column (1 x 1 m) whose joint has friction 0.05 and its base 0.7: under 1 m/s^2 for 0.2 s the lower
    drum moves with the ground and the upper one slides the closed-form slip over it; the line through their
    centres, 0.5 m apart, then leans by atan(slip / 0.5)."""
    scene = scenes.column(2, width=1.0, height=1.0, friction=0.7, interface_friction={("drum1", "drum2"): 0.05})
    done = simulate(scene, rectangular_pulse(PULSE, LENGTH), duration=1.5, integrator="moreau")
    slip = newmark_slip(PULSE, LENGTH, 0.05)
    assert residual_dislocation(scene, done) == pytest.approx(slip, rel=1e-3)
    assert residual_tilt(done) == pytest.approx(math.atan(slip / 0.5), rel=1e-3)
    assert still_at_end(done, STILL_SPEED)


def test_a_motion_extended_past_its_end_is_the_ground_at_rest():
    motion = scaled(record("kalamata_1986"), 2.0)
    longer = extended(motion, 5.0)
    assert longer.end_time == pytest.approx(motion.end_time + 5.0) and longer.name == motion.name
    assert strong_motion(longer.horizontal) == strong_motion(motion.horizontal)
    t = np.linspace(0.0, longer.end_time, 4001)
    np.testing.assert_array_equal(longer.horizontal.acceleration(t), motion.horizontal.acceleration(t))
    after = t[t > motion.end_time]
    assert np.max(np.abs(longer.horizontal.velocity(after))) < 1e-12  # baseline-corrected: at rest
    assert extended(motion, 0.0) is motion
    with pytest.raises(ValueError, match="at least 0"):
        extended(motion, -1.0)


def test_residual_states_are_fitted_each_measure_together_after_a_rest():
    """A block under pulses: the peak states and each residual measure's states fitted as families, none crossing
    another of its family; every run given RESIDUAL_REST s at rest after its pulse."""
    block = scenes.block(0.6, 3.0)
    records = {f"pulse {t:g} s": rectangular_pulse(1.0, t) for t in (0.3, 0.5, 0.8)}
    with warnings.catch_warnings():
        warnings.simplefilter("ignore", RuntimeWarning)
        study = fragility_study(block, records, stripes(6, 12.0), (0.5, 1.0), integrator="moreau", samples=50,
                                residual={"dislocation": (20.0, 1.0), "tilt": (0.01,)})
    table = study.table()
    assert list(zip(table["measure"], table["state"])) == [("peak", 0.5), ("peak", 1.0), ("dislocation", 1.0),
                                                          ("dislocation", 20.0), ("tilt", 0.01)]
    assert study.settings["rest"] == RESIDUAL_REST
    fell = study.runs["overturned"].astype(bool).to_numpy()
    lasted = (study.runs["dt_s"] * study.runs["steps"]).to_numpy()
    assert np.allclose(lasted[~fell], np.array([t + RESIDUAL_REST for t in (0.3, 0.5, 0.8)] * 6)[~fell], atol=2e-3)
    assert 0 < fell.sum() < len(fell)  # runs stop where they overturn
    assert state_label(("dislocation", 20.0)) == "residual dislocation >= 20 mm"
    for measure in ("peak", "dislocation"):
        family = table[table["measure"] == measure]
        placed = family[np.isfinite(family["median"])]
        assert placed["median"].is_monotonic_increasing and placed["beta"].nunique() <= 1
    assert study.runs.loc[fell, "residual_dislocation_mm"].isna().all()


@pytest.mark.parametrize(("options", "said"), [
    ({"residual": {"drift": (1.0,)}}, "residual states are set on dislocation or tilt"),
    ({"residual": {"tilt": (-0.1,)}}, "residual tilt states must be positive thresholds in rad"),
    ({"residual": {"tilt": True}}, "residual tilt states must be positive thresholds in rad, got True"),
    ({"residual": {"dislocation": (5.0, True)}}, r"must be positive thresholds in mm, got \(5.0, True\)"),
    ({"residual": {"tilt": [0.01] * 40 + [-1.0]}}, r"in rad, got -1\.0 in \[0\.01, 0\.01, [0-9., ]{40,50}\.\.\.$"),
    ({"residual": {"tilt": (0.01,)}, "duration": 1.0}, "follows each whole record: give no duration"),
    ({"rest": -1.0}, "rest must be a finite number of seconds"),
])
def test_bad_residual_states_are_refused_naming_them(options, said):
    with warnings.catch_warnings(), pytest.raises(ValueError, match=said):
        warnings.simplefilter("ignore", RuntimeWarning)
        fragility_study(scenes.block(0.6, 3.0), {"p": rectangular_pulse(2.0, 0.5)}, [1.0, 2.0], **options)
