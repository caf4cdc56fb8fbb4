"""Running a scene under ground motion: ``simulate(scene, excitation, ...)``.

The scene is the immutable model; the state (positions and half-step
velocities, tangential contact forces) is created here, advanced by the
compiled kernel in :mod:`dem_core.engine._kernels` and returned as a
:class:`~dem_core.engine.result.Result`.
"""

import math
import time

import numpy as np

from . import _kernels, contact, stability
from ..inputs.excitation import GroundMotion, still
from .geometry import transform
from .result import Result
from .stacks import columns, find_stacks, kernel_arrays

#: largest fraction of the stability limit used when dt is not given (the scheme is stable up to the
#: limit: mirror-image runs stay mirror images to round-off there)
DEFAULT_SAFETY = 0.8
#: time steps per shortest impact when dt is not given: resolving impacts matters for the energy they
#: take.  The Housner block's peaks after five impacts are 5.7% too high at 5 steps per impact, within
#: 2.2% at 10 (``python -m comparisons.calibrate_damping``)
DEFAULT_STEPS_PER_IMPACT = 10
#: a pair overlapping by more than this fraction of the smaller block's area stops the run
MAX_OVERLAP_FRACTION = 0.05
#: a block moving faster than this multiple of the fastest physical speed stops the run
SPEED_LIMIT_FACTOR = 10.0
#: energy gained beyond the ground's work, as a fraction of sum(m g R) plus the gross ground work, that stops the run
ENERGY_TOLERANCE = 0.05
GROUND_MOTION_MODES = ("inertial", "moving_base")
#: with stop_at_overturn=False the automatic step shrinks by this factor: a pile of fallen blocks has more
#: and stiffer contacts than the standing scene the stability limit is computed for (the 8-drum column
#: under El Centro at 10 m/s^2 goes through its collapse at a quarter of the step, not at a half)
COLLAPSE_STEP_FACTOR = 0.25


class SimulationUnstable(RuntimeError):
    """The run lost stability; ``partial`` holds the result up to the last good output."""

    def __init__(self, message: str, partial: Result | None):
        super().__init__(message)
        self.partial = partial


def simulate(scene, excitation: GroundMotion | None = None, duration: float | None = None,
             dt: float | None = None, output_dt: float | None = None, *,
             ground_motion: str = "inertial", safety: float = DEFAULT_SAFETY,
             steps_per_impact: float = DEFAULT_STEPS_PER_IMPACT,
             stop_at_overturn: bool = True, enforce_stability_limit: bool = True) -> Result:
    """Simulate ``scene`` under ``excitation`` with the native soft-contact DEM.

    scene : :class:`~dem_core.inputs.scene.Scene`.
    excitation : :class:`~dem_core.inputs.excitation.GroundMotion` (None: no ground motion).
    duration : s; default the excitation's natural end (records, pulses).
    dt : s; None picks the smaller of ``safety`` x the stability limit
        (:func:`dem_core.engine.stability.stability_limit`) and the shortest impact
        over ``steps_per_impact`` (:func:`dem_core.engine.stability.impact_duration`).
        A dt above the limit is refused.
    output_dt : s between outputs (rounded to a whole number of steps; the
        final state is always an output); default 0.01 s.
    ground_motion : ``"inertial"`` (base fixed, load ``-m a_g`` on every block,
        FORMULATION section 2) or ``"moving_base"`` (the base follows u_g, v_g).
        Either way positions are reported in the fixed frame, with
        ``base_x`` the ground displacement.
    stop_at_overturn : end the run when a block first overturns (passes its
        critical angle or falls half its size); the result then ends at that
        time and ``info["stopped"]`` says why.  With False the run goes on
        through the collapse, with an automatic step small enough for blocks
        lying on their long sides (see :func:`dem_core.engine.stability.stability_limit`)
        and for piles of fallen blocks (``COLLAPSE_STEP_FACTOR``).
    enforce_stability_limit : refuse an explicit dt above the stability limit.
        Only for stress tests that study what happens past it
        (``comparisons/stability_probe.py``).

    Raises ``ValueError`` for bad arguments (a dt above the stability limit
    among them) and :class:`SimulationUnstable`, carrying the result up to
    that point, when the run loses stability or a block leaves the base.
    """
    excitation = still() if excitation is None else excitation
    if ground_motion not in GROUND_MOTION_MODES:
        raise ValueError(f"ground_motion must be one of {GROUND_MOTION_MODES}, got {ground_motion!r}")
    if duration is None:
        duration = excitation.end_time
        if not np.isfinite(duration) or duration <= 0:
            raise ValueError(f"give a duration: the excitation '{excitation.name}' has no natural end")
    if not duration > 0:
        raise ValueError(f"duration must be positive, got {duration}")
    interfaces = contact.interface_arrays(scene)
    limit = stability.stability_limit(scene, interfaces, toppled=not stop_at_overturn)
    impact = stability.impact_duration(scene, interfaces)
    auto_dt = dt is None
    dt = _time_step(scene, dt, limit, impact, safety, steps_per_impact, enforce_stability_limit)
    if auto_dt and not stop_at_overturn:
        dt *= COLLAPSE_STEP_FACTOR
    n_steps = math.ceil(duration / dt - 1e-9)
    stride = max(1, round((0.01 if output_dt is None else output_dt) / dt))
    out_steps = np.arange(0, n_steps + 1, stride)
    if out_steps[-1] != n_steps:
        out_steps = np.append(out_steps, n_steps)

    arrays = _scene_arrays(scene)
    pos = arrays["pos0"].copy()
    vel = np.zeros_like(pos)
    ground = _ground_arrays(excitation, ground_motion, pos[0], n_steps, dt)
    if ground_motion == "moving_base":
        vel[1:, :2] = ground["base_v"][:, 0]  # the blocks start at rest relative to the ground
    speed_limit = _speed_limit(scene, excitation, np.arange(n_steps + 1) * dt)
    nb = pos.shape[0]
    ft_el = np.zeros((nb, nb))
    slip = np.zeros((nb, nb))
    out_pos = np.full((len(out_steps), nb, 3), np.nan)
    peak = np.abs(pos[:, 2])
    overturn_step = np.full(nb, -1, np.int64)
    column_stacks = find_stacks(scene)
    stack_arrays = kernel_arrays(scene, column_stacks)
    stack_step = np.full(len(column_stacks), -1, np.int64)
    followed = [(i, j) for i, j, _ in scene.touching_pairs() if interfaces.active[i, j]]
    if_i = np.array([i for i, _ in followed], np.int64)
    if_j = np.array([j for _, j in followed], np.int64)
    out_slip = np.full((len(out_steps), len(followed)), np.nan)

    def run(steps, out, out_slip):
        return _kernels.integrate(
            pos, vel, arrays["local_x"], arrays["local_y"], arrays["vstart"], arrays["inv_mass"],
            arrays["inv_inertia"], arrays["radius"], arrays["area"], interfaces.kn, interfaces.cn, interfaces.cr,
            interfaces.kt, interfaces.ct, interfaces.mu, interfaces.active, ft_el, slip, scene.gravity,
            ground["load"][0], ground["load"][1], ground["base"][0], ground["base"][1], ground["base_v"][0],
            ground["base_v"][1], dt, steps, stride, out, arrays["crit_angle"], arrays["y_start"],
            arrays["drop_limit"], peak, overturn_step, MAX_OVERLAP_FRACTION, arrays["skin"], speed_limit,
            ENERGY_TOLERANCE, stop_at_overturn, arrays["floor"], stack_arrays["stack_id"],
            stack_arrays["stack_bottom"], stack_arrays["stack_mass"], stack_arrays["stack_foot"], stack_step,
            if_i, if_j, out_slip)

    t0 = time.perf_counter()
    _ensure_compiled(run, pos, vel, nb, len(followed))
    compile_time = time.perf_counter() - t0
    t0 = time.perf_counter()
    status, step, i, j, written, n_narrow = run(n_steps, out_pos, out_slip)
    run_time = time.perf_counter() - t0

    bodies = scene.bodies
    out_t = out_steps[:written] * dt
    if status == _kernels.STATUS_OVERTURNED:
        out_t[-1] = step * dt  # the kernel wrote the state at the overturn as the last output
    x, y, theta = out_pos[:written, 1:, 0], out_pos[:written, 1:, 1], out_pos[:written, 1:, 2]
    if ground_motion == "inertial":  # the kernel moved the blocks relative to the ground: add the ground back
        ground_x, ground_y = excitation.displacement(out_t)
        x, y = x + ground_x[:, None], y + ground_y[:, None]
    else:
        ground_x = out_pos[:written, 0, 0] - arrays["pos0"][0, 0]
        ground_y = out_pos[:written, 0, 1] - arrays["pos0"][0, 1]
    interface_slip = {(bodies[a].name, bodies[b].name): float(slip[a, b])
                      for a, b in zip(*np.nonzero(np.triu(slip) > 0))}
    info = {
        "engine": "dem",
        "stability_limit_s": limit,
        "impact_duration_s": impact,
        "steps": int(step),
        "narrow_phase_per_step": n_narrow / max(int(step), 1),
        "ground_motion": ground_motion,
        "excitation": excitation.name,
        "compile_time_s": compile_time,
        "run_time_s": run_time,
        "kn": scene.contact.kn,
    }
    tipped = [k for k in range(len(column_stacks)) if 0 <= stack_step[k] <= step]
    if tipped:
        info["tipped_stacks"] = {_stack_label(scene, column_stacks[k]): float(stack_step[k] * dt) for k in tipped}
    if status == _kernels.STATUS_OVERTURNED:
        whole = [k for k in tipped if stack_step[k] == step and column_stacks[k].blocks[0] == i - 1]
        what = (f"the stack {_stack_label(scene, column_stacks[whole[0]])} tipped past its base"
                if whole else f"block '{bodies[i].name}' overturned")
        info["stopped"] = f"{what} at t = {step * dt:.6g} s"
    over_t = np.where(overturn_step[1:] >= 0, overturn_step[1:] * dt, np.nan)
    result = Result(out_t, x, y, theta, ground_x, ground_y, tuple(scene.block_names), peak[1:], over_t,
                    interface_slip, dt, info, interfaces=tuple((bodies[a].name, bodies[b].name) for a, b in followed),
                    slip_history=out_slip[:written], critical_angle=arrays["crit_angle"][1:].copy(),
                    columns=columns(scene, column_stacks))
    if status not in (_kernels.STATUS_OK, _kernels.STATUS_OVERTURNED):
        raise SimulationUnstable(_stop_message(scene, status, step, dt, i, j, speed_limit, out_t), result)
    return result


def _stack_label(scene, stack) -> str:
    names = [scene.blocks[b].name for b in stack.blocks]
    return f"{names[0]}..{names[-1]}"


def automatic_time_step(scene, *, toppled: bool = False, safety: float = 0.8,
                        steps_per_impact: float = 10) -> float:
    """The step :func:`simulate` chooses when given none, s: the smaller of ``safety`` times the
    stability limit (with ``toppled``, the limit of blocks lying on their long sides) and the
    shortest impact over ``steps_per_impact``.  (Going on through a collapse, ``simulate`` takes
    ``COLLAPSE_STEP_FACTOR`` of the toppled value.)"""
    interfaces = contact.interface_arrays(scene)
    limit = stability.stability_limit(scene, interfaces, toppled=toppled)
    return _time_step(scene, None, limit, stability.impact_duration(scene, interfaces), safety, steps_per_impact,
                      True)


def _time_step(scene, dt, limit, impact, safety, steps_per_impact, enforce) -> float:
    if not 0.0 < safety <= 1.0:
        raise ValueError(f"safety is the fraction of the stability limit used as dt; it must be in (0, 1], "
                         f"got {safety}")
    if not steps_per_impact > 0:
        raise ValueError(f"steps_per_impact must be positive, got {steps_per_impact}")
    if dt is None:
        return min(safety * limit, impact / steps_per_impact)
    if not dt > 0:
        raise ValueError(f"dt must be positive, got {dt}")
    if dt > limit and enforce:
        raise ValueError(f"dt = {dt:.4g} s is above the stability limit {limit:.4g} s of this scene "
                         f"(contact stiffness kn = {scene.contact.kn:.3g}); use dt <= {limit:.4g} or dt=None")
    return float(dt)


def _ground_arrays(excitation, mode, base_start, n_steps, dt) -> dict:
    """Per-step ground input of the kernel: inertial load (2, n_steps) m/s^2, base position
    (2, n_steps + 1) m at step times, base velocity (2, n_steps + 1) m/s at the half steps before."""
    t = np.arange(n_steps + 1) * dt
    if mode == "inertial":
        return {
            "load": -np.array(excitation.acceleration(t[:-1])),
            "base": np.repeat(base_start[:2, None], n_steps + 1, axis=1),
            "base_v": np.zeros((2, n_steps + 1)),
        }
    return {
        "load": np.zeros((2, n_steps)),
        "base": base_start[:2, None] + np.array(excitation.displacement(t)),
        "base_v": np.array(excitation.velocity(t - 0.5 * dt)),
    }


def _stop_message(scene, status, step, dt, i, j, speed_limit, out_t) -> str:
    bodies = scene.bodies
    if status == _kernels.STATUS_NONFINITE:
        what = f"the state of block '{bodies[i].name}' became non-finite"
    elif status == _kernels.STATUS_RUNAWAY:
        what = (f"block '{bodies[i].name}' moved faster than {speed_limit:.3g} m/s relative to the ground, "
                f"{SPEED_LIMIT_FACTOR:g} times the fastest speed its fall and the ground motion can give")
    elif status == _kernels.STATUS_FELL_OFF:
        what = f"block '{bodies[i].name}' fell off the edge of the base; make the base wider (base_width)"
    elif status == _kernels.STATUS_ENERGY:
        what = (f"the blocks gained energy that neither gravity nor the ground supplied "
                f"(more than {ENERGY_TOLERANCE:.0%} of the energy scale)")
    else:
        what = (f"blocks '{bodies[i].name}' and '{bodies[j].name}' overlap by more than "
                f"{MAX_OVERLAP_FRACTION:.0%} of the smaller block's area")
    advice = ("nothing after this time is physical" if status == _kernels.STATUS_FELL_OFF else
              f"reduce dt below {dt:.4g} s or check the contact parameters (kn = {scene.contact.kn:.3g})")
    last = out_t[-1] if len(out_t) else 0.0
    return (f"simulation stopped at t = {step * dt:.6g} s (step {step}, dt = {dt:.4g} s): {what}; {advice}. "
            f"The result up to t = {last:.6g} s is in this error's .partial")


def _speed_limit(scene, excitation, t_steps) -> float:
    """Bound on any block's speed relative to the ground (m/s) that no stable run reaches.

    ``SPEED_LIMIT_FACTOR`` times the free-fall speed from the top of the scene
    plus the largest ground velocity change over the run.
    """
    top = max(b.vertices[:, 1].max() for b in scene.blocks) - scene.base.vertices[:, 1].max()
    fall = np.sqrt(2.0 * scene.gravity * max(top, 0.0))
    vx, vy = excitation.velocity(t_steps)
    ground = np.ptp(vx) + np.ptp(vy)
    return SPEED_LIMIT_FACTOR * (fall + ground + 1e-3)


def _ensure_compiled(run, pos, vel, nb, n_interfaces):
    """Trigger compilation (or loading from numba's cache) with a zero-step call."""
    saved = pos.copy(), vel.copy()
    run(0, np.empty((1, nb, 3)), np.empty((1, n_interfaces)))
    pos[:], vel[:] = saved


def _scene_arrays(scene) -> dict:
    """Structure-of-arrays view of the scene for the kernel (base at index 0)."""
    bodies = scene.bodies
    centroids = np.array([b.centroid for b in bodies])
    local = [b.vertices - c for b, c in zip(bodies, centroids)]
    vstart = np.zeros(len(bodies) + 1, np.int64)
    vstart[1:] = np.cumsum([len(v) for v in local])
    mass = np.array([b.mass for b in bodies])
    inertia = np.array([b.inertia for b in bodies])
    inv_mass = 1.0 / mass
    inv_inertia = 1.0 / inertia
    inv_mass[0] = inv_inertia[0] = 0.0
    # theta starts at each block's initial angle, so the local outline is the start outline rotated back
    angle0 = np.array([b.angle for b in bodies])
    pos0 = np.column_stack([centroids, angle0])
    allv = np.concatenate([transform(v, -a) for v, a in zip(local, angle0)])
    radius = np.array([b.circumradius for b in bodies])
    sizes = np.array([min(b.width, b.height) for b in bodies])
    return {
        "pos0": pos0,
        "local_x": np.ascontiguousarray(allv[:, 0]),
        "local_y": np.ascontiguousarray(allv[:, 1]),
        "vstart": vstart,
        "inv_mass": inv_mass,
        "inv_inertia": inv_inertia,
        "radius": radius,
        "area": np.array([b.area for b in bodies]),
        "crit_angle": np.array([b.critical_angle for b in bodies]),
        "y_start": centroids[:, 1].copy(),
        "drop_limit": 0.5 * sizes,
        "skin": 0.1 * float(sizes[1:].min()),
        "floor": float(scene.base.vertices[:, 1].max() - centroids[0, 1]),
    }
