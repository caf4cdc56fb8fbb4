"""The scene in PyBullet (Bullet's sequential-impulse solver), 3D kept in the plane.

Mapping (docs/method.md sections 1 and 2), the scene's plane x-y becoming
Bullet's x-z (z up) and the out-of-plane depth running along y:

* geometry (:mod:`adapters._geometry`): each block is a prism of the scene's
  depth: a box for a rectangle whose edges run along the axes at the start,
  otherwise the convex hull of the extruded outline; the base likewise,
  fixed.  A rectangle released from a tilt is a hull too (MuJoCo turns its
  box instead): the shape PyBullet's free-rocking bands in
  tests/test_adapters.py were measured with.
* planar motion: Bullet has no planar joint in PyBullet, so each block is a
  multibody of three links on a fixed, massless root at its starting centre:
  a prismatic joint along x, one along z and a revolute joint about -y (a
  positive angle is counter-clockwise in the scene's plane).  The block's
  collision shape, mass and inertia are on the last link; the two
  intermediate links carry 1e-6 of the block's mass (Featherstone's
  algorithm needs positive masses), so the translational mass is off by
  2e-6.  The joint motors PyBullet switches on by default (which act as
  friction) are switched off.
* mass and inertia: from the scene (``localInertiaDiagonal`` of the block's
  link holds the scene's rotational inertia about the hinge).
* friction: Bullet multiplies the two bodies' lateral friction.  Each body
  gets a value such that the products equal the scene's coefficient at every
  interface touching at the start (``sqrt(mu)`` when all are equal); overrides
  that cannot be written as products raise ``ValueError`` (PyBullet offers no
  per-contact friction).  Rolling and spinning friction are 0.
* restitution 0 on every body (a plastic impact, Housner's assumption);
  ``restitutionVelocityThreshold`` 0.
* contact softness: rigid contacts with split-impulse position correction
  (``useSplitImpulse``), ``contactSlop`` = 1e-5 m (the allowed overlap),
  ``numSolverIterations`` 50, linear and angular damping 0 (PyBullet's
  default is 0.04).  Boxes keep their collision margin inside the shape.
  Convex hulls (tapered drums) get a 1 mm margin around them, which showed as
  1 mm gaps between resting drums; ``changeDynamics(collisionMargin=...)`` on
  a link changes the multibody's root instead (and takes every other setting
  of that call with it), so the outline is inset by 1 mm instead: the
  contact surface is the scene's, with corners rounded to 1 mm.
* ground motion: the inertial load, gravity ``(-a_gx, 0, -g - a_gy)`` set
  before each step.
* dt: 1e-3 s by default.
"""

import numpy as np
import pybullet

from . import _geometry as geometry
from ._driver import EngineRun, engine_settings, product_friction, run

DEFAULT_DT = 1e-3
OPTIONS = {"iterations": 50, "contact_slop": 1e-5, "split_impulse": True}
LINK_MASS_FRACTION = 1e-6
CONVEX_MARGIN = 1e-3  # m, the margin PyBullet gives the convex hulls it builds (measured: 1 mm gaps)


def simulate(scene, excitation=None, duration=None, dt=None, output_dt=None, **options):
    """Run ``scene`` in PyBullet; same arguments and result as :func:`dem_core.simulate`.

    options : any of ``OPTIONS`` (see the module docstring).
    """
    settings = engine_settings("pybullet", options, OPTIONS)
    dt = DEFAULT_DT if dt is None else float(dt)
    return run("pybullet", scene, excitation, duration, dt, output_dt, lambda: _build(scene, dt, settings))


def _shape(client, outline, depth):
    """The collision shape of a body whose frame holds ``outline`` (n, 2), m, with ``depth`` (m)."""
    box = geometry.rectangle(outline)
    if box is not None and box.axis_aligned():
        half_x, half_z = box.half_extents_on_axes()
        return pybullet.createCollisionShape(pybullet.GEOM_BOX, halfExtents=[half_x, depth / 2, half_z],
                                             collisionFramePosition=[box.centre[0], 0.0, box.centre[1]],
                                             physicsClientId=client)
    # Bullet puts a collision margin around a convex hull: inset the prism by it so the surface is the scene's
    hull = geometry.prism(outline, depth, inset_by=CONVEX_MARGIN)
    return pybullet.createCollisionShape(pybullet.GEOM_MESH, vertices=hull.vertices.tolist(), physicsClientId=client)


def _build(scene, dt, settings) -> EngineRun:
    client = pybullet.connect(pybullet.DIRECT)
    pybullet.setTimeStep(dt, physicsClientId=client)
    pybullet.setPhysicsEngineParameter(numSolverIterations=int(settings["iterations"]),
                                       useSplitImpulse=int(bool(settings["split_impulse"])),
                                       contactSlop=float(settings["contact_slop"]),
                                       restitutionVelocityThreshold=0.0, physicsClientId=client)
    pairs = [(i, j) for i, j, _ in scene.touching_pairs()]
    friction = product_friction("pybullet", scene, pairs)
    base_shape = _shape(client, scene.base.vertices, scene.base.depth)  # the fixed base's frame is the world's
    base = pybullet.createMultiBody(0.0, base_shape, -1, [0, 0, 0], physicsClientId=client)
    pybullet.changeDynamics(base, -1, lateralFriction=float(friction[0]), restitution=0.0, rollingFriction=0.0,
                            spinningFriction=0.0, physicsClientId=client)
    ids = []
    for k, blk in enumerate(scene.blocks, start=1):
        c = geometry.start_pose(blk).centroid
        shape = _shape(client, geometry.outline_at_start(blk), blk.depth)  # hinge angle 0 at the start
        eps = LINK_MASS_FRACTION * blk.mass
        body = pybullet.createMultiBody(
            baseMass=0.0, baseCollisionShapeIndex=-1, basePosition=[c[0], 0.0, c[1]],
            linkMasses=[eps, eps, blk.mass], linkCollisionShapeIndices=[-1, -1, shape],
            linkVisualShapeIndices=[-1, -1, -1], linkPositions=[[0, 0, 0]] * 3,
            linkOrientations=[[0, 0, 0, 1]] * 3, linkInertialFramePositions=[[0, 0, 0]] * 3,
            linkInertialFrameOrientations=[[0, 0, 0, 1]] * 3, linkParentIndices=[0, 1, 2],
            linkJointTypes=[pybullet.JOINT_PRISMATIC, pybullet.JOINT_PRISMATIC, pybullet.JOINT_REVOLUTE],
            linkJointAxis=[[1, 0, 0], [0, 0, 1], [0, -1, 0]], physicsClientId=client)
        for link in (0, 1, 2):
            pybullet.changeDynamics(body, link, linearDamping=0.0, angularDamping=0.0, jointDamping=0.0,
                                    physicsClientId=client)
        pybullet.changeDynamics(body, 0, localInertiaDiagonal=[eps * 1e-3] * 3, physicsClientId=client)
        pybullet.changeDynamics(body, 1, localInertiaDiagonal=[eps * 1e-3] * 3, physicsClientId=client)
        pybullet.changeDynamics(body, 2, localInertiaDiagonal=[blk.inertia] * 3,
                                lateralFriction=float(friction[k]), restitution=0.0, rollingFriction=0.0,
                                spinningFriction=0.0, physicsClientId=client)
        pybullet.setJointMotorControlArray(body, [0, 1, 2], pybullet.VELOCITY_CONTROL, forces=[0.0, 0.0, 0.0],
                                           physicsClientId=client)
        ids.append(body)
    start = geometry.start_states(scene.blocks)

    def set_gravity(gx, gy):
        pybullet.setGravity(gx, 0.0, gy, physicsClientId=client)

    def state():
        q = np.array([[s[0] for s in pybullet.getJointStates(body, [0, 1, 2], physicsClientId=client)]
                      for body in ids])
        return start + q

    return EngineRun(set_gravity, lambda: pybullet.stepSimulation(physicsClientId=client), state,
                     {**settings, "link_mass_fraction": LINK_MASS_FRACTION},
                     lambda: pybullet.disconnect(physicsClientId=client))
