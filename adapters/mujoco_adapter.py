"""The scene in MuJoCo (soft contacts solved as a convex optimisation), 3D kept in the plane.

Mapping (docs/method.md sections 1 and 2), the scene's plane x-y becoming
MuJoCo's x-z (z up) and the out-of-plane depth running along y:

* geometry (:mod:`adapters._geometry`): each block is a prism of the
  scene's depth: a box for a rectangle (turned to its starting angle),
  otherwise a convex mesh of the extruded outline; the base likewise, fixed
  to the world, with the depth of the deepest block.
* planar motion: each block's body has three joints, slide x, slide z and a
  hinge about -y (so that a positive angle is counter-clockwise in the
  scene's plane); nothing else can move.
* mass and inertia: an explicit ``<inertial>`` with the scene's mass and the
  scene's rotational inertia about the hinge (the other two axes get the same
  value; they are locked), with ``inertiafromgeom`` off.
* friction: MuJoCo combines two geoms' parameters itself (the larger
  friction wins).  Instead every geom has ``contype = conaffinity = 0`` and
  each pair of bodies gets an explicit ``<pair>`` with the scene's
  coefficient for that interface (per-interface overrides included), so no
  combination rule applies.  ``condim = 3`` (sliding friction only: no
  torsional or rolling resistance, as in the plane).
* contact softness and restitution: ``solref = (timeconst, dampratio)`` with
  ``timeconst = 2 dt`` (MuJoCo's own lower bound; stiffer would be unsafe) and
  ``dampratio = 1`` (critically damped: no rebound, Housner's plastic
  impact); ``solimp = (0.99, 0.999, 0.001)`` so the constraint is nearly at
  full strength from the first millimetre of penetration.
* solver: Newton, elliptic friction cone, ``impratio = 1``,
  ``implicitfast`` integrator, 50 iterations, tolerance 1e-10.
* ground motion: the inertial load, ``model.opt.gravity`` set to
  ``(-a_gx, 0, -g - a_gy)`` before each step.
* dt: 1e-3 s by default.
"""

import mujoco
import numpy as np

from . import _geometry as geometry
from ._driver import EngineRun, engine_settings, run

DEFAULT_DT = 1e-3
OPTIONS = {"dampratio": 1.0, "timeconst": None, "solimp": (0.99, 0.999, 0.001), "iterations": 50,
           "integrator": "implicitfast", "cone": "elliptic", "impratio": 1.0}


def simulate(scene, excitation=None, duration=None, dt=None, output_dt=None, **options):
    """Run ``scene`` in MuJoCo; same arguments and result as :func:`dem_core.simulate`.

    options : any of ``OPTIONS`` (see the module docstring); ``timeconst=None`` means 2 dt.
    """
    settings = engine_settings("mujoco", options, OPTIONS)
    dt = DEFAULT_DT if dt is None else float(dt)
    if settings["timeconst"] is None:
        settings["timeconst"] = 2.0 * dt
    return run("mujoco", scene, excitation, duration, dt, output_dt, lambda: _build(scene, dt, settings))


def model_xml(scene, dt: float, settings: dict) -> str:
    """The MJCF text of ``scene``."""
    assets, bodies, pairs = [], [], []
    # the world's frame holds the base's outline
    base_geom = _geom_xml(0, scene.base.vertices, max(b.depth for b in scene.bodies), assets)
    for k, blk in enumerate(scene.blocks, start=1):
        c = geometry.start_pose(blk).centroid
        geom = _geom_xml(k, geometry.outline_at_start(blk), blk.depth, assets)  # hinge angle 0 at the start
        bodies.append(
            f'<body name="b{k}" pos="{_f(c[0])} 0 {_f(c[1])}">'
            f'<joint name="x{k}" type="slide" axis="1 0 0"/><joint name="z{k}" type="slide" axis="0 0 1"/>'
            f'<joint name="r{k}" type="hinge" axis="0 -1 0"/>'
            f'<inertial pos="0 0 0" mass="{_f(blk.mass)}" diaginertia="{_f(blk.inertia)} {_f(blk.inertia)} '
            f'{_f(blk.inertia)}"/>{geom}</body>')
    names = [b.name for b in scene.bodies]
    solref = f'{_f(settings["timeconst"])} {_f(settings["dampratio"])}'
    solimp = " ".join(_f(v) for v in settings["solimp"])
    for i in range(len(names)):
        for j in range(i + 1, len(names)):
            mu = scene.friction(names[i], names[j])
            pairs.append(f'<pair geom1="g{i}" geom2="g{j}" condim="3" friction="{_f(mu)} {_f(mu)} 0 0 0" '
                         f'solref="{solref}" solimp="{solimp}"/>')
    return (f'<mujoco model="scene"><compiler inertiafromgeom="false" angle="radian"/>'
            f'<option timestep="{_f(dt)}" gravity="0 0 {_f(-scene.gravity)}" integrator="{settings["integrator"]}" '
            f'cone="{settings["cone"]}" impratio="{_f(settings["impratio"])}" solver="Newton" '
            f'iterations="{int(settings["iterations"])}" tolerance="1e-10"/>'
            f'<asset>{"".join(assets)}</asset><worldbody>{base_geom}{"".join(bodies)}</worldbody>'
            f'<contact>{"".join(pairs)}</contact></mujoco>')


def _geom_xml(k, outline, depth, assets) -> str:
    """The geom ``g{k}`` of a body whose frame holds ``outline`` (n, 2), m, with ``depth`` (m); a mesh goes to
    ``assets``."""
    box = geometry.rectangle(outline)
    if box is not None:
        half_x, half_z = box.half_extents
        quat = f"{_f(np.cos(box.angle / 2))} 0 {_f(-np.sin(box.angle / 2))} 0"  # about -y: counter-clockwise
        centred = np.max(np.abs(box.centre)) <= geometry.RECTANGLE_TOLERANCE * np.max(box.half_extents)
        pos = "" if centred else f' pos="{_f(box.centre[0])} 0 {_f(box.centre[1])}"'
        return (f'<geom name="g{k}" type="box" size="{_f(half_x)} {_f(depth / 2)} {_f(half_z)}"{pos} '
                f'quat="{quat}" contype="0" conaffinity="0"/>')
    points = " ".join(f"{_f(x)} {_f(y)} {_f(z)}" for x, y, z in geometry.prism(outline, depth).vertices)
    assets.append(f'<mesh name="m{k}" vertex="{points}"/>')
    return f'<geom name="g{k}" type="mesh" mesh="m{k}" contype="0" conaffinity="0"/>'


def _f(x) -> str:
    return repr(float(x))


def _build(scene, dt, settings) -> EngineRun:
    try:
        model = mujoco.MjModel.from_xml_string(model_xml(scene, dt, settings))
    except ValueError as exc:
        raise ValueError(f"mujoco could not build the scene: {exc}") from None
    data = mujoco.MjData(model)
    start = geometry.start_states(scene.blocks)

    def set_gravity(gx, gy):
        model.opt.gravity[0] = gx
        model.opt.gravity[2] = gy

    def state():
        return start + data.qpos.reshape(-1, 3)

    return EngineRun(set_gravity, lambda: mujoco.mj_step(model, data), state,
                     {k: (list(v) if isinstance(v, tuple) else v) for k, v in settings.items()})
