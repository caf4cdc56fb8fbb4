"""The simulation driver: ground motion applied two ways, outputs, overturning, result type."""

import tracemalloc

import numpy as np
import pytest

import dem_core
from dem_core import excitation, scenes
from dem_core.engine.settings import MOREAU_DT
from dem_core.simulation import COLLAPSE_STEP_FACTOR, Simulation, set_up_scene


def _mode_difference(scene, motion, duration, refine=1, integrator="explicit"):
    dt = (dem_core.automatic_time_step(scene) if integrator == "explicit" else MOREAU_DT) / refine
    a = dem_core.simulate(scene, motion, duration=duration, ground_motion="inertial", output_dt=1e-3, dt=dt,
                          integrator=integrator)
    b = dem_core.simulate(scene, motion, duration=duration, ground_motion="moving_base", output_dt=1e-3, dt=dt,
                          integrator=integrator)
    np.testing.assert_allclose(a.base_x, b.base_x, atol=1e-9)
    scale_x = max(np.max(np.abs(a.relative_x - a.relative_x[0])), 1e-3)
    scale_t = max(np.max(np.abs(a.theta)), 1e-3)
    return max(np.max(np.abs(a.relative_x - b.relative_x)) / scale_x, np.max(np.abs(a.theta - b.theta)) / scale_t)


@pytest.mark.parametrize("integrator", ["explicit", "moreau"])
@pytest.mark.parametrize("make_scene, motion, duration", [
    (lambda: scenes.block(1.0, 0.5, friction=0.2, base_width=20.0), excitation.record("el_centro_1940"), 12.0),
    (lambda: scenes.column(3), excitation.harmonic(0.02, 1.5), 2.0),
    (lambda: scenes.column(2), excitation.harmonic(pga=10.0, frequency=1.0), 0.5),
])
def test_moving_base_and_inertial_load_give_the_same_relative_response(make_scene, motion, duration, integrator):
    """docs/method.md 2: both ways must agree, up to the error of sampling the ground motion at step times: to
    rounding for central differences at the automatic step (6.5e-9 at most over these cases), and under 1.5e-4 for
    Moreau-Jean at 1e-3 s, whose moving base meets the ground at step and part ends.  A harmonic's ground starts at
    1.6 m/s (the last case): the blocks start moving with it, and the energy balance counts that kinetic energy from
    the start instead of taking it for energy from nowhere."""
    band = {"explicit": 1e-7, "moreau": 5e-4}[integrator]
    assert _mode_difference(make_scene(), motion, duration, integrator=integrator) < band


@pytest.mark.parametrize("scene, motion, duration", [
    (scenes.block(1.0, 0.5, friction=0.2, base_width=20.0), excitation.record("el_centro_1940"), 12.0),
    (scenes.block(0.25, 1.0), excitation.sine_pulse(6.0, 0.25), 1.5),
], ids=["sliding", "rocking"])
def test_under_moreau_jean_the_two_ways_converge_together_at_second_order(scene, motion, duration):
    """Moreau-Jean's velocities are those of the step's end: a moving base moves at the ground's velocity there (of
    a part's end where an impact splits the step), where the inertial load's cell ends, so that a block sliding on
    the base under El Centro, and one rocking and striking it under a pulse, are the same relative motion both ways
    to the second order in dt."""
    coarse = _mode_difference(scene, motion, duration, integrator="moreau")
    fine = _mode_difference(scene, motion, duration, refine=2, integrator="moreau")
    assert coarse < 2e-4
    assert fine < 0.3 * coarse  # second order gives 0.25, first order 0.5


def test_the_two_ways_of_applying_ground_motion_converge_together():
    """A rocking block is the sensitive case: 1.2e-4 apart at the automatic step, 6e-6 at a quarter of it."""
    scene, motion = scenes.block(0.25, 1.0), excitation.sine_pulse(6.0, 0.25)
    coarse = _mode_difference(scene, motion, 1.5)
    fine = _mode_difference(scene, motion, 1.5, refine=4)
    assert coarse < 1e-3
    assert fine < 0.1 * coarse


@pytest.mark.parametrize("integrator", ["explicit", "moreau"])
def test_a_ground_that_sinks_carries_the_block_on_it_without_a_fall(integrator):
    """A ground accelerating down at 2 m/s^2 (under g) for 0.5 s, then sinking on at 1 m/s, carries the 0.25 x 1 m
    block on it unturned: no overturn in 1 s either way, the block 0.75 m down at the end, still on the base (the
    overturn rule's fall is measured from the base)."""
    motion = excitation.GroundMotion(vertical=excitation.Pulse(-2.0, 0.5), name="sinking ground")
    for ground_motion in ("inertial", "moving_base"):
        run = dem_core.simulate(scenes.block(0.25, 1.0), motion, duration=1.0, ground_motion=ground_motion,
                                integrator=integrator)
        assert "ended_at_overturn" not in run.info, (ground_motion, run.info["ended_at_overturn"])
        assert np.max(np.abs(run.theta)) < 1e-9
        assert run.y[0, 0] - run.y[-1, 0] > 0.7  # down with the ground, 5.6 times the fall the rule allows
        # on the base: no more than the contact's give (explicit's springs 1.3e-7 m under the block's weight)
        assert run.y[-1, 0] - run.base_y[-1] == pytest.approx(run.y[0, 0] - run.base_y[0], abs=1e-6)


def test_under_moreau_jean_a_base_moving_up_and_down_is_where_the_ground_has_it_in_each_part_of_a_step():
    """Where an impact splits a step, the next part's gaps are measured from the base where the ground has moved
    it by then, not where it was at the step's start (v_gy tau_1 off): a block rocking under a pulse on a ground
    shaking up and down at 3 m/s^2 is the same relative motion both ways to 3.4e-4 at 1e-3 s, 9e-3 with the base
    left at the step's start."""
    motion = excitation.GroundMotion(horizontal=excitation.sine_pulse(6.0, 0.25).horizontal,
                                     vertical=excitation.harmonic(pga=3.0, frequency=2.0).horizontal,
                                     name="pulse, shaking up and down")
    assert _mode_difference(scenes.block(0.25, 1.0), motion, 1.5, integrator="moreau") < 1e-3


def test_within_a_step_the_ground_is_on_the_line_between_its_values_at_the_step_s_ends():
    """A part that starts with ``left`` of a step to go finds the base where the ground has it then (the step's
    end at 0, its start at dt); a Moreau-Jean part that ends leaving ``left`` has the base's velocity there."""
    from dem_core.engine._ground import ground_before_end, place_base_within

    dt = 1e-3
    window = np.array([[0.0, 0.0], [0.0, 0.0], [1.0, 1.5], [-2.0, -2.25], [0.3, 0.7], [-0.1, 0.2]])
    pos = np.zeros((2, 3))
    place_base_within(pos, window, 0.25 * dt, dt)
    np.testing.assert_allclose(pos[0, :2], [1.375, -2.1875], rtol=0, atol=1e-15)
    assert np.all(pos[1] == 0.0)
    for row in range(2, 6):
        assert ground_before_end(window, row, 0.0, dt) == window[row, 1]
        assert ground_before_end(window, row, dt, dt) == pytest.approx(window[row, 0], rel=0, abs=1e-15)
        assert ground_before_end(window, row, 0.5 * dt, dt) == pytest.approx(window[row].mean(), rel=0, abs=1e-15)


def test_outputs_at_output_dt_and_result_tables():
    r = dem_core.simulate(scenes.column(3), excitation.sine_pulse(2.0, 0.3), duration=1.0, output_dt=0.01)
    stride = round(0.01 / r.dt)
    np.testing.assert_allclose(np.diff(r.t)[:-1], stride * r.dt)
    assert r.t[-1] == pytest.approx(1.0, abs=r.dt)  # the final state closes the record
    assert r.x.shape == r.y.shape == r.theta.shape == (len(r.t), 3)
    frame = r.to_frame()
    assert list(frame.columns) == ["t", "block", "x", "y", "theta", "x_rel", "base_x", "base_y"]
    assert len(frame) == 3 * len(r.t)
    metrics = r.metrics()
    assert list(metrics["block"]) == ["drum1", "drum2", "drum3"]
    assert np.all(metrics["peak_abs_theta_rad"] >= np.max(np.abs(r.theta), axis=0) - 1e-15)
    assert r.summary()["dt_s"] == r.dt


def test_a_run_takes_the_memory_of_its_outputs_and_scratch_at_its_first_step():
    """A run set up and not stepped holds its state, not its outputs or scratch (a GPU batch's members write theirs
    into the batch's arrays): less than the smaller of the two, the column's 194 KB of scratch against 5.8 MB of
    outputs for 200 s; its result is then its start, with no rows."""
    scene, motion = scenes.column(), excitation.sine_pulse(2.0, 0.5)
    shared = set_up_scene(scene)
    Simulation(scene, motion, 200.0, scene_set_up=shared)  # the record's speed limit cached, the kernel compiled
    tracemalloc.start()
    run = Simulation(scene, motion, 200.0, scene_set_up=shared)
    held = tracemalloc.get_traced_memory()[0]
    tracemalloc.stop()
    assert run.outputs is None and run.scratch is None
    assert held < min(sum(a.nbytes for a in run.empty_outputs(run.output_rows)),
                      sum(a.nbytes for a in run.new_scratch()))
    assert len(run.result().t) == 0
    stride = int(run.settings.stride)
    run.advance(stride)
    assert np.array_equal(run.result().t, [0.0, stride * run.dt]) and len(run.outputs.step) == run.output_rows


def test_overturn_stops_the_run_and_says_when():
    scene = scenes.block(0.25, 1.0)
    r = dem_core.simulate(scene, excitation.sine_pulse(3.5, 1.0), duration=4.0)
    assert r.overturned
    assert r.t[-1] == pytest.approx(r.time_of_overturn)
    assert abs(r.theta[-1, 0]) >= scene.blocks[0].critical_angle
    assert "overturned" in r.info["ended_at_overturn"]
    goes_on = dem_core.simulate(scene, excitation.sine_pulse(3.5, 1.0), duration=4.0, stop_at_overturn=False)
    assert goes_on.t[-1] == pytest.approx(4.0, abs=goes_on.dt * 2)
    assert abs(goes_on.theta[-1, 0]) == pytest.approx(np.pi / 2, abs=0.01)  # lying on its side


def test_going_on_past_an_overturn_takes_the_same_steps_until_a_block_is_overturned():
    """With stop_at_overturn=False the step is the automatic one, bit for bit the stopping run's trajectory, until a
    block passes its critical angle; from then on each step is taken in substeps (docs/method.md 1.7)."""
    scene = scenes.block(1.0, 6.0)
    for pga, overturns in ((3.0, False), (9.0, True)):
        motion = excitation.record("el_centro_1940", pga=pga)
        stops = dem_core.simulate(scene, motion, duration=15.0, output_dt=1e-3, integrator="explicit")
        goes_on = dem_core.simulate(scene, motion, duration=15.0, output_dt=1e-3, stop_at_overturn=False,
                                    integrator="explicit")
        assert stops.overturned == goes_on.overturned == overturns
        assert goes_on.dt == stops.dt
        n = len(stops.t) - 1  # the stopping run's last output is the overturn, between output times
        assert np.array_equal(stops.theta[:n], goes_on.theta[:n]) and np.array_equal(stops.x[:n], goes_on.x[:n])
        assert (goes_on.info["substepped_steps"] > 0) == overturns
        if overturns:
            assert goes_on.time_of_overturn == stops.time_of_overturn
            assert goes_on.info["substepped_steps"] <= goes_on.info["steps"] - round(stops.time_of_overturn / stops.dt)


@pytest.mark.parametrize("ground_motion", ["inertial", "moving_base"])
def test_the_substeps_past_an_overturn_follow_the_fall_a_short_step_gives(ground_motion):
    """A block thrown over by a pulse falls onto its side: taken in substeps past its critical angle, and at the
    substeps' length throughout, it lands within one output (1 ms) and comes to rest within 2 mm of each other."""
    scene, motion = scenes.block(0.25, 1.0), excitation.sine_pulse(3.5, 1.0)
    options = dict(duration=2.0, stop_at_overturn=False, output_dt=1e-3, ground_motion=ground_motion)
    substepped = dem_core.simulate(scene, motion, **options, integrator="explicit")
    n = substepped.info["collapse_substeps"]
    fine = dem_core.simulate(scene, motion, dt=substepped.dt / n, **options, integrator="explicit")
    assert n > 1 and fine.info["substepped_steps"] == 0 < substepped.info["substepped_steps"]
    landed = [r.t[np.argmax(np.abs(r.theta[:, 0]) > np.pi / 2 - 0.02)] for r in (substepped, fine)]
    assert landed[0] == pytest.approx(landed[1], abs=1.5e-3) and landed[0] > substepped.time_of_overturn
    assert abs(substepped.theta[-1, 0]) == pytest.approx(np.pi / 2, abs=1e-3)
    assert substepped.relative_x[-1, 0] == pytest.approx(fine.relative_x[-1, 0], abs=2e-3)


def test_duration_defaults_to_the_record_length():
    motion = excitation.record("kalamata_1986")
    r = dem_core.simulate(scenes.block(1.0, 1.0), motion, output_dt=0.1)
    assert r.t[-1] == pytest.approx(motion.end_time, abs=0.1)
    with pytest.raises(ValueError, match="duration"):
        dem_core.simulate(scenes.block(1.0, 1.0), excitation.harmonic(0.01, 1.0))


@pytest.mark.slow
def test_a_column_collapses_through_to_rest_when_asked_to_go_on():
    """Past the overturn the drums fall into a pile: the run must finish, with the energy balance intact."""
    motion = excitation.record("el_centro_1940", pga=10.0)
    r = dem_core.simulate(scenes.column(8), motion, duration=12.0, stop_at_overturn=False)
    assert r.overturned and r.t[-1] == pytest.approx(12.0, abs=r.dt)
    top_start = 6.0 - 0.375
    assert r.y[-1, -1] < 0.5 * top_start  # the top drum has come down
    assert np.all(np.isfinite(r.theta))


def test_automatic_time_step_is_the_step_simulate_takes():
    for scene in (scenes.column(8), scenes.colonnade(3, 2, epistyle="b")):
        assert dem_core.simulate(scene, duration=1e-3, integrator="explicit").dt == dem_core.automatic_time_step(scene)
        # going on past an overturn keeps the step and takes the fewest substeps within the collapse step
        goes_on = dem_core.simulate(scene, duration=1e-3, stop_at_overturn=False, integrator="explicit")
        assert goes_on.dt == dem_core.automatic_time_step(scene)
        n = goes_on.info["collapse_substeps"]
        collapse = dem_core.automatic_time_step(scene, toppled=True) * COLLAPSE_STEP_FACTOR
        assert n > 1 and goes_on.dt / n <= collapse < goes_on.dt / (n - 1)


def test_a_step_fraction_runs_the_automatic_step_over_n_as_an_explicit_dt_does():
    """``step_fraction=1/N`` is the convergence studies' ``auto/N``: the same dt and the same trajectory as
    ``dt=automatic_time_step(scene) / N``, bit for bit, with the scene compiled once."""
    scene, motion = scenes.column(3), excitation.sine_pulse(3.0, 0.25)
    for n in (2, 4):
        fraction = dem_core.simulate(scene, motion, duration=0.3, step_fraction=1.0 / n, integrator="explicit")
        explicit = dem_core.simulate(scene, motion, duration=0.3, dt=dem_core.automatic_time_step(scene) / n,
                                     integrator="explicit")
        assert fraction.dt == explicit.dt
        assert np.array_equal(fraction.theta, explicit.theta) and np.array_equal(fraction.x, explicit.x)
    for bad in (0.0, 1.5, -0.25):
        with pytest.raises(ValueError, match="step_fraction"):
            dem_core.simulate(scene, duration=1e-3, step_fraction=bad)
    with pytest.raises(ValueError, match="give it or dt, not both"):
        dem_core.simulate(scene, duration=1e-3, dt=1e-6, step_fraction=0.5)


def test_threads_and_the_broad_phase_margin_do_not_change_the_trajectory(monkeypatch):
    """The pair loop writes each pair's resultants to its own row and the gather sums them body by body
    in one order, so the threaded kernel gives the serial one's trajectory bit for bit; the broad phase
    only decides which pairs are tested, so its margin (hence how often it lists pairs again) changes
    nothing either."""
    from dem_core.engine import model as model_module

    scene = scenes.colonnade(5, 3, epistyle="b", epistyle_density=8000.0)
    motion = excitation.harmonic(pga=4.0, frequency=1.0)
    runs = [dem_core.simulate(scene, motion, duration=1.5, parallel=flag, integrator="explicit")
            for flag in (False, True)]
    monkeypatch.setattr(model_module, "SKIN_FRACTION", 0.02)
    runs.append(dem_core.simulate(scene, motion, duration=1.5, integrator="explicit"))
    assert np.max(np.abs(runs[0].theta)) > 0.01  # the colonnade rocks
    assert runs[2].info["pair_lists"] > runs[0].info["pair_lists"]
    for other in runs[1:]:
        np.testing.assert_array_equal(other.x, runs[0].x)
        np.testing.assert_array_equal(other.theta, runs[0].theta)


def test_no_two_compiled_kernels_of_the_engine_share_an_entry_of_numbas_disk_cache():
    """Numba's disk cache files a kernel by name and line, not by its options (``parallel=True``) or the functions
    it calls: two builds of one function under one name share an entry, and one loads the other's code (the
    threaded driver ran the serial one's, on one thread, once the serial had been cached a moment before in the same
    process).  Every cached dispatcher of ``dem_core.engine`` (each build made by ``_build.variant`` under a name of
    its own) has an entry of its own."""
    import importlib
    import pkgutil

    from numba.core.registry import CPUDispatcher

    import dem_core.engine
    from dem_core.engine._driver import drive_serial, drive_threaded

    kernels = {}
    for module in pkgutil.iter_modules(dem_core.engine.__path__):
        for value in vars(importlib.import_module(f"dem_core.engine.{module.name}")).values():
            if isinstance(value, CPUDispatcher) and value._cache.__class__.__name__ == "FunctionCache":
                kernels[id(value)] = value
    entries = {}
    for kernel in kernels.values():
        entries.setdefault((kernel._cache._cache_path, kernel._cache._cache_file._index_name), []).append(kernel)
    shared = {entry: [k.py_func.__qualname__ for k in found] for entry, found in entries.items() if len(found) > 1}
    assert not shared, shared
    assert {id(drive_serial), id(drive_threaded)} <= kernels.keys()
    assert drive_threaded.targetoptions.get("parallel") and not drive_serial.targetoptions.get("parallel")


def test_a_run_pickled_halfway_continues_to_the_same_trajectory_in_another_process(tmp_path):
    """A Simulation stopped, saved and loaded in a fresh process (where it finds its kernel by name, not
    as a pickled dispatcher) ends where the uninterrupted run ends, bit for bit."""
    import pickle
    import subprocess
    import sys

    from dem_core.simulation import Simulation

    scene, motion = scenes.column(3), excitation.harmonic(pga=3.0, frequency=1.0)
    whole = dem_core.simulate(scene, motion, duration=0.5, integrator="explicit")
    half = Simulation(scene, motion, duration=0.5, integrator="explicit")
    half.advance(half.settings.last_step // 2)
    saved = tmp_path / "half.pkl"
    saved.write_bytes(pickle.dumps(half))
    script = ("import pickle, sys, numpy as np; run = pickle.loads(open(sys.argv[1], 'rb').read()); "
              "run.advance(); r = run.result(); np.save(sys.argv[2], np.stack([r.x, r.theta]))")
    done = subprocess.run([sys.executable, "-c", script, str(saved), str(tmp_path / "end.npy")],
                          capture_output=True, text=True, timeout=600)
    assert done.returncode == 0, done.stderr[-2000:]
    np.testing.assert_array_equal(np.load(tmp_path / "end.npy"), np.stack([whole.x, whole.theta]))


def test_ctrl_c_stops_a_run_between_chunks_and_it_can_go_on():
    """Ctrl-C is held back while the compiled kernel runs (an exception in a callback from compiled code
    crashes the process) and raised after the chunk: the state is whole, and the run goes on to the
    trajectory of an uninterrupted run, bit for bit."""
    import os
    import signal
    import threading

    scene, motion = scenes.column(2), excitation.harmonic(pga=2.0, frequency=1.0)
    whole = dem_core.simulate(scene, motion, duration=240.0, integrator="explicit")
    run = dem_core.Simulation(scene, motion, duration=240.0, integrator="explicit")
    timer = threading.Timer(0.4, lambda: os.kill(os.getpid(), signal.SIGINT))
    timer.start()
    with pytest.raises(KeyboardInterrupt):
        run.advance()
    timer.join()
    assert 0 < run.step < run.settings.last_step
    run.advance()
    resumed = run.result()
    assert np.array_equal(resumed.theta, whole.theta) and np.array_equal(resumed.x, whole.x)


def test_runs_of_one_scene_sharing_its_set_up_are_the_runs_each_sets_up_alone():
    """set_up_scene, made once, serves runs of its scene under other motions (a batch's members) bit for bit,
    and no other scene or step options."""
    scene = scenes.column(3)
    shared = set_up_scene(scene, stop_at_overturn=False)
    for pga in (2.0, 6.0):
        motion = excitation.sine_pulse(pga, 0.5)
        alone = dem_core.simulate(scene, motion, 1.0, stop_at_overturn=False)
        together = Simulation(scene, motion, 1.0, stop_at_overturn=False, scene_set_up=shared)
        together.advance()
        together = together.result()
        assert np.array_equal(alone.theta, together.theta) and alone.info["steps"] == together.info["steps"]
    for other_scene, options in ((scenes.column(3), {"stop_at_overturn": False}), (scene, {})):
        with pytest.raises(ValueError, match="another scene or other step options"):
            Simulation(other_scene, excitation.sine_pulse(2.0, 0.5), 1.0, scene_set_up=shared, **options)
