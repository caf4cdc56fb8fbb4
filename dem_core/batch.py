"""Many runs of one scene at once: ``simulate_batch(scene, motions, ...)``, one row of measures per member.

A study is many runs of one scene under different ground motions (a threshold scan's scales, an ensemble's
records, a fragility curve's stripes), or with different parameters (friction, contact stiffness).  Each member
here is the run :func:`~dem_core.simulate` gives with the same options, bit for bit: it is a
:class:`~dem_core.simulation.Simulation` stepped by the same compiled kernel.  The kernels release the GIL, so
the members run side by side on ``threads`` Python threads, one member per thread at a time; a member's time
history is kept only where asked for, so memory does not grow with the number of members.
"""

from __future__ import annotations

import difflib
import inspect
import itertools
import queue
import threading
import time
import warnings
from concurrent.futures import FIRST_COMPLETED, ThreadPoolExecutor, wait
from dataclasses import dataclass, field

import numba
import numpy as np
import pandas as pd

from . import batch_gpu
from .batch_gpu import gpu_available, numba_cuda_installed
from .gpu_kernels import load_named_kernels
from .engine.result import Result
from .inputs.excitation import GroundMotion, MotionSequence, describe, strong_motion_cuts
from .inputs.number_types import is_integer
from .inputs.run_settings import check_settings
from .simulation import Simulation, SimulationUnstable, check_run_arguments, set_up_scene, warn_caller

#: where a batch can run: ``"auto"`` takes the GPU where numba-cuda finds one and the batch has at least
#: GPU_MEMBERS_PER_THREAD members per CPU thread, else the CPU's threads
DEVICES = ("auto", "cpu", "gpu")
#: a GPU thread steps a member about 320 times slower than a CPU core, under either integrator (the device check on
#: an H200 against the development machine's cores, docs/performance.md "The device check on an H200: first
#: measurements"), so the GPU is the faster where a batch has more members than this many per CPU thread
GPU_MEMBERS_PER_THREAD = 320
#: members queued per thread at a time (so that waiting for the next to finish does not grow with the batch)
IN_FLIGHT_PER_THREAD = 4
#: s the main thread waits for a member at most before it looks again: a Ctrl-C is taken between two looks
WAKE_SECONDS = 0.2
#: one member at a time records the warnings of its set-up (the warnings module's filters are global, not per
#: thread); the caller's thread gives each distinct one once, attributed to the caller's line, holding it too
_RECORDING = threading.Lock()
#: the options of simulate that a scene's set-up depends on (set_up_scene's keywords)
STEP_OPTIONS = tuple(inspect.signature(set_up_scene).parameters)[1:]
#: the keywords of simulate that a batch passes to every member's run (``simulate_options``): Simulation's after
#: its scene, motion and duration, but the set-up, which the batch makes, and ``parallel``, which does not apply
MEMBER_OPTIONS = tuple(name for name in tuple(inspect.signature(Simulation).parameters)[3:]
                       if name not in ("scene_set_up", "parallel"))
#: the options check_settings checks without a scene
CHECKED_SETTINGS = tuple(inspect.signature(check_settings).parameters)


@dataclass(frozen=True)
class Batch:
    """What :func:`simulate_batch` returns.

    table : one row per member, in the order of the motions (see :func:`member_row` for the columns).
    histories : {member index: :class:`Result`} of the members asked for.
    device : where the members ran, in words (``"cpu, 2 threads"``).
    wall_time_s : s, the batch from its first member's set-up to its last member's measures.
    """

    table: pd.DataFrame
    histories: dict = field(default_factory=dict)
    device: str = ""
    wall_time_s: float = float("nan")


class _Rows(dict):
    """The members' rows by member, and the members whose rows came since :meth:`taken` was last called."""

    def __init__(self):
        super().__init__()
        self._new = []

    def __setitem__(self, member, row):
        if member not in self:
            self._new.append(member)
        super().__setitem__(member, row)

    def taken(self) -> list:
        """The members whose rows came since the last call, in the order they came."""
        new, self._new = self._new, []
        return new


class BatchInterrupted(KeyboardInterrupt):
    """Ctrl-C during a batch: the members that finished are in ``partial`` (a :class:`Batch`)."""

    def __init__(self, partial: Batch):
        super().__init__(f"interrupted after {len(partial.table)} members")
        self.partial = partial


def simulate_batch(scene, motions, duration: float | None = None, *, device: str = "auto",
                   threads: int | None = None, histories=(), measures=None, progress=None, finished=None,
                   **simulate_options) -> Batch:
    """Run ``scene`` under each of ``motions``; one row of measures per member.

    scene : :class:`~dem_core.Scene`, shared by every member, or a list (or tuple) of M scenes, one per member:
        the same blocks (by name) with parameters of their own (friction, contact stiffness, ...).
    motions : sequence of M :class:`~dem_core.inputs.excitation.GroundMotion`, one per member, or one motion for
        every member of a sequence of scenes.
    duration : s, as :func:`~dem_core.simulate` takes it (None: each motion's natural end).
    device : ``"cpu"`` (Python threads, each running the compiled kernel, which releases the GIL), ``"gpu"``
        (every member at once on an NVIDIA GPU, :mod:`dem_core.batch_gpu`, a kernel per integrator; refused
        naming why where numba-cuda finds no GPU, or where a member's motion is a sequence of ground motions,
        :func:`~dem_core.inputs.excitation.sequence`, whose events only the CPU's runs start at their own steps), or
        ``"auto"``: the GPU where there is one, no member's motion is a sequence and there are at least
        GPU_MEMBERS_PER_THREAD members per thread, else the CPU.
        :attr:`Batch.device` says which ran.
    threads : how many members run at once on the CPU (default ``numba.get_num_threads()``, all cores).
    histories : indices of the members whose :class:`Result` is kept (in :attr:`Batch.histories`).
    measures : optional ``function(result) -> dict`` whose items are added to each member's row.  On the GPU the
        histories of a result outside ``histories`` are views of the batch's outputs: a ``measures`` that keeps
        such a result keeps them all.
    progress : optional ``function(done, total)`` called as members finish.
    finished : optional ``function(member, row)`` called on the caller's thread with each member's row as soon as
        the batch has it (as each member ends on the CPU, when the batch ends on the GPU, and for the members that
        finished when the batch is stopped), to save it as it comes.
    simulate_options : the keyword arguments of :func:`~dem_core.simulate` (``dt``, ``integrator``, ...), the
        same for every member; ``parallel`` does not apply (the batch spreads members, not one run).

    A member that loses stability does not stop the others: its row has ``status`` ``"unstable"``, the
    error's message and the measures of its partial result; a member whose motion cannot be run (no natural end
    and no duration, too many steps, a peak beyond 50 g) has ``status`` ``"refused"`` and the reason.  The scene,
    the motions and the options are checked before any member runs (``TypeError``/``ValueError`` naming the
    culprit, or member 0 when every member is refused).  Ctrl-C stops the running members after their current
    chunk (a quarter of a second) and raises :class:`BatchInterrupted` carrying the members that finished; any
    other exception (from ``measures``, say) stops the batch the same way and goes on.  The members' warnings (a
    step beyond the stability limit, a long run) are given on the caller's thread as members start (within
    WAKE_SECONDS), each distinct one once, at the caller's line.
    """
    threads, scenes, motions, keep = _checked(scene, motions, duration, device, threads, histories,
                                              simulate_options)
    for said in strong_motion_cuts((motion, duration) for motion in motions):
        warn_caller(f"the strong motion is cut: {said}")
    gpu = _gpu_for(device, motions, threads)
    started = time.perf_counter()
    rows, given, shared = _Rows(), set(), {}
    first, built, said = _first_member(scenes, motions, duration, simulate_options, rows, shared)
    _give(said, given)
    def announce():
        for m in rows.taken():
            if finished is not None:
                finished(m, rows[m])

    def told(done, total):
        announce()
        if progress is not None:
            progress(done, total)

    run = _on_gpu if gpu else _on_cpu
    try:
        return run(gpu or threads, scenes, motions, duration, simulate_options, keep, measures, told, rows, first,
                   built, given, started, shared)
    finally:
        announce()


def _on_cpu(threads: int, scenes, motions, duration, simulate_options, keep, measures, progress, rows: dict,
            first: int, built, given: set, started: float, shared: dict) -> Batch:
    """The batch's members from ``first`` on, on ``threads`` threads (:func:`_run_members`), each set up in its
    thread and its warnings given on this one; the arguments as :func:`_on_gpu` takes them."""
    kept, heard = {}, queue.SimpleQueue()

    def give_heard():
        while not heard.empty():
            _give(heard.get(), given)

    stop = threading.Event()

    def halt(done, total):
        if stop.is_set():
            raise _Stopped

    def run_member(m: int) -> tuple:
        set_up = time.perf_counter()
        try:
            if m == first:
                run = built
            else:
                run, said = _set_up(scenes[m], motions[m], duration, simulate_options, shared)
                heard.put(said)
        except (ValueError, TypeError) as error:
            return _refused(m, motions[m], error), None
        try:
            run.advance(progress=halt)
        except _Stopped:
            return None, None
        row, result = _measured(m, motions[m], run, time.perf_counter() - set_up, measures)
        return row, (result if m in keep else None)

    try:
        _run_members(run_member, range(first, len(motions)), threads, stop, progress, rows, kept, give_heard,
                     len(motions))
    except KeyboardInterrupt:
        raise BatchInterrupted(_batch(rows, kept, _cpu(threads), started)) from None
    finally:
        give_heard()
    return _batch(rows, kept, _cpu(threads), started)


def _measured(m: int, motion: GroundMotion, run: Simulation, seconds: float, measures) -> tuple:
    """``(row, result)`` of member ``m``'s finished ``run`` (:func:`member_row`, ``seconds`` its wall time, with the
    items of ``measures(result)``); an unstable run's row has its error and the measures of its partial result."""
    try:
        result, status, error = run.result(), "ok", ""
    except SimulationUnstable as unstable:
        result, status, error = unstable.partial, "unstable", str(unstable)
    row = member_row(m, motion, result, status, error, seconds)
    if measures is not None:
        row.update(measures(result))
    return row, result


class _Stopped(Exception):
    """A member's run stopped between its chunks because the batch was interrupted."""


def _set_up(scene, motion, duration, simulate_options, scenes_set_up: dict) -> tuple:
    """``(Simulation, [the warnings its set-up gave])``, the warnings kept off the screen.  The scene's
    :func:`~dem_core.simulation.set_up_scene` (its model and time step) is made once per scene object and kept in
    ``scenes_set_up`` (by the object's id: the batch holds the scenes) for the members that share it."""
    with _RECORDING, warnings.catch_warnings(record=True) as said:
        warnings.simplefilter("always")
        if id(scene) not in scenes_set_up:
            scenes_set_up[id(scene)] = set_up_scene(scene, **{name: simulate_options[name] for name in STEP_OPTIONS
                                                              if name in simulate_options})
        return Simulation(scene, motion, duration, scene_set_up=scenes_set_up[id(scene)], **simulate_options), said


def _give(said: list, given: set) -> None:
    """The warnings ``said`` that are not in ``given`` (message and category), warned on this thread and added."""
    with _RECORDING:
        for warning in said:
            key = (str(warning.message), warning.category)
            if key not in given:
                given.add(key)
                warn_caller(*key)


def _refused(m: int, motion, error: Exception) -> dict:
    """A refused member's row: what its motion is (:func:`~dem_core.inputs.excitation.describe`, as
    :func:`member_row` gives it), its status and why."""
    return {"member": m, **describe(motion), "status": "refused", "error": str(error)}


def _first_member(scenes, motions, duration, simulate_options, rows: dict, shared: dict) -> tuple:
    """``(index, Simulation, its warnings)`` of the first member that can be set up (which compiles the kernel),
    the members before it put in ``rows`` as refused; the error of member 0, naming it, when none can be.
    ``shared``: the scenes' set-ups (:func:`_set_up`)."""
    for m, motion in enumerate(motions):
        try:
            return (m, *_set_up(scenes[m], motion, duration, simulate_options, shared))
        except (ValueError, TypeError) as error:
            rows[m] = _refused(m, motion, error)
            if m == 0:
                refusal = error
    raise type(refusal)(f"every member was refused; member 0 ({motions[0].name}): {refusal}")


def _run_members(run_member, members, threads: int, stop: threading.Event, progress, rows: dict, kept: dict,
                 give_heard, total: int) -> None:
    """``run_member(m)`` for each of ``members`` on ``threads`` threads, at most IN_FLIGHT_PER_THREAD of them
    queued per thread, its ``(row, result or None)`` put in ``rows`` and ``kept`` as it finishes; ``progress(done,
    total)`` after each; ``give_heard()`` on this thread at every look (the warnings of the members set up since).
    On any exception (Ctrl-C among them) the running members stop after their chunk (``stop``), those not started
    are dropped, and the exception goes on once the running ones have handed back what they have."""
    waiting = iter(members)
    with ThreadPoolExecutor(threads, thread_name_prefix="dem-batch") as pool:
        pending = {}

        def collect(future, m):
            row, result = future.result()
            if row is not None:
                rows[m] = row
            if result is not None:
                kept[m] = result

        try:
            for m in itertools.islice(waiting, IN_FLIGHT_PER_THREAD * threads):
                pending[pool.submit(run_member, m)] = m
            while pending:
                done, _ = wait(pending, timeout=WAKE_SECONDS, return_when=FIRST_COMPLETED)
                give_heard()
                for future in done:
                    collect(future, pending.pop(future))
                    if progress is not None:
                        progress(len(rows), total)
                    for m in itertools.islice(waiting, 1):
                        pending[pool.submit(run_member, m)] = m
        except BaseException:
            stop.set()
            for future in pending:
                future.cancel()
            wait(pending)
            for future, m in pending.items():
                if not future.cancelled() and future.exception() is None:
                    collect(future, m)
            raise


def check_device(device: str) -> None:
    """``ValueError`` naming why a batch cannot run on ``device``: not one of :data:`DEVICES`, or ``"gpu"`` where
    numba-cuda finds no GPU."""
    if device not in DEVICES:
        raise ValueError(f"device must be one of {DEVICES}, got {device!r}")
    if device == "gpu" and not gpu_available():
        why = ("numba-cuda finds no CUDA GPU here (an NVIDIA GPU and its driver are needed)" if numba_cuda_installed()
               else "numba-cuda, the GPU extra, is not installed (pip install -e '.[gpu]', on a machine with an "
                    "NVIDIA GPU and its driver)")
        raise ValueError(f"device='gpu': {why}; device='cpu' or 'auto' runs the members on the CPU's threads")


def _gpu_for(device: str, motions: list, threads: int) -> str:
    """The GPU's name if the batch of members under ``motions`` runs there, else ''.  A member under a sequence of
    ground motions runs on the CPU, whose runs start each event at its own step (``"auto"`` takes the CPU, ``"gpu"``
    is refused naming the member)."""
    sequences = [m for m, motion in enumerate(motions) if isinstance(motion, MotionSequence)]
    if device == "gpu" and sequences:
        first = sequences[0]
        raise ValueError(f"device='gpu': member {first}'s motion '{motions[first].name}' is a sequence of ground "
                         f"motions, whose events the GPU's kernel does not start at their own steps: run the batch "
                         f"with device='cpu' (or 'auto'), whose threads run each member as simulate does")
    if sequences:
        return ""
    if device == "gpu" or (device == "auto" and len(motions) >= GPU_MEMBERS_PER_THREAD * threads):
        return gpu_available()
    return ""


def _on_gpu(gpu: str, scenes, motions, duration, simulate_options, keep, measures, progress, rows: dict,
            first: int, built, given: set, started: float, shared: dict) -> Batch:
    """The batch's members set up on this thread and stepped together on the GPU (:func:`batch_gpu.run_members`);
    the members before ``first`` are refused in ``rows``, ``built`` is member ``first`` set up, ``shared`` the
    scenes' set-ups (:func:`_set_up`)."""
    load_named_kernels()
    runs, set_up = {first: built}, {first: 0.0}
    for m in range(first + 1, len(motions)):
        began = time.perf_counter()
        try:
            runs[m], said = _set_up(scenes[m], motions[m], duration, simulate_options, shared)
        except (ValueError, TypeError) as error:
            rows[m] = _refused(m, motions[m], error)
            continue
        _give(said, given)
        set_up[m] = time.perf_counter() - began
    members = sorted(runs)
    kept = {}
    try:
        took = batch_gpu.run_members([runs[m] for m in members], progress=(
            None if progress is None else lambda done, total: progress(done + len(rows), len(motions))))
    except KeyboardInterrupt:
        _gpu_rows(runs, members, motions, measures, keep, rows, kept, set_up, 0.0, ended_only=True)
        raise BatchInterrupted(_batch(rows, kept, f"gpu, {gpu}", started)) from None
    _gpu_rows(runs, members, motions, measures, keep, rows, kept, set_up, took / len(members))
    return _batch(rows, kept, f"gpu, {gpu}", started)


def _gpu_rows(runs: dict, members: list, motions, measures, keep, rows: dict, kept: dict, set_up: dict,
              share: float, ended_only: bool = False) -> None:
    """The rows (and kept results) of the GPU's members, ``share`` (s) of the kernel's time added to each one's
    set-up; with ``ended_only`` only the members whose runs ended."""
    for m in members:
        run = runs[m]
        if ended_only and run.status is None:
            continue
        if m in keep and run.outputs is not None:  # its own outputs, not views that hold every member's
            run.outputs = type(run.outputs)(*(a.copy() for a in run.outputs))
        rows[m], result = _measured(m, motions[m], run, set_up[m] + share, measures)
        if m in keep:
            kept[m] = result


def _check_options(simulate_options: dict) -> None:
    """``TypeError`` naming the first of ``simulate_options`` that is not an option of the members' runs (with the
    closest of simulate_batch's keywords and theirs)."""
    for name in simulate_options:
        if name not in MEMBER_OPTIONS:
            known = [*MEMBER_OPTIONS, *(k for k in inspect.signature(simulate_batch).parameters
                                        if k != "simulate_options")]
            close = difflib.get_close_matches(name, known, n=1)
            raise TypeError(f"simulate_batch has no option {name!r}"
                            + (f" (did you mean {close[0]!r}?)" if close else "")
                            + f"; its members' runs take {', '.join(MEMBER_OPTIONS)}")


def _checked(scene, motions, duration, device, threads, histories, simulate_options) -> tuple:
    """``(threads, the members' scenes and motions as lists, members whose histories are kept)``, or the error
    naming what is wrong."""
    check_device(device)
    if "parallel" in simulate_options:
        raise TypeError("simulate_batch spreads its members over threads; 'parallel' (one run over threads) does "
                        "not apply")
    _check_options(simulate_options)
    check_settings(duration=duration, **{name: value for name, value in simulate_options.items()
                                         if name in CHECKED_SETTINGS})
    threads = _thread_count(threads)
    scenes, motions = _member_inputs(scene, motions)
    for m, (member_scene, motion) in enumerate(zip(scenes, motions)):
        try:
            check_run_arguments(member_scene, motion)
        except TypeError as error:
            raise TypeError(f"member {m}: {error}") from None
        if member_scene.block_names != scenes[0].block_names:
            raise ValueError(f"member {m}'s scene has blocks {member_scene.block_names}, member 0's "
                             f"{scenes[0].block_names}: the members of a batch share their blocks (the table has a "
                             f"column per block)")
    return threads, scenes, motions, _members(histories, len(motions))


def _member_inputs(scene, motions) -> tuple:
    """The members' scenes and motions, two lists of M: a scene or a motion given once stands for every member."""
    scenes = list(scene) if isinstance(scene, (list, tuple)) else None
    if isinstance(motions, GroundMotion):
        if scenes is None:
            raise TypeError("motions is one ground motion: give a sequence, one per member, or a sequence of scenes")
        motions = [motions] * len(scenes)
    motions = list(motions)
    if scenes is None:
        scenes = [scene] * len(motions)
    if not motions:
        raise ValueError("motions is empty: give one ground motion per member")
    if len(scenes) != len(motions):
        raise ValueError(f"{len(scenes)} scenes and {len(motions)} motions: give one of each per member, or one "
                         f"motion for every scene")
    return scenes, motions


def member_row(member: int, motion: GroundMotion, result: Result, status: str, error: str,
               wall_time: float) -> dict:
    """One member's row: ``member``; ``motion`` (its name), ``record`` (what it scales), ``scale`` (the factor),
    ``pga_m_s2`` and ``pgv_m_s`` (:func:`~dem_core.inputs.excitation.describe`); ``status`` (``"ok"``,
    ``"unstable"``, ``"refused"``), ``error`` (the message, or ''), the scene's measures
    (:meth:`Result.measures`), ``dt_s``, ``steps``, ``wall_time_s`` (its set-up, run and measures), where the
    scene has connectors how many ``connectors_yielded`` and ``connectors_ruptured`` (``connectors_pulled_out`` of
    them in tension) and their ``peak_connector_shear_N``, and for each block ``<measure>[<block>]`` of its measures
    (:func:`block_columns`)."""
    row = {"member": member, **describe(motion), "status": status, "error": error, **result.measures(),
           "dt_s": result.dt, "steps": int(result.info.get("steps", 0)), "wall_time_s": wall_time}
    if result.connectors is not None:
        row.update(connectors_yielded=int(result.connectors.yielded.sum()),
                   connectors_ruptured=int(result.connectors.ruptured.sum()),
                   connectors_pulled_out=int(result.connectors.pulled_out.sum()),
                   peak_connector_shear_N=float(result.connectors.peak_shear_N.max()))
    return {**row, **block_columns(result)}


def block_columns(result: Result) -> dict:
    """``{"<measure>[<block>]": value}``: each block's :data:`~dem_core.engine.result.BLOCK_MEASURES`
    (:meth:`Result.block_measures`) as plain numbers, a block's measures together, the blocks in the scene's order:
    the per-block columns of a batch's rows and of a sweep's."""
    measures = {measure: np.asarray(values).tolist() for measure, values in result.block_measures().items()}
    return {f"{measure}[{name}]": values[b] for b, name in enumerate(result.names)
            for measure, values in measures.items()}


def _cpu(threads: int) -> str:
    return f"cpu, {threads} thread{'s' * (threads > 1)}"


def _batch(rows: dict, kept: dict, device: str, started: float) -> Batch:
    table = pd.DataFrame([rows[m] for m in sorted(rows)])
    if "overturned" in table:  # a refused member's row has none: missing, not True
        table["overturned"] = table["overturned"].astype("boolean")
    return Batch(table, {m: kept[m] for m in sorted(kept)}, device, time.perf_counter() - started)


def _thread_count(threads) -> int:
    if threads is None:
        return numba.get_num_threads()
    if not is_integer(threads) or threads < 1:
        raise ValueError(f"threads must be a whole number of at least 1, got {threads!r}")
    return int(threads)


def _members(histories, count: int) -> set:
    if isinstance(histories, (str, bytes)) or not hasattr(histories, "__iter__"):
        raise TypeError(f"histories must be a sequence of members' indices, such as [0, 3], got {histories!r}")
    keep = set()
    for m in histories:
        if not is_integer(m) or not 0 <= m < count:
            raise ValueError(f"histories names member {m!r}; members are 0 to {count - 1}")
        keep.add(int(m))
    return keep
