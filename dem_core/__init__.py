"""Native 2D soft-contact discrete element method for stone blocks under ground motion.

>>> import dem_core
>>> scene = dem_core.scenes.column(n_drums=8, width=1.0, height=6.0)
>>> result = dem_core.simulate(scene, dem_core.excitation.record("el_centro_1940"))

Parametric sweeps: :mod:`dem_core.sweep`; overturning and onset searches: :mod:`dem_core.thresholds`;
response spectra: :mod:`dem_core.spectra`; animations: :mod:`dem_core.animation` (imports matplotlib).
Method, scenes and benchmarks: FORMULATION.md (shared with the project).
"""

from . import contact, excitation, geometry, records, scenes, spectra, stability, sweep, thresholds
from .contact import ContactParameters
from .result import Result
from .scene import Block, Scene, SceneError
from .simulation import SimulationUnstable, automatic_time_step, simulate

__all__ = [
    "Block", "ContactParameters", "Result", "Scene", "SceneError", "SimulationUnstable", "automatic_time_step",
    "contact", "excitation", "geometry", "records", "scenes", "simulate", "spectra", "stability", "sweep",
    "thresholds",
]
