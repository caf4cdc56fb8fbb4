"""The scene in pymunk (Chipmunk2D: impulse-based, iterative contact solver).

Mapping (FORMULATION sections 1 and 2):

* geometry: each block is a ``pymunk.Poly`` with the scene's vertices about
  its centre of mass; the base is a static polygon.
* mass and inertia: set on each ``pymunk.Body`` from the scene (not from
  pymunk's own shape densities).
* friction: Chipmunk multiplies the two shapes' coefficients.  When every
  interface of the scene has the same coefficient mu, every shape gets
  sqrt(mu); otherwise a pre-solve callback sets each contact's friction to
  the scene's interface value (slower: one Python call per contact per step).
* restitution: elasticity 0 on every shape (a plastic impact, Housner's
  assumption; Chipmunk multiplies the two values too).
* contact softness: ``collision_slop`` (allowed overlap, default 0.1 in the
  scene's length unit, far too much for metres) is set to ``slop`` (1e-4 m
  by default); ``iterations`` solver iterations (default 10).
* ground motion: the inertial load, a time-varying gravity
  ``(-a_gx, -g - a_gy)`` on a fixed base, evaluated at each step's start.
"""

import time

import numpy as np
import pymunk
import pymunk.batch

from dem_core.excitation import GroundMotion, still
from dem_core.geometry import transform
from dem_core.result import Result

DEFAULT_DT = 1e-3
DEFAULT_ITERATIONS = 10
DEFAULT_SLOP = 1e-4


def build_space(scene, iterations: int = DEFAULT_ITERATIONS, slop: float = DEFAULT_SLOP):
    """A pymunk Space holding ``scene``; returns ``(space, bodies)`` with bodies in scene order."""
    space = pymunk.Space()
    space.iterations = int(iterations)
    space.collision_slop = float(slop)
    space.gravity = (0.0, -scene.gravity)
    frictions = {scene.friction(a.name, b.name) for i, a in enumerate(scene.bodies)
                 for b in scene.bodies[i + 1:]}
    uniform = len(frictions) == 1
    shape_mu = float(np.sqrt(frictions.pop())) if uniform else 1.0
    base = pymunk.Poly(space.static_body, [tuple(v) for v in scene.base.vertices])
    base.friction = shape_mu
    base.elasticity = 0.0
    base.collision_type = 0
    space.add(base)
    names = {0: scene.base.name}
    bodies = []
    for k, blk in enumerate(scene.blocks, start=1):
        body = pymunk.Body(blk.mass, blk.inertia)
        body.position = tuple(blk.centroid)
        body.angle = blk.angle
        local = transform(blk.vertices - blk.centroid, -blk.angle)
        shape = pymunk.Poly(body, [tuple(v) for v in local])
        shape.friction = shape_mu
        shape.elasticity = 0.0
        shape.collision_type = k
        names[k] = blk.name
        space.add(body, shape)
        bodies.append(body)
    if not uniform:
        def set_friction(arbiter, _space, _data):
            a, b = arbiter.shapes
            arbiter.friction = scene.friction(names[a.collision_type], names[b.collision_type])

        space.on_collision(pre_solve=set_friction)
    return space, bodies


def simulate(scene, excitation: GroundMotion | None = None, duration: float | None = None,
             dt: float | None = None, output_dt: float | None = None, *, iterations: int = DEFAULT_ITERATIONS,
             slop: float = DEFAULT_SLOP) -> Result:
    """Run ``scene`` in pymunk; same arguments and result as :func:`dem_core.simulate`.

    dt : s, default 1e-3 (pymunk has no stability limit of its own to derive it from).
    iterations, slop : the pymunk solver settings described in the module docstring.
    """
    excitation = still() if excitation is None else excitation
    if duration is None:
        duration = excitation.end_time
        if not np.isfinite(duration) or duration <= 0:
            raise ValueError(f"pymunk: give a duration: the excitation '{excitation.name}' has no natural end")
    dt = DEFAULT_DT if dt is None else float(dt)
    n_steps = int(np.ceil(duration / dt - 1e-9))
    stride = max(1, round((0.01 if output_dt is None else output_dt) / dt))
    t0 = time.perf_counter()
    space, bodies = build_space(scene, iterations, slop)
    build_time = time.perf_counter() - t0
    n = len(bodies)
    t_steps = np.arange(n_steps) * dt
    ax, ay = excitation.acceleration(t_steps)
    gx = -ax
    gy = -scene.gravity - ay
    out_t = np.arange(0, n_steps + 1, stride) * dt
    out = np.empty((len(out_t), n, 3))
    peak = np.abs([b.angle for b in bodies])
    buffer = pymunk.batch.Buffer()
    fields = pymunk.batch.BodyFields.BODY_ID | pymunk.batch.BodyFields.POSITION | pymunk.batch.BodyFields.ANGLE
    pymunk.batch.get_space_bodies(space, fields, buffer)
    ids = list(memoryview(buffer.int_buf()).cast("P"))
    order = np.array([ids.index(b.id) for b in bodies])  # the space also lists its static body

    def read_state():
        buffer.clear()
        pymunk.batch.get_space_bodies(space, fields, buffer)
        return np.frombuffer(buffer.float_buf(), dtype=float).reshape(-1, 3)[order]

    t0 = time.perf_counter()
    k_out = 0
    for step in range(n_steps + 1):
        if step % stride == 0:
            state = read_state()
            out[k_out] = state
            peak = np.maximum(peak, np.abs(state[:, 2]))
            k_out += 1
        if step == n_steps:
            break
        space.gravity = (gx[step], gy[step])
        space.step(dt)
    run_time = time.perf_counter() - t0
    if not np.all(np.isfinite(out)):
        bad = int(np.argmax(~np.all(np.isfinite(out), axis=(1, 2))))
        raise RuntimeError(f"pymunk: the state became non-finite by t = {out_t[bad]:.6g} s")
    crit = np.array([b.critical_angle for b in scene.blocks])
    over = np.abs(out[:, :, 2]) > crit
    overturn_time = np.where(over.any(axis=0), out_t[np.argmax(over, axis=0)], np.nan)
    info = {"engine": "pymunk", "steps": n_steps, "iterations": iterations, "slop": slop,
            "compile_time_s": build_time, "run_time_s": run_time, "excitation": excitation.name,
            "ground_motion": "inertial"}
    ground_x, ground_y = excitation.displacement(out_t)
    return Result(out_t, out[:, :, 0] + ground_x[:, None], out[:, :, 1] + ground_y[:, None], out[:, :, 2],
                  ground_x, ground_y, tuple(scene.block_names), peak, overturn_time, {}, dt, info)
