"""The time step: the stability limit, impact resolution, and what happens past the limit."""

import warnings

import numpy as np
import pytest

import dem_core
from dem_core.engine.model import compile_model
from dem_core import excitation, scenes, stability


def test_explicit_dt_above_the_stability_limit_is_refused():
    scene = scenes.column(4)
    limit = stability.stability_limit(compile_model(scene))
    with pytest.raises(ValueError, match=f"stability limit {limit:.4g}"):
        dem_core.simulate(scene, duration=0.1, dt=1.01 * limit, integrator="explicit")
    assert dem_core.simulate(scene, duration=0.01, dt=0.5 * limit, integrator="explicit").dt == 0.5 * limit


@pytest.mark.parametrize("scene", [scenes.column(8), scenes.block(1.0, 6.0)], ids=["drums", "monolith"])
def test_auto_dt_is_reported_below_the_limit_and_resolves_impacts(scene):
    r = dem_core.simulate(scene, duration=0.01, integrator="explicit")
    limit, impact = r.info["stability_limit_s"], r.info["impact_duration_s"]
    assert r.dt == pytest.approx(min(dem_core.simulation.DEFAULT_SAFETY * limit,
                                     impact / dem_core.simulation.DEFAULT_STEPS_PER_IMPACT))
    assert r.dt < limit
    # impact duration of the stiffest face: pi sqrt(m_eff / (K_n d L))
    masses = [b.mass for b in scene.blocks]
    m_eff = masses[0] / 2 if len(masses) > 1 else masses[0]
    width = min(b.width for b in scene.blocks)
    assert impact == pytest.approx(np.pi * np.sqrt(m_eff / (scene.contact.kn * width)), rel=1e-9)


def test_estimated_limit_is_where_a_resting_colonnade_starts_to_creep():
    """A colonnade at rest settles under gravity (its epistyle is carried by three columns): below the
    estimated limit it stays put to a hundredth of a micrometre; just above it the unstable stiff modes,
    bounded by friction, make it creep ten thousand times more, which no check would notice (hence dt
    above the limit is refused)."""
    scene = scenes.colonnade(3, 3)
    limit = stability.stability_limit(compile_model(scene))
    creep = {}
    for factor in (0.95, 1.05):
        r = _simulate_unchecked(scene, excitation.still(), duration=0.5, dt=factor * limit, output_dt=0.01)
        creep[factor] = np.max(np.abs(r.x - r.x[0]))
    assert creep[0.95] < 1e-8  # measured 1.8e-12 m
    assert creep[1.05] > 1e4 * creep[0.95]  # measured 5.6e-8 m


def _simulate_unchecked(scene, motion, **run):
    """Simulate past the limit, as a stress test may (or as if the estimate were too high), without
    the warning that says so."""
    with warnings.catch_warnings():
        warnings.filterwarnings("ignore", "dt = .* times the stability limit", RuntimeWarning)
        return dem_core.simulate(scene, motion, enforce_stability_limit=False, **run, integrator="explicit")


def test_safety_above_one_is_refused():
    with pytest.raises(ValueError, match="safety"):
        dem_core.simulate(scenes.column(2), duration=0.1, safety=1.5, integrator="explicit")


def test_run_that_loses_stability_stops_with_time_and_partial_result():
    scene = scenes.column(8)
    motion = excitation.record("el_centro_1940", pga=6.0)
    with pytest.raises(dem_core.SimulationUnstable, match=r"stopped at t = [0-9.]+ s .*dt = ") as info:
        _simulate_unchecked(scene, motion, duration=3.0, dt=2.5 * stability.stability_limit(compile_model(scene)),
                            output_dt=1e-4)
    partial = info.value.partial
    assert partial is not None and len(partial.t) > 1
    assert np.all(np.isfinite(partial.theta))
    assert partial.t[-1] < 3.0


def test_broad_phase_passes_only_pairs_that_can_touch():
    """A stack of drums touches only its neighbours: the exact overlap is computed for those pairs alone."""
    r = dem_core.simulate(scenes.column(8), excitation.sine_pulse(2.0, 0.3), duration=0.5, integrator="explicit")
    # 7 drum joints and the base, a joint at the top opening now and then (measured 7.93)
    assert 7.5 < r.info["narrow_phase_per_step"] <= 8.0


@pytest.mark.slow
@pytest.mark.parametrize("law", ["corner", "overlap_area"])
@pytest.mark.parametrize("make_scene", [
    lambda c: scenes.block(1.0, 6.0, contact=c), lambda c: scenes.column(8, contact=c),
    lambda c: scenes.colonnade(3, 3, contact=c), lambda c: scenes.two_tier_colonnade(contact=c),
    lambda c: scenes.stack([(2.5, 2.5), (2.0, 5.0)], tilt=0.1, contact=c),
    lambda c: scenes.column(4, taper=0.3, capital=(1.4, 0.5), contact=c),
], ids=["block", "column", "colonnade", "two-tier", "stack", "tapered"])
def test_fast_limits_against_the_amplification_matrix(make_scene, law):
    """The energy criterion (the default up to 100 blocks) is the amplification matrix's limit to its
    bisection tolerance; the linear-time bound (the default above) is below it, by at most twice (measured 1.0 to
    1.93, the two-tier colonnade the loosest: the heavier the dashpots, the looser)."""
    scene = make_scene(dem_core.ContactParameters(law=law))
    exact = stability.stability_limit(compile_model(scene), method="amplification")
    assert stability.stability_limit(compile_model(scene), method="energy") == pytest.approx(exact, rel=2e-3)
    bound = stability.stability_limit(compile_model(scene), method="bound")
    assert exact / 2.0 < bound < exact * (1 + 2e-3)
