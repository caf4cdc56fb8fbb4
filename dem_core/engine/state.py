"""Where a run is: positions and velocities, the contacts' memory, and what the checks track.

A :class:`State` is mutable and separate from the :class:`~dem_core.engine.model.Model`; the
kernels advance it in place (and hand back the contact store when it had to grow), so a run can be
stopped after any number of steps, kept (it pickles) and continued.
"""

from dataclasses import dataclass
from typing import NamedTuple

import numba as nb
import numpy as np

#: columns of Contacts.ids
PAIR_I, PAIR_J, PAIR_KEY, PAIR_INTERFACE = range(4)
#: columns of Contacts.constants
K_N, C_N, K_T, C_T, C_R, MU = range(6)
#: columns of Contacts.memory (int64) and Contacts.forces (float)
REFERENCE, POINT_KEY = 0, 1  # POINT_KEY and POINT_KEY + 1: the two points' feature keys
#: POINT_FORCE and POINT_FORCE + 1: the points' tangential spring force (explicit) or impulse (Moreau-Jean);
#: IMPULSE_N and IMPULSE_N + 1: their normal impulses (Moreau-Jean)
POINT_FORCE, SLIP, IMPULSE_N = 0, 2, 3


class Contacts(NamedTuple):
    """The broad phase's candidate pairs and their contact memory, sorted by key; rows ``[:count[0]]``
    are valid (grown by the kernel when full).  A few packed arrays rather than one per field, so that
    the compiled stages take few arguments; the columns are named by this module's constants.

    ids : (cap, 4) int64: the bodies i < j, ``key = i * nb + j``, and the index of the pair among the
        model's recorded interfaces (-1 if not one).
    constants : (cap, 6) the pair's constants: k_n, c_n, k_t, c_t, c_r (see
        :func:`~dem_core.engine._contact_law.pair_parameters`) and mu.
    memory : (cap, 3) int64: last step's reference face code (corner law, -1 if none) and the feature
        keys of the contact points (-1: empty).
    forces : (cap, 5): the points' tangential springs' force along the reference face (N; the explicit
        integrator) or their tangential impulses (N s; Moreau-Jean), the slip (m) accumulated by a pair that is
        not a recorded interface, and the points' normal impulses (N s; Moreau-Jean).
    count : (1,) int64.
    """

    ids: np.ndarray
    constants: np.ndarray
    memory: np.ndarray
    forces: np.ndarray
    count: np.ndarray


class Retired(NamedTuple):
    """Slip of pairs that left the candidate list and are not recorded interfaces: ``key`` (cap,)
    int64, ``slip`` (cap,) m, entries ``[:count[0]]`` valid (a pair may appear more than once)."""

    key: np.ndarray
    slip: np.ndarray
    count: np.ndarray


class Tracking(NamedTuple):
    """What the checks and the outputs follow.

    peak_theta : (nb,) rad, largest |theta| so far.  overturn_step : (nb,) int64, step at which each
    body overturned (-1: not yet).  stack_step : (ns,) int64, step at which each stack tipped.
    interface_slip : (n_if,) m, slip accumulated at each recorded interface.
    built_at : (nb, 3) positions when the candidate pairs were last listed.
    ledger : (3,) J, the mechanical energy at the start, the ground's net work and its gross work.
    counters : (10,) int64: steps done, narrow-phase tests (contact points solved, Moreau-Jean), broad-phase
        rebuilds, outputs written, for Moreau-Jean per (sub)step Gauss-Seidel sweeps, solves that ended
        unconverged, direct passes and direct solves left to Gauss-Seidel, and for central differences the
        substeps the last step was taken in (0 before the first) and the steps taken in substeps.
    """

    peak_theta: np.ndarray
    overturn_step: np.ndarray
    stack_step: np.ndarray
    interface_slip: np.ndarray
    built_at: np.ndarray
    ledger: np.ndarray
    counters: np.ndarray


(STEP, NARROW, REBUILDS, OUTPUTS, SOLVER_SWEEPS, UNCONVERGED, STATUS_PASSES, STATUS_FALLBACKS, LAST_SUBSTEPS,
 SUBSTEPPED) = range(10)


@dataclass
class State:
    """pos : (nb, 3) x, y, theta of each centre of mass (m, rad) at the current step; vel : (nb, 3)
    velocities at the half step before it (central differences) or at the step (Moreau-Jean); contacts,
    retired, tracking as above.
    The base (body 0) is placed by the ground motion."""

    pos: np.ndarray
    vel: np.ndarray
    contacts: Contacts
    retired: Retired
    tracking: Tracking

    @property
    def step(self) -> int:
        return int(self.tracking.counters[STEP])


@nb.njit(cache=True)
def empty_contacts(capacity):
    """A contact store for ``capacity`` pairs with none listed."""
    return Contacts(np.full((capacity, 4), -1, np.int64), np.zeros((capacity, 6)),
                    np.full((capacity, 3), -1, np.int64), np.zeros((capacity, 5)), np.zeros(1, np.int64))


def initial_state(model) -> State:
    """The state at the start of ``model`` (:class:`~dem_core.engine.model.Model`): blocks where the scene
    puts them, at rest, no contact memory."""
    b = model.bodies
    nb = len(b.mass)
    pos = np.column_stack([b.centroid0, b.angle0])
    vel = np.zeros_like(pos)
    tracking = Tracking(
        peak_theta=np.abs(b.angle0).copy(), overturn_step=np.full(nb, -1, np.int64),
        stack_step=np.full(len(model.stacks.bottom), -1, np.int64),
        interface_slip=np.zeros(len(model.interface_keys)), built_at=np.full((nb, 3), np.inf),
        ledger=np.zeros(3), counters=np.zeros(10, np.int64))
    return State(pos, vel, empty_contacts(1),
                 Retired(np.zeros(nb, np.int64), np.zeros(nb), np.zeros(1, np.int64)), tracking)
