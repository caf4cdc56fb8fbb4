"""Where a run is: positions and velocities, the candidate pairs and their contact memory, what the checks follow,
and the outputs written so far.

A :class:`State` is a few arrays, mutable, apart from the :class:`~dem_core.engine.model.Model`; the compiled driver
advances it in place.  Its stores have fixed capacities (no array is allocated while a run steps, on the CPU or a
GPU): a chunk of steps that would overflow one stops, and the run takes the chunk again from a copy of the state
at the chunk's start with that store doubled (:meth:`State.grown`).  A run can be stopped
after any number of steps, kept (it pickles) and continued.
"""

from typing import NamedTuple

import numpy as np

from ._connector_law import N_STATE, OPENING, PEAK_SHEAR, PEAK_TENSION, RUPTURE_STEP, SHEAR_FORCE, YIELD_STEP
from ._interfaces import follow_interfaces
from .settings import PAIR_STORE

#: the columns of a connector's state its outputs copy, SHEAR_FORCE to OPENING
CONNECTOR_OUTPUTS = OPENING + 1 - SHEAR_FORCE
#: columns of State.pair_ids
PAIR_I, PAIR_J, PAIR_KEY, PAIR_INTERFACE = range(4)
#: columns of State.pair_constants
K_N, C_N, K_T, C_T, C_R, MU = range(6)
#: columns of State.pair_memory: last step's reference face code (corner law, -1 if none) and the feature keys
#: of the two contact points (-1: empty)
REFERENCE, POINT_KEY = 0, 1
#: columns of State.counters
(STEP, NARROW, REBUILDS, OUTPUTS, SOLVER_SWEEPS, UNCONVERGED, STATUS_PASSES, STATUS_FALLBACKS, LAST_SUBSTEPS,
 SUBSTEPPED, LISTED, RETIRED, SHORTENED) = range(13)
N_COUNTERS = 13
#: the fields of the pairs' store and of the retired slips' store
PAIR_FIELDS = ("pair_ids", "pair_constants", "pair_memory", "spring_force", "normal_impulse", "tangential_impulse",
               "pair_slip")
RETIRED_FIELDS = ("retired_key", "retired_slip")
#: a run's first stores: this many pairs a body (or every pair, where fewer) and retired slips; a store that fills
#: is doubled (:meth:`State.grown`)
PAIRS_PER_BODY = 4
RETIRED_PER_BODY = 1


def first_capacities(n_bodies: int) -> tuple:
    """(pairs, retired slips): the stores a run of ``n_bodies`` bodies starts with."""
    every_pair = n_bodies * (n_bodies - 1) // 2
    return max(1, min(every_pair, PAIRS_PER_BODY * n_bodies)), max(1, RETIRED_PER_BODY * n_bodies)


class State(NamedTuple):
    """A run's state, ``nb`` bodies (the base first), ``ns`` stacks, ``n_if`` recorded interfaces, and stores for
    ``C`` candidate pairs and ``R`` retired slips.

    pos : (nb, 3) x, y, theta of each centre of mass (m, rad) at the current step.
    vel : (nb, 3) velocities at the half step before it (central differences) or at the step (Moreau-Jean).
    pair_ids : (C, 4) int64 of the listed pairs (rows ``[:counters[LISTED]]``, in key order): the bodies i < j,
        ``key = i * nb + j`` and the pair's index among the model's recorded interfaces (-1 if not one).
    pair_constants : (C, 6) k_n, c_n, k_t, c_t, c_r (:func:`~dem_core.engine._contact_law.pair_parameters`), mu.
    pair_memory : (C, 3) int64, the reference face code and the points' feature keys.
    spring_force : (C, 2) N, the corner points' tangential springs (the overlap law's in column 0; explicit).
    normal_impulse, tangential_impulse : (C, 2) N s, the points' impulses of the last step (Moreau-Jean).
    pair_slip : (C,) m, the slip of a listed pair that is not a recorded interface.
    retired_key, retired_slip : (R,) the slips of pairs that left the list (entries ``[:counters[RETIRED]]``;
        a pair may appear more than once).
    peak_theta : (nb,) rad, the largest |theta| so far.  overturn_step : (nb,) int64, the step at which each body
        overturned (-1: not yet).  stack_step : (ns,) int64, the step at which each stack tipped.
    interface_slip : (n_if,) m, the slip accumulated at each recorded interface (its offset's travel).
    interface_offset : (n_if,) m, each recorded interface's offset at the last step (:mod:`._interfaces`).
    built_at : (nb, 3) positions when the pairs were last listed.
    ledger : (3,) J, the mechanical energy at the start, the ground's net work and its gross work.
    connectors : (n_c, N_STATE) each connector's state (:mod:`._connector_law`).
    counters : (N_COUNTERS,) int64: steps done, narrow-phase pairs (central differences) or contact points
        (Moreau-Jean), lists made, outputs written, Moreau-Jean's Gauss-Seidel sweeps, unconverged solves, direct
        passes and direct solves left to Gauss-Seidel, the parts the last step was taken in and the steps taken
        in more than one, the listed pairs, the retired slips and Moreau-Jean's parts taken again shorter.
    """

    pos: np.ndarray
    vel: np.ndarray
    pair_ids: np.ndarray
    pair_constants: np.ndarray
    pair_memory: np.ndarray
    spring_force: np.ndarray
    normal_impulse: np.ndarray
    tangential_impulse: np.ndarray
    pair_slip: np.ndarray
    retired_key: np.ndarray
    retired_slip: np.ndarray
    peak_theta: np.ndarray
    overturn_step: np.ndarray
    stack_step: np.ndarray
    interface_slip: np.ndarray
    interface_offset: np.ndarray
    built_at: np.ndarray
    ledger: np.ndarray
    connectors: np.ndarray
    counters: np.ndarray

    @property
    def step(self) -> int:
        return int(self.counters[STEP])

    @property
    def capacities(self) -> tuple:
        """(pairs, retired slips): the stores' capacities."""
        return len(self.pair_ids), len(self.retired_key)

    def copy(self) -> "State":
        return State(*(a.copy() for a in self))

    def grown(self, store: int) -> "State":
        """A copy with ``store`` (PAIR_STORE or RETIRED_STORE of :mod:`.settings`) of twice the capacity, the entries
        kept."""
        pairs, retired = self.capacities
        if store == PAIR_STORE:
            pairs *= 2
        else:
            retired *= 2
        return with_capacities(self, pairs, retired)


def with_capacities(state: State, pairs: int, retired: int) -> State:
    """A copy of ``state`` with stores of ``pairs`` pairs and ``retired`` slips, the entries kept
    (:func:`stacked_with_capacities` of one)."""
    return State(*(a[0] for a in stacked_with_capacities([state], pairs, retired)))


def stacked_with_capacities(states: list, pairs: int, retired: int) -> State:
    """``states`` (M of one shape but their stores') as one :class:`State` of C-ordered (M, ...) arrays, each
    member's stores of ``pairs`` pairs and ``retired`` slips: its rows copied as far as both its store and the new
    one reach (its entries, the first ``counters[LISTED]`` and ``counters[RETIRED]`` rows, among them), the rows
    beyond its store empty (-1, or 0.0 where not integers); ``ValueError`` naming the member and the store where a
    capacity is below its entries."""
    for m, state in enumerate(states):
        for store, entries, capacity in (("pair", state.counters[LISTED], pairs),
                                         ("retired slip", state.counters[RETIRED], retired)):
            if capacity < entries:
                raise ValueError(f"member {m} holds {entries} {store} entries, more than a store of {capacity}")
    fields = {}
    for name, members in zip(State._fields, zip(*states)):
        if name not in PAIR_FIELDS + RETIRED_FIELDS:
            fields[name] = np.ascontiguousarray(np.stack(members))
            continue
        capacity = pairs if name in PAIR_FIELDS else retired
        first = members[0]
        stores = np.full((len(members), capacity) + first.shape[1:], -1 if first.dtype == np.int64 else 0.0,
                         first.dtype)
        for store, old in zip(stores, members):
            kept = min(capacity, len(old))
            store[:kept] = old[:kept]
        fields[name] = stores
    return State(**fields)


class Outputs(NamedTuple):
    """The outputs of a run, ``n_out`` rows of which ``counters[OUTPUTS]`` are written: ``pos`` (n_out, nb, 3) the
    state, ``slip`` (n_out, n_if) m the recorded interfaces' slips, ``step`` (n_out,) int64 the step of each,
    ``connectors`` (n_out, n_c, CONNECTOR_OUTPUTS) each connector's shear force and tension (N), slip and opening
    (m) (:mod:`._connector_law`'s SHEAR_FORCE .. OPENING)."""

    pos: np.ndarray
    slip: np.ndarray
    step: np.ndarray
    connectors: np.ndarray


def interface_offsets(model, pos: np.ndarray) -> np.ndarray:
    """(n_if,) m: each recorded interface's offset (:mod:`._interfaces`) with the bodies at ``pos`` (nb, 3)."""
    offsets, travel = np.zeros(len(model.interface_keys)), np.zeros(len(model.interface_keys))
    follow_interfaces(np.ascontiguousarray(pos, float), model.interface_keys, model.interface_geometry, offsets,
                      travel)
    return offsets


def initial_state(model) -> State:
    """The state at the start of ``model`` (:class:`~dem_core.engine.model.Model`): blocks where the scene puts
    them, at rest, no pair listed (the first step lists them), stores of :func:`first_capacities`."""
    b = model.bodies
    nb = len(b.mass)
    pairs, retired = first_capacities(nb)
    pos = np.column_stack([b.centroid0, b.angle0])
    return State(
        pos=pos, vel=np.zeros((nb, 3)),
        pair_ids=np.full((pairs, 4), -1, np.int64), pair_constants=np.zeros((pairs, 6)),
        pair_memory=np.full((pairs, 3), -1, np.int64), spring_force=np.zeros((pairs, 2)),
        normal_impulse=np.zeros((pairs, 2)), tangential_impulse=np.zeros((pairs, 2)), pair_slip=np.zeros(pairs),
        retired_key=np.full(retired, -1, np.int64), retired_slip=np.zeros(retired),
        peak_theta=np.abs(b.angle0).copy(), overturn_step=np.full(nb, -1, np.int64),
        stack_step=np.full(len(model.stacks.bottom), -1, np.int64),
        interface_slip=np.zeros(len(model.interface_keys)), interface_offset=interface_offsets(model, pos),
        built_at=np.full((nb, 3), np.inf),
        ledger=np.zeros(3), connectors=initial_connectors(len(model.connectors.law)),
        counters=np.zeros(N_COUNTERS, np.int64))


def initial_connectors(count: int) -> np.ndarray:
    """(count, N_STATE): connectors as set, unloaded, not yielded, not ruptured."""
    connectors = np.zeros((count, N_STATE))
    connectors[:, [YIELD_STEP, RUPTURE_STEP]] = -1.0
    return connectors


def continued(state: State) -> State:
    """A copy of ``state`` for a new run to start from: the bodies where they are and as they move, the listed pairs
    with their contact memory, springs and impulses, where the pairs were listed, the parts of the last step and the
    stores' capacities kept; the step, the outputs, the counts, the slips, the overturns and the energy ledger as a
    run that has not begun has them, and each body's peak |theta| its |theta| now; each connector as it is, its peak
    forces those of the new run, and where it yielded or ruptured before, at the new run's start (step 0)."""
    fresh = state.copy()
    kept = fresh.counters[[LISTED, LAST_SUBSTEPS]]
    fresh.counters[:] = 0
    fresh.counters[[LISTED, LAST_SUBSTEPS]] = kept
    for name in ("pair_slip", "retired_slip", "interface_slip", "ledger"):
        getattr(fresh, name)[:] = 0.0
    for name in ("retired_key", "overturn_step", "stack_step"):
        getattr(fresh, name)[:] = -1
    fresh.peak_theta[:] = np.abs(fresh.pos[:, 2])
    fresh.connectors[:, [PEAK_SHEAR, PEAK_TENSION]] = 0.0
    for column in (YIELD_STEP, RUPTURE_STEP):
        fresh.connectors[:, column] = np.minimum(fresh.connectors[:, column], 0.0)
    return fresh


def empty_outputs(n_out: int, n_bodies: int, n_interfaces: int, n_connectors: int = 0) -> Outputs:
    return Outputs(np.full((n_out, n_bodies, 3), np.nan), np.full((n_out, n_interfaces), np.nan),
                   np.zeros(n_out, np.int64), np.full((n_out, n_connectors, CONNECTOR_OUTPUTS), np.nan))
