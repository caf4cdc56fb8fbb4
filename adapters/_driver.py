"""What every adapter shares: the time loop with the ground motion as an inertial load,
outputs at output_dt, the joints' slip measured as the native core measures it, instability checks, friction
mapping, and the common result type."""

import time
import warnings
from dataclasses import dataclass

import numpy as np

from dem_core.engine._interfaces import follow_interfaces
from dem_core.engine.model import compile_model, interface_pairs
from dem_core.engine.result import Result
from dem_core.engine.settings import interface_stride
from dem_core.engine.stacks import columns, find_stacks, first_overturns
from dem_core.engine.state import interface_offsets
from dem_core.inputs.excitation import still
from dem_core.simulation import SimulationUnstable, run_duration

#: a block further than this many scene heights from where it started has left the scene
RUNAWAY_HEIGHTS = 5.0


@dataclass
class EngineRun:
    """An engine built for one scene.

    set_gravity(gx, gy) : the inertial load plus gravity for the next step (m/s^2, in the scene's plane).
    step() : advance one time step.
    state() : (n_blocks, 3) array of x, y, theta of each block's centre of mass, in scene order.
    info : the engine's settings, reported with the result.
    close() : release the engine (called after the run, whatever happened).
    """

    set_gravity: object
    step: object
    state: object
    info: dict
    close: object = lambda: None


def engine_settings(engine: str, options: dict, defaults: dict) -> dict:
    """The engine's defaults updated with ``options``; an unknown option raises ``TypeError`` naming it."""
    unknown = set(options) - set(defaults)
    if unknown:
        raise TypeError(f"{engine}: unknown option(s) {sorted(unknown)}; known: {sorted(defaults)}")
    return {**defaults, **options}


def run(engine: str, scene, excitation, duration, dt, output_dt, build) -> Result:
    """Build with ``build()`` (an :class:`EngineRun`) and run it like :func:`dem_core.simulate`; an unstable
    run raises :class:`dem_core.SimulationUnstable`, as the native core does."""
    excitation = still() if excitation is None else excitation
    try:
        duration = run_duration(excitation, duration)
    except ValueError as exc:
        raise ValueError(f"{engine}: {exc}") from None
    if not dt > 0:
        raise ValueError(f"{engine}: dt must be positive, got {dt}")
    if scene.contact.impact_restitution:
        raise ValueError(f"{engine}: the scene asks a restitution of {scene.contact.impact_restitution:g}; this "
                         f"adapter builds plastic impacts only (docs/validation.md), the native core gives any")
    if scene.connectors:
        raise ValueError(f"{engine}: the scene has {len(scene.connectors)} connector(s) ({scene.connectors[0].name}, "
                         f"...); this adapter cannot model connectors, and a run without them would be another "
                         f"monument: run the native core (engine 'dem')")
    n_steps = int(np.ceil(duration / dt - 1e-9))
    stride = max(1, round((0.01 if output_dt is None else output_dt) / dt))
    out_steps = np.arange(0, n_steps + 1, stride)
    if out_steps[-1] != n_steps:
        out_steps = np.append(out_steps, n_steps)
    t0 = time.perf_counter()
    engine_run = build()
    build_time = time.perf_counter() - t0
    ax, ay = excitation.acceleration(np.arange(n_steps) * dt)
    gx, gy = (-ax).tolist(), (-scene.gravity - ay).tolist()  # plain floats: the loop below is Python
    out = np.full((len(out_steps), len(scene.blocks), 3), np.nan)
    start = np.array([[*b.centroid, b.angle] for b in scene.blocks])
    reach = RUNAWAY_HEIGHTS * max(max(b.vertices[:, 1].max() for b in scene.blocks), 1.0)
    joints = _Joints(scene, len(out_steps), interface_stride(dt))
    written, failure = 0, None
    t0 = time.perf_counter()
    set_gravity, advance, next_out = engine_run.set_gravity, engine_run.step, 0
    try:
        for step in range(n_steps + 1):
            sampled = step % joints.stride == 0 or step == n_steps
            if step == next_out or sampled:
                asked = time.perf_counter()
                state = engine_run.state()
                bad = ~np.all(np.isfinite(state), axis=1) | (np.hypot(*(state[:, :2] - start[:, :2]).T) > reach)
                if np.any(bad):
                    failure = (step, int(np.argmax(bad)))
                    break
                if sampled:
                    joints.follow(state, asked if step != next_out else time.perf_counter())
                if step == next_out:
                    out[written] = state
                    joints.write(written)
                    written += 1
                    next_out = int(out_steps[written]) if written < len(out_steps) else -1
            if step == n_steps:
                break
            set_gravity(gx[step], gy[step])
            advance()
    finally:
        engine_run.close()
    run_time = time.perf_counter() - t0 - joints.seconds
    result = _result(engine, scene, excitation, out[:written], out_steps[:written] * dt, dt,
                     {**engine_run.info, "engine": engine, "steps": int(step), "compile_time_s": build_time,
                      "run_time_s": run_time, "excitation": excitation.name, "ground_motion": "inertial"},
                     joints, written)
    if failure is not None:
        step, k = failure
        raise SimulationUnstable(
            f"{engine}: unstable at t = {step * dt:.6g} s (dt = {dt:.4g} s): block '{scene.blocks[k].name}' "
            f"has a non-finite state or flew more than {reach:.3g} m from where it started; reduce dt. "
            f"The result up to t = {result.t[-1] if len(result.t) else 0.0:.6g} s is in this error's .partial",
            result)
    return result


class _Joints:
    """The slip of the interfaces touching at the start, measured on the engine's states every ``stride`` steps by
    the native core's own stage (:func:`dem_core.engine._interfaces.follow_interfaces`, docs/method.md section 3),
    and the time that takes (s), which is ours and not the engine's."""

    def __init__(self, scene, n_out: int, stride: int):
        self.model = compile_model(scene, find_stacks(scene))
        self.stride = stride
        self.base = np.array([*self.model.bodies.centroid0[0], self.model.bodies.angle0[0]])
        self.offset = interface_offsets(self.model, np.vstack([self.base, [[*b.centroid, b.angle]
                                                                            for b in scene.blocks]]))
        self.travel = np.zeros(len(self.offset))
        self.history = np.full((n_out, len(self.offset)), np.nan)
        self.seconds = 0.0

    def follow(self, state, since: float):
        """The joints' travel on to ``state`` (nb - 1, 3); what it took from ``since`` (``time.perf_counter()``: when
        the state was asked for, where it was asked for this alone) counted as ours."""
        follow_interfaces(np.vstack([self.base, state]), self.model.interface_keys, self.model.interface_geometry,
                          self.offset, self.travel)
        self.seconds += time.perf_counter() - since

    def write(self, row: int):
        self.history[row] = self.travel


def _result(engine, scene, excitation, out, t, dt, info, joints, written) -> Result:
    ground_x, ground_y = excitation.displacement(t)
    theta = out[:, :, 2]
    model = joints.model
    first, _ = first_overturns(model, out[:, :, 0], out[:, :, 1], theta)
    overturn_time = np.where(first >= 0, t[np.maximum(first, 0)] if len(t) else np.nan, np.nan)
    peak = np.max(np.abs(theta), axis=0) if len(t) else np.abs([b.angle for b in scene.blocks])
    names = [b.name for b in scene.bodies]
    interfaces = tuple((names[a], names[b]) for a, b in interface_pairs(model))
    history = joints.history[:written]
    slips = {pair: float(s) for pair, s in zip(interfaces, history[-1]) if s > 0} if written else {}
    return Result(t, out[:, :, 0] + ground_x[:, None], out[:, :, 1] + ground_y[:, None], theta, ground_x, ground_y,
                  tuple(scene.block_names), peak, overturn_time, slips, dt, info, interfaces=interfaces,
                  slip_history=history, critical_angle=np.array([b.critical_angle for b in scene.blocks]),
                  columns=columns(scene, find_stacks(scene)))


def product_friction(engine: str, scene, pairs) -> np.ndarray:
    """Per-body friction values whose products give the scene's coefficient at every interface in ``pairs``.

    For engines that multiply the two bodies' coefficients.  ``pairs`` are
    (i, j) body indices (0 = base) of the interfaces that must be exact (those
    touching at the start).  Solved in logarithms by least squares, those
    interfaces weighted a million times more than the other pairs of blocks,
    which should come as close to the scene's values as the products allow
    (they matter only if the blocks meet later; the base's other pairs are
    left out: a block far above it meets it only after a collapse).  An interface in ``pairs`` that
    cannot be matched (inconsistent overrides around a loop of contacts)
    raises ``ValueError`` naming it; other pairs that differ are announced by
    a warning.
    """
    bodies = scene.bodies
    n = len(bodies)
    must = set(pairs)
    every = [(i, j) for i in range(n) for j in range(i + 1, n) if i > 0 or (i, j) in must]
    mu = {(i, j): scene.friction(bodies[i].name, bodies[j].name) for i, j in every}
    zero = [f"{bodies[i].name}-{bodies[j].name}" for (i, j), m in mu.items() if m <= 0 and (i, j) in must]
    if zero:
        raise ValueError(f"{engine}: zero friction at {', '.join(zero)} cannot be written as a product")
    rows = np.zeros((len(every), n))
    rhs = np.zeros(len(every))
    for k, (i, j) in enumerate(every):
        weight = 1e6 if (i, j) in must else 1.0
        rows[k, i] = rows[k, j] = weight
        rhs[k] = weight * np.log(max(mu[(i, j)], 1e-12))
    values = np.exp(np.linalg.lstsq(rows, rhs, rcond=None)[0])
    for i, j in must:
        if abs(values[i] * values[j] / mu[(i, j)] - 1.0) > 1e-6:
            raise ValueError(f"{engine} multiplies the two bodies' friction coefficients: the scene's interface "
                             f"friction cannot all be reproduced (interface {bodies[i].name}-{bodies[j].name} "
                             f"would get {values[i] * values[j]:.4g} instead of {mu[(i, j)]:.4g})")
    off = [(bodies[i].name, bodies[j].name) for i, j in every
           if (i, j) not in must and abs(values[i] * values[j] / mu[(i, j)] - 1.0) > 1e-6]
    if off:
        warnings.warn(f"{engine}: {len(off)} pairs of bodies not in contact at the start (e.g. "
                      f"{off[0][0]}-{off[0][1]}) would meet with the product of their coefficients, not the "
                      f"scene's value", stacklevel=3)
    return values
