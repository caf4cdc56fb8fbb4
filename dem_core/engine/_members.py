"""Compiled: the members of a batch, each taken through a chunk by the one step loop, a GPU thread each.

Private module.  A batch's arrays are the driver's named tuples (:mod:`._driver`) with the members on their first
axis; :func:`member` takes one member's rows of them, and :func:`advance_member` drives that member through the
chunk with the loop of a single run.  :data:`KERNELS` holds, per integrator, the CUDA kernel (numba-cuda, float64)
that runs it for every member of a batch, a thread each, and :data:`SERIAL` the same on one CPU thread, which checks
the GPU path where there is no GPU.  Each integrator has its own build of the driver (``BUILT_FOR``), with stubs in
place of the other integrator's stage (:data:`LEFT_OUT`), so that a kernel holds one integrator's stage and its
build types and inlines only that one: the members of a batch share their integrator.  A member's motion is a row of
the chunk's samples at unit scale, shared by every member that scales it (:func:`~._ground.ground_at`).  The
kernels are made at import: numba's CUDA simulator replaces this module's ``cuda``, which they then see.
"""

import numba as nb
from numba import cuda
from numba.extending import overload

from ._build import ENGINE_DIGEST, variant
from ._driver import drive
from .settings import EXPLICIT, INTEGRATORS, LAST_STEP, MOREAU, STATUS_OK
from .state import STEP

#: a member's status while it can take more steps (its run's STATUS_* once it ended)
RUNNING = -1
#: threads per CUDA block
THREADS_PER_BLOCK = 64
#: the build of the driver that :func:`advance_member` calls, set in each integrator's builds (:func:`_builds`)
drive_member = None


def member(arrays, m):
    """Member ``m``'s rows of the named tuple ``arrays``, a named tuple of the same kind."""
    return type(arrays)(*(field[m] for field in arrays))


@overload(member, target="generic")
def _member(arrays, m):
    fields = ", ".join(f"arrays[{k}][m]" for k in range(len(arrays)))
    source = f"def rows(arrays, m):\n    return kind({fields})\n"
    scope = {"kind": arrays.instance_class}
    exec(source, scope)  # noqa: S102 (the one way to build a tuple of as many fields as the type has)
    return scope["rows"]


def advance_member(m, model, settings, state, outputs, scratch, samples, motion, n_steps, status):
    """Member ``m`` through up to ``n_steps`` steps by its integrator's build of the driver (``drive_member``) if it
    is running (``status[m, 0] == RUNNING``), under the motion of row ``motion[m]`` of ``samples`` (G, 4,
    n_steps + 2).  A member that ends gets its run's ``(status, i, j)`` in ``status[m]``, or STATUS_OK and 0, 0 at
    its last step."""
    if status[m, 0] != RUNNING:
        return
    own = member(settings, m)
    code, i, j = drive_member(member(model, m), own, member(state, m), member(outputs, m), member(scratch, m),
                              samples[motion[m]], n_steps)
    if code != STATUS_OK or state.counters[m, STEP] >= own.integer[LAST_STEP]:
        status[m, 0] = code
        status[m, 1] = i
        status[m, 2] = j


def advance_members(model, settings, state, outputs, scratch, samples, motion, n_steps, status):
    """The GPU kernel: thread m takes member m through the chunk (:func:`advance_member`)."""
    m = cuda.grid(1)
    if m < status.shape[0]:
        advance_member(m, model, settings, state, outputs, scratch, samples, motion, n_steps, status)


def advance_members_serial(model, settings, state, outputs, scratch, samples, motion, n_steps, status):
    """The same chunk for every member in turn on one CPU thread: the GPU kernel's code at the CPU's speed."""
    for m in range(status.shape[0]):
        advance_member(m, model, settings, state, outputs, scratch, samples, motion, n_steps, status)


@nb.njit(inline="always")
def _no_moreau_part(model, settings, state, scratch, part, remaining, load_x, load_y):
    """Moreau-Jean's stage where a build takes only explicit runs: never called, its types those of the stage's."""
    return STATUS_OK, 0, 0, 0.0


@nb.njit(inline="always")
def _no_explicit_parts(model, settings, state):
    """The explicit step's division where a build takes only Moreau-Jean runs: never called."""
    return 1, 0.0, 0.0


@nb.njit(inline="always")
def _no_explicit_part(model, settings, state, scratch, part, h, kick, load_x, load_y):
    """The explicit stage where a build takes only Moreau-Jean runs: never called."""
    return STATUS_OK, 0, 0


#: per integrator, the driver's stages of the other integrator and their stubs in that integrator's build: numba
#: prunes the branch that reads the integrator but keeps the stages it calls, which would take most of the build's
#: time to type, inline and lower
LEFT_OUT = {EXPLICIT: {"moreau_part": _no_moreau_part},
            MOREAU: {"explicit_part": _no_explicit_part, "explicit_parts": _no_explicit_parts}}


def _builds(integrator: int) -> tuple:
    """``(kernel, serial)`` for the members of one integrator (settings EXPLICIT or MOREAU)."""
    name = INTEGRATORS[integrator]
    driver = nb.njit(cache=True, nogil=True, _nrt=False)(
        variant(drive, f"drive_{name}_{ENGINE_DIGEST}", BUILT_FOR=integrator, **LEFT_OUT[integrator]))
    one = nb.njit(variant(advance_member, f"advance_member_{name}", drive_member=driver))
    return (cuda.jit(variant(advance_members, f"advance_members_{name}", advance_member=one)),
            nb.njit(variant(advance_members_serial, f"advance_members_serial_{name}", advance_member=one)))


#: per integrator (settings EXPLICIT, MOREAU): the CUDA kernel, and the same code for one CPU thread
KERNELS, SERIAL = (tuple(built) for built in zip(*(_builds(k) for k in range(len(INTEGRATORS)))))
