"""Connectors across joints (docs/method.md 1.12, 4.9): the law against its envelope, the closed-form cases of
comparisons/cases/connectors.py within their bands for both integrators, Moreau-Jean's step kept with stiff bars, a
weak bar's rupture, an answer that does not hang on the bars' stiffness, and bad input refused naming the culprit
(the GPU path's code with connectors: tests/test_batch_gpu.py)."""

import dataclasses

import numpy as np
import pytest

from comparisons.cases.connectors import connector_cases
from comparisons.harness import engines
from dem_core import Scene, excitation, scenes, simulate, simulate_batch
from dem_core.engine._connector_law import ACCUMULATED, RUPTURE_STEP, SHEAR_FORCE, commit
from dem_core.engine.model import connector_terms
from dem_core.engine.settings import MOREAU_DT
from dem_core.engine.state import initial_connectors
from dem_core.inputs.connectors import OAK_POLOS, Connector, ConnectorKind, place, titanium_bar
from dem_core.inputs.scene import SceneError
from dem_core.inputs.scene_file import SceneFileError, load

CASES = connector_cases()


def push(kind: ConnectorKind, slips) -> tuple:
    """The shear force (N) at each slip of ``slips`` (m) taken in turn, and the state at the end."""
    law, state = connector_terms(kind), initial_connectors(1)[0]
    forces = []
    for step, slip in enumerate(slips):
        if state[RUPTURE_STEP] < 0:  # the engine commits intact connectors only
            commit(slip, 0.0, law, state, step)
        forces.append(state[SHEAR_FORCE])
    return np.array(forces), state


def test_a_monotonic_push_follows_the_envelope_to_rupture():
    """Free within the clearance, elastic to F_y, hardening to F_u at the ultimate slip, flat to the rupture slip."""
    kind = ConnectorKind("bar", shear_stiffness=1e7, yield_force=1e4, ultimate_force=2e4, ultimate_slip=5e-3,
                         rupture_slip=1e-2, clearance=1e-3)
    slips = np.linspace(0.0, 1.2e-2, 12001)
    forces, state = push(kind, slips)
    engaged = slips - kind.clearance
    tangent = (2e4 - 1e4) / (5e-3 - 1e-3)
    envelope = np.where(engaged <= 0, 0.0, np.minimum(np.minimum(1e7 * engaged, 1e4 + tangent * (engaged - 1e-3)), 2e4))
    before = engaged < 1e-2 - 1e-9
    assert np.allclose(forces[before], envelope[before], rtol=0, atol=1e-6 * 2e4)
    first = np.flatnonzero(engaged >= 1e-2 - 1e-9)[0]
    assert state[RUPTURE_STEP] - first in (0, 1)  # within one increment: the capacity is met to round-off
    assert np.all(forces[int(state[RUPTURE_STEP]):] == 0.0)


def test_a_perfectly_plastic_loop_dissipates_yield_force_times_plastic_slip():
    kind = ConnectorKind("bar", shear_stiffness=1e7, yield_force=1e4)
    slips = 4e-3 * np.sin(np.linspace(0.0, 6 * np.pi, 30001))
    forces, state = push(kind, slips)
    loop = np.sum(0.5 * (forces[1:] + forces[:-1]) * np.diff(slips))
    stored = forces[-1] ** 2 / (2 * 1e7)
    assert loop - stored == pytest.approx(1e4 * state[ACCUMULATED], rel=1e-6)


@pytest.mark.parametrize("case, engine", [(c, e) for c in CASES for e in c.engines], ids=lambda x: getattr(x, "name", x))
def test_connector_cases_within_their_bands(case, engine):
    run = engines.simulate(case.scene(), case.motion(), case.duration, engine, None, {}, output_dt=case.output_dt)
    assert run.status == "ok", run.message
    for metric, error in case.errors(run.result, case.reference()).items():
        assert case.within_band(metric, engine, error), (metric, error, case.band(metric, engine))


def test_moreau_keeps_its_step_with_titanium_bars_at_every_joint():
    """The bars are in Moreau-Jean's solve: its default step stands, no part of a step is taken again shorter, and
    the solve leaves no more steps unconverged than the bare column's."""
    column = scenes.column()
    barred = column.replace(connectors=place(column, titanium_bar(), "all"))
    motion = excitation.record("el_centro_1940", pga=3.0)
    bare, moreau = simulate(column, motion, duration=8.0), simulate(barred, motion, duration=8.0)
    assert moreau.dt == MOREAU_DT and moreau.info["shortened_parts"] == 0
    assert moreau.info["unconverged_steps"] <= bare.info["unconverged_steps"]
    assert len(moreau.connectors) == 7 and moreau.connectors.peak_tension_N.max() > 0


def test_a_weak_bar_ruptures_and_leaves_the_block_to_slide():
    weak = ConnectorKind("weak bar", shear_stiffness=2e7, yield_force=500.0, rupture_slip=2e-3)
    block = scenes.block(1.0, 0.5, friction=0.3)
    held = block.replace(connectors=(Connector(("base", "block"), weak),))
    pulse = excitation.rectangular_pulse(6.0, 0.3)
    result = simulate(held, pulse, duration=1.0)
    free = simulate(block, excitation.rectangular_pulse(6.0, 0.3), duration=1.0)
    row = result.connectors.iloc[0]
    assert row.ruptured and 0 < row.rupture_time_s < 0.3
    assert row.plastic_slip_m == pytest.approx(weak.slip_capacity, rel=0.05)
    slip = abs(result.relative_x[-1, 0] - result.relative_x[0, 0])
    assert slip == pytest.approx(abs(free.relative_x[-1, 0] - free.relative_x[0, 0]), rel=0.05)


def test_presets_carry_their_sources_and_a_consistent_envelope():
    for kind in (OAK_POLOS, titanium_bar(0.012), titanium_bar(0.02)):
        assert kind.source and kind.ultimate_force > kind.yield_force > 0
        assert kind.ultimate_slip * kind.shear_stiffness > kind.ultimate_force
        assert 0 < kind.slip_capacity < kind.rupture_slip
    assert OAK_POLOS.axial_stiffness == 0 and OAK_POLOS.clearance > 0
    assert titanium_bar(0.02).ultimate_force == pytest.approx(titanium_bar(0.01).ultimate_force * 4)


def test_adapters_refuse_a_scene_with_connectors():
    column = scenes.column(2)
    barred = column.replace(connectors=place(column, OAK_POLOS, "capital"))
    with pytest.raises(ValueError, match="pymunk: the scene has 1 connector.*cannot model connectors"):
        engines.simulate(barred, excitation.still(), 0.1, "pymunk", 1e-3, {})


@pytest.mark.parametrize("build, message", [
    (lambda c: Connector(("drum1", "drum3"), OAK_POLOS), "do not touch at the start"),
    (lambda c: Connector(("drum1", "drum9"), OAK_POLOS), "no block named 'drum9'"),
    (lambda c: Connector(("drum1", "drum2"), OAK_POLOS, position=0.6), "off its joint"),
], ids=["no joint", "no block", "off the joint"])
def test_a_connector_off_any_joint_is_refused(build, message):
    column = scenes.column()
    with pytest.raises(SceneError, match=message):
        column.replace(connectors=(build(column),))


@pytest.mark.parametrize("kwargs, message", [
    (dict(shear_stiffness=1e7, clearance=-1e-3), "clearance must be >= 0"),
    (dict(yield_force=1e4), "yield_force given without a shear_stiffness"),
    (dict(shear_stiffness=1e7, axial_strength=1e4), "axial_strength given without an axial_stiffness"),
    (dict(shear_stiffness=1e7, yield_force=1e4, ultimate_force=2e4), "needs the ultimate_slip"),
    (dict(shear_stiffness=1e7, yield_force=2e4, ultimate_force=1e4), "below its yield_force"),
], ids=["negative clearance", "strength without stiffness", "tension without stiffness", "no ultimate slip",
        "ultimate below yield"])
def test_a_connector_kind_that_cannot_be_is_refused(kwargs, message):
    with pytest.raises(SceneError, match=message):
        ConnectorKind("bar", **kwargs)


def test_capital_puts_one_connector_under_each_columns_top_block():
    colonnade = scenes.colonnade(3, 3)
    placed = place(colonnade, OAK_POLOS, "capital")
    assert [c.between for c in placed] == [(f"c{k}_drum2", f"c{k}_drum3") for k in (1, 2, 3)]
    assert isinstance(colonnade.replace(connectors=placed), Scene)


def test_ten_times_stiffer_bars_move_the_peaks_less_than_the_responses_own_sensitivity():
    """The titanium bars at every joint at ten times their stiffness, under El Centro at amplitudes from 1.2 to 3 times
    the column's uplift acceleration, change the member-by-member peaks by less (median |log|) than amplitudes
    1.001 times larger do: the answer is not an artefact of the bars' stiffness."""
    bar = titanium_bar()
    stiff = dataclasses.replace(bar, shear_stiffness=10 * bar.shear_stiffness, axial_stiffness=10 * bar.axial_stiffness)
    record = excitation.record("el_centro_1940")
    column = scenes.column()
    amplitudes = np.linspace(1.2, 3.0, 10) * 9.81 * np.tan(column.rocking_slenderness)
    pga = excitation.peak_acceleration(record)

    def peaks(kind, factor):
        batch = simulate_batch(scenes.column(connectors=[(kind, "all")]),
                               [excitation.scaled(record, a * factor / pga) for a in amplitudes])
        return batch.table.max_peak_abs_theta_rad.to_numpy(), batch.table.overturned.to_numpy(bool)

    (own, fell), (stiffer, fell_stiff), (nudged, fell_nudged) = peaks(bar, 1.0), peaks(stiff, 1.0), peaks(bar, 1.001)
    standing = ~(fell | fell_stiff | fell_nudged)
    assert standing.sum() >= 5
    change = np.median(np.abs(np.log(stiffer[standing] / own[standing])))
    floor = np.median(np.abs(np.log(nudged[standing] / own[standing])))
    assert change < floor, (change, floor)


SCENE_FILE = '''[scene]
builder = "column"
n_drums = 4

[[connector]]
{connector}
'''


def test_a_scene_file_places_preset_and_own_connectors(tmp_path):
    path = tmp_path / "restored.toml"
    path.write_text(SCENE_FILE.format(connector='preset = "titanium_bar"\ndiameter = 0.02\nat = "capital"\n\n'
                                                '[[connector]]\nname = "steel dowel"\nshear_stiffness = 2e8\n'
                                                'yield_force = 3e4\nat = [["drum1", "drum2"]]'))
    scene = load(path).scene
    assert [(c.name, c.kind.name) for c in scene.connectors] == [("drum3/drum4", "titanium bar 20 mm"),
                                                                  ("drum1/drum2", "steel dowel")]
    assert scene.connectors[0].kind == titanium_bar(0.02)


@pytest.mark.parametrize("connector, message", [
    ('preset = "oak_polo"', "unknown preset 'oak_polo' \\(did you mean 'oak_polos'\\?\\)"),
    ('shear_stiffness = 1e7\nclearance = -0.001', "clearance must be >= 0"),
    ('yield_force = 1e4', "yield_force given without a shear_stiffness"),
    ('preset = "oak_polos"\nat = [["drum1", "drum4"]]', "do not touch at the start"),
    ('preset = "oak_polos"\nclearance = 0.002', "preset 'oak_polos' takes no clearance"),
], ids=["unknown preset", "negative clearance", "strength without stiffness", "no such joint", "preset changed"])
def test_a_scene_file_connector_that_cannot_be_is_refused_in_one_line(tmp_path, connector, message):
    path = tmp_path / "restored.toml"
    path.write_text(SCENE_FILE.format(connector=connector))
    with pytest.raises(SceneFileError, match=message) as info:
        load(path)
    assert "\n" not in str(info.value) and str(path) in str(info.value)

