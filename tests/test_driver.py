"""The one step driver (dem_core/engine/_driver.py): one loop calls every per-step stage, the run's settings are
named once, and a chunk that would overflow a store of fixed capacity is taken again with the store grown, to the
trajectory of a run whose stores never filled, bit for bit."""

import ast
from pathlib import Path

import numpy as np
import pytest

import dem_core
from dem_core import scenes
from dem_core.engine import settings as settings_module
from dem_core.engine import state as state_module
from dem_core.engine.settings import INTEGER_NAMES, REAL_NAMES, make_settings
from dem_core.engine.state import LISTED, RETIRED
from dem_core.inputs.excitation import record, scaled
from dem_core.simulation import Simulation

ENGINE = Path(dem_core.__file__).parent / "engine"
#: the stages a step runs, each called from the driver's loop alone
STAGES = ("ground_at", "place_base", "place_base_within", "write_due", "explicit_parts", "world_geometry",
          "bounding_boxes", "needs_relist", "list_pairs", "pairs_listed", "explicit_part", "moreau_part", "end_step")
EL_CENTRO = record("el_centro_1940")


def _callers(stage: str) -> set:
    """``module.function`` of every function in the engine that calls ``stage``."""
    found = set()
    for path in ENGINE.glob("*.py"):
        for node in ast.walk(ast.parse(path.read_text())):
            if isinstance(node, ast.FunctionDef):
                calls = {n.func.id for n in ast.walk(node) if isinstance(n, ast.Call) and isinstance(n.func, ast.Name)}
                if stage in calls and node.name != stage:
                    found.add(f"{path.stem}.{node.name}")
    return found


@pytest.mark.parametrize("stage", STAGES)
def test_every_stage_of_a_step_is_called_by_the_one_loop(stage):
    assert _callers(stage) == {"_driver.drive"}


def test_the_serial_driver_allocates_nothing_and_counts_no_references():
    """Compiled without numba's runtime, the driver (the explicit stage inlined in it) and its stages compiled apart
    could not allocate an array: what a GPU thread cannot do, no build does."""
    from dem_core.engine import _broadphase, _driver, _moreau

    for compiled in (_driver.drive_serial, _moreau.moreau_part, _broadphase.list_pairs):
        assert compiled.targetoptions.get("_nrt") is False, compiled


def test_the_settings_are_named_once_and_read_by_name():
    values = {name: 1.5 for name in REAL_NAMES} | {name: 2 for name in INTEGER_NAMES}
    settings = make_settings(**values)
    for name in REAL_NAMES:
        assert settings.real[getattr(settings_module, name.upper())] == getattr(settings, name) == 1.5
    for name in INTEGER_NAMES:
        assert settings.integer[getattr(settings_module, name.upper())] == getattr(settings, name) == 2
    changed = settings.replace(dt=0.25, max_sweeps=7)
    assert (changed.dt, changed.max_sweeps, settings.dt) == (0.25, 7, 1.5)
    with pytest.raises(TypeError, match="missing \\['dt'\\]"):
        make_settings(**{k: v for k, v in values.items() if k != "dt"})
    with pytest.raises(AttributeError, match="no 'tolerance'"):
        settings.tolerance  # noqa: B018


#: (scene, motion, duration, options, whether pairs leave the list with a slip, which fills the retired store)
CASES = {
    "Moreau-Jean, a colonnade to its collapse": (scenes.colonnade(), scaled(EL_CENTRO, 4.0), 10.0,
                                                 {"integrator": "moreau", "stop_at_overturn": False}, True),
    "central differences, a column to its collapse": (scenes.column(), scaled(EL_CENTRO, 4.0), 4.0,
                                                      {"stop_at_overturn": False}, False),
}


@pytest.mark.slow
@pytest.mark.parametrize("case", CASES)
def test_a_run_whose_stores_fill_goes_on_with_them_grown_to_the_same_trajectory(case, monkeypatch):
    scene, motion, duration, options, retires = CASES[case]
    roomy = Simulation(scene, motion, duration, **options)
    roomy.advance()
    monkeypatch.setattr(state_module, "PAIRS_PER_BODY", 0)  # stores of one pair and one retired slip
    monkeypatch.setattr(state_module, "RETIRED_PER_BODY", 0)
    tight = Simulation(scene, motion, duration, **options)
    assert tight.state.capacities == (1, 1)
    tight.advance()
    pairs, retired = tight.state.capacities
    assert pairs >= tight.state.counters[LISTED] > 1
    assert (roomy.state.counters[RETIRED] > 1) == retires
    assert retired >= tight.state.counters[RETIRED] == roomy.state.counters[RETIRED]
    a, b = roomy.result(), tight.result()
    for name in ("x", "y", "theta", "peak_theta", "slip_history"):
        assert np.array_equal(getattr(a, name), getattr(b, name)), name
    assert a.interface_slip == b.interface_slip and a.info["steps"] == b.info["steps"]


@pytest.mark.parametrize("wanted", ["room to spare", "just the entries"])
def test_a_batchs_stores_keep_each_members_entries_and_leave_the_rest_empty(wanted):
    """A GPU batch packs its members' states into stores of one capacity: each member's entries first, then its
    store's other rows as far as both reach, then empty rows (-1, or 0.0 where not integers); every other field
    is the member's own, C-ordered whatever the member's order.  A store smaller than a member's entries is
    refused naming the member."""
    runs = [Simulation(scenes.column(3), scaled(EL_CENTRO, f), 2.0, integrator="moreau") for f in (2.0, 3.0)]
    for run in runs:
        run.advance()
    states = [run.state for run in runs]
    states[0] = states[0]._replace(pos=np.asfortranarray(states[0].pos))
    listed, retired_slips = ([int(s.counters[k]) for s in states] for k in (LISTED, RETIRED))
    assert min(listed) > 0 and max(listed) < max(s.capacities[0] for s in states)
    if wanted == "room to spare":
        pairs, retired = max(s.capacities[0] for s in states) + 3, max(s.capacities[1] for s in states) + 2
    else:
        pairs, retired = max(listed), max(1, max(retired_slips))
    batch = state_module.stacked_with_capacities(states, pairs, retired)
    assert all(a.flags.c_contiguous for a in batch)
    for m, state in enumerate(states):
        for name, own, packed in zip(state_module.State._fields, state, batch):
            packed = packed[m]
            if name not in state_module.PAIR_FIELDS + state_module.RETIRED_FIELDS:
                assert np.array_equal(packed, own, equal_nan=True), name
                continue
            capacity = pairs if name in state_module.PAIR_FIELDS else retired
            entries = listed[m] if name in state_module.PAIR_FIELDS else retired_slips[m]
            assert len(packed) == capacity, name
            assert np.array_equal(packed[:entries], own[:entries], equal_nan=True), name
            kept = min(capacity, len(own))
            assert np.array_equal(packed[entries:kept], own[entries:kept], equal_nan=True), name
            assert np.all(packed[kept:] == (-1 if own.dtype == np.int64 else 0.0)), name
        single = state_module.with_capacities(state, pairs, retired)
        assert all(np.array_equal(a, b[m], equal_nan=True) and a.flags.c_contiguous and not np.shares_memory(a, own)
                   for a, b, own in zip(single, batch, state))
    fullest = int(np.argmax(listed))
    with pytest.raises(ValueError, match=f"member {fullest} holds {listed[fullest]} pair entries, more than a store "
                                         f"of {listed[fullest] - 1}"):
        state_module.stacked_with_capacities(states, listed[fullest] - 1, retired)
