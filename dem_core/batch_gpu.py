"""A batch's members stepped together on an NVIDIA GPU (numba-cuda, float64), one thread per member.

:func:`run_members` takes members set up on the CPU as :class:`~dem_core.simulation.Simulation` runs, copies
their models and states to the device as arrays with the members on their first axis, advances them all by the
kernel of :mod:`dem_core.engine._members` in chunks of steps, and hands each run its state and outputs back, so
that :meth:`Simulation.result` gathers each member as it does a run of :func:`~dem_core.simulate`.  A motion
that is a scaled record (:func:`~dem_core.inputs.excitation.scaled`) is sampled once for all the members that
scale it, and each member's thread scales it.
"""

from __future__ import annotations

import inspect
import time
from dataclasses import dataclass

import numpy as np

from .engine import _step
from .engine._broadphase import relist
from .engine._contact_law import CORNER
from .engine._ground import ground_samples
from .engine.state import Retired, empty_contacts
from .inputs.excitation import GroundMotion, Scaled
from .simulation import CHUNK_SECONDS, Simulation

#: steps in a member's first chunk; later chunks aim at CHUNK_SECONDS of wall time
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


def check_members(runs: list) -> None:
    """``ValueError`` naming the member the GPU kernel cannot take: Moreau-Jean's runs, or members whose scenes
    differ in their numbers of bodies, vertices, stacks or recorded interfaces from member 0's."""
    shape0 = _shape(runs[0])
    for m, run in enumerate(runs):
        if run.integrator != "explicit":
            raise ValueError(f"member {m}: the GPU kernel steps by central differences (integrator='explicit'); "
                             f"Moreau-Jean's runs go on the CPU (device='cpu')")
        if _shape(run) != shape0:
            raise ValueError(f"member {m}'s scene has {_shape(run)} (bodies, vertices, stacks, interfaces), member "
                             f"0's {shape0}: the members of a GPU batch share their shape")


def _shape(run: Simulation) -> tuple:
    b = run.model.bodies
    return len(b.mass), len(b.local_x), len(run.model.stacks.bottom), len(run.model.interface_keys)


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


def _all_pairs(run: Simulation):
    """The contact store of every pair of bodies, in key order (constants as the broad phase gives them)."""
    n = len(run.model.bodies.mass)
    keys = np.array([i * n + j for i in range(n) for j in range(i + 1, n)], np.int64)
    retired = Retired(np.zeros(1, np.int64), np.zeros(1), np.zeros(1, np.int64))
    contacts, _ = relist(run.model.bodies, run.model.law, run.model.interface_keys, empty_contacts(1), retired, keys)
    return contacts


#: the model's arrays of each member, by the kernel's argument names: (where in the run, dtype)
_MODEL = {
    "local_x": ("bodies.local_x", float), "local_y": ("bodies.local_y", float),
    "normal_x": ("bodies.normal_x", float), "normal_y": ("bodies.normal_y", float),
    "vstart": ("bodies.vstart", np.int64), "mass": ("bodies.mass", float), "inv_mass": ("bodies.inv_mass", float),
    "inv_inertia": ("bodies.inv_inertia", float), "radius": ("bodies.radius", float),
    "critical_angle": ("bodies.critical_angle", float), "y_start": ("bodies.y_start", float),
    "drop_limit": ("bodies.drop_limit", float), "stack_id": ("stacks.stack_id", np.int64),
    "bottom": ("stacks.bottom", np.int64), "stack_mass": ("stacks.mass", float), "foot": ("stacks.foot", float),
}
#: the tracking arrays of each member's state, by the kernel's argument names (the same as the fields')
_TRACKING = ("interface_slip", "peak_theta", "overturn_step", "stack_step", "ledger", "counters", "built_at")


def _pack(runs: list, motions: _Motions) -> dict:
    """The kernel's arrays, members on the first axis, by the names of
    :func:`~dem_core.engine._members.advance_members`' arguments; ``"_stores"`` the members' contact stores."""
    from .engine import _members as k

    count = len(runs)
    nb, nv, ns, n_if = _shape(runs[0])
    stores = [_all_pairs(run) for run in runs]
    n_pairs = int(stores[0].count[0])
    corner = [run.model.law.law == CORNER for run in runs]
    clip = 2 * max(3, int(np.max(np.diff(runs[0].model.bodies.vstart)))) + 2
    points = n_pairs if any(corner) else 1  # the corner law's points, the overlap law's polygons, per pair
    polygons = 1 if all(corner) else n_pairs
    n_out = max(len(run.out_step) for run in runs)

    def stacked(values, dtype=float):
        return np.ascontiguousarray(np.stack([np.asarray(v, dtype) for v in values]))

    arrays = {name: stacked([_field(run.model, where) for run in runs], dtype)
              for name, (where, dtype) in _MODEL.items()}
    arrays.update({name: stacked([getattr(run.state.tracking, name) for run in runs],
                                 np.int64 if name in ("overturn_step", "stack_step", "counters") else float)
                   for name in _TRACKING})
    # the list is made at the first step (built_at is infinite): none listed before
    arrays.update(listed=np.zeros((count, n_pairs), np.int64), in_list=np.zeros((count, n_pairs), np.int64),
                  n_listed=np.zeros(count, np.int64), fill=np.zeros((count, nb), np.int64))
    real = np.zeros((count, k.REAL_SETTINGS))
    integer = np.zeros((count, k.INTEGER_SETTINGS), np.int64)
    for m, run in enumerate(runs):
        s, law, model = run.settings, run.model.law, run.model
        real[m, [k.DT, k.SPEED_LIMIT, k.ENERGY_TOLERANCE, k.ENERGY_SCALE, k.GRAVITY, k.FLOOR, k.ZETA_N, k.ZETA_T,
                 k.SCALE, k.START_X, k.START_Y, k.HALF_SKIN]] = (
            s.dt, s.speed_limit, s.energy_tolerance, s.energy_scale, model.gravity, model.floor, law.zeta_n,
            law.zeta_t, motions.scale[m], *model.bodies.centroid0[0], 0.5 * law.skin)
        integer[m, [k.STRIDE, k.LAST_STEP, k.STOP_AT_OVERTURN, k.SUBSTEPS, k.CORNER_LAW, k.INERTIAL, k.MOTION]] = (
            s.stride, s.last_step, s.stop_at_overturn, s.substeps, law.law == CORNER, run.inertial,
            motions.index[m])
    arrays.update(
        real=real, integer=integer,
        limits=stacked([run.model.law.max_penetration * (run.model.bodies.size if run.model.law.law == CORNER
                                                          else run.model.bodies.area) for run in runs]),
        ids=stacked([store.ids[:n_pairs] for store in stores], np.int64),
        constants=stacked([store.constants[:n_pairs] for store in stores]),
        memory=stacked([store.memory[:n_pairs] for store in stores], np.int64),
        forces=stacked([store.forces[:n_pairs] for store in stores]),
        start=np.zeros((count, nb + 1), np.int64), entries=np.zeros((count, 2 * n_pairs), np.int64),
        pos=stacked([run.state.pos for run in runs]), vel=stacked([run.state.vel for run in runs]),
        out_pos=np.full((count, n_out, nb, 3), np.nan), out_slip=np.full((count, n_out, n_if), np.nan),
        out_step=np.zeros((count, n_out), np.int64),
        status=np.tile(np.array([k.RUNNING, 0, 0], np.int64), (count, 1)),
        wx=np.zeros((count, nv)), wy=np.zeros((count, nv)), wnx=np.zeros((count, nv)), wny=np.zeros((count, nv)),
        boxes=np.zeros((count, 4, nb)), force=np.zeros((count, nb, 3)), stack_moment=np.zeros((count, ns)),
        window=np.zeros((count, 6, 2)), pair_force=np.zeros((count, n_pairs, 6)),
        pair_touching=np.zeros((count, n_pairs), np.int64), pair_excess=np.zeros((count, n_pairs)),
        points=np.zeros((count, points, 2, 3)), keys=np.zeros((count, points, 2), np.int64),
        ox=np.zeros((count, polygons, clip)), oy=np.zeros((count, polygons, clip)),
        clip_scratch=np.zeros((count, polygons, 2, 2, clip)), _stores=stores)
    return arrays


def _field(model, where: str):
    part, name = where.split(".")
    return getattr(getattr(model, part), name)


#: the arrays a finished batch hands back to its runs
STATE_ARRAYS = ("pos", "vel", "memory", "forces", *_TRACKING, "out_pos", "out_slip", "out_step", "status")


def _kernel_arguments() -> tuple:
    """The names of the kernels' arrays, in order: :func:`~dem_core.engine._members.member_chunk`'s arguments
    after the member (the keys of :func:`_pack`'s arrays, and the chunk's ``samples`` and ``n_steps``)."""
    from .engine._members import member_chunk

    return tuple(inspect.signature(getattr(member_chunk, "py_func", member_chunk)).parameters)[1:]  # or, JIT off


def cuda_launcher():
    """``(launch, fetch)``: ``launch(arrays, samples, n_steps)`` runs the CUDA kernel over the members for a chunk
    and returns their status (M, 3), the arrays moved to the GPU at its first call and kept there;
    ``fetch(arrays)`` copies the state (:data:`STATE_ARRAYS`) back into ``arrays``."""
    from numba import cuda

    from .engine._members import THREADS_PER_BLOCK, advance_members

    names = _kernel_arguments()
    on_device = {}

    def launch(arrays: dict, samples: np.ndarray, n_steps: int) -> np.ndarray:
        if not on_device:
            on_device.update({name: cuda.to_device(arrays[name]) for name in names
                              if name not in ("samples", "n_steps")})
        given = dict(on_device, samples=cuda.to_device(samples), n_steps=n_steps)
        members = arrays["pos"].shape[0]
        blocks = (members + THREADS_PER_BLOCK - 1) // THREADS_PER_BLOCK
        advance_members[blocks, THREADS_PER_BLOCK](*(given[name] for name in names))
        cuda.synchronize()
        return on_device["status"].copy_to_host()

    def fetch(arrays: dict) -> None:
        for name in STATE_ARRAYS:
            arrays[name] = on_device[name].copy_to_host() if on_device else arrays[name]

    return launch, fetch


def run_members(runs: list, progress=None, launcher=None) -> float:
    """Advance every run of ``runs`` (explicit :class:`Simulation` runs set up and not yet stepped) to its end on
    the GPU, each left as its own :meth:`Simulation.run` would leave it; returns the kernel's wall time (s).

    progress : optional ``function(done, total)`` after each chunk, ``done`` the members that ended; what it raises
    (Ctrl-C too) stops the batch, each run keeping the state of the last chunk.  launcher : ``(launch, fetch)``
    (default :func:`cuda_launcher`)."""
    from .engine._members import RUNNING

    check_members(runs)
    motions = _motions(runs)
    arrays = _pack(runs, motions)
    launch, fetch = launcher if launcher is not None else cuda_launcher()
    last = max(run.settings.last_step for run in runs)
    step, chunk, took = 0, FIRST_CHUNK, 0.0
    try:
        while step < last:
            n_steps = min(chunk, last - step)
            started = time.perf_counter()
            status = launch(arrays, motions.samples(step, n_steps), n_steps)
            spent = time.perf_counter() - started
            took += spent
            step += n_steps
            if progress is not None:
                progress(int(np.sum(status[:, 0] != RUNNING)), len(runs))
            if np.all(status[:, 0] != RUNNING):
                break
            chunk = int(min(max(chunk * CHUNK_SECONDS / max(spent, 1e-6), 100), 50 * chunk))
    finally:
        fetch(arrays)
        _hand_back(runs, arrays, took)
    return took


def _hand_back(runs: list, arrays: dict, took: float) -> None:
    """Each run's state, outputs and status from the batch's arrays (its share of the kernel's wall time as
    its run time)."""
    from .engine._members import RUNNING

    for m, run in enumerate(runs):
        s = run.state
        s.pos[:], s.vel[:] = arrays["pos"][m], arrays["vel"][m]
        store = arrays["_stores"][m]
        n_pairs = arrays["memory"].shape[1]
        store.memory[:n_pairs], store.forces[:n_pairs] = arrays["memory"][m], arrays["forces"][m]
        s.contacts = store
        t = s.tracking
        for name in _TRACKING:
            getattr(t, name)[:] = arrays[name][m]
        n_out = len(run.out_step)
        run.out_pos[:] = arrays["out_pos"][m, :n_out]
        run.out_slip[:] = arrays["out_slip"][m, :n_out]
        run.out_step[:] = arrays["out_step"][m, :n_out]
        code, i, j = (int(x) for x in arrays["status"][m])
        if code != RUNNING:
            run.status, run.stopped_by = code, ((i, j) if code != _step.STATUS_OK else None)
        run.run_time = took / len(runs)


def serial_launcher():
    """``(launch, fetch)`` of the GPU kernel's code compiled for one CPU thread
    (:func:`~dem_core.engine._members.advance_members_serial`): the GPU path checked without a GPU."""
    from .engine._members import advance_members_serial

    names = _kernel_arguments()

    def launch(arrays: dict, samples: np.ndarray, n_steps: int) -> np.ndarray:
        given = dict(arrays, samples=samples, n_steps=n_steps)
        advance_members_serial(arrays["pos"].shape[0], *(given[name] for name in names))
        return arrays["status"]

    return launch, lambda arrays: None
