"""Compiled: the one step loop of every run, on every target, switching only the integrator's stage.

Private module.  :func:`drive` advances a run (:class:`~.model_arrays.ModelArrays`, :class:`~.settings.Settings`,
:class:`~.state.State`, :class:`~.state.Outputs`, :class:`~.scratch.Scratch`) through a chunk of steps in place.
It is the loop of a single run on the CPU (:data:`drive_serial`, and :data:`drive_threaded` with the explicit
stage's loops on numba's threads), of each member of a batch on the CPU's threads, and of each member of a batch on
a GPU, a thread a member (:mod:`._members`).  As MuJoCo's ``mj_step`` runs named stages and switches only its
integrator, the loop runs these stages, each a function of its own, and only the integrator's differs (after
Siconos' split of an integrator from its one-step problem):

Per step:

1. ground: the input of the step and of the next from the motion's samples (:func:`~._ground.ground_at`), the base
   placed (:func:`~._ground.place_base`);
2. interfaces: every INTERFACE_STRIDE steps and at the last, each recorded interface's offset, whose travel is
   its slip (:func:`~._interfaces.follow_interfaces`);
3. outputs: the state written if the step is an output (:func:`~._outputs.write_due`);
4. the step's division: central differences take it whole, or in SUBSTEPS parts while a block is overturned
   (:func:`~._explicit.explicit_parts`); Moreau-Jean splits it where a point meets its face, into MAX_SUBSTEPS
   parts at most, and a part whose contact solve failed is taken again shorter (MOREAU_MAX_PARTS parts at most).

Per part:

5. geometry: after the first part, the base placed where the ground has it then
   (:func:`~._ground.place_base_within`); world vertices, normals and boxes (:func:`~._world.world_geometry`,
   :func:`~._world.bounding_boxes`);
6. broad phase: the pairs listed again when a body has moved half a skin (:func:`~._broadphase.needs_relist`,
   :func:`~._broadphase.list_pairs`), and their incidence and order (:func:`pairs_listed`);
7. the integrator's stage: the contact forces and central differences (:func:`~._explicit.explicit_part`), or
   Moreau-Jean's velocity solve and position update (:func:`~._moreau.moreau_part`).

After the step:

8. checks, with the base where the ground has it at the step's end: the counters, a lost state, the overturns and
   the energy balance (:func:`~._checks.end_step`); an overturn that ends the run writes the state as the last
   output.

Every stage takes scalars and arrays, or the named tuples of arrays above, and allocates nothing, so that the loop
compiles for numba's CPU and CUDA targets alike.  The serial build is compiled without numba's reference counting
(``_nrt=False``): it could not compile if a stage allocated, and an array passed from stage to stage costs no
atomic count (counting the named tuples' arrays took most of a step's time).  Moreau-Jean's stage and the broad
phase are compiled as functions of their own rather than inlined, which halves the time it takes to compile; the
explicit stage is inlined, since a compiled call passing the run's arrays costs more than a block's whole step.
"""

import numba as nb

from ._active_set import pair_order
from ._broadphase import incidence, list_pairs, needs_relist
from ._build import ENGINE_DIGEST, variant
from ._checks import end_step
from ._explicit import explicit_part, explicit_parts
from ._ground import ground_at, place_base, place_base_within
from ._interfaces import follow_interfaces
from ._moreau import moreau_part
from ._outputs import write_due, write_output
from ._world import bounding_boxes, world_geometry
from .model_arrays import INV_MASS, LOCAL_X, LOCAL_Y, NORMAL_X, NORMAL_Y, RADIUS
from .settings import (DT, HALF_SKIN, INERTIAL, INTEGRATOR, INTERFACE_STRIDE, LAST_STEP, MOREAU, MOREAU_MAX_PARTS,
                       SCALE, START_X, START_Y, STATUS_FULL, STATUS_OK, STATUS_OVERTURNED)
from .state import LISTED, STEP

#: a build of the driver reads the integrator from each run's settings (ANY_INTEGRATOR), or is made for one
#: integrator (``variant(drive, name, BUILT_FOR=EXPLICIT, ...)``, the other integrator's stage swapped for stubs),
#: whose code then holds only that integrator's stage: the GPU's kernels (:mod:`._members`), where the other stage's
#: code would take registers and its compile time
ANY_INTEGRATOR = -1
BUILT_FOR = ANY_INTEGRATOR


@nb.njit(cache=True, inline="always")
def pairs_listed(model, state, scratch, moreau):
    """Stage 6, after a list is made and when a chunk starts: which listed pairs each body belongs to
    (:func:`~._broadphase.incidence`) and, for Moreau-Jean, the pairs' order of its solve
    (:func:`~._active_set.pair_order`)."""
    listed = state.counters[LISTED]
    incidence(state.pair_ids, listed, scratch.pair_start, scratch.pair_entries, scratch.body_fill)
    if moreau:
        pair_order(state.pair_ids, listed, model.body[INV_MASS], scratch.pair_start, scratch.pair_entries,
                   scratch.pair_degree, scratch.pair_reached, scratch.pair_order)


def drive(model, settings, state, outputs, scratch, samples, n_steps):
    """Take up to ``n_steps`` steps of the run, in place, by the stages of the module docstring.

    samples : (4, n_steps + 2) the ground motion's samples for these steps at unit scale
    (:func:`~._ground.ground_samples`), which settings SCALE scales.  Returns ``(status, i, j)``: STATUS_OK and 0, 0
    while the run can go on (or at its last step), else why it stopped (:mod:`.settings`) and the bodies concerned
    (STATUS_FULL: the store that filled, and the state is to be taken back to the chunk's start).  The step it
    stopped at is ``state.counters[STEP]``.  A build for one integrator (BUILT_FOR) takes only runs of that one.
    """
    real, integer = settings.real, settings.integer
    pos, vel, window, world, boxes = state.pos, state.vel, scratch.window, scratch.world, scratch.boxes
    moreau = integer[INTEGRATOR] == MOREAU if BUILT_FOR == ANY_INTEGRATOR else BUILT_FOR == MOREAU
    dt, inertial = real[DT], integer[INERTIAL] == 1
    pairs_listed(model, state, scratch, moreau)
    for k in range(n_steps + 1):
        ground_at(samples, k, real[SCALE], real[START_X], real[START_Y], dt, inertial, window, 0)
        place_base(pos, vel, window, 0)
        step = state.counters[STEP]
        if step % integer[INTERFACE_STRIDE] == 0 or step >= integer[LAST_STEP]:
            follow_interfaces(pos, model.interface_keys, model.interface_geometry, state.interface_offset,
                              state.interface_slip)
        write_due(settings, state, outputs)
        if k == n_steps or state.counters[STEP] >= integer[LAST_STEP]:
            break
        ground_at(samples, k + 1, real[SCALE], real[START_X], real[START_Y], dt, inertial, window, 1)
        if moreau:
            parts, h, kick = MOREAU_MAX_PARTS, dt, 0.0
        else:
            parts, h, kick = explicit_parts(model, settings, state)
        remaining = dt
        taken = 0
        for part in range(parts):
            if part > 0:
                place_base_within(pos, window, remaining, dt)
            world_geometry(pos, model.vertices[LOCAL_X], model.vertices[LOCAL_Y], model.vertices[NORMAL_X],
                           model.vertices[NORMAL_Y], model.vstart, world[0], world[1], world[2], world[3])
            bounding_boxes(world[0], world[1], model.vstart, boxes)
            if needs_relist(pos, model.body[RADIUS], state.built_at, real[HALF_SKIN]):
                full = list_pairs(model, settings, state, scratch)
                if full >= 0:
                    return STATUS_FULL, full, 0
                pairs_listed(model, state, scratch, moreau)
            if moreau:
                status, i, j, tau = moreau_part(model, settings, state, scratch, part, remaining, window[0, 0],
                                                window[1, 0])
            else:
                status, i, j = explicit_part(model, settings, state, scratch, part, h, kick, window[0, 0],
                                             window[1, 0])
                tau = h
            if status != STATUS_OK:
                return status, i, j
            taken += 1
            remaining -= tau
            if remaining <= 0.0:
                break
        place_base(pos, vel, window, 1)
        status, b = end_step(model, settings, state, scratch, taken)
        if status == STATUS_OVERTURNED:
            follow_interfaces(pos, model.interface_keys, model.interface_geometry, state.interface_offset,
                              state.interface_slip)
            write_output(state, outputs)
        if status != STATUS_OK:
            return status, b, b
    return STATUS_OK, 0, 0


#: the driver, serial, without reference counting; it releases the GIL, so that a batch runs members on several
#: Python threads
drive_serial = nb.njit(cache=True, nogil=True, _nrt=False)(variant(drive, f"drive_{ENGINE_DIGEST}"))
#: the same driver with the explicit stage's loops over pairs and bodies on numba's threads (numba's parallel loops
#: count references)
drive_threaded = nb.njit(cache=True, parallel=True)(variant(
    drive, f"drive_threaded_{ENGINE_DIGEST}",
    explicit_part=nb.njit(inline="always")(variant(explicit_part, "explicit_part_threaded", prange=nb.prange))))
