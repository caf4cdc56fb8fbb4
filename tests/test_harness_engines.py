"""The harness's runs of many members (:func:`comparisons.harness.engines.simulate_members`): the native core's members,
batched on the CPU's threads, are the runs :func:`~comparisons.harness.engines.simulate` gives one by one, bit for bit
(rotation histories, status and step), under either integrator; another engine's runs pass through one by one."""

import numpy as np
import pytest

import dem_core

from comparisons.cases.strong_motion import strong_motion
from comparisons.harness import engines
from comparisons.harness.ensembles import ensemble
from dem_core import excitation, scenes

#: the quick rocking ensemble's 1 x 6 m monolith under El Centro at 1.2 and 3 g tan(alpha) (rocks, overturns)
SCALES = (1.2, 3.0)


def _members():
    ens = ensemble("rocking_records_quick")
    chosen = [m for m in ens.members() if m.scale in SCALES]
    return ens.scene(chosen[0].block), [strong_motion(m.record, m.pga) for m in chosen], chosen[0].duration


@pytest.mark.parametrize("engine, step", [("dem", 1), ("dem-moreau", 1), ("dem-overlap", 2)])
def test_a_native_member_is_its_single_run_bit_for_bit(engine, step):
    scene, motions, duration = _members()
    batched = engines.simulate_members(scene, motions, duration, engine, step, output_dts=0.005)
    single = [engines.simulate(scene, motion, duration, engine, step, output_dt=0.005) for motion in motions]
    assert [r.result.overturned for r in single] == [False, True]  # one member rocks, one overturns
    for b, s in zip(batched, single):
        assert (b.status, b.label, b.dt, b.steps) == (s.status, s.label, s.dt, s.steps)
        np.testing.assert_array_equal(b.result.theta, s.result.theta)
        np.testing.assert_array_equal(b.result.peak_theta, s.result.peak_theta)
        assert b.wall_time_s > 0


def test_members_of_other_scenes_and_lengths_come_back_in_their_order_bit_for_bit():
    """Members batched by the scene, duration and output step they share (three batches here), handed back in the
    order they were given."""
    scene, motions, duration = _members()
    other = scenes.block(1.5, 6.0)
    member_scenes, lengths = [scene, other, scene, other], [duration, duration, duration / 2, duration]
    members = list(zip(member_scenes, [motions[0], motions[0], motions[1], motions[1]], lengths))
    batched = engines.simulate_members(member_scenes, [m for _, m, _ in members], lengths, "dem", output_dts=0.01)
    for b, (member_scene, motion, length) in zip(batched, members):
        single = engines.simulate(member_scene, motion, length, "dem", output_dt=0.01)
        assert b.result.t[-1] == single.result.t[-1]
        np.testing.assert_array_equal(b.result.theta, single.result.theta)
    assert batched[1].result.peak_theta[0] != batched[0].result.peak_theta[0]  # another block, the same motion


def test_a_stiffer_contact_is_passed_to_the_batch():
    scene, motions, duration = _members()
    settings = {"kn_factor": 10}
    batched = engines.simulate_members(scene, motions[:1], duration, "dem", 1, settings)
    single = engines.simulate(scene, motions[0], duration, "dem", 1, settings)
    assert batched[0].label == single.label == "auto/1, 10 x K_n"
    assert batched[0].dt == single.dt < engines.simulate(scene, motions[0], duration, "dem", 1).dt
    np.testing.assert_array_equal(batched[0].result.theta, single.result.theta)


def test_an_unstable_native_member_is_stopped_with_its_message_and_the_others_go_on(monkeypatch):
    """The native core's automatic step keeps the harness's runs stable, so the batch's verdict on member 0 is
    replaced by the one an unstable member gets (status ``"unstable"``, the error's message, its partial result)."""
    simulate_batch = dem_core.simulate_batch

    def member_0_unstable(*args, **kwargs):
        batch = simulate_batch(*args, **kwargs)
        batch.table.loc[0, ["status", "error"]] = ["unstable", "lost stability at t = 1 s"]
        return batch

    monkeypatch.setattr(dem_core, "simulate_batch", member_0_unstable)
    scene, motions, duration = _members()
    runs = engines.simulate_members(scene, motions, duration, "dem")
    assert [(r.status, r.message) for r in runs] == [("stopped", "lost stability at t = 1 s"), ("ok", "")]
    assert runs[0].result is not None


def test_a_refused_native_member_is_an_error_naming_its_motion():
    scene, motions, _ = _members()
    endless = excitation.harmonic(1.0, 1.0)  # no natural end, and no duration given
    with pytest.raises(ValueError, match="dem at auto/1, motion .*harmonic"):
        engines.simulate_members(scene, [motions[0], endless], None, "dem")


def test_another_engines_members_run_one_by_one():
    scene, motions, duration = _members()
    ran = []
    runs = engines.simulate_members(scene, motions, duration, "pymunk", 1e-3, progress=lambda: ran.append(1))
    assert len(runs) == len(ran) == 2 and all(r.status == "ok" and r.dt == 1e-3 for r in runs)
    assert [r.result.overturned for r in runs] == [False, True]
