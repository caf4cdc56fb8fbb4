"""The scenes of :mod:`dem_core` built in other physics engines, with the same result type.

``adapters.simulate(scene, excitation, duration, engine="pymunk" | "pybullet" | "mujoco" | "dem", dt=None,
output_dt=None, **engine_options)`` returns a :class:`dem_core.Result` like :func:`dem_core.simulate`
(the slip at each interface is measured on the blocks' motion every millisecond by the native core's own stage,
:func:`dem_core.engine._interfaces.follow_interfaces`); an unstable run raises
:class:`dem_core.SimulationUnstable` in every engine.  How each engine maps the
scene (geometry, mass, friction, restitution, contact softness, ground motion) is in its module's
docstring and in the README's engine table.
"""

import dem_core

from . import mujoco_adapter, pybullet_adapter, pymunk_adapter

ENGINES = {
    "dem": dem_core.simulate,
    "pymunk": pymunk_adapter.simulate,
    "pybullet": pybullet_adapter.simulate,
    "mujoco": mujoco_adapter.simulate,
}

__all__ = ["ENGINES", "simulate"]


def simulate(scene, excitation=None, duration=None, engine: str = "pymunk", dt=None, output_dt=None,
             **engine_options):
    """Run ``scene`` under ``excitation`` in ``engine``; see the module docstring."""
    if engine not in ENGINES:
        raise ValueError(f"unknown engine {engine!r}; choose one of {', '.join(ENGINES)}")
    return ENGINES[engine](scene, excitation, duration, dt, output_dt, **engine_options)
