"""The members the batch benchmarks run (``batch-throughput``, ``gpu-check``): the 1 x 6 m block and the 8-drum
column (6 m x 1 m), each under the 1940 El Centro record scaled evenly from 1.2 to 3 times its rocking threshold
g tan(alpha), the spread of the report's ensembles.  It imports no other engine, so that ``gpu-check`` runs where
only dem_core's own dependencies are installed."""

import warnings

import numpy as np

from dem_core import excitation, scenes
from dem_core.inputs.records import G_STANDARD

#: scene name -> (builder, its rocking threshold's tan(alpha))
SCENES = {
    "block": (lambda: scenes.block(1.0, 6.0), 1.0 / 6.0),
    "column": (lambda: scenes.column(n_drums=8, width=1.0, height=6.0), 1.0 / 6.0),
}
#: the device check's cases (scene, integrator): those the issue marks (the block by central differences, the column
#: by Moreau-Jean), then the other two
MARKED_CASES = (("block", "explicit"), ("column", "moreau"))
OTHER_CASES = (("block", "moreau"), ("column", "explicit"))
CASES = MARKED_CASES + OTHER_CASES
#: the members' amplitudes span these multiples of g tan(alpha)
LOWEST, HIGHEST = 1.2, 3.0
#: the amplitude of a lone member, midway
MIDDLE = 0.5 * (LOWEST + HIGHEST)
RECORD = "el_centro_1940"


def motion(tan_alpha: float, amplitude: float, nudge: float = 0.0, record=None):
    """The record (``record``, else :data:`RECORD` loaded) scaled to ``amplitude`` times g tan(alpha), times
    ``1 + nudge``."""
    record = excitation.record(RECORD) if record is None else record
    return excitation.scaled(record, amplitude * (G_STANDARD * tan_alpha / record.horizontal.peak_acceleration
                                                  * (1.0 + nudge)))


def motions(tan_alpha: float, members: int, nudge: float = 0.0) -> list:
    """The members' ground motions: one record, loaded once, at ``members`` amplitudes from LOWEST to HIGHEST g
    tan(alpha) (one member: MIDDLE), each scale times ``1 + nudge``.  The members scale the same record, so that a
    batch samples it once for all of them."""
    record = excitation.record(RECORD)
    amplitudes = np.linspace(LOWEST, HIGHEST, members) if members > 1 else np.array([MIDDLE])
    return [motion(tan_alpha, a, nudge, record) for a in amplitudes]


def ignore_the_cut_strong_motion() -> None:
    """Silence the warning that a run stops before the record's strong motion ends: the issue's measures run 20 s
    of El Centro, short of its strong motion's end (26.3 s), by design."""
    warnings.filterwarnings("ignore", message="the strong motion is cut")
