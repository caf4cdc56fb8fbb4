"""simulate_batch: each member is the run simulate gives, bit for bit, whatever the threads; failures stay with
their member; bad input is refused before any member runs."""

import ctypes
import threading
import time
import warnings

import numpy as np
import pandas as pd
import pytest

import dem_core
from dem_core import compile_model, excitation, scenes, stability
from dem_core.batch import BatchInterrupted, block_columns, simulate_batch
from dem_core.engine.result import BLOCK_MEASURES

MEASURED = ["overturned", "overturn_time_s", "max_peak_abs_theta_rad", "total_sliding_m", "dt_s", "steps"]


def _motions():
    return [excitation.sine_pulse(a, 0.4) for a in (1.5, 4.0, 9.0)]


@pytest.mark.parametrize("integrator", ["explicit", "moreau"])
def test_members_are_the_runs_simulate_gives(integrator):
    block = scenes.block(0.6, 3.0)
    motions = _motions()
    batch = simulate_batch(block, motions, 1.5, integrator=integrator, threads=2, histories=[1])
    for m, motion in enumerate(motions):
        alone = dem_core.simulate(block, motion, 1.5, integrator=integrator)
        row = batch.table.iloc[m]
        assert row["status"] == "ok" and row["motion"] == motion.name
        assert row["peak_abs_theta_rad[block]"] == alone.peak_theta[0]
        assert row["residual_displacement_m[block]"] == alone.residual_displacement[0]
        assert row["overturned"] == alone.overturned
        np.testing.assert_array_equal(row["overturn_time_s[block]"], alone.overturn_time[0])
    assert batch.table["max_peak_abs_theta_rad"].nunique() == 3, "the three pulses rock the block differently"
    assert list(batch.histories) == [1]
    np.testing.assert_array_equal(batch.histories[1].theta,
                                  dem_core.simulate(block, motions[1], 1.5, integrator=integrator).theta)


def test_an_explicit_column_member_is_the_run_simulate_gives():
    """The explicit core relists a stack's contact pairs as the drums move: each member keeps its own list."""
    column = scenes.column(n_drums=3, width=1.0, height=4.0)
    motions = [excitation.sine_pulse(a, 0.6) for a in (2.0, 5.0)]
    table = simulate_batch(column, motions, 1.0, threads=2).table
    for m, motion in enumerate(motions):
        alone = dem_core.simulate(column, motion, 1.0)
        assert [table[f"peak_abs_theta_rad[{n}]"][m] for n in alone.names] == alone.peak_theta.tolist()
        assert table["total_sliding_m"][m] == alone.total_sliding


def test_a_members_block_columns_are_its_runs_metrics_block_by_block():
    """A row's ``<measure>[<block>]`` columns are Result.metrics() of the run alone, each block's measures together
    in the scene's order, as plain Python numbers (a row is written out as JSON by the studies' logs)."""
    column = scenes.column(n_drums=3, width=1.0, height=4.0)
    motions = [excitation.sine_pulse(a, 0.6) for a in (2.0, 9.0)]
    table = simulate_batch(column, motions, 1.0, integrator="moreau", threads=1).table
    for m, motion in enumerate(motions):
        alone = dem_core.simulate(column, motion, 1.0, integrator="moreau")
        assert {type(value) for value in block_columns(alone).values()} == {float, bool}
        metrics = alone.metrics()
        assert [c for c in table if "[" in c] == [f"{measure}[{block}]" for block in metrics["block"]
                                                  for measure in BLOCK_MEASURES]
        for block in metrics.itertuples(index=False):
            for measure in BLOCK_MEASURES:
                np.testing.assert_array_equal(table[f"{measure}[{block.block}]"][m], getattr(block, measure))
    assert table["max_peak_abs_theta_rad"].nunique() == 2


def test_a_column_batch_is_the_same_on_one_thread_and_on_two():
    column = scenes.column(n_drums=3, width=1.0, height=4.0)
    motions = [excitation.record("el_centro_1940", pga=a) for a in (2.0, 3.0, 4.0, 5.0)]
    one = simulate_batch(column, motions, 3.0, integrator="moreau", threads=1)
    two = simulate_batch(column, motions, 3.0, integrator="moreau", threads=2)
    columns = MEASURED + [c for c in one.table if c.split("[")[0] in BLOCK_MEASURES]
    pd.testing.assert_frame_equal(one.table[columns], two.table[columns])
    assert one.device == "cpu, 1 thread" and two.device == "cpu, 2 threads"
    assert len([c for c in one.table if c.startswith("peak_abs_theta_rad[")]) == 3


def test_members_with_their_own_friction_are_the_runs_simulate_gives():
    """A list of scenes gives each member its parameters: a squat block under one pulse slides less on more friction,
    each member bit for bit its simulate run."""
    blocks = [scenes.block(1.0, 0.5, friction=mu, base_width=20.0) for mu in (0.2, 0.3, 0.5)]
    motion = excitation.sine_pulse(4.0, 0.5)
    table = simulate_batch(blocks, motion, 1.5, threads=2).table
    slid = table["sliding_at_its_joints_m[block]"].tolist()
    assert slid == [dem_core.simulate(block, motion, 1.5).block_sliding[0] for block in blocks]
    assert slid[0] > slid[1] > slid[2] >= 0.0
    with pytest.raises(ValueError, match="3 scenes and 2 motions"):
        simulate_batch(blocks, [motion, motion], 1.5)
    with pytest.raises(ValueError, match="member 1's scene has blocks"):
        simulate_batch([blocks[0], scenes.column(2)], motion, 1.5)
    with pytest.raises(TypeError, match="one ground motion"):
        simulate_batch(blocks[0], motion, 1.5)


def test_the_members_warnings_point_at_the_callers_line_and_one_said_by_many_members_shows_once():
    block = scenes.block(1.0, 6.0)
    beyond = 1.5 * stability.stability_limit(compile_model(block))
    motions = [excitation.sine_pulse(a, 0.2) for a in (2.0, 2.0, 3.0, 2.0)]
    with warnings.catch_warnings(record=True) as said:
        warnings.simplefilter("always")
        simulate_batch(block, motions, 0.01, threads=2, dt=beyond, enforce_stability_limit=False, integrator="explicit")
    assert len(said) == 1 and str(said[0].message).startswith(f"dt = {beyond:.4g} s is 1.50 times")
    assert {w.filename for w in said} == {__file__}


def test_a_member_beyond_fifty_g_is_refused_and_the_others_run():
    motions = [excitation.sine_pulse(a, 0.2) for a in (2.0, 600.0, 3.0)]
    table = simulate_batch(scenes.block(1.0, 6.0), motions, 0.2, threads=2).table
    assert table["status"].tolist() == ["ok", "refused", "ok"]
    assert "beyond the 50 g" in table["error"][1]
    # the refused member's row says what it was asked to run, as the others' rows do
    assert (table["record"][1], table["scale"][1], table["pga_m_s2"][1]) == (motions[1].name, 1.0, 600.0)


def test_an_unstable_member_keeps_its_partial_measures_and_a_refused_one_its_reason():
    block = scenes.block(0.6, 3.0)
    beyond = 3.0 * stability.stability_limit(compile_model(block))
    motions = [excitation.sine_pulse(3.0, 0.5), excitation.harmonic(0.01, 1.0)]
    with pytest.warns(RuntimeWarning, match="stability limit"):
        table = simulate_batch(block, motions, None, dt=beyond, enforce_stability_limit=False,
                               integrator="explicit").table
    assert table["status"].tolist() == ["unstable", "refused"]
    assert "gained energy" in table["error"][0] and np.isfinite(table["max_peak_abs_theta_rad"][0])
    assert "no natural end" in table["error"][1]


def test_measures_add_columns_to_each_row():
    table = simulate_batch(scenes.block(0.6, 3.0), _motions(), 0.5, integrator="moreau",
                           measures=lambda result: {"outputs": len(result.t)}).table
    assert table["outputs"].tolist() == [51, 51, 51]


def test_progress_counts_every_member():
    seen = []
    simulate_batch(scenes.block(0.6, 3.0), _motions(), 0.2, integrator="moreau",
                   progress=lambda done, total: seen.append((done, total)))
    assert seen == [(1, 3), (2, 3), (3, 3)]


@pytest.mark.parametrize("arguments, error, words", [
    ({"motions": [excitation.sine_pulse(1.0, 0.4), 3.0]}, TypeError, "member 1"),
    ({"motions": []}, ValueError, "motions is empty"),
    ({"device": "gpu"}, ValueError, "CUDA"),
    ({"device": "tpu"}, ValueError, "device must be one of"),
    ({"histories": [5]}, ValueError, "histories names member 5"),
    ({"histories": 0}, TypeError, r"histories must be a sequence of members' indices, such as \[0, 3\], got 0"),
    ({"duraton": 1.0}, TypeError, r"simulate_batch has no option 'duraton' \(did you mean 'duration'\?\)"),
    ({"integrater": "moreau"}, TypeError, r"no option 'integrater' \(did you mean 'integrator'\?\); its members"),
    ({"threads": 0}, ValueError, "threads must be"),
    ({"parallel": True}, TypeError, "parallel"),
    ({"dt": -1.0}, ValueError, "dt must be positive"),
])
def test_bad_input_is_refused_naming_it(arguments, error, words):
    given = {"motions": _motions(), **arguments}
    with pytest.raises(error, match=words):
        simulate_batch(scenes.block(0.6, 3.0), given.pop("motions"), 0.5, **given)


def test_a_wrong_duration_is_refused_once_for_the_batch():
    with pytest.raises(ValueError, match="^duration must be positive"):  # not "every member was refused; ..."
        simulate_batch(scenes.block(0.6, 3.0), _motions(), -2.0)


def test_ctrl_c_hands_back_the_members_that_finished():
    def interrupt_on_second(done, total):
        if done == 2:
            raise KeyboardInterrupt

    with pytest.raises(BatchInterrupted) as caught:
        simulate_batch(scenes.block(0.6, 3.0), _motions() * 2, 0.3, integrator="moreau", threads=1,
                       progress=interrupt_on_second)
    handed = caught.value.partial.table["member"].tolist()
    # members 0 and 1, and any of those already queued (4 per thread) that finished before the interrupt was met;
    # member 5 is never started
    assert handed[:2] == [0, 1] and handed == list(range(len(handed))) and len(handed) <= 5
    assert (caught.value.partial.table["status"] == "ok").all()


def test_each_members_row_is_handed_over_as_it_ends_and_those_finished_when_stopped():
    """``finished`` gets every member's row once, the table's row, as the member ends; stopped after two, it has had
    every row the interrupted batch hands back."""
    said = []
    done = simulate_batch(scenes.block(0.6, 3.0), _motions(), 0.3, integrator="moreau", threads=2,
                          finished=lambda m, row: said.append((m, row)))
    assert sorted(m for m, _ in said) == list(range(len(_motions())))
    for m, row in said:
        peak = done.table.loc[m, "peak_abs_theta_rad[block]"]
        assert row["member"] == m and row["peak_abs_theta_rad[block]"] == peak
    said.clear()

    def interrupt_on_second(finished, total):
        if finished == 2:
            raise KeyboardInterrupt

    with pytest.raises(BatchInterrupted) as caught:
        simulate_batch(scenes.block(0.6, 3.0), _motions() * 2, 0.3, integrator="moreau", threads=1,
                       progress=interrupt_on_second, finished=lambda m, row: said.append(m))
    assert sorted(said) == caught.value.partial.table["member"].tolist()


@pytest.mark.filterwarnings("ignore:a long run")
def test_ctrl_c_stops_a_running_member_between_its_chunks():
    """A KeyboardInterrupt raised in the calling thread while one long member runs (as Ctrl-C raises it in the main
    thread; raised here asynchronously, since pytest-xdist may run a test outside the main thread): the member
    stops at its next chunk (a quarter of a second), long before its run would end, and none is handed back."""
    block, pulse = scenes.block(0.6, 3.0), excitation.sine_pulse(1.0, 0.4)
    simulate_batch(block, [pulse], 0.01)  # compiled before the clock starts
    caller = ctypes.c_ulong(threading.get_ident())
    interrupt = ctypes.py_object(KeyboardInterrupt)
    timer = threading.Timer(0.5, lambda: ctypes.pythonapi.PyThreadState_SetAsyncExc(caller, interrupt))
    timer.start()
    started = time.perf_counter()
    with pytest.raises(BatchInterrupted) as caught:
        simulate_batch(block, [pulse], 3000.0, threads=1)
    timer.join()
    assert time.perf_counter() - started < 5.0, "the 3000 s run takes about half a minute: the member did not stop"
    assert len(caught.value.partial.table) == 0


def test_an_error_in_measures_stops_the_batch_without_running_the_rest():
    ran = []

    def failing(result):
        ran.append(result)
        raise RuntimeError("a measure that fails")

    with pytest.raises(RuntimeError, match="a measure that fails"):
        simulate_batch(scenes.block(0.6, 3.0), _motions() * 8, 0.3, integrator="moreau", threads=1,
                       measures=failing)
    assert len(ran) < 8, "the members queued behind the failure did not run"


def test_a_refused_first_member_is_a_row_like_any_other():
    motions = [excitation.harmonic(0.01, 1.0), excitation.sine_pulse(3.0, 0.5)]
    table = simulate_batch(scenes.block(0.6, 3.0), motions, None, integrator="moreau").table
    assert table["status"].tolist() == ["refused", "ok"] and "no natural end" in table["error"][0]
    assert table["overturned"].isna().tolist() == [True, False]
    with pytest.raises(ValueError, match=r"every member was refused; member 0 \(harmonic"):
        simulate_batch(scenes.block(0.6, 3.0), motions[:1] * 3, None)


def test_each_members_row_names_its_record_its_scale_and_the_pga_and_pgv_it_was_scaled_to():
    """A member asked for as a PGA shows that PGA, its factor and its record; a record's baseline correction and
    its velocity are linear in its samples, so the PGA and the PGV are the unscaled record's times the factor."""
    record = excitation.record("el_centro_1940")
    motions = [excitation.record("el_centro_1940", pga=2.0), excitation.scaled(record, 0.5),
               excitation.sine_pulse(3.0, 0.5)]
    table = simulate_batch(scenes.block(1.0, 6.0), motions, 0.2, threads=1).table
    peak, own = record.horizontal.peak_acceleration, excitation.peak_velocity(record)
    assert list(table["record"]) == ["el_centro_1940", "el_centro_1940", motions[2].name]
    assert list(table["motion"]) == [m.name for m in motions]
    assert table["pga_m_s2"][0] == pytest.approx(2.0, rel=1e-15)
    np.testing.assert_allclose(table["pga_m_s2"][1:], [0.5 * peak, 3.0], rtol=1e-12)
    np.testing.assert_allclose(table["scale"], [table["pga_m_s2"][0] / peak, 0.5, 1.0], rtol=1e-12)
    np.testing.assert_allclose(table["pgv_m_s"][:2], table["scale"][:2] * own, rtol=1e-12)
    # a one-sine pulse's peak velocity, a_p T_p / pi, comes at T_p / 2, one of the samples PGV is taken at
    assert table["pgv_m_s"][2] == pytest.approx(3.0 * 0.5 / np.pi, rel=1e-12)
