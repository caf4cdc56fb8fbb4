"""Native 2D soft-contact discrete element method for stone blocks under ground motion.

>>> import dem_core
>>> scene = dem_core.scenes.column(n_drums=8, width=1.0, height=6.0)
>>> result = dem_core.simulate(scene, dem_core.excitation.record("el_centro_1940"))

The package is laid out by what each part is for:

* :mod:`dem_core.engine`: contact laws, geometry, the compiled model, the time step, the compiled kernels;
* :mod:`dem_core.inputs`: scenes and their builders, scene files, ground motions and records;
* :mod:`dem_core.simulation`: ``simulate`` and ``Simulation``, a scene and a ground motion run by the engine;
* :mod:`dem_core.batch`: ``simulate_batch``, many ground motions through one scene on every core;
* :mod:`dem_core.analyses`: threshold searches, parametric sweeps, response spectra, stiffness convergence,
  fragility curves;
* :mod:`dem_core.pictures`: figures and animations (import matplotlib).

The modules users reach for are also names here: ``dem_core.scenes``, ``excitation``, ``records``,
``contact``, ``geometry``, ``stability``, ``thresholds``, ``sweep``, ``spectra``, ``convergence``.
The method is written out in the project's docs/method.md.
"""

from .analyses import convergence, spectra, sweep, thresholds
from .engine import contact, geometry, stability
from .engine.contact import ContactParameters
from .engine.model import compile_model
from .engine.result import Result
from .simulation import RunTooLarge, Simulation, SimulationUnstable, automatic_time_step, simulate
from .batch import simulate_batch
from .inputs import excitation, records, scenes
from .inputs.scene import Block, Scene, SceneError

__all__ = [
    "Block", "ContactParameters", "Result", "RunTooLarge", "Scene", "SceneError", "Simulation", "SimulationUnstable",
    "automatic_time_step", "compile_model",
    "contact", "convergence", "excitation", "geometry", "records", "scenes", "simulate", "simulate_batch", "spectra",
    "stability",
    "sweep", "thresholds",
]
