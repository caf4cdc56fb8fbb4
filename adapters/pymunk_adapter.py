"""The scene in pymunk (Chipmunk2D: impulse-based, iterative contact solver), 2D like the scene.

Mapping (docs/method.md sections 1 and 2):

* geometry (:mod:`adapters._geometry`): each block is a ``pymunk.Poly``
  with the scene's vertices about its centre of mass in the reference
  orientation, on a body turned to its initial angle; the base is a static
  polygon.
* mass and inertia: set on each ``pymunk.Body`` from the scene (not from
  shape densities).
* friction: Chipmunk multiplies the two shapes' coefficients.  Each shape
  gets a value such that the products equal the scene's coefficient at every
  interface touching at the start (``sqrt(mu)`` when all are equal, solved
  in logarithms otherwise, see :func:`adapters._driver.product_friction`).
  When the overrides cannot be written as products (a loop of contacts with
  inconsistent values), a pre-solve callback sets every contact's friction to
  the scene's value instead, at the cost of a Python call per contact per step.
* restitution: elasticity 0 on every shape (Chipmunk multiplies the values
  too): a plastic impact, as Housner assumes.
* contact softness: Chipmunk resolves overlap with a bias velocity; the
  ``collision_slop`` it tolerates (default 0.1, meant for pixels) is set to
  ``slop`` = 1e-4 m, ``collision_bias`` is left at its default (10% of the
  overlap fixed per 1/60 s), and the solver runs ``iterations`` = 10 passes.
* ground motion: the inertial load, a time-varying gravity
  ``(-a_gx, -g - a_gy)`` on the fixed base, set before each step.
* the state is read in bulk with ``pymunk.batch`` at output times only.
* dt: 1e-3 s by default.
"""

from functools import partial

import numpy as np
import pymunk
import pymunk.batch

from . import _geometry as geometry
from ._driver import EngineRun, engine_settings, product_friction, run

DEFAULT_DT = 1e-3
OPTIONS = {"iterations": 10, "slop": 1e-4}


def simulate(scene, excitation=None, duration=None, dt=None, output_dt=None, **options):
    """Run ``scene`` in pymunk; same arguments and result as :func:`dem_core.simulate`.

    options : any of ``OPTIONS`` (see the module docstring).
    """
    settings = engine_settings("pymunk", options, OPTIONS)
    dt = DEFAULT_DT if dt is None else float(dt)
    return run("pymunk", scene, excitation, duration, dt, output_dt,
               lambda: _build(scene, dt, settings["iterations"], settings["slop"]))


def _build(scene, dt, iterations, slop) -> EngineRun:
    space = pymunk.Space()
    space.iterations = int(iterations)
    space.collision_slop = float(slop)
    pairs = [(i, j) for i, j, _ in scene.touching_pairs()]
    try:
        shape_mu = product_friction("pymunk", scene, pairs)
        per_contact = False
    except ValueError:
        shape_mu, per_contact = np.ones(len(scene.bodies)), True
    base = pymunk.Poly(space.static_body, [tuple(v) for v in scene.base.vertices])
    shapes = [base]
    bodies = []
    for blk in scene.blocks:
        pose = geometry.start_pose(blk)
        body = pymunk.Body(blk.mass, blk.inertia)
        body.position = tuple(pose.centroid)
        body.angle = pose.angle
        shape = pymunk.Poly(body, [tuple(v) for v in geometry.outline_in_reference(blk)])
        space.add(body)
        bodies.append(body)
        shapes.append(shape)
    for k, shape in enumerate(shapes):
        shape.friction = float(shape_mu[k])
        shape.elasticity = 0.0
        shape.collision_type = k
        space.add(shape)
    if per_contact:
        names = [b.name for b in scene.bodies]

        def set_friction(arbiter, _space, _data):
            a, b = arbiter.shapes
            arbiter.friction = scene.friction(names[a.collision_type], names[b.collision_type])

        space.on_collision(pre_solve=set_friction)

    buffer = pymunk.batch.Buffer()
    fields = pymunk.batch.BodyFields.BODY_ID | pymunk.batch.BodyFields.POSITION | pymunk.batch.BodyFields.ANGLE
    pymunk.batch.get_space_bodies(space, fields, buffer)
    ids = list(memoryview(buffer.int_buf()).cast("P"))
    order = np.array([ids.index(b.id) for b in bodies])  # the space lists its static body too

    def state():
        buffer.clear()
        pymunk.batch.get_space_bodies(space, fields, buffer)
        return np.frombuffer(buffer.float_buf(), dtype=float).reshape(-1, 3)[order].copy()

    def set_gravity(gx, gy):
        space.gravity = (gx, gy)

    return EngineRun(set_gravity, partial(space.step, dt), state,
                     {"iterations": int(iterations), "slop": float(slop), "friction": "per contact" if per_contact
                      else "product of shape values"})
