"""Earthquake sequences (dem_core.excitation.sequence) and runs that go on from another run's end (start=): a
sequence's run is, bit for bit, its first event's run followed by a run going on from it; each event's residual
state against a sliding drum's closed form; the scene file, the command line and the batch; bad input in one line."""

import dataclasses
import re
import textwrap
import warnings

import numpy as np
import pandas as pd
import pytest

import dem_core
from dem_core import batch, scenes, simulate, simulate_batch
from dem_core.analyses.damage import residual_dislocation, residual_tilt
from dem_core.cli import main
from dem_core.engine import stability
from dem_core.engine.model import compile_model
from dem_core.inputs import scene_file
from dem_core.inputs.excitation import (
    ExcitationError,
    MotionSequence,
    describe,
    extended,
    record,
    rectangular_pulse,
    scaled,
    sequence,
)
from dem_core.inputs.scene import STANDARD_GRAVITY

#: the rest after each event (s); with the records' pieces of 4 s each event with its rest lasts 5 s
REST = 1.0
#: the explicit core's step (s), under its stability limit on the column: 5 s are 500 000 steps, outputs every 1000
EXPLICIT_DT = 1e-5


def _piece(name: str, seconds: float, pga: float):
    """The first ``seconds`` of a bundled record, baseline-corrected again and scaled to ``pga`` (m/s^2)."""
    whole = record(name)
    samples = whole.horizontal.samples[:round(seconds / whole.horizontal.dt) + 1]
    return record(samples, dt=whole.horizontal.dt, pga=pga)


EL_CENTRO, KALAMATA = _piece("el_centro_1940", 4.0, 4.0), _piece("kalamata_1986", 4.0, 4.0)


@pytest.fixture(scope="module", params=["moreau", "explicit"])
def chained(request):
    """``(A, B1, B2)`` on the 8-drum column: A under El Centro then Kalamata as a sequence, B1 under El Centro and
    its rest, B2 under Kalamata and its rest going on from B1."""
    options = {"integrator": request.param, "dt": EXPLICIT_DT if request.param == "explicit" else None}
    scene = scenes.column()
    whole = simulate(scene, sequence([EL_CENTRO, KALAMATA], rest=REST), **options)
    first = simulate(scene, extended(EL_CENTRO, REST), **options)
    return whole, first, simulate(scene, extended(KALAMATA, REST), start=first, **options)


def test_a_sequence_runs_bit_for_bit_as_a_run_going_on_from_its_first_events_run(chained):
    whole, first, second = chained
    assert whole.info["steps"] == first.info["steps"] + second.info["steps"]
    assert np.array_equal(whole.final_state.pos, second.final_state.pos)
    assert np.array_equal(whole.final_state.vel, second.final_state.vel)
    boundary = len(first.t) - 1  # the outputs fall on the second event's start: its first output is the first's last
    np.testing.assert_allclose(whole.t[boundary:] - whole.t[boundary], second.t, rtol=0, atol=1e-9)
    assert np.array_equal(whole.theta[boundary:], second.theta)
    assert np.array_equal(whole.theta[:boundary + 1], first.theta)
    assert second.peak_theta.max() > 0.01  # the column rocks under both events


def test_each_event_leaves_its_residual_state_as_the_damage_measures_read_it(chained):
    whole, first, _ = chained
    events = whole.events
    assert list(events["event"]) == [1, 2] and list(events["start_s"]) == [0.0, first.t[-1]]
    np.testing.assert_allclose(events["end_s"], [first.t[-1], whole.t[-1]], rtol=1e-12)
    assert events["motion"].tolist() == [EL_CENTRO.name, KALAMATA.name]
    dislocations = events.filter(like="residual_dislocation_m[").to_numpy()
    assert dislocations.shape == (2, 8)
    scene = scenes.column()
    for row, run in ((0, first), (1, whole)):
        assert np.max(np.abs(dislocations[row])) == pytest.approx(residual_dislocation(scene, run), rel=1e-9, abs=1e-12)
        assert events.loc[row, "residual_tilt_rad[drum1..drum8]"] == pytest.approx(residual_tilt(run), rel=1e-9,
                                                                                  abs=1e-12)


#: a 2-drum column (1 x 1 m) whose joint has friction 0.05, the base 0.7, under pulses of 1 m/s^2 for 0.2 s: the
#: upper drum slides over the lower one the closed-form slip each time (tests/test_residual_damage.py)
PULSE, LENGTH, JOINT = 1.0, 0.2, 0.05


def _two_drums():
    return scenes.column(2, width=1.0, height=1.0, friction=0.7, interface_friction={("drum1", "drum2"): JOINT})


@pytest.mark.parametrize("ground_motion", ["inertial", "moving_base"])
def test_a_drum_that_slides_at_each_event_is_left_the_sum_of_its_slips(ground_motion):
    """Newmark's slip a_p T_p^2 / 2 (a_p / (mu g) - 1) after the first pulse, twice it after the second (the upper
    drum lags the ground the pulse moves: its offset is negative), the line through the drums' centres, 0.5 m apart,
    leaning by atan(slip / 0.5); under a moving base too, the blocks placed on the sequence's ground without a jump
    where the second event starts its base."""
    slip = PULSE * LENGTH**2 / 2.0 * (PULSE / (JOINT * STANDARD_GRAVITY) - 1.0)
    pulse = rectangular_pulse(PULSE, LENGTH)
    run = simulate(_two_drums(), sequence([pulse, pulse], rest=REST), ground_motion=ground_motion)
    events = run.events
    dislocation = -events["residual_dislocation_m[drum1/drum2]"].to_numpy()
    np.testing.assert_allclose(dislocation, [slip, 2 * slip], rtol=1e-3)
    assert dislocation[1] == pytest.approx(2 * dislocation[0], rel=1e-6)
    np.testing.assert_allclose(events["residual_tilt_rad[drum1..drum2]"], np.arctan(dislocation / 0.5), rtol=1e-6)
    assert np.max(np.abs(np.diff(run.relative_x, axis=0))) < 1e-3  # m per output: no jump at the second event


def test_under_a_moving_base_a_run_going_on_from_another_is_moved_with_the_base():
    """The base ends the first pulse and its rest 0.22 m from where the second starts it: the run going on from there
    moves the blocks with it, and is the sequence's second event bit for bit."""
    pulse, scene = rectangular_pulse(PULSE, LENGTH), _two_drums()
    whole = simulate(scene, sequence([pulse, pulse], rest=REST), ground_motion="moving_base")
    first = simulate(scene, extended(pulse, REST), ground_motion="moving_base")
    second = simulate(scene, extended(pulse, REST), ground_motion="moving_base", start=first)
    assert np.array_equal(whole.final_state.pos, second.final_state.pos)
    assert second.relative_x[0] == pytest.approx(first.relative_x[-1], abs=1e-12)


def test_a_sequence_is_a_ground_motion_whose_velocity_and_displacement_run_on():
    motion = sequence([EL_CENTRO, scaled(KALAMATA, 0.5)], rest=[2.0, 3.0])
    assert isinstance(motion, MotionSequence) and motion.name == f"{EL_CENTRO.name} + {KALAMATA.name} x0.5"
    assert motion.end_time == pytest.approx(EL_CENTRO.end_time + KALAMATA.end_time + 5.0)
    assert motion.horizontal.peak_acceleration == max(EL_CENTRO.horizontal.peak_acceleration,
                                                      0.5 * KALAMATA.horizontal.peak_acceleration)
    start = EL_CENTRO.end_time + 2.0
    t = np.linspace(0.0, KALAMATA.end_time + 3.0, 2001)
    for name in ("acceleration", "velocity", "displacement"):
        here = getattr(motion.horizontal, name)(start + t)
        np.testing.assert_allclose(here - here[0] * (name == "displacement"),
                                   0.5 * getattr(KALAMATA.horizontal, name)(t), atol=1e-12)
    steps = motion.event_steps(1e-3)
    assert steps.tolist() == [0, round(start / 1e-3), round(motion.end_time / 1e-3)]
    assert extended(motion, 1.0).events[-1].rest == 4.0
    assert scaled(motion, 2.0).horizontal.peak_acceleration == 2.0 * motion.horizontal.peak_acceleration


def test_a_scaled_sequence_is_described_as_its_sequence_times_the_factor():
    """A batch's row of a scaled sequence names the sequence it scales and the factor, however often it is scaled
    or run on; each event keeps its own factor in its motion's name."""
    motion = sequence([EL_CENTRO, scaled(KALAMATA, 2.0)], rest=REST)
    assert describe(motion)["record"] == motion.name and describe(motion)["scale"] == 1.0
    for made in (scaled(scaled(motion, 1.5), 2.0), extended(scaled(motion, 3.0), 1.0),
                 scaled(motion, 3.0).on_steps(1e-3)):
        row = describe(made)
        assert row["record"] == motion.name
        assert row["scale"] == pytest.approx(3.0, rel=1e-15)
        assert row["pga_m_s2"] == pytest.approx(3.0 * motion.horizontal.peak_acceleration, rel=1e-15)


def test_records_of_another_sampling_interval_are_resampled_only_when_asked():
    el_centro, mexico = record("el_centro_1940"), record("mexico_city_1985")
    with pytest.raises(ExcitationError, match=r"^sequence: 'mexico_city_1985 x1' is sampled every 0\.02 s and "
                                              r"'el_centro_1940 x1' every 0\.01 s: give resample=True") as refused:
        sequence([el_centro, mexico], rest=1.0)
    assert "\n" not in str(refused.value)
    resampled = sequence([el_centro, mexico], rest=1.0, resample=[False, True]).events[1].motion
    assert resampled.horizontal.dt == 0.01
    t = np.linspace(0.0, mexico.end_time, 20001)
    np.testing.assert_allclose(resampled.horizontal.acceleration(t), mexico.horizontal.acceleration(t), atol=1e-9)
    np.testing.assert_allclose(resampled.horizontal.displacement(t), mexico.horizontal.displacement(t), atol=1e-9)


@pytest.mark.parametrize("motions, rest, message", [
    ([], 1.0, "sequence: no motions"),
    ([EL_CENTRO, KALAMATA], -1.0, (f"sequence: the rest after '{EL_CENTRO.name}' must be a finite number of "
                                   f"seconds, at least 0, got -1.0")),
    ([EL_CENTRO, KALAMATA], [1.0], re.escape("sequence: 1 value(s) of rest for 2 motions")),
    ([EL_CENTRO, dem_core.excitation.harmonic(0.01, 1.0)], 1.0, "has no natural end"),
])
def test_a_sequence_that_cannot_be_is_refused_in_one_line(motions, rest, message):
    with pytest.raises(ExcitationError, match=message) as refused:
        sequence(motions, rest=rest)
    assert "\n" not in str(refused.value)


def _refused_start(start, scene=None, **options) -> str:
    with pytest.raises((ValueError, TypeError)) as refused:
        simulate(scene or _two_drums(), rectangular_pulse(PULSE, LENGTH), start=start, **options)
    assert "\n" not in str(refused.value)
    return str(refused.value)


def test_a_run_cannot_go_on_from_a_result_it_does_not_continue():
    done = simulate(_two_drums(), rectangular_pulse(PULSE, LENGTH), duration=0.3)
    assert "blocks drum1, drum2, this scene's are drum1, drum2, drum3" in _refused_start(done, scenes.column(3))
    other = scenes.column(2, width=1.0, height=1.0, friction=0.7)
    assert "its compiled model" in _refused_start(done, other)
    assert "integrator 'moreau', this run 'explicit'" in _refused_start(done, integrator="explicit")
    adapter = dataclasses.replace(done, final_state=None, info={"engine": "pymunk"})
    assert "no final state (engine 'pymunk')" in _refused_start(adapter)
    assert "must be a Result" in _refused_start(done.final_state)
    fallen = simulate(scenes.block(0.2, 1.0), rectangular_pulse(8.0, 0.5), duration=1.0)
    assert "stopped when block 'block' overturned" in _refused_start(fallen, scenes.block(0.2, 1.0))
    info = {("stopped" if key == "ended_at_overturn" else key): value for key, value in fallen.info.items()}
    pickled_earlier = dataclasses.replace(fallen, info=info)  # the name of a Result pickled before 66abfcb
    assert "stopped when block 'block' overturned" in _refused_start(pickled_earlier, scenes.block(0.2, 1.0))


def test_a_run_cannot_go_on_from_one_that_lost_stability():
    scene = scenes.column(8)
    with warnings.catch_warnings(), pytest.raises(dem_core.SimulationUnstable) as lost:
        warnings.filterwarnings("ignore", "dt = .* times the stability limit", RuntimeWarning)
        simulate(scene, record("el_centro_1940", pga=6.0), duration=3.0, integrator="explicit",
                 dt=2.5 * stability.stability_limit(compile_model(scene)), enforce_stability_limit=False)
    assert lost.value.partial.lost_stability == str(lost.value)
    assert "lost stability" in _refused_start(lost.value.partial, scene, integrator="explicit")


SEQUENCE_FILE = """
    [scene]
    builder = "column"
    n_drums = 3
    [excitation]
    kind = "record"
    source = ["el_centro_1940", "kalamata_1986"]
    pga = [3.0, 4.0]
    rest = 2.0
"""


def test_a_scene_file_lists_the_records_of_a_sequence_and_their_keys_one_each_or_one_for_all(tmp_path):
    path = tmp_path / "sequence.toml"
    path.write_text(textwrap.dedent(SEQUENCE_FILE))
    motion = scene_file.load(path).excitation
    assert [event.motion.name for event in motion.events] == [record(name, pga=pga).name for name, pga in
                                                              (("el_centro_1940", 3.0), ("kalamata_1986", 4.0))]
    assert [event.rest for event in motion.events] == [2.0, 2.0]
    data = scene_file.read_toml(path)
    for key, value, message in (("pga", [1.0, 2.0, 3.0], "pga: 3 value(s) for 2 record(s) in source"),
                                ("rest", [1.0], "rest: 1 value(s) for 2 record(s) in source"),
                                ("source", ["el_centro_1940", "mexico_city_1985"], "give resample=True")):
        changed = {**data, "excitation": {**data["excitation"], key: value}}
        with pytest.raises(scene_file.SceneFileError, match=re.escape(message)):
            scene_file.from_dict(changed, path)
    changed = {**data, "excitation": {**data["excitation"], "source": ["el_centro_1940", "mexico_city_1985"],
                                      "resample": True}}
    assert scene_file.from_dict(changed, path).excitation.events[1].motion.horizontal.dt == 0.01


def test_the_run_command_prints_and_writes_what_each_event_left(tmp_path, capsys):
    path = tmp_path / "sequence.toml"
    path.write_text(textwrap.dedent(SEQUENCE_FILE))
    out = tmp_path / "out"
    assert main(["run", str(path), "--out", str(out), "--no-plots"]) == 0
    printed = capsys.readouterr().out
    events = pd.read_csv(out / "events.csv")
    assert list(events["event"]) == [1, 2] and events["end_s"].iloc[-1] == pytest.approx(83.6)
    for row in events.to_dict("records"):
        tilt = row["residual_tilt_rad[drum1..drum3]"]
        largest = max(abs(v) for k, v in row.items() if k.startswith("residual_dislocation_m["))
        assert (f"event {row['event']}, {row['motion']} ({row['start_s']:.4g} to {row['end_s']:.4g} s): residual tilt "
                f"{tilt:.3g} rad, largest dislocation {1e3 * largest:.3g} mm") in printed


def test_a_batch_runs_sequences_on_the_cpu_as_simulate_does_and_refuses_them_the_gpu(monkeypatch):
    scene, pulse = _two_drums(), rectangular_pulse(PULSE, LENGTH)
    motions = [sequence([pulse, scaled(pulse, k)], rest=REST) for k in (1.0, 1.5)]
    ran = simulate_batch(scene, motions, device="cpu", histories=(1,))
    alone = simulate(scene, motions[1])
    assert np.array_equal(ran.histories[1].final_state.pos, alone.final_state.pos)
    pd.testing.assert_frame_equal(ran.histories[1].events, alone.events)
    monkeypatch.setattr(batch, "check_device", lambda device: None)
    monkeypatch.setattr(batch, "gpu_available", lambda: "a GPU")
    with pytest.raises(ValueError, match=r"^device='gpu': member 0's motion .* is a sequence .* device='cpu'"):
        simulate_batch(scene, motions, device="gpu")
    assert simulate_batch(scene, motions * 8, device="auto", threads=1).device.startswith("cpu")
