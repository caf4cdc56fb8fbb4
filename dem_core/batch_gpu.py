"""A batch's members stepped together on an NVIDIA GPU (numba-cuda, float64), one thread per member.

:func:`run_members` takes members set up on the CPU as :class:`~dem_core.simulation.Simulation` runs, copies
their models and states to the device as arrays with the members on their first axis, advances them all by the
kernel of :mod:`dem_core.engine._members` in chunks of steps, and hands each run its state and outputs back, so
that :meth:`Simulation.result` gathers each member as it does a run of :func:`~dem_core.simulate`.  A motion
that is a scaled record (:func:`~dem_core.inputs.excitation.scaled`) is sampled once for all the members that
scale it, and each member's thread scales it.
"""

from __future__ import annotations

import importlib.util
import time
from dataclasses import dataclass

import numpy as np

from .engine.model_arrays import NO_KEY, ModelArrays
from .engine.scratch import make_scratch
from .engine.settings import CONTACT_LAW, INTEGRATOR, INTEGRATORS, SCALE, STATUS_FULL, STATUS_OK
from .engine.state import Outputs, State, stacked_with_capacities
from .engine._ground import ground_samples
from .inputs.excitation import GroundMotion, Scaled
from .simulation import Simulation, next_chunk

#: steps in a member's first chunk; later chunks aim at a quarter of a second (simulation.next_chunk)
FIRST_CHUNK = 200


def gpu_available() -> str:
    """The name of the CUDA GPU numba finds ("CUDA simulator" under NUMBA_ENABLE_CUDASIM=1), or '' if none."""
    try:
        from numba import config, cuda
        if not cuda.is_available():
            return ""
        if config.ENABLE_CUDASIM:
            return "CUDA simulator"
        name = cuda.get_current_device().name
        return name.decode() if isinstance(name, bytes) else str(name)
    except Exception:  # noqa: BLE001  (no driver, no toolkit, a broken install: no GPU to use)
        return ""


def numba_cuda_installed() -> bool:
    """Whether the GPU extra's numba-cuda is installed (numba's own ``numba.cuda`` imports without it)."""
    return importlib.util.find_spec("numba_cuda") is not None


def check_members(runs: list) -> None:
    """``ValueError`` naming the member a batch's kernel cannot take: members whose scenes differ in their numbers of
    bodies, vertices, stacks, recorded interfaces or connectors from member 0's, or whose integrator differs from
    member 0's (each integrator has a kernel of its own)."""
    shape0, integrator0 = _shape(runs[0]), runs[0].settings.integrator
    for m, run in enumerate(runs):
        if _shape(run) != shape0:
            raise ValueError(f"member {m}'s scene has {_shape(run)} (bodies, vertices, stacks, interfaces, "
                             f"connectors), member 0's {shape0}: the members of a batch share their shape")
        if run.settings.integrator != integrator0:
            raise ValueError(f"member {m} runs integrator {INTEGRATORS[run.settings.integrator]!r}, member 0 "
                             f"{INTEGRATORS[integrator0]!r}: the members of a batch share their integrator")


def _shape(run: Simulation) -> tuple:
    b = run.model.bodies
    return (len(b.mass), len(b.local_x), len(run.model.stacks.bottom), len(run.model.interface_keys),
            len(run.model.connectors.law))


@dataclass
class _Motions:
    """The distinct motions at unit scale that the members scale: ``units`` [(GroundMotion, dt, inertial, lead)],
    per member its row ``index`` (M,) and ``scale`` (M,)."""

    units: list
    index: np.ndarray
    scale: np.ndarray

    def samples(self, first: int, steps: int) -> np.ndarray:
        """(G, 4, steps + 2) :func:`~dem_core.engine._ground.ground_samples` of each motion from step ``first``."""
        return np.stack([ground_samples(motion, dt, inertial, lead, first, steps)
                         for motion, dt, inertial, lead in self.units])


def _motions(runs: list) -> _Motions:
    """Group the members by the motion they scale, their step and frame: a scaled record at its unit scale
    (both components scaled by one factor), any other motion as it is at scale 1."""
    rows, units = {}, []
    index = np.empty(len(runs), np.int64)
    scale = np.ones(len(runs))
    for m, run in enumerate(runs):
        motion = run.excitation
        h, v = motion.horizontal, motion.vertical
        if isinstance(h, Scaled) and isinstance(v, Scaled) and h.factor == v.factor:
            unit, scale[m], key = GroundMotion(h.component, v.component), h.factor, (id(h.component), id(v.component))
        else:
            unit, key = motion, (id(motion),)
        key += (run.dt, run.inertial, run.ground_lead)
        if key not in rows:
            rows[key] = len(units)
            units.append((unit, run.dt, run.inertial, run.ground_lead))
        index[m] = rows[key]
    return _Motions(units, index, scale)


@dataclass
class Members:
    """A batch's arrays: the driver's named tuples with the members on their first axis (:mod:`.engine._members`),
    ``motion`` (M,) each member's row of the chunk's samples and ``status`` (M, 3) its run's end (RUNNING while it
    goes on).  What every member has alike, the blank outputs and scratch they start with and the model where every
    member shares one set-up (:func:`~dem_core.simulation.set_up_scene`), is one member's :func:`repeated` until a
    launcher writes it out where its kernel runs (:func:`written_out` on the host, on the GPU by
    :func:`_on_device`).  The members' runs keep their own states as they started."""

    model: ModelArrays
    settings: tuple
    state: State
    outputs: Outputs
    scratch: tuple
    motion: np.ndarray
    status: np.ndarray

    @property
    def integrator(self) -> int:
        """The integrator the members share (settings EXPLICIT or MOREAU), which picks their kernel."""
        return int(self.settings.integer[0, INTEGRATOR])


def _stacked(tuples: list):
    """One named tuple of the members' named tuples, each field stacked on a new first axis."""
    return type(tuples[0])(*(np.ascontiguousarray(np.stack(fields)) for fields in zip(*tuples)))


def repeated(one: tuple, count: int):
    """``one`` (a named tuple of one member's arrays) as ``count`` members' (count, ...) arrays: read-only views
    of ``one`` itself (stride 0 on the members' axis), which take no memory.  The batch's other arrays are
    writable."""
    return type(one)(*(np.broadcast_to(a, (count,) + a.shape) for a in one))


def _is_repeated(a: np.ndarray) -> bool:
    """Whether ``a`` is a :func:`repeated` view (read-only; the batch's other arrays are writable)."""
    return not a.flags.writeable


def written_out(part: tuple):
    """``part`` (a named tuple of the members' arrays) with each :func:`repeated` array copied into a C-contiguous
    array of its own (the others as they are): what the compiled kernels take."""
    return type(part)(*(np.array(a, order="C") if _is_repeated(a) else a for a in part))


def _padded_frictions(arrays: list) -> list:
    """The members' model arrays with their interfaces' own frictions padded to one length (NO_KEY matches none)."""
    longest = max(len(a.friction_keys) for a in arrays)

    def pad(a):
        extra = longest - len(a.friction_keys)
        return a._replace(friction_keys=np.concatenate([a.friction_keys, np.full(extra, NO_KEY, np.int64)]),
                          friction_values=np.concatenate([a.friction_values, np.full(extra, np.nan)]))

    return [pad(a) for a in arrays]


def pack(runs: list, motions: _Motions) -> Members:
    """The batch's :class:`Members` of ``runs`` (set up, not yet stepped, of one shape: :func:`check_members`): every
    member with a store of every pair of its bodies (a list cannot overflow it) and as many retired slips as the
    most any member starts with, and a scratch with room for the largest polygon of any member."""
    from .engine._members import RUNNING

    n_bodies = runs[0].arrays.body.shape[1]
    pairs = max(1, n_bodies * (n_bodies - 1) // 2)
    retired = max(run.state.capacities[1] for run in runs)
    settings = _stacked([run.settings for run in runs])
    settings.real[:, SCALE] = motions.scale
    outputs = runs[0].empty_outputs(max(run.output_rows for run in runs))
    arrays = [run.arrays for run in runs]
    shared = all(a is arrays[0] for a in arrays)  # one scene's set-up (set_up_scene)
    widest = arrays[0] if shared else max(arrays, key=lambda a: int(np.max(np.diff(a.vstart))))  # clipping's room
    scratch = make_scratch(widest, pairs, set(settings.integer[:, INTEGRATOR].tolist()),
                           set(settings.integer[:, CONTACT_LAW].tolist()))
    return Members(
        model=repeated(arrays[0], len(runs)) if shared else _stacked(_padded_frictions(arrays)),
        settings=settings, state=stacked_with_capacities([run.state for run in runs], pairs, retired),
        outputs=repeated(outputs, len(runs)), scratch=repeated(scratch, len(runs)), motion=motions.index.copy(),
        status=np.tile(np.array([RUNNING, 0, 0], np.int64), (len(runs), 1)))


def _on_device(members: Members, cuda) -> Members:
    """``members`` with every array copied to the GPU (named tuples of device arrays), a :func:`repeated` array
    written out there from its one member's row."""
    def moved(a):
        return _repeated_on_device(np.array(a[0], order="C"), len(a), cuda) if _is_repeated(a) else cuda.to_device(a)

    def part_moved(part):
        return type(part)(*(moved(a) for a in part)) if isinstance(part, tuple) else moved(part)

    return Members(*(part_moved(getattr(members, name)) for name in Members.__dataclass_fields__))


def _repeated_on_device(row: np.ndarray, count: int, cuda):
    """A (count, ...) device array whose every row is ``row`` (an array of its own: a row of a :func:`repeated`
    view has stride 0 on its axes of length 1, which numba's copies drop as broadcast): one copy to the GPU, then
    the rows written so far copied on the GPU after themselves, doubling them (log2(count) copies, nothing the size
    of the batch on the host)."""
    rows = cuda.device_array((count,) + row.shape, row.dtype)
    rows[0].copy_to_device(row)
    done = 1
    while done < count:
        more = min(done, count - done)
        rows[done:done + more].copy_to_device(rows[:more])
        done += more
    return rows


def cuda_launcher(threads_per_block: int | None = None):
    """``(launch, fetch)``: ``launch(members, samples, n_steps)`` runs the CUDA kernel of the members' integrator
    over them for a chunk, ``threads_per_block`` a block of threads (default
    :data:`~dem_core.engine._members.THREADS_PER_BLOCK`), and returns their status (M, 3), the arrays moved to the
    GPU at its first call and kept there;
    ``fetch(members)`` copies what the kernel writes (the state, the outputs, the status) back into ``members``."""
    from numba import cuda

    from .engine._members import KERNELS, THREADS_PER_BLOCK

    threads = threads_per_block or THREADS_PER_BLOCK
    held = []

    def launch(members: Members, samples: np.ndarray, n_steps: int) -> np.ndarray:
        if not held:
            held.append(_on_device(members, cuda))
        d = held[0]
        blocks = (len(members.status) + threads - 1) // threads
        KERNELS[members.integrator][blocks, threads](d.model, d.settings, d.state, d.outputs, d.scratch,
                                                     cuda.to_device(samples), d.motion, n_steps, d.status)
        cuda.synchronize()
        return d.status.copy_to_host()

    def fetch(members: Members) -> None:
        if held:
            members.state = State(*(a.copy_to_host() for a in held[0].state))
            members.outputs = Outputs(*(a.copy_to_host() for a in held[0].outputs))
            members.status = held[0].status.copy_to_host()

    return launch, fetch


def run_members(runs: list, progress=None, launcher=None) -> float:
    """Advance every run of ``runs`` (:class:`Simulation` runs set up and not yet stepped) to its end on the GPU,
    each left as its own :meth:`Simulation.advance` would leave it; returns the kernel's wall time (s).  A member whose
    store of retired slips fills is run again from its start on the CPU.

    progress : optional ``function(done, total)`` after each chunk, ``done`` the members that ended; what it raises
    (Ctrl-C too) stops the batch, each run keeping the state of the last chunk.  launcher : ``(launch, fetch)``
    (default :func:`cuda_launcher`; :func:`serial_launcher` runs the kernel's code on the CPU)."""
    from .engine._members import RUNNING

    check_members(runs)
    motions = _motions(runs)
    members = pack(runs, motions)
    launch, fetch = launcher if launcher is not None else cuda_launcher()
    last = max(run.settings.last_step for run in runs)
    step, chunk, took = 0, FIRST_CHUNK, 0.0
    try:
        while step < last:
            n_steps = min(chunk, last - step)
            started = time.perf_counter()
            status = launch(members, motions.samples(step, n_steps), n_steps)
            spent = time.perf_counter() - started
            took += spent
            step += n_steps
            if progress is not None:
                progress(int(np.sum(status[:, 0] != RUNNING)), len(runs))
            if np.all(status[:, 0] != RUNNING):
                break
            chunk = next_chunk(chunk, spent)
    finally:
        fetch(members)
        _hand_back(runs, members, took)
    return took


def _hand_back(runs: list, members: Members, took: float) -> None:
    """Each run's state, outputs and status from the batch's arrays (its share of the kernel's wall time as its run
    time); a member whose store filled is run again from its start on the CPU, and a batch stopped before its
    launcher first wrote the outputs out leaves each run as it was set up.  A run's outputs are views of its rows of
    the batch's (copying them would hold every member's outputs twice): the batch's outputs stay in memory while any
    run's do."""
    from .engine._members import RUNNING

    for m, run in enumerate(runs):
        code, i, j = (int(x) for x in members.status[m])
        run.run_time = took / len(runs)
        if code == STATUS_FULL:  # the run's own state is still its start's
            run.advance()
            continue
        if _is_repeated(members.outputs.pos):  # no kernel wrote them out: the batch stopped before its first chunk
            continue
        run.state = State(*(a[m].copy() for a in members.state))
        run.outputs = Outputs(*(a[m, :run.output_rows] for a in members.outputs))
        if code != RUNNING:
            run.status, run.stopped_by = code, ((i, j) if code != STATUS_OK else None)


def serial_launcher():
    """``(launch, fetch)`` of the GPU kernel's code compiled for one CPU thread
    (:data:`~dem_core.engine._members.SERIAL`): the GPU path checked without a GPU."""
    from .engine._members import SERIAL

    def launch(members: Members, samples: np.ndarray, n_steps: int) -> np.ndarray:
        members.model = written_out(members.model)
        members.outputs = written_out(members.outputs)
        members.scratch = written_out(members.scratch)
        SERIAL[members.integrator](members.model, members.settings, members.state, members.outputs, members.scratch,
                               samples, members.motion, n_steps, members.status)
        return members.status

    return launch, lambda members: None
