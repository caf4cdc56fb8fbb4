"""The engines the harness judges, their steps, and one run of a scene in any of them.

* ``dem``: the native core with its default contact law (springs at the corners);
* ``dem-overlap``: the native core with the thesis' overlap-area law;
* ``dem-moreau``: the native core's Moreau-Jean integrator on the corner law's points (rigid contacts, no stiffness);
* ``pymunk``, ``pybullet``, ``mujoco``: the adapters of :mod:`adapters`.

A native run replaces the scene's contact with its law's default parameters, with K_n multiplied by ``kn_factor``
when its settings ask for a stiffer contact (``{"kn_factor": 100}``), and stops at the first overturn, as
:func:`dem_core.simulate` does by default.  Its step is a divisor N of the automatic step, labelled ``auto/N``: the
step :func:`dem_core.simulate` picks when given none (explicit: the smaller of 0.8 of the stability limit and a
fifteenth of the shortest impact, both for the contact it runs with; Moreau-Jean:
:func:`dem_core.simulation.moreau_time_step`) divided by N.  The other engines take a step in seconds and their own
solver settings (``{"iterations": 200}``).
"""

import contextlib
import json
import time
import warnings
from dataclasses import dataclass

import numpy as np

import adapters
import dem_core
from comparisons.cases.case import ENGINES

#: the native core's engine names and the contact law each runs
NATIVE_LAWS = {"dem": "corner", "dem-overlap": "overlap_area", "dem-moreau": "corner"}
#: the native core's integrator under each of its engine names
NATIVE_INTEGRATORS = {"dem": "explicit", "dem-overlap": "explicit", "dem-moreau": "moreau"}
#: each engine's usual step: the native core's automatic one, 1e-3 s for the others (their defaults)
USUAL_STEP = {"dem": 1, "dem-overlap": 1, "dem-moreau": 1, "pymunk": 1e-3, "pybullet": 1e-3, "mujoco": 1e-3}


def is_native(engine: str) -> bool:
    return engine in NATIVE_LAWS


def _refined(engine: str, kn_factor: float, divisor: int, step: float) -> tuple:
    """(step, settings) of a refined run: the explicit native core at its automatic step with K_n times
    ``kn_factor``, Moreau-Jean (rigid, no K_n) at its automatic step over ``divisor``, the others at
    ``step`` s."""
    if NATIVE_INTEGRATORS.get(engine) == "explicit":
        return 1, {"kn_factor": kn_factor}
    return (divisor, {}) if is_native(engine) else (step, {})


#: (step, settings) of each engine's finest run, and of the run next to it: the consensus of a
#: multi-block scene is made of finest runs whose answer agrees with the next-finest one.  The explicit
#: native core's finest is its automatic step at 100 x K_n (a stiffer contact than any other run);
#: Moreau-Jean's and the others' is their finest step (more solver iterations at that step take
#: PyBullet three times as long, and moved none of the column's answers by more than the step did)
FINEST = {engine: _refined(engine, kn_factor=100, divisor=4, step=2.5e-4) for engine in ENGINES}
NEXT_FINEST = {engine: _refined(engine, kn_factor=10, divisor=2, step=5e-4) for engine in ENGINES}


def native_scene(scene, engine: str, kn_factor: float = 1.0):
    """``scene`` with the contact law of ``engine`` at its default parameters, K_n times ``kn_factor``."""
    defaults = dem_core.ContactParameters(law=NATIVE_LAWS[engine])
    return scene.replace(contact=dem_core.contact.stiffer(defaults, kn_factor))


def step_label(engine: str, step, settings: dict | None = None) -> str:
    """How a step reads in tables: ``auto/4`` (native), ``0.001`` (s, the others); a stiffer native
    contact adds ``, 100 x K_n``."""
    settings = settings or {}
    if is_native(engine):
        label = f"auto/{step:g}"
        factor = settings.get("kn_factor", 1)
        return label if factor == 1 else f"{label}, {factor:g} x K_n"
    return f"{step:g}"


def settings_label(settings: dict) -> str:
    """Solver settings as stored in the tables (JSON, ``{}`` for the defaults)."""
    return json.dumps(settings, sort_keys=True)


@dataclass(frozen=True)
class EngineRun:
    """One simulation as the harness records it.

    result : the engine's result (up to the failure when it stopped; None if it never started).
    status : ``"ok"``, or ``"stopped"`` when the engine raised its own stability error.
    message : the engine's message when it stopped (whole, never cut).
    dt : s.  label : the step as :func:`step_label` writes it.
    wall_time_s : s of the time loop (building and compiling apart).
    """

    result: object
    status: str
    message: str
    dt: float
    label: str
    wall_time_s: float
    compile_time_s: float
    steps: float


def _options(engine: str, step, settings: dict | None) -> tuple:
    """``(engine name for adapters.simulate, K_n factor, timing, settings, label)`` of a run of ``engine`` at
    ``step`` (default its usual one) with ``settings``."""
    if engine not in ENGINES:
        raise ValueError(f"unknown engine {engine!r}; the harness judges {', '.join(ENGINES)}")
    step = USUAL_STEP[engine] if step is None else step
    settings = dict(settings or {})
    label = step_label(engine, step, settings)
    if not is_native(engine):
        return engine, 1.0, {"dt": float(step)}, settings, label
    kn_factor = settings.pop("kn_factor", 1.0)
    settings["integrator"] = NATIVE_INTEGRATORS[engine]
    # a divisor of the automatic step, which the native core works out as it compiles the scene
    return "dem", kn_factor, {"dt": None, "step_fraction": 1.0 / step}, settings, label


@contextlib.contextmanager
def _quietly():
    """The warning every engine gives on a scene whose friction is the product of its blocks' coefficients, off."""
    with warnings.catch_warnings():
        warnings.filterwarnings("ignore", message=".*product of their coefficients")
        yield


def simulate(scene, motion, duration: float, engine: str, step=None, settings: dict | None = None,
             output_dt: float | None = None) -> EngineRun:
    """Run ``scene`` under ``motion`` for ``duration`` s in ``engine`` at ``step`` (default its usual one)."""
    name, kn_factor, timing, settings, label = _options(engine, step, settings)
    if is_native(engine):
        scene = native_scene(scene, engine, kn_factor)
    start = time.perf_counter()
    try:
        with _quietly():
            result = adapters.simulate(scene, motion, duration, engine=name, output_dt=output_dt, **timing, **settings)
        status, message = "ok", ""
    except dem_core.SimulationUnstable as exc:
        result, status, message = exc.partial, "stopped", str(exc)
    wall = time.perf_counter() - start
    return _engine_run(result, status, message, timing, label, wall)


def simulate_members(scenes, motions, durations, engine: str, step=None, settings: dict | None = None,
                output_dts=None, progress=None) -> list:
    """:func:`simulate` of each member, one :class:`EngineRun` per motion, in order.

    scenes, durations (s), output_dts (s) : one value for every member or a list, one per member, as ``motions``
        (a list of M ground motions) is.
    The native core's members that share a scene (the same object), a duration and an output step run in one
    :func:`dem_core.simulate_batch` over the CPU's threads, each the run :func:`run` gives, bit for bit; its
    ``wall_time_s`` is its own time loop, taken while other members share the machine.  The other engines' runs go
    one after another.  ``progress()`` is called as each run ends.
    """
    count = len(motions)
    scenes, durations, output_dts = (_per_member(value, count) for value in (scenes, durations, output_dts))
    if not is_native(engine):
        runs = []
        for scene, motion, duration, output_dt in zip(scenes, motions, durations, output_dts):
            runs.append(simulate(scene, motion, duration, engine, step, settings, output_dt))
            if progress is not None:
                progress()
        return runs
    _, kn_factor, timing, settings, label = _options(engine, step, settings)
    batches = {}
    for m in range(count):
        batches.setdefault((id(scenes[m]), durations[m], output_dts[m]), []).append(m)
    runs = [None] * count
    for members in batches.values():
        first = members[0]
        with _quietly():
            batch = dem_core.simulate_batch(native_scene(scenes[first], engine, kn_factor),
                                            [motions[m] for m in members], durations[first], device="cpu",
                                            histories=range(len(members)), output_dt=output_dts[first],
                                            progress=None if progress is None else lambda done, total: progress(),
                                            **timing, **settings)
        for m, member in zip(members, batch.table.itertuples()):
            if member.status == "refused":
                raise ValueError(f"{engine} at {label}, motion {member.motion!r}: {member.error}")
            status, message = ("ok", "") if member.status == "ok" else ("stopped", member.error)
            runs[m] = _engine_run(batch.histories[member.member], status, message, timing, label, member.wall_time_s)
    return runs


def _per_member(value, count: int) -> list:
    """``value`` as a list of ``count``: itself where it is a list or a tuple (one per member), else repeated."""
    return list(value) if isinstance(value, (list, tuple)) else [value] * count


def _engine_run(result, status: str, message: str, timing: dict, label: str, wall: float) -> EngineRun:
    """The :class:`EngineRun` of ``result``; ``wall`` (s) stands for its time loop where the result has none."""
    info = result.info if result is not None else {}
    dt = timing["dt"] if timing["dt"] is not None else (result.dt if result is not None else np.nan)
    return EngineRun(result, status, message, dt, label, float(info.get("run_time_s", wall)),
               float(info.get("compile_time_s", np.nan)), float(info.get("steps", np.nan)))
